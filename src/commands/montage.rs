//! `aograph montage`: one scene's reference and several techniques side by side in one PNG
//! (README's picture). Panels left to right: the scene shaded with the config's technique (its
//! AO on the ambient term, as `aograph render`'s shaded.png), reference, then each technique,
//! all from the same camera and g-buffer surfaces, separated by 2-pixel gaps.

use std::path::Path;

use aograph_ao_passes::TechniqueRegistry;
use aograph_graph::Extent;

use super::{CommonArgs, gpu};
use crate::shader_library;
use aograph_app_config::error::AppResult;
use aograph_bench::images::{prepare_output_dir, write_rgb_png};
use aograph_renderer::frame_graph::FrameOutputs;
use aograph_renderer::frame_reference::{ReferenceSettings, frame_reference};
use aograph_renderer::renderer::Renderer;

const GAP: u32 = 2;

pub fn montage(args: &CommonArgs, techniques: &[String], rays: u32, out: &Path) -> AppResult<()> {
    let registry = TechniqueRegistry::with_builtins();
    let config = args.resolve(&registry)?;
    for t in techniques {
        registry.get(t)?;
    }
    let prepared = config.prepare_scene()?;
    let scene = prepared.scene.clone();
    if let Some(dir) = out.parent().filter(|d| !d.as_os_str().is_empty()) {
        prepare_output_dir(dir)?;
    }
    let size = Extent::new(config.width, config.height);
    let gpu = gpu()?;
    let mut panels: Vec<Vec<[u8; 3]>> = Vec::new();
    let gray = |v: &[f32]| {
        v.iter()
            .map(|a| [(a.clamp(0.0, 1.0) * 255.0).round() as u8; 3])
            .collect::<Vec<_>>()
    };
    // The shaded panel carries the config's technique's AO (mssao unless the config says
    // otherwise): with `none` an unlit wall was one flat grey beside panels with AO.
    let base_ao = prepared.ao(&config.ao);
    let mut r = Renderer::new(
        gpu.clone(),
        shader_library(),
        &registry,
        scene.clone(),
        &base_ao,
        FrameOutputs {
            shaded: true,
            ..Default::default()
        },
        size,
    )?;
    for _ in 0..config.frames.max(1) {
        r.render(0.0)?;
    }
    panels.push(
        r.read_shaded()?
            .chunks_exact(4)
            .map(|c| [c[0], c[1], c[2]])
            .collect(),
    );
    panels.push(gray(
        &frame_reference(
            &r,
            &ReferenceSettings {
                radius: prepared.radius.get(),
                rays,
                mode: config.reference_mode,
                normals: config.reference_normals,
                tracer: config.reference_tracer,
            },
            true,
        )?
        .accessibility,
    ));
    for t in techniques {
        let mut ao = prepared.ao(&config.ao);
        ao.technique = t.clone();
        let mut r = Renderer::new(
            gpu.clone(),
            shader_library(),
            &registry,
            scene.clone(),
            &ao,
            FrameOutputs::default(),
            size,
        )?;
        for f in 0..config.frames.max(1) {
            r.render(f as f32 * 0.0)?;
        }
        panels.push(gray(&r.read_ao()?));
    }
    let n = panels.len() as u32;
    let width = n * size.width + (n - 1) * GAP;
    let mut rgb = vec![255u8; (width * size.height * 3) as usize];
    for (i, panel) in panels.iter().enumerate() {
        let x0 = i as u32 * (size.width + GAP);
        for y in 0..size.height {
            for x in 0..size.width {
                let px = panel[(y * size.width + x) as usize];
                let o = ((y * width + x0 + x) * 3) as usize;
                rgb[o..o + 3].copy_from_slice(&px);
            }
        }
    }
    write_rgb_png(out, width, size.height, &rgb)?;
    println!(
        "wrote {} (panels: shaded with {}, reference, {})",
        out.display(),
        config.ao.technique,
        techniques.join(", ")
    );
    Ok(())
}
