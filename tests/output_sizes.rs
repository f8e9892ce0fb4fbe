//! Every technique at the sizes users ship, not only 256x256: on a view that is exactly its own
//! mirror image, every technique's output must be its own mirror image, at sizes that do not
//! halve (or third) evenly and at non-square aspects, and on `columns`' default view at 640x360
//! the walls at the image's two sides must agree as the reference's do.
//!
//! The mirror check compares 8x8 block means of the output with the mirrored image's, so a
//! technique's per-pixel noise (a fixed dither or a rotation texture is not mirror-symmetric)
//! averages out while a deterministic left/right bias (a coarse level shifted by a texel, a
//! pyramid anchored at one side) stays. The bound is stated from the technique's own noise,
//! sigma_d, the standard deviation of the difference of two noise realisations of a block
//! mean: measured between two frames after a camera cut (the frame index reseeds the noise
//! of gtao, rtao and the other per-frame jittered techniques; their denoisers correlate the
//! noise, so no per-pixel figure predicts it), and for noise fixed in screen space (a dither,
//! a rotation texture) from the high-frequency residual sigma of the output (each pixel
//! against its 3x3 neighbours' mean) as sigma sqrt(2 / 64); the larger of the two. The mean
//! difference may be FLOOR_MEAN + 2 sigma_d and the 99th percentile FLOOR_P99 + 5 sigma_d. The floors are the view's own asymmetry: rasterisation
//! ties at silhouettes and the triangulation of mirrored faces (0.0009 mean, 0.012 99th
//! percentile for `mssao`, which has no noise, on the mirrored view at 320x180).

mod common;

use aograph_ao_passes::{PER_FRAME_OUTPUT, RadiusSetting, TechniqueRegistry};
use aograph_graph::Extent;
use aograph_renderer::Renderer;
use aograph_scene::{Camera, Scene, procedural_scene};
use glam::Vec3;

/// Block edge of the mirror check's means.
const BLOCK: usize = 8;
/// The view's own asymmetry (module docs).
const FLOOR_MEAN: f32 = 0.003;
const FLOOR_P99: f32 = 0.03;
/// Odd, non-square and degenerate sizes (1x1, 2x3): none halves evenly down a pyramid.
const SIZES: [(u32, u32); 7] = [
    (67, 41),
    (97, 64),
    (160, 90),
    (317, 211),
    (320, 180),
    (1, 1),
    (2, 3),
];

/// `columns` seen from the nave's mirror plane z = 0: the arcade, the aisles and the props
/// are symmetric about it, so the image is its own mirror image about its vertical centre line.
fn mirrored_columns() -> Scene {
    let mut scene = procedural_scene("columns").expect("columns exists");
    scene.camera = Camera::perspective(
        Vec3::new(11.5, 1.7, 0.0),
        Vec3::new(-12.0, 2.4, 0.0),
        60f32.to_radians(),
        0.05,
        200.0,
    );
    scene
}

fn renderer(technique: &str, scene: Scene, size: Extent) -> Option<Renderer> {
    renderer_with(technique, "", scene, size)
}

/// [`renderer`] with the technique's parameters `params` (TOML).
fn renderer_with(technique: &str, params: &str, scene: Scene, size: Extent) -> Option<Renderer> {
    let mut config = common::ao_config(technique, 1.0, params);
    config.radius = RadiusSetting::Auto;
    common::renderer(scene, &config, size)
}

/// One frame's accessibility and linear depth.
fn frame(r: &mut Renderer) -> (Vec<f32>, Vec<f32>) {
    r.render(0.0).expect("frame renders");
    (
        r.read_ao().expect("ao reads back"),
        r.read_linear_depth().expect("depth reads back"),
    )
}

/// The mirror check's figures for one image.
#[derive(Debug)]
struct Mirror {
    mean: f32,
    p99: f32,
    sigma_d: f32,
}

/// Block means (None where fewer than half the block's pixels and their mirrors are geometry),
/// of the image or of its mirror image.
fn block_means(ao: &[f32], depth: &[f32], w: usize, h: usize, mirror: bool) -> Vec<Option<f32>> {
    let geo = |x: usize, y: usize| depth[y * w + x] > 0.0;
    let b = BLOCK.min(w).min(h).max(1);
    let mut out = Vec::new();
    for by in 0..h / b {
        for bx in 0..w / b {
            let (mut s, mut k) = (0.0f32, 0);
            for y in by * b..(by + 1) * b {
                for x in bx * b..(bx + 1) * b {
                    let x = if mirror { w - 1 - x } else { x };
                    if geo(x, y) && geo(w - 1 - x, y) {
                        s += ao[y * w + x];
                        k += 1;
                    }
                }
            }
            out.push((k * 2 > b * b).then(|| s / k as f32));
        }
    }
    out
}

