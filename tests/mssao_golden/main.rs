//! Golden tests of MSSAO's own math: the real technique (built through the registry on
//! imported, hand-made g-buffers) runs on the GPU, every pass's output is read back and compared
//! with a CPU recomputation of the same arithmetic on the same inputs (the GPU's previous pass):
//! Table 2's downsampling exactly, Eq. 5's radius and every level's tap count exactly, the
//! Table 4 blur with Eqs. 8-9, the bilateral upsampling (Fig. 9), Eqs. 10-11, and the temporal
//! filter (Eqs. 13-14) exactly on an orthographic still camera, plus its flicker under a slow
//! camera motion. Formulas mirror shaders/common/mssao.wgsl and shaders/ao/mssao/*.wgsl.
//! Skips (saying so) only without an adapter and AOGRAPH_REQUIRE_GPU.

use std::sync::Arc;

use aograph_ao_passes::{AoBuildContext, TechniqueRegistry};
use aograph_frame::{GBufferChannel, GBufferTextures, VIEW_BUFFER, ViewUniforms};
use aograph_graph::{
    BufferDesc, CompileOptions, CompiledGraph, Executor, Extent, GpuContext, GraphBuilder,
    ResourceOrigin, SizeClass, TextureDesc, TextureHandle, compile, test_gpu,
};
use aograph_scene::view_block::{ViewFrame, view_uniforms};
use aograph_scene::{Camera, Projection};
use glam::{DMat4, DVec3, Vec3};

type V3 = [f32; 3];
type V4 = [f32; 4];

mod compare;
mod cpu;
mod downsampling;
mod gpu;
mod inputs;
mod temporal;

use compare::*;
use cpu::*;
use gpu::*;
use inputs::*;

// ---------------------------------------------------------------------------------------------
// 1. Table 2: downsampling

