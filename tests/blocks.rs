//! The shared AO blocks on the GPU: each runs on a known image (imported R32Float textures)
//! and is compared with a CPU computation of the same arithmetic: the 3x3-average pyramid
//! exactly on integer data, min/max exactly, blurs of constants and impulses, edge-stopping of
//! the bilateral filters, XeGTAO's depth prefilter and edge-aware denoiser against CPU mirrors.
//! Skips (saying so) only without an adapter and AOGRAPH_REQUIRE_GPU.

use std::sync::Arc;

use aograph_ao::blocks::depth_pyramid::reduce_cpu;
use aograph_ao::blocks::*;
use aograph_graph::{
    CompileOptions, Executor, Extent, GraphBuilder, SizeClass, TextureDesc, TextureHandle, compile,
    test_gpu,
};
use wgpu::TextureFormat::{R32Float, Rgba32Float};

/// An imported texture: name, size, format (R32Float or Rgba32Float) and texels.
struct Input {
    name: &'static str,
    size: Extent,
    format: wgpu::TextureFormat,
    data: Vec<f32>,
}

fn r32(name: &'static str, w: u32, h: u32, data: Vec<f32>) -> Input {
    assert_eq!(data.len(), (w * h) as usize);
    Input {
        name,
        size: Extent::new(w, h),
        format: R32Float,
        data,
    }
}

/// Declares `inputs` (with the given size classes), lets `declare` add the block, runs one frame
/// at `output` and reads back every returned handle.
fn run(
    output: Extent,
    inputs: &[(&Input, SizeClass)],
    declare: impl FnOnce(&mut GraphBuilder, &[TextureHandle]) -> Vec<TextureHandle>,
) -> Option<Vec<Vec<f32>>> {
    let gpu = test_gpu()?;
    let mut b = GraphBuilder::new();
    let handles: Vec<TextureHandle> = inputs
        .iter()
        .map(|(i, s)| b.import_texture(i.name, TextureDesc::new(i.format, *s)))
        .collect();
    let outs = declare(&mut b, &handles);
    outs.iter().for_each(|h| b.export(*h));
    let plan = Arc::new(
        compile(
            b.build(),
            &aograph::shader_library(),
            CompileOptions::default(),
        )
        .expect("block graph compiles"),
    );
    let mut exec = Executor::with_shaders(gpu.clone(), aograph::shader_library());
    for (i, _) in inputs {
        let tex = gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some(i.name),
            size: wgpu::Extent3d {
                width: i.size.width,
                height: i.size.height,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: i.format,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        });
        let bytes: Vec<u8> = if i.format == wgpu::TextureFormat::Rgba8Unorm {
            i.data.iter().map(|f| (f * 255.0).round() as u8).collect()
        } else {
            i.data.iter().flat_map(|f| f.to_le_bytes()).collect()
        };
        let row = i.size.width * i.format.block_copy_size(None).unwrap();
        gpu.queue.write_texture(
            tex.as_image_copy(),
            &bytes,
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(row),
                rows_per_image: None,
            },
            tex.size(),
        );
        exec.import_texture(i.name, tex);
    }
    exec.execute(&plan, output).expect("block graph runs");
    Some(
        outs.iter()
            .map(|h| exec.read_texture(&plan, *h).unwrap().channel(0).unwrap())
            .collect(),
    )
}

/// Deterministic pseudo-random values in [0, 1).
fn noise(n: usize, seed: u32) -> Vec<f32> {
    (0..n as u32)
        .map(|i| {
            ((i.wrapping_mul(2654435761) ^ seed.wrapping_mul(40503)).wrapping_mul(2246822519) >> 8)
                as f32
                / 16777216.0
        })
        .collect()
}

fn assert_close(got: &[f32], want: &[f32], tol: f32, what: &str) {
    assert_eq!(got.len(), want.len(), "{what}: length");
    for (i, (g, w)) in got.iter().zip(want).enumerate() {
        assert!(
            g.is_finite() && (g - w).abs() <= tol * w.abs().max(1.0),
            "{what}: texel {i}: got {g}, want {w}"
        );
    }
}