/// |a - b| of the blocks both have.
fn block_differences(a: &[Option<f32>], b: &[Option<f32>]) -> Vec<f32> {
    a.iter()
        .zip(b)
        .filter_map(|(a, b)| Some((a.as_ref()? - b.as_ref()?).abs()))
        .collect()
}

impl Mirror {
    /// `again`: a second frame of the same view after a camera cut (other noise, where the
    /// technique's noise moves per frame).
    fn of(ao: &[f32], again: &[f32], depth: &[f32], w: usize, h: usize) -> Mirror {
        let geo = |x: usize, y: usize| depth[y * w + x] > 0.0;
        // Residual against the 3x3 neighbours' mean, over geometry pixels.
        let (mut r2, mut n) = (0.0f64, 0usize);
        for y in 1..h.saturating_sub(1) {
            for x in 1..w.saturating_sub(1) {
                if !geo(x, y) {
                    continue;
                }
                let (mut s, mut k) = (0.0f32, 0);
                for (dx, dy) in [
                    (-1i32, -1i32),
                    (0, -1),
                    (1, -1),
                    (-1, 0),
                    (1, 0),
                    (-1, 1),
                    (0, 1),
                    (1, 1),
                ] {
                    let (qx, qy) = ((x as i32 + dx) as usize, (y as i32 + dy) as usize);
                    if geo(qx, qy) {
                        s += ao[qy * w + qx];
                        k += 1;
                    }
                }
                if k > 0 {
                    r2 += ((ao[y * w + x] - s / k as f32) as f64).powi(2);
                    n += 1;
                }
            }
        }
        let sigma = (r2 / n.max(1) as f64).sqrt() as f32;
        let b = BLOCK.min(w).min(h).max(1);
        // Each block against the mirror image's block at the same place (each pixel read at
        // its mirror position, so blocks need not divide the width).
        let here = block_means(ao, depth, w, h, false);
        let mut d = block_differences(&here, &block_means(ao, depth, w, h, true));
        let frames = block_differences(&here, &block_means(again, depth, w, h, false));
        let frame_sigma =
            (frames.iter().map(|v| v * v).sum::<f32>() / frames.len().max(1) as f32).sqrt();
        d.sort_by(f32::total_cmp);
        let mean = d.iter().sum::<f32>() / d.len().max(1) as f32;
        let p99 = d
            .get((d.len() as f32 * 0.99) as usize)
            .copied()
            .unwrap_or(0.0);
        Mirror {
            mean,
            p99,
            sigma_d: (sigma * (2.0 / (b * b) as f32).sqrt()).max(frame_sigma),
        }
    }

    fn check(&self, what: &str) {
        let (mean_bound, p99_bound) = (
            FLOOR_MEAN + 2.0 * self.sigma_d,
            FLOOR_P99 + 5.0 * self.sigma_d,
        );
        assert!(
            self.mean <= mean_bound && self.p99 <= p99_bound,
            "{what}: block means differ from the mirror image by {:.4} on average (allowed {mean_bound:.4}) and {:.4} at the 99th percentile (allowed {p99_bound:.4}); noise sigma_d {:.4}",
            self.mean,
            self.p99,
            self.sigma_d
        );
    }
}

/// The depth is its own mirror image: the premise of the mirror check.
#[test]
fn the_mirrored_view_is_its_own_mirror_image() {
    let size = Extent::new(160, 90);
    let Some(mut r) = renderer("none", mirrored_columns(), size) else {
        return;
    };
    let (_, depth) = frame(&mut r);
    let (w, h) = (160, 90);
    let mut differ = 0;
    for y in 0..h {
        for x in 0..w {
            let (a, b) = (depth[y * w + x], depth[y * w + w - 1 - x]);
            if (a - b).abs() > 1e-3 * a.max(b) {
                differ += 1;
            }
        }
    }
    // Silhouette pixels whose centre lies on a triangle edge can differ (rasterisation ties).
    assert!(
        differ <= w * h / 200,
        "{differ} of {} depths differ from their mirror",
        w * h
    );
}

