//! The peer comparison: bevy's own SSAO at its four quality levels and aograph's techniques,
//! on the same bevy frames, scored against aograph's ray-traced reference of the same file and
//! camera, and timed the same way.
//!
//! ```text
//! cargo run --example peer_table -- OUT_DIR SCENE.gltf [SCENE.gltf ...]
//! ```
//! (environment: `WIDTH`, `HEIGHT`, `RAYS`, `FRAMES`.) For each file: aograph loads it and
//! places its camera and radius R as `aograph bench` does (the "default" view, R = "auto");
//! its reference traces RAYS cosine-weighted rays per pixel (binary visibility within R). bevy
//! loads the same file with its own glTF loader and renders it from that camera; binding 17's
//! AO (what bevy's PBR pass reads) is read back for each configuration and scored over the
//! reference's non-sky pixels with the bench's metrics. bevy's SSAO gets the same R.
//!
//! Time: bevy's render diagnostics (`RenderDiagnosticsPlugin`) time bevy's SSAO passes as its
//! `ssao` span and aograph's as the plugin's `aograph_ao` span, with the same timestamp
//! queries: the median over FRAMES frames. On lavapipe those timestamps measure its CPU
//! threads executing the passes. On a device without timestamps the time is whole frames
//! minus frames without AO (`cpu-wall` in the table).
//!
//! Writes OUT_DIR/peer.md (a table per scene) and OUT_DIR/peer-pareto.{svg,png}.

#[path = "common/aograph_view.rs"]
mod aograph_view;
#[path = "../tests/support/mod.rs"]
mod support;

use std::path::{Path, PathBuf};
use std::sync::Arc;

use aograph_bench::metrics::{MetricOptions, compare};
use aograph_bench::run::{FrameTimes, RunRecord};
use aograph_bench::stats::Spread;
use aograph_bevy::AographAo;
use aograph_graph::{Extent, GpuContext};
use aograph_renderer::frame_reference::{
    FrameView, ReferenceSettings, reference_surfaces, trace_surfaces,
};
use aograph_view::AographView;
use bevy::pbr::ScreenSpaceAmbientOcclusionQualityLevel as Quality;
use bevy::prelude::*;
use support::Harness;

/// aograph's techniques compared (aograph_embed::feedable_techniques, the temporal tssao left
/// out: its score depends on how many frames it has accumulated), at their defaults.
const AOGRAPH: [&str; 6] = ["gtao", "vbao", "mssao", "hbao", "pyramid-hbao", "ssao"];
const BEVY: [(&str, Quality); 4] = [
    ("low", Quality::Low),
    ("medium", Quality::Medium),
    ("high", Quality::High),
    ("ultra", Quality::Ultra),
];
const TIME_LABEL: &str = "ms of the AO passes (bevy's render-diagnostics timestamps)";

fn env(name: &str, default: u32) -> u32 {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [out, scenes @ ..] = args.as_slice() else {
        return Err("usage: peer_table OUT_DIR SCENE.gltf [SCENE.gltf ...]".into());
    };
    if scenes.is_empty() {
        return Err("usage: peer_table OUT_DIR SCENE.gltf [SCENE.gltf ...]".into());
    }
    let out = PathBuf::from(out);
    std::fs::create_dir_all(&out)?;
    let (width, height) = (env("WIDTH", 320), env("HEIGHT", 180));
    let (rays, frames) = (env("RAYS", 64), env("FRAMES", 8));
    let gpu = Arc::new(GpuContext::new()?);
    let mut records = Vec::new();
    let mut markdown = format!(
        "Made by `cargo run{} --example peer_table` in crates/bevy at {width}x{height}, \
         {rays} reference rays per pixel, {frames} timed frames per row, on {}. Time: the \
         median of the AO passes' milliseconds (`gpu-timestamps`: bevy's render-diagnostics \
         spans `ssao` and `aograph_ao`; on a software device, its CPU executing them).\n",
        if cfg!(debug_assertions) {
            ""
        } else {
            " --release"
        },
        gpu.describe()
    );
    for scene in scenes {
        let rows = score_scene(&gpu, Path::new(scene), width, height, rays, frames)?;
        let name = Path::new(scene)
            .file_name()
            .unwrap_or_default()
            .to_string_lossy();
        markdown.push_str(&table(&name, &rows));
        records.extend(rows);
    }
    std::fs::write(out.join("peer.md"), &markdown)?;
    let techniques: Vec<String> = std::iter::once("bevy-ssao".to_owned())
        .chain(AOGRAPH.iter().map(|t| t.to_string()))
        .collect();
    aograph_bench::plot::write_pareto(
        &out.join("peer-pareto.svg"),
        &out.join("peer-pareto.png"),
        &records,
        &techniques,
        TIME_LABEL,
    )?;
    print!("{markdown}");
    Ok(())
}