#[test]
fn downsampling_keeps_the_median_within_d_threshold_and_the_second_nearest_beyond() {
    // 6x4 -> 3x2; sub-pixel i of block (bx, by) is (2 bx + (i & 1), 2 by + (i >> 1)).
    let mut g = GBuffer::sky(6, 4);
    let mut put = |bx: usize, by: usize, i: usize, p: V3, n: V3| {
        g.set(2 * bx + (i & 1), 2 * by + (i >> 1), p, n)
    };
    // (0, 0): depths 2.5, 2.0, 3.0, 2.25: range 1.0 = d_threshold exactly ("at most"): the
    // mean of the 2nd and 3rd nearest (2.25 and 2.5), normals (1,0,0) + (0,1,0) renormalised.
    put(0, 0, 0, [-0.5, 0.5, -2.5], [0.0, 1.0, 0.0]);
    put(0, 0, 1, [-0.25, 0.5, -2.0], [0.0, 0.0, 1.0]);
    put(0, 0, 2, [-0.5, 0.25, -3.0], [0.0, 0.0, 1.0]);
    put(0, 0, 3, [-0.25, 0.25, -2.25], [1.0, 0.0, 0.0]);
    // (1, 0): depths 4.0, 2.0, 2.5, 3.5: range 2 > 1: the second-nearest (2.5) as it is.
    put(1, 0, 0, [0.25, 0.5, -4.0], [0.0, 0.0, 1.0]);
    put(1, 0, 1, [0.5, 0.5, -2.0], [0.0, 0.0, 1.0]);
    put(1, 0, 2, [0.25, 0.25, -2.5], [0.0, 0.6, 0.8]);
    put(1, 0, 3, [0.5, 0.25, -3.5], [0.0, 0.0, 1.0]);
    // (2, 0): one sky sub-pixel sorts last, so the range is unbounded: the second-nearest of
    // 3.0, 3.125, 3.25 (3.125), although the geometry alone spans only 0.25.
    put(2, 0, 1, [1.0, 0.5, -3.0], [0.0, 0.0, 1.0]);
    put(2, 0, 2, [0.75, 0.25, -3.25], [0.0, 1.0, 0.0]);
    put(2, 0, 3, [1.0, 0.25, -3.125], [1.0, 0.0, 0.0]);
    // (0, 1): three sky sub-pixels (one with w = 0 but a position in front of the camera):
    // sky.
    put(0, 1, 3, [-0.25, -0.25, -5.0], [0.0, 0.0, 1.0]);
    // (1, 1): two sky sub-pixels (one a point behind the camera, w = 1, z > 0): the
    // second-nearest is the farther geometry sub-pixel (7.0).
    put(1, 1, 0, [0.25, -0.25, -2.0], [0.0, 0.0, 1.0]);
    put(1, 1, 2, [0.25, -0.5, 1.0], [0.0, 0.0, 1.0]);
    put(1, 1, 3, [0.5, -0.5, -7.0], [0.0, 1.0, 0.0]);
    // (2, 1): equal depths (range 0): the stable sort keeps sub-pixels 1 and 2 in the middle;
    // their normals cancel, so the normal falls back to sub-pixel 1's.
    put(2, 1, 0, [0.75, -0.25, -6.0], [0.0, 0.0, 1.0]);
    put(2, 1, 1, [1.0, -0.25, -6.0], [1.0, 0.0, 0.0]);
    put(2, 1, 2, [0.75, -0.5, -6.0], [-1.0, 0.0, 0.0]);
    put(2, 1, 3, [1.0, -0.5, -6.0], [0.0, 0.0, 1.0]);
    // Block (0, 1)'s sub-pixel 0, texel (0, 2): w = 0 with a position in front of the camera.
    g.positions[2 * 6] = [0.3, -0.2, -1.0, 0.0];

    let Some(mut m) = Mssao::new(6, 4, 1.0, "levels = 2\nd_threshold = 1.0") else {
        return;
    };
    m.frame(&g, front_camera());
    let l1 = m.level(1, &g);
    // Block (0, 1) has three sky sub-pixels: sky, depth 0 and code 0. Block (2, 0) keeps the
    // second-nearest (3.125, normal +x), but its plane x = const is not where the block's
    // centre looks within the geometry's depths, and the block has sky: sky too.
    assert_eq!((l1.z[3], l1.bits[3]), (0.0, 0), "sky texel");
    assert_eq!(
        (l1.z[2], l1.bits[2]),
        (0.0, 0),
        "looks past its surface into the sky"
    );
    // Block (1, 1) likewise: two sky sub-pixels, the kept 7.0 with normal +y.
    assert_eq!(
        (l1.z[4], l1.bits[4]),
        (0.0, 0),
        "looks past its surface into the sky"
    );
    // Every other texel's depth is that of the kept point's plane at the texel's centre,
    // within the block's geometry depths (0,0): [2.0, 3.0]; (1,0): [2.0, 4.0]; (2,1): 6.0.
    for (i, (lo, hi)) in [(0, (2.0, 3.0)), (1, (2.0, 4.0)), (5, (6.0, 6.0))] {
        assert!(
            (lo..=hi).contains(&l1.z[i]),
            "texel {i}: depth {} outside [{lo}, {hi}]",
            l1.z[i]
        );
    }
    // Block (2, 1): four equal depths facing the camera's axis at 6.0 with the fallback
    // normal (1, 0, 0) of sub-pixel 1 (the middle normals cancel): the plane x = const meets
    // the centre's line of sight elsewhere, and the block's range [6, 6] holds it at 6.
    assert_eq!(l1.z[5], 6.0);
    // Normals decoded: within the octahedral encoding's error (1/32767 of the square per
    // component, about 1e-4 of the unit vector after decoding), twice for a mean of two.
    let r = std::f32::consts::FRAC_1_SQRT_2;
    let want_n: [V3; 6] = [
        [r, r, 0.0],
        [0.0, 0.6, 0.8],
        [0.0, 0.0, 1.0],
        [0.0, 0.0, 1.0],
        [0.0, 0.0, 1.0],
        [1.0, 0.0, 0.0],
    ];
    const OCT: f32 = 2e-4;
    for c in 0..3 {
        let want: Vec<f32> = want_n.iter().map(|n| n[c]).collect();
        assert_within(
            &channel(&l1.n, c),
            &want,
            |_| OCT,
            &format!("level-1 normals[{c}]"),
        );
    }
    // Positions: rebuilt at each level-1 texel's centre with its depth.
    let grid = m.grid(1);
    for (i, p) in l1.p.iter().enumerate() {
        if l1.z[i] > 0.0 {
            let q = grid.position(i % 3, i / 3, l1.z[i]);
            assert_eq!([p[0], p[1], p[2], p[3]], [q[0], q[1], q[2], 1.0]);
        } else {
            assert_eq!(*p, [0.0; 4]);
        }
    }
    let cpu = downsample(&m.level(0, &g), 1.0, &m.grid(0), &grid);
    assert_within(&cpu.z, &l1.z, |z| DEPTH_TOL * z, "CPU model depths");
    assert_eq!(
        cpu.bits, l1.bits,
        "CPU model normals (the same f32 operations)"
    );

    // A 4-level pyramid of the box scene at odd sizes (clamped fetches), level by level from
    // the GPU's previous level.
    let Some((m, g)) = box_scene_run(4, 1.0, "d_threshold = 0.5") else {
        return;
    };
    let mut prev = m.level(0, &g);
    for l in 1..4 {
        let got = m.level(l, &g);
        let want = downsample(&prev, 0.5, &m.grid(l - 1), &m.grid(l));
        assert_eq!((got.w, got.h), (want.w, want.h));
        let worst_z = assert_within(
            &got.z,
            &want.z,
            |z| DEPTH_TOL * z,
            &format!("level {l} depths"),
        );
        // Normals: the GPU's sqrt and division may differ from the CPU's by an ulp before
        // the encoding rounds, which can move a component by one step of 1/32767.
        let worst = (0..3)
            .map(|c| {
                assert_within(
                    &channel(&got.n, c),
                    &channel(&want.n, c),
                    |_| 1e-4,
                    &format!("level {l} normals[{c}]"),
                )
            })
            .fold(0.0, f32::max);
        let medians = (0..want.z.len())
            .filter(|&i| want.z[i] > 0.0 && !prev.z.contains(&want.z[i]))
            .count();
        println!(
            "box scene level {l} ({}x{}): depths within {worst_z:e}, normals within {worst:e}, {medians} of {} texels are new depths",
            want.w,
            want.h,
            want.z.len()
        );
        assert!(medians > 0, "level {l} has texels averaged by Table 2");
        prev = got;
    }
}