#[test]
fn average_pyramid_of_a_9x9_image_is_exact() {
    // Block b (3x3) holds c_b + offsets summing to 0 over its non-sky taps; block 4 is all sky.
    let mut data = vec![0.0f32; 81];
    let offsets: [f32; 9] = [-4.0, -3.0, -2.0, -1.0, 0.0, 1.0, 2.0, 3.0, 4.0];
    for by in 0..3 {
        for bx in 0..3 {
            let b = by * 3 + bx;
            let c = 10.0 * (b + 1) as f32;
            for (k, o) in offsets.iter().enumerate() {
                let (x, y) = (bx * 3 + k % 3, by * 3 + k / 3);
                // In block 0 the +-4 taps are sky: a block mixing sky and geometry takes its
                // centre tap, c.
                let sky = b == 4 || (b == 0 && o.abs() == 4.0);
                data[y * 9 + x] = if sky { 0.0 } else { c + o };
            }
        }
    }
    let input = r32("depth", 9, 9, data.clone());
    let Some(out) = run(Extent::new(9, 9), &[(&input, SizeClass::FULL)], |b, h| {
        depth_pyramid(b, "t", h[0], DepthReduction::Average3x3, 3)
            .unwrap()
            .levels[1..]
            .to_vec()
    }) else {
        return;
    };
    let (l1, ..) = reduce_cpu(&data, 9, 9, DepthReduction::Average3x3);
    assert_eq!(l1, [10.0, 20.0, 30.0, 40.0, 0.0, 60.0, 70.0, 80.0, 90.0]);
    assert_eq!(out[0], l1, "level 1 (3x3) equals the CPU mean exactly");
    assert_eq!(
        out[1],
        [0.0],
        "level 2 (1x1): its block mixes sky and geometry and its centre (block 4) is sky"
    );
}

#[test]
fn pyramids_of_odd_sizes_match_the_cpu_per_level() {
    let (w, h) = (97u32, 61u32);
    let mut data: Vec<f32> = noise((w * h) as usize, 7)
        .iter()
        .map(|v| 1.0 + 20.0 * v)
        .collect();
    for (i, v) in data.iter_mut().enumerate() {
        if ((i as u32 % w) < 20 && (i as u32 / w) < 15) || i % 7 == 0 {
            *v = 0.0; // sky: a corner block and scattered texels
        }
    }
    let input = r32("depth", w, h, data.clone());
    for r in [
        DepthReduction::Average3x3,
        DepthReduction::Min2x2,
        DepthReduction::Max2x2,
    ] {
        let Some(out) = run(Extent::new(w, h), &[(&input, SizeClass::FULL)], |b, hs| {
            depth_pyramid(b, "t", hs[0], r, 4).unwrap().levels[1..].to_vec()
        }) else {
            return;
        };
        let (mut cur, mut cw, mut ch) = (data.clone(), w, h);
        for (l, got) in out.iter().enumerate() {
            (cur, cw, ch) = reduce_cpu(&cur, cw, ch, r);
            assert_eq!(
                Extent::new(cw, ch),
                level_size(r, Extent::new(w, h), l as u32 + 1)
            );
            if r == DepthReduction::Average3x3 {
                assert_close(got, &cur, 1e-6, &format!("{r:?} level {}", l + 1));
                cur = got.clone(); // continue from the GPU's level (rounding may differ by an ulp)
            } else {
                assert_eq!(got, &cur, "{r:?} level {} is exact", l + 1);
            }
        }
        let sizes: Vec<Extent> = (1..4)
            .map(|l| level_size(r, Extent::new(w, h), l))
            .collect();
        if r == DepthReduction::Average3x3 {
            // Centred: 11 -> 5, since ceil(11 / 3) = 4 would leave an odd overhang of 1.
            assert_eq!(
                sizes,
                [Extent::new(33, 21), Extent::new(11, 7), Extent::new(5, 3)]
            );
        }
    }
}

/// Level `l` of a `r` pyramid over `base`: centred for the 3x3 average, ceil-sized otherwise.
fn level_size(r: DepthReduction, base: Extent, l: u32) -> Extent {
    match r {
        DepthReduction::Average3x3 => centred_level_extent(base, 3, l),
        _ => level_extent(base, r.factor(), l),
    }
}