#[test]
fn every_technique_is_its_own_mirror_image_at_odd_and_non_square_sizes() {
    let registry = TechniqueRegistry::with_builtins();
    for technique in registry.names() {
        let Some(mut r) = renderer(&technique, mirrored_columns(), Extent::new(67, 41)) else {
            return;
        };
        for (w, h) in SIZES {
            r.resize(Extent::new(w, h)).expect("resizes");
            let (ao, depth) = frame(&mut r);
            r.cut();
            let (again, _) = frame(&mut r);
            let what = format!("{technique} at {w}x{h}");
            common::assert_valid_ao(&ao, &depth, &what);
            let m = Mirror::of(&ao, &again, &depth, w as usize, h as usize);
            println!("{what}: {m:?}");
            m.check(&what);
        }
    }
}

/// The same at `resolution = "half"`, asserted where the width halves evenly. The half grid's
/// 2x2 blocks start at the top-left pixel, so at an odd width (or height) its last block
/// covers one column and lies half a pixel further out than the first: the half image is not
/// the mirror of itself there, and the odd sizes are printed, not asserted (measured in
/// docs/results/half-resolution.md).
/// Upsampled noise is correlated over two pixels, which the 3x3 residual does not see, so a
/// technique with the shared temporal option is measured on its per-frame images
/// (`temporal = true`, `per_frame_accessibility`) of two frames, whose noise differs, and rtao
/// on two frames without accumulation.
#[test]
fn every_technique_at_half_resolution_is_its_own_mirror_image() {
    let registry = TechniqueRegistry::with_builtins();
    for technique in registry.names() {
        let takes_it = registry
            .get(&technique)
            .is_ok_and(|t| t.parameters().iter().any(|p| p.name == "resolution"));
        if !takes_it {
            continue;
        }
        // rtao's rays change every frame by themselves (`sequence = "per-frame"`): its own
        // output of two frames without accumulation differs by its noise.
        let per_frame = technique != "rtao"
            && registry
                .get(&technique)
                .is_ok_and(|t| t.parameters().iter().any(|p| p.name == "temporal_frames"));
        let params = if technique == "rtao" {
            "resolution = \"half\"\ntemporal = false"
        } else if per_frame {
            "resolution = \"half\"\ntemporal = true"
        } else {
            "resolution = \"half\""
        };
        let Some(mut r) =
            renderer_with(&technique, params, mirrored_columns(), Extent::new(67, 41))
        else {
            return;
        };
        let image = |r: &mut Renderer| {
            let (ao, depth) = frame(r);
            if per_frame {
                (
                    r.read_extra(PER_FRAME_OUTPUT).expect("per-frame image"),
                    depth,
                )
            } else {
                (ao, depth)
            }
        };
        for (w, h) in SIZES {
            r.resize(Extent::new(w, h)).expect("resizes");
            let (ao, depth) = image(&mut r);
            let (again, _) = image(&mut r);
            let what = format!("{technique} at half, {w}x{h}");
            common::assert_valid_ao(&ao, &depth, &what);
            let m = Mirror::of(&ao, &again, &depth, w as usize, h as usize);
            println!("{what}: {m:?}");
            if w % 2 == 0 || w == 1 {
                m.check(&what);
            }
        }
    }
}

/// Mean accessibility of the left and right fifth of the image, rows 28 % to 83 % (the walls
/// of `columns`' default view), over geometry pixels.
fn walls(ao: &[f32], depth: &[f32], w: usize, h: usize) -> (f32, f32) {
    let (mut l, mut r, mut nl, mut nr) = (0.0f64, 0.0f64, 0usize, 0usize);
    for y in (h * 28).div_ceil(100)..(h * 83).div_ceil(100) {
        for x in 0..w / 5 {
            let (i, j) = (y * w + x, y * w + w - 1 - x);
            if depth[i] > 0.0 {
                l += ao[i] as f64;
                nl += 1;
            }
            if depth[j] > 0.0 {
                r += ao[j] as f64;
                nr += 1;
            }
        }
    }
    ((l / nl.max(1) as f64) as f32, (r / nr.max(1) as f64) as f32)
}