/// Relative tolerance of a rebuilt depth: the plane's depth is a quotient of two dot
/// products of rebuilt positions, each within a few ulp (2^-24) of the CPU's, and the GPU may
/// fuse their multiply-adds.
const DEPTH_TOL: f32 = 1e-5;

#[test]
fn a_planes_pyramid_stays_on_the_plane_at_every_level() {
    // The floor alone (y = -1.2 in view space, which is world space for the front camera),
    // far enough to fill the lower half of the view; every level's rebuilt positions away
    // from the horizon (texels whose 3x3 neighbourhood is all geometry) lie on it, whether
    // Table 2 kept a median (d_threshold = 1e3) or the second-nearest (d_threshold = 0).
    let floor = vec![(DVec3::new(-1e3, -1.4, -1e3), DVec3::new(1e3, -1.2, -1.0))];
    let camera = front_camera();
    let (g, _) = cast(&camera, W, H, &floor);
    for d_threshold in [1e3, 0.0] {
        let Some(mut m) = Mssao::new(
            W,
            H,
            1.0,
            &format!("levels = 5\nd_threshold = {d_threshold}"),
        ) else {
            return;
        };
        m.frame(&g, camera);
        for l in 0..5 {
            let level = m.level(l, &g);
            let mut checked = 0;
            for y in 1..level.h as i32 - 1 {
                for x in 1..level.w as i32 - 1 {
                    let all_geometry = (-1..=1)
                        .all(|dy| (-1..=1).all(|dx| level.surface(x + dx, y + dy).is_some()));
                    if !all_geometry {
                        continue;
                    }
                    let s = level.surface(x, y).unwrap();
                    let off = (s.p[1] + 1.2).abs();
                    assert!(
                        off <= 1e-5 * -s.p[2],
                        "d_threshold {d_threshold}, level {l}, texel ({x}, {y}): {:?} is {off:e} off the floor",
                        s.p
                    );
                    checked += 1;
                }
            }
            println!("d_threshold {d_threshold}: level {l}: {checked} texels on the plane");
            assert!(checked > 0 || l >= 3, "level {l} checks nothing");
        }
    }
}