/// CPU mirror of the separable Gaussian (renormalised over in-bounds, non-sky taps; sky = 1).
fn gaussian_cpu(
    src: &[f32],
    depth: Option<&[f32]>,
    w: usize,
    h: usize,
    weights: &[f32],
) -> Vec<f32> {
    let r = (weights.len() / 2) as i32;
    let sky = |i: usize| depth.is_some_and(|d| d[i] <= 0.0);
    let pass = |src: &[f32], ax: (i32, i32)| -> Vec<f32> {
        (0..w * h)
            .map(|i| {
                if sky(i) {
                    return 1.0;
                }
                let (x, y) = ((i % w) as i32, (i / w) as i32);
                let (mut s, mut ws) = (0.0f32, 0.0f32);
                for k in -r..=r {
                    let (qx, qy) = (x + ax.0 * k, y + ax.1 * k);
                    if qx < 0
                        || qy < 0
                        || qx >= w as i32
                        || qy >= h as i32
                        || sky(qy as usize * w + qx as usize)
                    {
                        continue;
                    }
                    s += weights[(k + r) as usize] * src[qy as usize * w + qx as usize];
                    ws += weights[(k + r) as usize];
                }
                s / ws
            })
            .collect()
    };
    pass(&pass(src, (1, 0)), (0, 1))
}

#[test]
fn gaussian_of_a_constant_is_the_constant_and_of_an_impulse_the_weights() {
    let (w, h) = (15u32, 13u32);
    let constant = r32("ao", w, h, vec![0.625; (w * h) as usize]);
    let blur = GaussianBlur::default();
    let Some(out) = run(
        Extent::new(w, h),
        &[(&constant, SizeClass::FULL)],
        |b, hs| vec![gaussian_blur(b, "g", hs[0], None, &blur).unwrap()],
    ) else {
        return;
    };
    assert_close(&out[0], &vec![0.625; (w * h) as usize], 1e-6, "constant");

    let mut impulse = vec![0.0f32; (w * h) as usize];
    let (cx, cy) = (7usize, 6usize);
    impulse[cy * w as usize + cx] = 1.0;
    let input = r32("ao", w, h, impulse);
    let out = run(Extent::new(w, h), &[(&input, SizeClass::FULL)], |b, hs| {
        vec![gaussian_blur(b, "g", hs[0], None, &blur).unwrap()]
    })
    .unwrap();
    let wts = gaussian_weights(1.5, 5);
    let want: Vec<f32> = (0..(w * h) as usize)
        .map(|i| {
            let (dx, dy) = (
                (i % w as usize) as i32 - cx as i32,
                (i / w as usize) as i32 - cy as i32,
            );
            if dx.abs() <= 2 && dy.abs() <= 2 {
                wts[(dx + 2) as usize] * wts[(dy + 2) as usize]
            } else {
                0.0
            }
        })
        .collect();
    assert_close(&out[0], &want, 1e-6, "impulse response = w x w");
}

#[test]
fn gaussian_with_depth_keeps_sky_at_one_and_matches_the_cpu() {
    let (w, h) = (23usize, 17usize);
    let ao = noise(w * h, 3);
    let depth: Vec<f32> = (0..w * h)
        .map(|i| {
            if (i % w) + (i / w) < 9 {
                0.0
            } else {
                2.0 + (i % w) as f32 * 0.1
            }
        })
        .collect();
    let (a, d) = (
        r32("ao", w as u32, h as u32, ao.clone()),
        r32("depth", w as u32, h as u32, depth.clone()),
    );
    let p = GaussianBlur {
        sigma: 2.0,
        taps: 7,
        depth_sigma: None,
    };
    let Some(out) = run(
        Extent::new(w as u32, h as u32),
        &[(&a, SizeClass::FULL), (&d, SizeClass::FULL)],
        |b, hs| vec![gaussian_blur(b, "g", hs[0], Some(hs[1]), &p).unwrap()],
    ) else {
        return;
    };
    let want = gaussian_cpu(&ao, Some(&depth), w, h, &gaussian_weights(2.0, 7));
    assert_close(&out[0], &want, 2e-6, "sky-masked Gaussian");
    assert!(
        depth
            .iter()
            .zip(&out[0])
            .all(|(z, v)| *z > 0.0 || *v == 1.0),
        "sky is exactly 1"
    );
}

/// A depth step at x = w/2 (near left, far right), AO 0.2 left and 0.9 right.
fn step_scene(w: usize, h: usize) -> (Vec<f32>, Vec<f32>) {
    let left = |i: usize| i % w < w / 2;
    (
        (0..w * h)
            .map(|i| if left(i) { 0.2 } else { 0.9 })
            .collect(),
        (0..w * h)
            .map(|i| if left(i) { 1.0 } else { 5.0 })
            .collect(),
    )
}

