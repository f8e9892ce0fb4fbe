//! `tssao` on the GPU: valid output and no self-occlusion on a plane; on `columns` under a
//! static camera the error against the ray-traced reference falls as frames accumulate and
//! after 32 frames is at least as low as `ssao`'s with 32 samples per frame; frame-to-frame
//! flicker; on `dynamic` no stale values in a band around the moving objects (absolute bounds
//! against the reference), and pixels a moving object left are back within 0.05 of the
//! reference 10 frames later, which they are not with the smooth-invalidation clamp disabled;
//! camera cuts and resizes restart the history; `aograph render --frames N --every` on
//! `dynamic`.
//!
//! Files: the shared rig is here; `still.rs` (a plane, sphere-on-plane, convergence, flicker),
//! `moving.rs` (`dynamic`: stale values, pixels a moving object left), `history.rs` (camera
//! cuts, resizes, the render command, the config, the temporal block).

#[path = "../common/mod.rs"]
mod common;

mod history;
mod moving;
mod still;

use aograph_ao_passes::AoConfig;
use aograph_graph::{Extent, PassTimings};
use aograph_renderer::PassOwner;
use aograph_renderer::ReferenceSettings;
use aograph_renderer::Renderer;
use aograph_scene::Scene;

const RADIUS: f32 = 1.0;
/// Rays per pixel of the reference (its standard error is ~0.5 / sqrt(RAYS) per pixel).
const RAYS: u32 = 1024;
const FRAME_TIME: f32 = 1.0 / 30.0;

fn renderer(scene: Scene, config: &AoConfig, size: Extent) -> Option<Renderer> {
    common::renderer(scene, config, size)
}

fn tssao(params: &str) -> AoConfig {
    common::ao_config("tssao", RADIUS, params)
}

fn reference(r: &Renderer) -> Vec<f32> {
    aograph_renderer::frame_reference(r, &ReferenceSettings::new(RADIUS, RAYS), false)
        .expect("reference traces")
        .accessibility
}

fn ao(r: &Renderer) -> Vec<f32> {
    r.read_ao().expect("ao reads back")
}

fn depth(r: &Renderer) -> Vec<f32> {
    r.read_linear_depth().expect("depth reads back")
}

/// Mean absolute error over the pixels where `mask` holds.
fn masked_mae(a: &[f32], b: &[f32], mask: &[bool]) -> f32 {
    let (sum, n) = a
        .iter()
        .zip(b)
        .zip(mask)
        .filter(|(_, m)| **m)
        .fold((0.0f64, 0usize), |(s, n), ((x, y), _)| {
            (s + (x - y).abs() as f64, n + 1)
        });
    (sum / n.max(1) as f64) as f32
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

/// Milliseconds of the AO technique's passes (the frame graph's owners say which).
fn technique_ms(r: &Renderer, t: &PassTimings) -> f64 {
    r.graph.owners.total_ms(t, PassOwner::Technique)
}

/// Median per-frame (total, technique-only) milliseconds over `frames` further frames at `time`.
fn frame_times(r: &mut Renderer, frames: u32, time: f32) -> (f64, f64) {
    let (mut total, mut tech) = (Vec::new(), Vec::new());
    for _ in 0..frames {
        r.render(time).unwrap();
        let t = r.timings().unwrap();
        total.push(t.total_ms());
        tech.push(technique_ms(r, &t));
    }
    (median(total), median(tech))
}