// ---------------------------------------------------------------------------------------------
// 2. Eq. 5 and the kernels per level

/// The CPU's coarsest-level tuple of level `l`: (sum / N, sum, N), 0 on sky.
fn coarsest_cpu(l: &Level, level: u32, k: &Consts) -> Vec<V3> {
    let mut out = vec![[0.0; 3]; l.w * l.h];
    for y in 0..l.h as i32 {
        for x in 0..l.w as i32 {
            if let Some(s) = l.surface(x, y) {
                let r = kernel_radius(k, -s.p[2], level);
                out[l.index(x, y)] = combine(near_interleaved(l, x, y, &s, r, k.d_max), [0.0; 3]);
            }
        }
    }
    out
}

/// N of a kernel wholly on screen at radius R: ring k holds 4k odd-offset taps, each counted
/// with the ring's weight (`cpu::ring_weight`); 4, 16 and 36 at R = 1, 3 and 5.
fn on_screen_count(r: f32) -> f32 {
    (1..=9)
        .step_by(2)
        .map(|k| 4.0 * k as f32 * cpu::ring_weight(k, r))
        .sum()
}

#[test]
fn coarse_levels_weigh_the_odd_offset_rings_of_the_eq_5_radius_continuously() {
    // R = 1.5: r_0 = R * 19 * cot(30 deg) / z = 49.4 / z px runs from 23 to 5.4, so level 1
    // is capped at r_max = 5 (36 taps) near the camera, and levels 1-3 see every ring partly
    // weighed.
    assert_eq!(
        [1.0, 2.0, 3.0, 4.0, 5.0].map(on_screen_count),
        [4.0, 10.0, 16.0, 26.0, 36.0],
        "the paper's 4, 16 and 36 taps at odd R, halfway between at even R"
    );
    let radius = 1.5;
    let mut seen = std::collections::BTreeSet::<(u32, &str)>::new();
    for levels in 2..=4u32 {
        let Some((m, g)) = box_scene_run(levels, radius, "") else {
            return;
        };
        let l = levels - 1;
        let k = m.consts(radius, &DEFAULTS);
        let level = m.level(l, &g);
        let got = m.read(&format!("mssao.ao{l}"), "ao");
        let want = coarsest_cpu(&level, l, &k);
        // Counts are sums of at most 36 weights in [0, 1]: f32-exact up to rounding.
        let e_n = assert_close(&channel(&got, 2), &channel3(&want, 2), 1e-5, "count");
        let e_sum = assert_close(&channel(&got, 1), &channel3(&want, 1), SUM_FLOOR, "sum");
        let e_mean = assert_close(&channel(&got, 0), &channel3(&want, 0), FLOOR, "mean");
        for y in 0..level.h as i32 {
            for x in 0..level.w as i32 {
                let Some(s) = level.surface(x, y) else {
                    continue;
                };
                // Kernels wholly on screen: the closed-form count of Eq. 5's radius.
                let r = kernel_radius(&k, -s.p[2], l);
                let kk = if r > 0.0 {
                    (((r + 1.0) * 0.5).ceil() as i32 * 2 - 1).min(9)
                } else {
                    0
                };
                if x - kk >= 0 && y - kk >= 0 && x + kk < level.w as i32 && y + kk < level.h as i32
                {
                    let n = got[level.index(x, y)][2];
                    let full = on_screen_count(r);
                    assert!(
                        (n - full).abs() <= 1e-4 * full.max(1.0),
                        "level {l} texel ({x}, {y}), radius {r}: N {n}, want {full}"
                    );
                    let class = match n {
                        n if n >= 36.0 - 1e-4 => "36",
                        n if n > 16.0 => "16-36",
                        n if n > 4.0 => "4-16",
                        n if n > 0.0 => "0-4",
                        _ => "0",
                    };
                    seen.insert((l, class));
                }
            }
        }
        println!(
            "level {l} ({}x{}): relative errors: counts {e_n:e}, sums {e_sum:e}, means {e_mean:e}",
            level.w, level.h
        );
    }
    println!("(level, N) of on-screen kernels: {seen:?}");
    for want in [
        (1, "36"),
        (1, "16-36"),
        (1, "4-16"),
        (2, "4-16"),
        (3, "0-4"),
    ] {
        assert!(
            seen.contains(&want),
            "a level-{} kernel with N in {}",
            want.0,
            want.1
        );
    }
}