#[test]
fn bilateral_blur_keeps_constants_and_stops_at_depth_and_normal_edges() {
    let (w, h) = (20usize, 12usize);
    let (ao, depth) = step_scene(w, h);
    // Normals: +z on the top half, +x on the bottom half (a crease at constant depth there).
    let normals: Vec<f32> = (0..w * h)
        .flat_map(|i| {
            if i / w < h / 2 {
                [0.0, 0.0, 1.0, 1.0]
            } else {
                [1.0, 0.0, 0.0, 1.0]
            }
        })
        .collect();
    let flat_ao: Vec<f32> = (0..w * h)
        .map(|i| if i / w < h / 2 { 0.3 } else { 0.7 })
        .collect();
    let n = Input {
        name: "normals",
        size: Extent::new(w as u32, h as u32),
        format: Rgba32Float,
        data: normals,
    };
    let p = BilateralBlur::default();
    for (ao, depth, what) in [
        (ao, depth, "depth edge"),
        (flat_ao, vec![3.0; w * h], "normal edge"),
    ] {
        let (a, d) = (
            r32("ao", w as u32, h as u32, ao.clone()),
            r32("depth", w as u32, h as u32, depth),
        );
        let Some(out) = run(
            Extent::new(w as u32, h as u32),
            &[
                (&a, SizeClass::FULL),
                (&d, SizeClass::FULL),
                (&n, SizeClass::FULL),
            ],
            |b, hs| vec![bilateral_blur(b, "b", hs[0], hs[1], hs[2], &p).unwrap()],
        ) else {
            return;
        };
        assert_close(&out[0], &ao, 1e-5, what);
    }
}

#[test]
fn upsample_is_bilinear_on_a_continuous_surface_and_does_not_blend_across_edges() {
    let (w, h) = (16usize, 10usize);
    let (lw, lh) = (w / 2, h / 2);
    let low = noise(lw * lh, 11);
    let (a, dl, df) = (
        r32("ao", lw as u32, lh as u32, low.clone()),
        r32("depth_low", lw as u32, lh as u32, vec![4.0; lw * lh]),
        r32("depth_full", w as u32, h as u32, vec![4.0; w * h]),
    );
    let ins = [
        (&a, SizeClass::half_pow(1)),
        (&dl, SizeClass::half_pow(1)),
        (&df, SizeClass::FULL),
    ];
    let up = |b: &mut GraphBuilder, hs: &[TextureHandle]| {
        vec![
            bilateral_upsample(
                b,
                "u",
                &UpsampleInputs {
                    ao: hs[0],
                    depth_low: hs[1],
                    depth_full: hs[2],
                    normals: None,
                },
                &BilateralUpsample::default(),
            )
            .unwrap(),
        ]
    };
    let Some(out) = run(Extent::new(w as u32, h as u32), &ins, up) else {
        return;
    };
    // Bilinear with clamp-to-edge taps: u = (p + 0.5) / 2 - 0.5.
    let at = |x: i32, y: i32| {
        low[y.clamp(0, lh as i32 - 1) as usize * lw + x.clamp(0, lw as i32 - 1) as usize]
    };
    let want: Vec<f32> = (0..w * h)
        .map(|i| {
            let (ux, uy) = (
                ((i % w) as f32 + 0.5) / 2.0 - 0.5,
                ((i / w) as f32 + 0.5) / 2.0 - 0.5,
            );
            let (bx, by) = (ux.floor(), uy.floor());
            let (tx, ty) = (ux - bx, uy - by);
            let (bx, by) = (bx as i32, by as i32);
            (1.0 - tx) * (1.0 - ty) * at(bx, by)
                + tx * (1.0 - ty) * at(bx + 1, by)
                + (1.0 - tx) * ty * at(bx, by + 1)
                + tx * ty * at(bx + 1, by + 1)
        })
        .collect();
    assert_close(&out[0], &want, 1e-5, "bilinear on a flat depth");

    // A depth step: each full-res pixel takes only the low-res AO of its own side.
    let (ao_full, depth_full) = step_scene(w, h);
    let (ao_low, depth_low): (Vec<f32>, Vec<f32>) = (0..lw * lh)
        .map(|i| {
            (
                ao_full[(i / lw) * 2 * w + (i % lw) * 2],
                depth_full[(i / lw) * 2 * w + (i % lw) * 2],
            )
        })
        .unzip();
    let (a, dl, df) = (
        r32("ao", lw as u32, lh as u32, ao_low),
        r32("depth_low", lw as u32, lh as u32, depth_low),
        r32("depth_full", w as u32, h as u32, depth_full),
    );
    let out = run(
        Extent::new(w as u32, h as u32),
        &[
            (&a, SizeClass::half_pow(1)),
            (&dl, SizeClass::half_pow(1)),
            (&df, SizeClass::FULL),
        ],
        up,
    )
    .unwrap();
    assert_close(&out[0], &ao_full, 1e-5, "no blending across the depth edge");
}

