//! `temporal = true` on every spatial technique (crates/ao-passes/src/temporal_option.rs):
//! known answers for the running mean, and no stale history where a moving object uncovers
//! the background.
//!
//! 1. On a still camera the accumulated image after n <= `temporal_frames` frames is exactly
//!    the mean of the n per-frame images the technique produced (TSSAO Eqs. 5-6 with one sample
//!    a frame is a running mean): each frame's own accessibility is read back (the extra output
//!    `per_frame_accessibility`) and averaged on the CPU. The noise must change from frame to
//!    frame, or the mean would be the first frame again.
//! 2. A moving object over a static background, seen by a still camera: where a static surface
//!    shows this frame and another surface showed in the previous frame (the pixel's depth
//!    changed by more than 10 %), the history is stale and must be dropped, so the accumulated
//!    value is this frame's own. With the disocclusion test switched off (epsilon 1: only depth
//!    ratios of 2 or more fail), the same check fails: the negative control.

mod common;

use aograph_ao_passes::{PER_FRAME_OUTPUT, RadiusSetting};
use aograph_frame::GBufferChannel;
use aograph_graph::Extent;
use aograph_renderer::FrameOutputs;
use aograph_renderer::Renderer;
use aograph_scene::{Camera, procedural_scene};
use glam::Vec3;

/// Every technique with temporal accumulation, the parameters that turn it on (rtao without
/// its denoiser, which runs after the mean), and whether its noise changes per frame (mssao
/// has none: its frames are equal, and its own filter, Eq. 14's fixed blend, must give that
/// image back).
const TECHNIQUES: [(&str, &str, bool); 7] = [
    ("ssao", "temporal = true", true),
    ("hbao", "temporal = true", true),
    ("pyramid-hbao", "temporal = true", true),
    ("gtao", "temporal = true", true),
    ("vbao", "temporal = true", true),
    ("rtao", "temporal = true\ndenoiser = \"none\"", true),
    ("mssao", "temporal = true", false),
];

/// An odd, non-square size: the accumulation must not care.
const SIZE: Extent = Extent {
    width: 67,
    height: 45,
};

/// A renderer that reads back linear depth and motion (where the scene moves).
fn renderer(scene: &str, technique: &str, params: &str, size: Extent) -> Option<Renderer> {
    let mut config = common::ao_config(technique, 1.0, params);
    config.radius = RadiusSetting::Auto;
    let scene = procedural_scene(scene).expect("scene exists");
    let outputs = FrameOutputs {
        linear_depth: true,
        motion: !scene.is_static(),
        ..Default::default()
    };
    common::renderer_with(scene, &config, size, outputs)
}

/// The technique's own accessibility of the last frame (before accumulation).
fn per_frame(r: &Renderer) -> Vec<f32> {
    r.read_extra(PER_FRAME_OUTPUT)
        .expect("a temporal technique outputs its per-frame accessibility")
}

#[test]
fn accumulated_image_is_the_mean_of_the_frames_it_averaged() {
    const FRAMES: usize = 32;
    for (technique, on, noisy) in TECHNIQUES {
        // mssao's filter has no frame cap (its blend is fixed).
        let params = if technique == "mssao" {
            on.to_string()
        } else {
            format!("{on}\ntemporal_frames = {FRAMES}")
        };
        let Some(mut r) = renderer("columns", technique, &params, SIZE) else {
            return;
        };
        let mut sum = vec![0.0f64; SIZE.width as usize * SIZE.height as usize];
        let mut first = Vec::new();
        let mut frames_differ = false;
        for f in 0..FRAMES {
            r.render(0.0).expect("frame renders");
            let a = per_frame(&r);
            if f == 0 {
                first = a.clone();
            } else if a.iter().zip(&first).any(|(x, y)| (x - y).abs() > 1e-3) {
                frames_differ = true;
            }
            for (s, v) in sum.iter_mut().zip(&a) {
                *s += *v as f64;
            }
        }
        assert_eq!(
            frames_differ, noisy,
            "{technique}: the noise must change from frame to frame when temporal = true (and only where the technique has noise)"
        );
        let acc = r.read_ao().expect("ao reads back");
        let depth = r.read_linear_depth().expect("depth reads back");
        let mean: Vec<f32> = sum.iter().map(|s| (*s / FRAMES as f64) as f32).collect();
        let mae = common::mae(&acc, &mean, &depth);
        let worst = acc
            .iter()
            .zip(&mean)
            .map(|(a, m)| (a - m).abs())
            .fold(0.0f32, f32::max);
        let moved = common::mae(&first, &mean, &depth);
        println!(
            "{technique}: accumulated vs mean of {FRAMES} frames MAE {mae:.2e}, worst {worst:.2e}; frame 0 vs mean {moved:.4}"
        );
        // The running mean in f32 (32 updates, each rounding by 2^-24 relative) and the
        // bilinear history fetch at a reprojected position a rounding away from the pixel
        // centre: 1e-4 leaves two orders of magnitude of room; the issue asks for 0.005.
        assert!(
            mae < 1e-4 && worst < 1e-3,
            "{technique}: the accumulated image is not the mean of its frames (MAE {mae}, worst {worst})"
        );
    }
}