fn score_scene(
    gpu: &Arc<GpuContext>,
    file: &Path,
    width: u32,
    height: u32,
    rays: u32,
    frames: u32,
) -> Result<Vec<RunRecord>, Box<dyn std::error::Error>> {
    // aograph's view of the file: the bench's camera and radius, and its reference.
    let view = AographView::of(file)?;
    let radius = view.radius;
    let frame = FrameView {
        scene: view.prepared.scene.clone(),
        camera: view.camera,
        time: 0.0,
        extent: Extent::new(width, height),
    };
    let settings = ReferenceSettings::new(radius, rays);
    let (surfaces, depth) = reference_surfaces(
        gpu.clone(),
        aograph_renderer::shader_library(),
        &frame,
        settings.normals,
    )?;
    let reference =
        trace_surfaces(gpu, &view.prepared.scene, 0.0, &surfaces, &settings, false)?.accessibility;

    // bevy's frames of the same file from the same camera.
    let transform = view.transform();
    let projection = view.projection(width as f32 / height as f32)?;
    let mut app = Harness::gltf(width, height, file, transform, projection);
    // Frames without AO, after a warm-up (the first frames still create bevy's pipelines and
    // shadow maps); measured again after every configuration ran, and the mean of the two
    // medians taken, so a drift in the machine's speed over the run splits evenly.
    app.time_frames(10);
    let no_ao_before = median(&app.time_frames(frames));

    let name = file
        .file_name()
        .unwrap_or_default()
        .to_string_lossy()
        .into_owned();
    let mut rows = Vec::new();
    let mut runs = Vec::new();
    let mut score = |app: &mut Harness, technique: &str, label: &str| {
        app.time_frames(3);
        let ao = app.probe_bound();
        let span = if technique == "bevy-ssao" {
            "ssao"
        } else {
            "aograph_ao"
        };
        let gpu = app.span_gpu_ms(span, frames);
        let times = app.time_frames(frames);
        let metrics = compare(
            &ao.bound,
            &reference,
            &depth,
            width,
            height,
            &MetricOptions::default(),
        );
        metrics
            .map(|metrics| runs.push((technique.to_owned(), label.to_owned(), gpu, times, metrics)))
    };
    for (label, quality) in BEVY {
        app.set_bevy_ssao(quality);
        // bevy's radius is the same R (its default is 0.7285 view-space units).
        let camera_entity = app.camera;
        app.world()
            .entity_mut(camera_entity)
            .get_mut::<bevy::pbr::ScreenSpaceAmbientOcclusion>()
            .ok_or("bevy's SSAO component")?
            .radius = radius;
        for _ in 0..3 {
            app.update();
        }
        score(&mut app, "bevy-ssao", label)?;
    }
    for technique in AOGRAPH {
        let ao = AographAo::from_toml(&format!("technique = \"{technique}\"\nradius = {radius}"))?;
        app.set_ao(ao);
        app.run_until_technique(technique, 120);
        score(&mut app, technique, "defaults")?;
    }
    let errors = app.status().errors();
    if !errors.is_empty() {
        return Err(format!("aograph recorded errors: {errors:?}").into());
    }
    app.clear_ao();
    app.time_frames(5);
    let no_ao = 0.5 * (no_ao_before + median(&app.time_frames(frames)));
    for (technique, label, gpu, times, metrics) in runs {
        // Timestamps where the device has them; else whole frames minus frames without AO.
        let (source, ms) = match gpu {
            Some(ms) => ("gpu-timestamps", ms),
            None => (
                "cpu-wall",
                times.iter().map(|t| (t - no_ao).max(1e-4)).collect(),
            ),
        };
        rows.push(record(
            &name, &technique, &label, width, height, radius, rays, frames, source, &ms, metrics,
        ));
    }
    Ok(rows)
}

#[allow(clippy::too_many_arguments)]
fn record(
    scene: &str,
    technique: &str,
    label: &str,
    width: u32,
    height: u32,
    radius: f32,
    rays: u32,
    frames: u32,
    source: &str,
    ms: &[f64],
    metrics: aograph_bench::metrics::Metrics,
) -> RunRecord {
    RunRecord {
        scene: scene.to_owned(),
        view: "default".into(),
        technique: technique.to_owned(),
        baseline: false,
        label: label.to_owned(),
        params: Default::default(),
        width,
        height,
        radius,
        radius_px: None,
        reach_px: None,
        reference_mean: None,
        rays,
        frames,
        warmup: 1,
        times: FrameTimes {
            timing_source: source.into(),
            total_ms: Spread::of(ms),
            frame_ms: Spread::of(ms),
            passes: Vec::new(),
        },
        texture_bytes: 0,
        texture_bytes_unshared: 0,
        metrics,
        image: None,
        roofline: Vec::new(),
        radiance: None,
        ceilings: None,
        convergence: Vec::new(),
    }
}

fn median(values: &[f64]) -> f64 {
    Spread::of(values).median
}

fn table(scene: &str, rows: &[RunRecord]) -> String {
    let mut s = format!(
        "\n### {scene}\n\n| AO | settings | MAE | SSIM | ms | timed by |\n|---|---|---|---|---|---|\n"
    );
    for r in rows {
        s.push_str(&format!(
            "| {} | {} | {:.4} | {:.4} | {:.2} | {} |\n",
            r.technique,
            r.label,
            r.metrics.mae,
            r.metrics.ssim,
            r.times.total_ms.median,
            r.times.timing_source
        ));
    }
    s
}
