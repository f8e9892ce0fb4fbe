//! rtao's history denoiser (`blocks::history_denoise`, the default `denoiser = "history"`)
//! against known answers, at odd non-square sizes:
//! - converged, it is the reference: 1 ray a frame over 256 still frames traces exactly the
//!   reference's 256 rays (the sequence continues frame to frame); the filter's radius has
//!   shrunk below half a pixel, so the output is the running mean bit for bit, within 4
//!   standard errors of the 256-ray reference on >= 99 % of pixels;
//! - its first frame after a reset, at one ray a pixel, scores a higher SSIM against the
//!   reference than gtao high's frame on `columns` and `cornell-box` (the history fix and
//!   the wide radius on new pixels);
//! - a camera cut resets every pixel's history length to 1 and widens its radius back to the
//!   new-pixel radius (the guide output, checked against the CPU mirror `radius_px`).

mod common;

use aograph_ao_passes::blocks::history_denoise::{HistoryDenoise, radius_px};
use aograph_bench::metrics::{MetricOptions, compare};
use aograph_graph::Extent;
use aograph_renderer::ReferenceSettings;

const SIZE: Extent = Extent {
    width: 77,
    height: 51,
};

fn scene(name: &str) -> aograph_scene::Scene {
    aograph_scene::procedural_scene(name).unwrap()
}

#[test]
fn converged_rtao_with_the_history_denoiser_is_the_reference_within_four_standard_errors() {
    if aograph_graph::test_gpu().is_none() {
        return;
    }
    for name in ["columns", "cornell-box"] {
        let s = scene(name);
        let radius = aograph_scene::suggested_radius(&s).radius;
        // One ray a frame over 256 still frames: the reference's own 256 rays.
        let params = "rays = 1\ntemporal_frames = 256";
        let config = common::ao_config("rtao", radius, params);
        let run = common::render_ao(s.clone(), &config, SIZE, 256).expect("a GPU");
        // Converged, the radius is 8 / (1 + 0.1 * 255) = 0.30 pixels or less, under half of
        // the first iteration's spacing: every iteration leaves every pixel as it is, so the
        // output is the running mean itself, bit for bit.
        let none = format!("{params}\ndenoiser = \"none\"");
        let unfiltered = common::render_ao(s, &common::ao_config("rtao", radius, &none), SIZE, 256)
            .expect("a GPU");
        let changed = (run.ao.iter().zip(&unfiltered.ao))
            .filter(|(a, b)| a != b)
            .count();
        assert_eq!(
            changed, 0,
            "{name}: the converged filter changed {changed} pixels"
        );
        let reference = aograph_renderer::frame_reference(
            &run.renderer,
            &ReferenceSettings::new(radius, 256),
            false,
        )
        .unwrap();
        let (mut geometry, mut beyond) = (0, 0);
        for i in 0..run.ao.len() {
            if run.depth[i] <= 0.0 {
                assert_eq!(run.ao[i], 1.0, "{name}: sky is exactly 1");
                continue;
            }
            geometry += 1;
            // The unfiltered mean is the reference's own 256 rays (equal to float rounding);
            // what the filter may add must stay inside the reference's 4 SE. Where all 256
            // rays agreed (SE 0) the reference only bounds the value: by the rule of three,
            // within 3 / 256 of it at 95 %.
            let se = reference.std_error[i];
            let floor = if se == 0.0 { 3.0 / 256.0 } else { 1e-3 };
            if (run.ao[i] - reference.accessibility[i]).abs() > 4.0 * se + floor {
                beyond += 1;
                if std::env::var_os("AOGRAPH_TEST_VERBOSE").is_some() {
                    eprintln!(
                        "  pixel ({}, {}): rtao {} reference {} se {}",
                        i % SIZE.width as usize,
                        i / SIZE.width as usize,
                        run.ao[i],
                        reference.accessibility[i],
                        reference.std_error[i]
                    );
                }
            }
        }
        eprintln!("{name}: {beyond} of {geometry} pixels beyond 4 SE");
        assert!(geometry > 1000, "{name}: the view sees geometry");
        assert!(
            beyond * 100 <= geometry,
            "{name}: {beyond} of {geometry} pixels beyond 4 SE"
        );
    }
}