/// (largest share of stale history kept, pixels checked) over 12 frames of `dynamic` seen by a
/// still camera, for `technique` with the temporal option's `epsilon`.
fn stale_history(technique: &str, on: &str, epsilon: f32) -> Option<(f32, usize)> {
    let params = if technique == "rtao" {
        // rtao's disocclusion test uses the block's epsilon; its test is exercised at 0.03.
        on.to_string()
    } else {
        format!("{on}\ntemporal_epsilon = {epsilon}")
    };
    let size = Extent::new(96, 54);
    let mut r = renderer("dynamic", technique, &params, size)?;
    let camera = Camera::perspective(
        Vec3::new(0.0, 2.2, 7.5),
        Vec3::new(0.0, 0.8, 0.0),
        60f32.to_radians(),
        0.05,
        100.0,
    );
    let mut prev_depth: Option<Vec<f32>> = None;
    let mut prev_acc: Option<Vec<f32>> = None;
    let (mut worst, mut checked) = (0.0f32, 0usize);
    for f in 0..12 {
        r.render_with_camera(f as f32 * 0.1, camera)
            .expect("frame renders");
        let depth = r.read_linear_depth().expect("depth reads back");
        let acc = r.read_ao().expect("ao reads back");
        let own = per_frame(&r);
        let motion = r
            .read_gbuffer(GBufferChannel::Motion)
            .expect("dynamic has motion")
            .to_f32()
            .expect("motion reads as floats");
        let stride = motion.len() / depth.len();
        let w = size.width as usize;
        if let (Some(pd), Some(pa)) = (&prev_depth, &prev_acc) {
            for i in 0..depth.len() {
                let m = &motion[i * stride..i * stride + 2];
                let still = m[0].abs() < 1e-6 && m[1].abs() < 1e-6;
                let (d, d0) = (depth[i], pd[i]);
                // A static surface now, another one here before: the history here is stale.
                if still && d > 0.0 && d0 > 0.0 && (1.0 - d / d0).abs() > 0.1 {
                    // The block may still carry the same surface's history from a neighbour
                    // of the 2x2 bilinear footprint (Eq. 7 passes there): the accumulated
                    // value must lie between this frame's own and such neighbours' previous
                    // values. How far it lies outside, over how far the stale value is, is
                    // the share of stale history kept.
                    let (x, y) = ((i % w) as i64, (i / w) as i64);
                    let (mut lo, mut hi) = (own[i], own[i]);
                    for (dx, dy) in (-1..=1).flat_map(|dy| (-1..=1).map(move |dx| (dx, dy))) {
                        let (nx, ny) = (x + dx, y + dy);
                        if nx < 0 || ny < 0 || nx >= w as i64 || ny >= (depth.len() / w) as i64 {
                            continue;
                        }
                        let j = ny as usize * w + nx as usize;
                        if pd[j] > 0.0 && (1.0 - d / pd[j]).abs() < 0.1 {
                            lo = lo.min(pa[j]);
                            hi = hi.max(pa[j]);
                        }
                    }
                    let outside = (lo - acc[i]).max(acc[i] - hi).max(0.0);
                    let stale = (pa[i] - own[i]).abs();
                    if stale > 0.01 {
                        worst = worst.max(outside / stale);
                        checked += 1;
                    }
                }
            }
        }
        prev_depth = Some(depth);
        prev_acc = Some(acc);
    }
    Some((worst, checked))
}

#[test]
fn a_moving_object_leaves_no_stale_history_behind() {
    for (technique, on, _) in TECHNIQUES {
        let Some((worst, checked)) = stale_history(technique, on, 0.03) else {
            return;
        };
        println!("{technique}: largest stale share {worst:.4} over {checked} uncovered pixels");
        assert!(
            checked >= 10,
            "{technique}: too few uncovered pixels ({checked}) to test"
        );
        // Dropped history leaves the accumulated value between this frame's own and the same
        // surface's neighbours' (share 0); f32 rounding of the blend leaves under 1e-4 of a
        // difference divided by at least 0.01.
        assert!(
            worst < 0.02,
            "{technique}: an uncovered pixel kept {:.1} % of a stale history",
            worst * 100.0
        );
    }
}

#[test]
fn without_the_disocclusion_test_stale_history_stays() {
    // The negative control of the test above: epsilon = 1 keeps every history whose depth
    // changed by less than a factor of 2.
    let Some((worst, checked)) = stale_history("gtao", "temporal = true", 1.0) else {
        return;
    };
    println!("gtao, epsilon 1: largest stale share {worst:.4} over {checked} uncovered pixels");
    assert!(
        worst > 0.3,
        "with the test off, uncovered pixels should keep stale history (largest share {worst})"
    );
}