/// Every technique's walls on `columns`' default view at `w` x `h`, within 0.02 of each other,
/// but those named in `measured`, each held to the difference docs/results/output-sizes.md
/// gives for it (plus the 0.002 a wall's mean moves between devices' rounding).
fn walls_agree_at(w: usize, h: usize, measured: &[(&str, f32)]) {
    let registry = TechniqueRegistry::with_builtins();
    let mut apart = Vec::new();
    for technique in registry.names() {
        let bound = measured
            .iter()
            .find(|(t, _)| *t == technique)
            .map_or(0.02, |(_, d)| d + 0.002);
        let scene = procedural_scene("columns").expect("columns exists");
        let Some(mut r) = renderer(&technique, scene, Extent::new(w as u32, h as u32)) else {
            return;
        };
        let (ao, depth) = frame(&mut r);
        let (left, right) = walls(&ao, &depth, w, h);
        println!("{technique} at {w}x{h}: walls {left:.4} {right:.4}");
        if (left - right).abs() > bound {
            apart.push(format!(
                "{technique}: {left:.4} and {right:.4} (allowed {bound})"
            ));
        }
    }
    assert!(
        apart.is_empty(),
        "at {w}x{h} the walls read too far apart: {}",
        apart.join("; ")
    );
}

#[test]
fn every_technique_reads_columns_walls_alike_at_640x360() {
    // The reference reads the two walls 0.713 and 0.714 at 640x360 (64 rays, standard error
    // about 0.001 over a wall). Before the fixes of crates/ao-passes/src/techniques/mssao.rs
    // ("At every output size") mssao read them 0.880 and 0.810.
    walls_agree_at(640, 360, &[]);
}

#[test]
fn every_technique_reads_columns_walls_alike_at_1920x1080() {
    // mssao read them 0.907 and 0.889 before issue 34 (both short of R).
    walls_agree_at(1920, 1080, &[]);
}

#[test]
fn columns_walls_at_1280x720_within_0_02_but_mssao_and_pyramid_hbao() {
    // Before issue 34 mssao read them 0.884 and 0.737. The two named are held to what
    // docs/results/output-sizes.md ("Left and right") measures and explains: their estimators
    // read the two walls' surroundings differently (0.020 and 0.033 averaged over the grid's
    // phase), so a larger difference is a regression, a smaller one a fix to write down.
    walls_agree_at(1280, 720, &[("mssao", 0.0233), ("pyramid-hbao", 0.0397)]);
}

/// A measurement, not a check: the walls of the techniques in `AOGRAPH_WALLS_TECHNIQUES`
/// (default mssao,pyramid-hbao) at the sizes in `AOGRAPH_WALLS_SIZES` (default the sizes
/// around 1280x720), with the largest difference. Which coarse texels the arcade lands on moves
/// with the size while the reference does not, so the spread over nearby sizes shows how much
/// of a wall difference is the coarse grid's phase.
#[test]
#[ignore = "a measurement: cargo test --release --test output_sizes -- --ignored --nocapture"]
fn walls_over_nearby_sizes() {
    let techniques =
        std::env::var("AOGRAPH_WALLS_TECHNIQUES").unwrap_or("mssao,pyramid-hbao".into());
    let sizes = std::env::var("AOGRAPH_WALLS_SIZES").unwrap_or(
        "1280x714,1280x717,1280x720,1280x723,1280x726,1276x720,1284x720,640x360,1920x1080".into(),
    );
    for technique in techniques.split(',') {
        let mut worst = 0.0f32;
        for size in sizes.split(',') {
            let (w, h) = size.split_once('x').expect("WxH");
            let (w, h): (usize, usize) = (w.parse().unwrap(), h.parse().unwrap());
            let scene = procedural_scene("columns").expect("columns exists");
            let params = std::env::var("AOGRAPH_WALLS_PARAMS").unwrap_or_default();
            let mut config = common::ao_config(technique, 1.0, &params);
            config.radius = RadiusSetting::Auto;
            let Some(mut r) = common::renderer(scene, &config, Extent::new(w as u32, h as u32))
            else {
                return;
            };
            let (ao, depth) = frame(&mut r);
            let (left, right) = walls(&ao, &depth, w, h);
            worst = worst.max((left - right).abs());
            println!(
                "{technique} {w}x{h}: {left:.4} {right:.4} ({:+.4})",
                left - right
            );
        }
        println!("{technique}: largest difference {worst:.4}");
    }
}