#[test]
fn depth_prefilter_matches_the_cpu_per_level_and_keeps_sky() {
    use aograph_ao::blocks::depth_prefilter::prefilter_cpu;
    // 13x7: odd sizes, partial edge blocks; depths 1..3 with a sky column, so some blocks mix
    // children near and far (weights below 1) and some are all sky.
    let (w, h) = (13u32, 7u32);
    let data: Vec<f32> = noise((w * h) as usize, 7)
        .iter()
        .enumerate()
        .map(|(i, v)| {
            if i as u32 % w == 4 {
                0.0
            } else {
                1.0 + 2.0 * v
            }
        })
        .collect();
    let input = r32("depth", w, h, data.clone());
    let (radius, falloff) = (0.8f32, 0.615f32);
    let Some(out) = run(Extent::new(w, h), &[(&input, SizeClass::FULL)], |b, hs| {
        depth_prefilter(b, "p", hs[0], 4, radius, falloff)
            .unwrap()
            .levels[1..]
            .to_vec()
    }) else {
        return;
    };
    let (mut level, mut lw, mut lh) = (data, w, h);
    for (l, got) in out.iter().enumerate() {
        let (next, nw, nh) = prefilter_cpu(&level, lw, lh, radius, falloff);
        assert_close(got, &next, 1e-6, &format!("prefilter level {}", l + 1));
        (level, lw, lh) = (next, nw, nh);
    }
    // A near child far in front of the farthest gets weight 0: texel (0, 0) of a block
    // {1, 5, 5, 5} at r = 0.75 x 0.8 = 0.6 is 5 exactly, where a plain mean would be 4.
    let block = r32("depth", 2, 2, vec![1.0, 5.0, 5.0, 5.0]);
    let Some(out) = run(Extent::new(2, 2), &[(&block, SizeClass::FULL)], |b, hs| {
        vec![
            depth_prefilter(b, "p", hs[0], 2, radius, falloff)
                .unwrap()
                .levels[1],
        ]
    }) else {
        return;
    };
    assert_eq!(out[0], vec![5.0]);
}

/// CPU mirror of shaders/blocks/edge_denoise.wgsl (one pass).
fn edge_denoise_cpu(
    ao: &[f32],
    edges: &[[f32; 4]],
    depth: &[f32],
    w: usize,
    h: usize,
    beta: f32,
    last: bool,
) -> Vec<f32> {
    let inside = |x: i64, y: i64| x >= 0 && y >= 0 && x < w as i64 && y < h as i64;
    let e_at = |x: i64, y: i64| {
        if inside(x, y) {
            edges[y as usize * w + x as usize]
        } else {
            [0.0; 4]
        }
    };
    let tap = |x: i64, y: i64, wt: f32| {
        if inside(x, y) && depth[y as usize * w + x as usize] > 0.0 {
            (wt * ao[y as usize * w + x as usize], wt)
        } else {
            (0.0, 0.0)
        }
    };
    let mut out = Vec::with_capacity(w * h);
    for y in 0..h as i64 {
        for x in 0..w as i64 {
            let i = y as usize * w + x as usize;
            if depth[i] <= 0.0 {
                out.push(1.0);
                continue;
            }
            let (l, r, t, b) = (
                e_at(x - 1, y),
                e_at(x + 1, y),
                e_at(x, y - 1),
                e_at(x, y + 1),
            );
            let c = e_at(x, y);
            let mut e = [c[0] * l[1], c[1] * r[0], c[2] * t[3], c[3] * b[2]];
            let leak = (4.0 - 2.5 - e.iter().sum::<f32>()).clamp(0.0, 1.0) / 1.5;
            e.iter_mut()
                .for_each(|v| *v = (*v + leak * 0.5).clamp(0.0, 1.0));
            let d = 0.425;
            let taps = [
                (x - 1, y, e[0]),
                (x + 1, y, e[1]),
                (x, y - 1, e[2]),
                (x, y + 1, e[3]),
                (x - 1, y - 1, d * (e[0] * l[2] + e[2] * t[0])),
                (x + 1, y - 1, d * (e[2] * t[1] + e[1] * r[2])),
                (x - 1, y + 1, d * (e[3] * b[0] + e[0] * l[3])),
                (x + 1, y + 1, d * (e[1] * r[3] + e[3] * b[1])),
            ];
            let (mut sum, mut wsum) = (beta * ao[i], beta);
            for (tx, ty, wt) in taps {
                let (s, ww) = tap(tx, ty, wt);
                sum += s;
                wsum += ww;
            }
            let v = sum / wsum;
            out.push(if last { v.clamp(0.0, 1.0) } else { v });
        }
    }
    out
}

