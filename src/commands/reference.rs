//! `aograph reference`: ray-traces the reference accessibility of a scene from the g-buffer's
//! own points and normals (so the reference and the techniques see the same surfaces) and
//! writes reference.png (16-bit), reference.f32 (raw) and gbuffer_depth.png.

use std::path::Path;
use std::sync::Arc;

use aograph_ao::TechniqueRegistry;
use aograph_graph::Extent;
use aograph_scene::reference::ProgressMode;
use aograph_scene::{ReferenceCache, ReferenceImage, ReferenceParams, TriangleBvh};

use super::{CommonArgs, gpu};
use crate::config::parse_mode;
use crate::error::{AppError, AppResult};
use crate::frame_graph::FrameOutputs;
use crate::images::{prepare_output_dir, write_gray_png};
use crate::renderer::{Renderer, shader_library};

/// Renders the g-buffer of `r`'s last frame and traces the reference for it, using the disk
/// cache under `target/reference-cache` (or `AOGRAPH_REFERENCE_CACHE`).
pub fn trace_for(
    r: &Renderer,
    radius: f32,
    rays: u32,
    mode: aograph_scene::ReferenceMode,
    progress: bool,
) -> AppResult<ReferenceImage> {
    let surfaces = r.surfaces()?;
    let tris = r.scene.world_triangles(r.time());
    let params = ReferenceParams {
        radius,
        rays_per_pixel: rays,
        mode,
        progress: if progress {
            ProgressMode::Auto
        } else {
            ProgressMode::Never
        },
    };
    let key =
        aograph_scene::CacheKey::new(&tris, &r.camera(), surfaces.width, surfaces.height, &params);
    let dir = std::env::var_os("AOGRAPH_REFERENCE_CACHE")
        .map(std::path::PathBuf::from)
        .unwrap_or_else(|| {
            std::path::PathBuf::from(concat!(
                env!("CARGO_MANIFEST_DIR"),
                "/target/reference-cache"
            ))
        });
    let cache = ReferenceCache::new(dir);
    Ok(cache.get_or_trace(key, || {
        let bvh = TriangleBvh::new(&tris);
        aograph_scene::trace_reference(&bvh, &surfaces, &params)
    })?)
}

pub fn reference(
    args: &CommonArgs,
    rays: Option<u32>,
    mode: Option<&str>,
    out: &Path,
) -> AppResult<()> {
    let registry = TechniqueRegistry::with_builtins();
    let mut config = args.resolve(&registry)?;
    config.ao.technique = "none".into();
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
    let scene = Arc::new(crate::load_scene(&config.scene)?);
    prepare_output_dir(out)?;
    let size = Extent::new(config.width, config.height);
    let mut r = Renderer::new(
        gpu()?,
        shader_library(),
        &registry,
        scene,
        &config.ao,
        FrameOutputs {
            surfaces: true,
            linear_depth: true,
            ..Default::default()
        },
        size,
    )?;
    r.render(0.0)?;
    let started = std::time::Instant::now();
    let image = trace_for(&r, config.ao.radius, rays, mode, true)?;
    let secs = started.elapsed().as_secs_f64();
    image.write_png(out.join("reference.png"))?;
    image.write_raw(out.join("reference.f32"))?;
    let depth = r.read_linear_depth()?;
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
        "reference of {} at {} with {} rays/pixel, R = {}, {:?} mode in {:.2} s (mean standard error {:.4})",
        config.scene.label(),
        size,
        rays,
        config.ao.radius,
        mode,
        secs,
        mean_err
    );
    for f in ["reference.png", "reference.f32", "gbuffer_depth.png"] {
        println!("wrote {}", out.join(f).display());
    }
    Ok(())
}