#[test]
fn finest_level_takes_the_16_point_poisson_disk_scaled_by_the_eq_5_radius() {
    // levels = 1: the disk's (sum, N) is the whole tuple and Eq. 11 gives (1 - sum / N)^2.
    // R = 1.5 (radius capped at r_max = 5 everywhere) and R = 0.25 (r_0 = 8.2 / z from 3.9
    // down to 0.9 px: disk points merge, round onto the pixel and vanish below 1 px).
    for radius in [1.5, 0.25] {
        let Some((m, g)) = box_scene_run(1, radius, "") else {
            return;
        };
        let k = m.consts(radius, &DEFAULTS);
        let l0 = m.level(0, &g);
        let mut want = vec![1.0f32; W * H];
        let mut counts = std::collections::BTreeMap::<u32, usize>::new();
        for y in 0..H as i32 {
            for x in 0..W as i32 {
                if let Some(s) = l0.surface(x, y) {
                    let r = kernel_radius(&k, -s.p[2], 0);
                    let near = near_poisson(&l0, x, y, &s, r, k.d_max);
                    want[l0.index(x, y)] = accessibility(combine(near, [0.0; 3]));
                    *counts.entry(near.1 as u32).or_default() += 1;
                }
            }
        }
        let worst = assert_close(&m.spatial(), &want, FLOOR, &format!("R = {radius}"));
        let occluded = want.iter().filter(|a| **a < 0.99).count();
        println!(
            "levels = 1, R = {radius}: accessibility within {worst:e} (relative) of the CPU; taps per pixel {counts:?}; {occluded} pixels below 0.99"
        );
        assert!(occluded > 50, "the scene is occluded somewhere");
    }
}

// ---------------------------------------------------------------------------------------------
// 3. Blur, bilateral upsampling, Eqs. 10-11