#[test]
fn edge_denoise_matches_the_cpu_keeps_constants_and_sky() {
    let (w, h) = (11usize, 9usize);
    // Raw AO up to 1.5 (gtao's pre-clamp range), sky in one row, and edge weights from the
    // 2-bit levels {0, 1/3, 2/3, 1}.
    let ao: Vec<f32> = noise(w * h, 3).iter().map(|v| 1.5 * v).collect();
    let depth: Vec<f32> = (0..w * h)
        .map(|i| if i / w == 4 { 0.0 } else { 2.0 })
        .collect();
    let edges: Vec<[f32; 4]> = noise(4 * w * h, 5)
        .chunks(4)
        .map(|c| [0, 1, 2, 3].map(|k| (c[k] * 4.0).floor().min(3.0) / 3.0))
        .collect();
    let e = Input {
        name: "edges",
        size: Extent::new(w as u32, h as u32),
        format: wgpu::TextureFormat::Rgba8Unorm,
        data: edges.iter().flatten().copied().collect(),
    };
    // The GPU reads each level back as round(255 q) / 255.
    let edges_read: Vec<[f32; 4]> = edges
        .iter()
        .map(|c| c.map(|v| (v * 255.0).round() / 255.0))
        .collect();
    for passes in [1u32, 3] {
        let (a, d) = (
            r32("ao", w as u32, h as u32, ao.clone()),
            r32("depth", w as u32, h as u32, depth.clone()),
        );
        let p = EdgeDenoise {
            passes,
            blur_beta: 1.2,
        };
        let Some(out) = run(
            Extent::new(w as u32, h as u32),
            &[
                (&a, SizeClass::FULL),
                (&e, SizeClass::FULL),
                (&d, SizeClass::FULL),
            ],
            |b, hs| vec![edge_denoise(b, "g", hs[0], hs[1], hs[2], &p, R32Float).unwrap()],
        ) else {
            return;
        };
        let mut want = ao.clone();
        for k in 1..=passes {
            let last = k == passes;
            let beta = if last { 1.2 } else { 1.2 / 5.0 };
            want = edge_denoise_cpu(&want, &edges_read, &depth, w, h, beta, last);
        }
        assert_close(
            &out[0],
            &want,
            1e-5,
            &format!("edge denoise, {passes} passes"),
        );
        for (i, v) in out[0].iter().enumerate() {
            if depth[i] <= 0.0 {
                assert_eq!(*v, 1.0, "sky texel {i}");
            }
        }
    }
    // A constant stays that constant whatever the edges.
    let (a, d) = (
        r32("ao", w as u32, h as u32, vec![0.625; w * h]),
        r32("depth", w as u32, h as u32, vec![2.0; w * h]),
    );
    let Some(out) = run(
        Extent::new(w as u32, h as u32),
        &[
            (&a, SizeClass::FULL),
            (&e, SizeClass::FULL),
            (&d, SizeClass::FULL),
        ],
        |b, hs| {
            vec![
                edge_denoise(
                    b,
                    "g",
                    hs[0],
                    hs[1],
                    hs[2],
                    &EdgeDenoise::default(),
                    R32Float,
                )
                .unwrap(),
            ]
        },
    ) else {
        return;
    };
    assert_close(&out[0], &vec![0.625; w * h], 1e-6, "constant");
}
