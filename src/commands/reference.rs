//! `aograph reference`: ray-traces the reference accessibility of a scene from the g-buffer's
//! own points (so the reference and the techniques see the same surfaces), oriented by the
//! configured normals (`[reference] normals`, geometric by default), and writes reference.png
//! (16-bit), reference.f32 (raw) and gbuffer_depth.png.

use std::path::Path;

use aograph_ao_passes::TechniqueRegistry;
use aograph_graph::Extent;
use aograph_scene::ReferenceNormals;

use super::{CommonArgs, gpu};
use crate::shader_library;
use aograph_app_config::config::parse_mode;
use aograph_app_config::error::{AppError, AppResult};
use aograph_bench::images::{prepare_output_dir, write_gray_png};
use aograph_renderer::frame_reference::{
    FrameView, ReferenceSettings, reference_surfaces, trace_surfaces,
};

pub fn reference(
    args: &CommonArgs,
    rays: Option<u32>,
    mode: Option<&str>,
    normals: Option<&str>,
    out: &Path,
) -> AppResult<()> {
    let registry = TechniqueRegistry::with_builtins();
    let config = args.resolve(&registry)?;
    let rays = rays.unwrap_or(config.reference_rays);
    if rays == 0 {
        return Err(AppError::InvalidArgument {
            name: "--rays".into(),
            value: "0".into(),
            allowed: "1 or more".into(),
        });
    }
    let mode = match mode {
        Some(m) => parse_mode(m).map_err(|e| AppError::InvalidArgument {
            name: "--mode".into(),
            value: m.into(),
            allowed: e,
        })?,
        None => config.reference_mode,
    };
    let normals = match normals {
        Some(n) => ReferenceNormals::parse(n).map_err(|e| AppError::InvalidArgument {
            name: "--normals".into(),
            value: n.into(),
            allowed: e,
        })?,
        None => config.reference_normals,
    };
    let prepared = config.prepare_scene()?;
    prepare_output_dir(out)?;
    let size = Extent::new(config.width, config.height);
    let view = FrameView {
        camera: prepared.scene.camera_at(0.0),
        scene: prepared.scene.clone(),
        time: 0.0,
        extent: size,
    };
    let (surfaces, depth) = reference_surfaces(gpu()?, shader_library(), &view, normals)?;
    let settings = ReferenceSettings {
        radius: prepared.radius.get(),
        rays,
        mode,
        normals,
        tracer: config.reference_tracer,
    };
    let gpu = gpu()?;
    let started = std::time::Instant::now();
    let image = trace_surfaces(&gpu, &view.scene, view.time, &surfaces, &settings, true)?;
    let secs = started.elapsed().as_secs_f64();
    image.write_png(out.join("reference.png"))?;
    image.write_raw(out.join("reference.f32"))?;
    let max = depth.iter().copied().fold(0.0f32, f32::max).max(1e-30);
    let shown: Vec<f32> = depth
        .iter()
        .map(|d| if *d > 0.0 { 1.0 - d / max } else { 0.0 })
        .collect();
    write_gray_png(
        &out.join("gbuffer_depth.png"),
        size.width,
        size.height,
        &shown,
    )?;
    let mean_err = image.std_error.iter().sum::<f32>() / image.std_error.len().max(1) as f32;
    println!(
        "reference of {} (view {}) at {} with {} rays/pixel, {}, {:?} mode, {} normals in {:.2} s (mean standard error {:.4})",
        config.scene.label(),
        prepared.view,
        size,
        rays,
        prepared.radius_line(),
        mode,
        normals.name(),
        secs,
        mean_err
    );
    for f in ["reference.png", "reference.f32", "gbuffer_depth.png"] {
        println!("wrote {}", out.join(f).display());
    }
    Ok(())
}