#[test]
fn blur_weighs_table_4_by_eqs_8_and_9_and_normalises() {
    let radius = 1.5;
    for bilateral in [true, false] {
        let Some((m, g)) = box_scene_run(3, radius, &format!("bilateral_blur = {bilateral}"))
        else {
            return;
        };
        let k = m.consts(
            radius,
            &Params {
                bilateral_blur: bilateral,
                ..DEFAULTS
            },
        );
        for l in 1..3 {
            let level = m.level(l, &g);
            let src = m.read(&format!("mssao.ao{l}"), "ao");
            let got = m.read(&format!("mssao.blur{l}"), "dst");
            let want = blur(&src, &level, &k);
            let worst = (0..3)
                .map(|c| {
                    assert_close(
                        &channel(&got, c),
                        &channel3(&want, c),
                        [FLOOR, SUM_FLOOR, 0.0][c],
                        &format!("bilateral_blur = {bilateral}, level {l}, channel {c}"),
                    )
                })
                .fold(0.0, f32::max);
            println!(
                "blur level {l}, bilateral_blur = {bilateral}: within {worst:e} (relative) of the CPU"
            );
        }
    }
}

/// Level `l`'s tuple as the CPU computes it from the GPU's pyramid and the GPU's blurred tuple
/// of level l + 1: (near (sum, N), upsampled far tuple) per texel (None on sky).
fn near_and_far(m: &Mssao, g: &GBuffer, l: u32, k: &Consts) -> Vec<Option<((f32, f32), V3)>> {
    let fine = m.level(l, g);
    let coarse = m.level(l + 1, g);
    let blurred = m.read(&format!("mssao.blur{}", l + 1), "dst");
    let mut out = vec![None; fine.w * fine.h];
    for y in 0..fine.h as i32 {
        for x in 0..fine.w as i32 {
            let Some(s) = fine.surface(x, y) else {
                continue;
            };
            let r = kernel_radius(k, -s.p[2], l);
            let near = if l == 0 {
                near_poisson(&fine, x, y, &s, r, k.d_max)
            } else {
                near_interleaved(&fine, x, y, &s, r, k.d_max)
            };
            out[fine.index(x, y)] = Some((near, upsample(&blurred, &coarse, x, y, &s, k)));
        }
    }
    out
}

#[test]
fn upsampling_weighs_the_2x2_coarse_texels_9_3_3_1_times_eqs_8_and_9() {
    // The sum and count channels of a level's tuple are its own (sum, N) plus the upsampled
    // blurred tuple of the level below (Eq. 10), so they check the upsampling alone.
    let radius = 1.5;
    let Some((m, g)) = box_scene_run(4, radius, "") else {
        return;
    };
    let k = m.consts(radius, &DEFAULTS);
    for l in 1..3 {
        let got = m.read(&format!("mssao.ao{l}"), "ao");
        let nf = near_and_far(&m, &g, l, &k);
        let want: Vec<V3> = nf
            .iter()
            .map(|t| t.map_or([0.0; 3], |(n, f)| combine(n, f)))
            .collect();
        let e_sum = assert_close(&channel(&got, 1), &channel3(&want, 1), SUM_FLOOR, "sum");
        let e_n = assert_close(&channel(&got, 2), &channel3(&want, 2), 0.0, "count");
        // The test has teeth: Eqs. 8-9 move the upsampled count away from the bilinear one.
        let bilinear = Consts {
            t_n: 0.0,
            t_z: 0.0,
            ..k
        };
        let plain = near_and_far(&m, &g, l, &bilinear);
        let differ = nf
            .iter()
            .zip(&plain)
            .filter(|(a, b)| match (a, b) {
                (Some((_, fa)), Some((_, fb))) => (fa[2] - fb[2]).abs() > 0.01,
                _ => false,
            })
            .count();
        println!(
            "level {l}: relative errors: sums {e_sum:e}, counts {e_n:e}; {differ} texels where Eqs. 8-9 move the count by > 0.01"
        );
        assert!(
            differ > 10,
            "level {l}: the bilateral weights matter somewhere"
        );
    }
}