/// 16:9. The filter's radius is in pixels, so its first frame is measured at a size the
/// bench uses (at 77x51 an 8-pixel radius spans a tenth of the image, and gtao's slices
/// resolve the tiny image better).
const WIDE: Extent = Extent {
    width: 256,
    height: 144,
};

#[test]
fn one_ray_first_frame_scores_above_gtao_high_on_columns_and_cornell_box() {
    if aograph_graph::test_gpu().is_none() {
        return;
    }
    for name in ["columns", "cornell-box"] {
        let s = scene(name);
        let radius = aograph_scene::suggested_radius(&s).radius;
        let ssim = |technique: &str, params: &str| {
            let config = common::ao_config(technique, radius, params);
            let run = common::render_ao(s.clone(), &config, WIDE, 1).expect("a GPU");
            let reference = aograph_renderer::frame_reference(
                &run.renderer,
                &ReferenceSettings::new(radius, 256),
                false,
            )
            .unwrap();
            compare(
                &run.ao,
                &reference.accessibility,
                &run.depth,
                WIDE.width,
                WIDE.height,
                &MetricOptions::default(),
            )
            .unwrap()
            .ssim
        };
        let rtao = ssim("rtao", "rays = 1");
        let gtao = ssim("gtao", "preset = \"high\"");
        eprintln!("{name}: frame 1 SSIM rtao (1 ray) {rtao:.4}, gtao high {gtao:.4}");
        assert!(
            rtao > gtao,
            "{name}: rtao's first frame ({rtao:.4}) must beat gtao high ({gtao:.4})"
        );
    }
}

#[test]
fn a_camera_cut_resets_the_history_length_and_the_radius_widens() {
    let s = scene("columns");
    let radius = aograph_scene::suggested_radius(&s).radius;
    let config = common::ao_config("rtao", radius, "rays = 1");
    let Some(mut r) = common::renderer(s, &config, SIZE) else {
        return;
    };
    let p = HistoryDenoise::default();
    // The guide's radius is the CPU mirror's for the pixel's n and nearest hit (f16: 3 digits).
    let check = |r: &aograph_renderer::Renderer, frames: f32| {
        let guide = r
            .read_extra(aograph_ao_passes::techniques::rtao::GUIDE_OUTPUT)
            .unwrap();
        let depth = r.read_linear_depth().unwrap();
        let mut geometry = 0;
        for (i, g) in guide.chunks_exact(4).enumerate() {
            if depth[i] <= 0.0 {
                continue;
            }
            geometry += 1;
            assert_eq!(g[2], frames, "pixel {i}: frames of history");
            let expected = radius_px(&p, g[2], g[3]);
            assert!(
                (g[1] - expected).abs() <= 2e-3 * expected,
                "pixel {i}: radius {} against {expected}",
                g[1]
            );
        }
        assert!(geometry > 1000);
        let mean = |f: &dyn Fn(&[f32]) -> f32| {
            guide
                .chunks_exact(4)
                .zip(&depth)
                .filter(|(_, d)| **d > 0.0)
                .map(|(g, _)| f(g))
                .sum::<f32>()
                / geometry as f32
        };
        mean(&|g| g[1])
    };
    for _ in 0..6 {
        r.render(0.0).unwrap();
    }
    let settled = check(&r, 6.0);
    r.cut();
    r.render(0.0).unwrap();
    let after_cut = check(&r, 1.0);
    eprintln!("mean radius: {settled:.3} px after 6 frames, {after_cut:.3} px after the cut");
    // 1 + k (n - 1) = 1.5 at n = 6, so the cut widens the mean radius 1.5 times, less what
    // the nearest hits (each frame's own rays) move: at least 1.4.
    let k = p.shrink;
    assert_eq!(k, 0.1, "the bound below is for k = 0.1");
    assert!(
        after_cut > 1.4 * settled,
        "the cut widens the radius ({settled} -> {after_cut})"
    );
}