#[test]
fn fig_8_upsampling_modes_take_the_enclosing_texel_or_the_bilinear_weights() {
    // `upsampling = "nearest"` passes on the enclosing coarse texel's tuple, "bilinear" the
    // four nearest with 9/16, 3/16, 3/16, 1/16 and no Eqs. 8-9; sums and counts checked as
    // above against the CPU; the three modes give different counts.
    let radius = 1.5;
    let mut counts = Vec::new();
    for (mode, name) in [(0, "nearest"), (1, "bilinear"), (2, "bilateral")] {
        let Some((m, g)) = box_scene_run(4, radius, &format!("upsampling = \"{name}\"")) else {
            return;
        };
        let k = m.consts(
            radius,
            &Params {
                upsampling: mode,
                ..DEFAULTS
            },
        );
        let l = 1;
        let got = m.read(&format!("mssao.ao{l}"), "ao");
        let want: Vec<V3> = near_and_far(&m, &g, l, &k)
            .iter()
            .map(|t| t.map_or([0.0; 3], |(n, f)| combine(n, f)))
            .collect();
        let e_sum = assert_close(&channel(&got, 1), &channel3(&want, 1), SUM_FLOOR, name);
        let e_n = assert_close(&channel(&got, 2), &channel3(&want, 2), 0.0, name);
        println!("{name}: level {l} sums within {e_sum:e}, counts within {e_n:e} (relative)");
        counts.push(channel(&got, 2));
    }
    let differ = |a: &[f32], b: &[f32]| {
        a.iter()
            .zip(b)
            .filter(|(x, y)| (*x - *y).abs() > 0.01)
            .count()
    };
    let (nb, bb) = (
        differ(&counts[0], &counts[1]),
        differ(&counts[1], &counts[2]),
    );
    println!("texels whose count differs: nearest/bilinear {nb}, bilinear/bilateral {bb}");
    assert!(nb > 10 && bb > 10, "the modes must differ: {nb}, {bb}");
}

#[test]
fn levels_combine_by_the_max_of_means_eq_10_and_into_accessibility_by_eq_11() {
    let radius = 1.5;
    let Some((m, g)) = box_scene_run(4, radius, "") else {
        return;
    };
    let k = m.consts(radius, &DEFAULTS);
    // Eq. 10's first channel at levels 1 and 2: max(sum / N, far.max).
    for l in 1..3 {
        let got = m.read(&format!("mssao.ao{l}"), "ao");
        let nf = near_and_far(&m, &g, l, &k);
        let want: Vec<f32> = nf
            .iter()
            .map(|t| t.map_or(0.0, |(n, f)| combine(n, f)[0]))
            .collect();
        let worst = assert_close(&channel(&got, 0), &want, FLOOR, &format!("level {l} max"));
        // The input tells max from mean: both sides of the max win somewhere, by > 0.01.
        let (mut near_wins, mut far_wins) = (0, 0);
        for (n, f) in nf.iter().flatten() {
            let mean = if n.1 > 0.0 { n.0 / n.1 } else { 0.0 };
            near_wins += (mean > f[0] + 0.01) as usize;
            far_wins += (f[0] > mean + 0.01) as usize;
        }
        println!(
            "level {l}: AO_max within {worst:e} (relative); the near mean wins at {near_wins} texels, the far max at {far_wins}"
        );
        assert!(
            near_wins > 0 && far_wins > 0,
            "level {l}: max(a, b) is not a or b alone"
        );
    }
    // Level 0 (ao_final.wgsl): Poisson disk + upsampled level 1 + Eq. 10, then Eq. 11.
    let want: Vec<f32> = near_and_far(&m, &g, 0, &k)
        .iter()
        .map(|t| t.map_or(1.0, |(n, f)| accessibility(combine(n, f))))
        .collect();
    let worst = assert_close(&m.spatial(), &want, FLOOR, "accessibility (Eq. 11)");
    let got = m.output();
    assert_eq!(
        got,
        m.spatial(),
        "without the temporal filter mssao.ao0 is the output"
    );
    let mean = got.iter().sum::<f32>() / got.len() as f32;
    println!("level 0: accessibility within {worst:e} (relative) of the CPU (mean {mean:.4})");
}
