//! Composing a custom pipeline on aograph's library crates: a user AO technique registered beside
//! the built-ins and chosen by config like any other, its WGSL mounted beside aograph's, and a
//! user pass added after it in the same graph through the renderer's extension point.
//!
//! Run: `cargo run --release --example custom_pipeline` (writes out/custom/ao.png and tint.png).
//! The same technique runs in an application's own renderer through aograph-embed
//! (`AmbientOcclusion::with_registry(.., registry, [unsharp_depth::shader_mount()])`): see
//! tests/embedding/user_technique.rs.

use std::path::Path;
use std::sync::{Arc, Mutex};

use aograph_ao_passes::{AoConfig, TechniqueRegistry};
use aograph_graph::{GpuContext, ShaderMount, SizeClass, TextureDesc, TextureHandle};
use aograph_renderer::{FrameOutputs, GraphExtension, Renderer};

#[path = "custom_pipeline/unsharp_depth.rs"]
mod unsharp_depth;
use unsharp_depth::UnsharpDepth;

/// The user pass's shader, mounted with the technique's.
const TINT: &str = "examples/tint.wgsl";

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // 1. Register the user technique beside the built-ins and pick it by config.
    let mut registry = TechniqueRegistry::with_builtins();
    registry.register(UnsharpDepth);
    let config: toml::Table =
        "technique = \"unsharp-depth\"\nradius = 1.0\n[unsharp-depth]\nstrength = 6.0\n".parse()?;
    let ao = AoConfig::from_table(&config, &registry)?;

    // 2. The user's shaders live outside aograph's shaders/: mount them beside aograph's.
    let shaders = aograph_renderer::shader_library();
    shaders.mount(unsharp_depth::shader_mount())?;
    shaders.mount(
        ShaderMount::new("custom-pipeline").with_file(TINT, include_str!("shaders/tint.wgsl")),
    )?;

    // 3. aograph's renderer draws the g-buffer and runs the technique; the extension adds a
    //    user pass that reads the AO, in the same graph (compiled once per settings).
    let scene = Arc::new(aograph_scene::procedural_scene("columns")?);
    let size = aograph_graph::Extent::new(320, 180);
    let gpu = Arc::new(GpuContext::new()?);
    let mut renderer = Renderer::new(
        gpu,
        shaders,
        &registry,
        scene,
        &ao,
        FrameOutputs::default(),
        size,
    )?;
    let tint: Arc<Mutex<Option<TextureHandle>>> = Arc::default();
    let tint_out = tint.clone();
    let extension: GraphExtension = Arc::new(move |builder, frame| {
        let target = builder.create_texture(
            "tint",
            TextureDesc::new(wgpu::TextureFormat::Rgba8Unorm, SizeClass::FULL),
        );
        let mut pass = builder.compute_pass("user.tint", TINT, "main");
        pass.sample("ao", frame.accessibility()?);
        let t = pass.write_storage("image", target);
        pass.dispatch_over(t);
        builder.export(t);
        *tint_out.lock().unwrap_or_else(|p| p.into_inner()) = Some(t);
        Ok(())
    });
    renderer.set_extension(extension)?;
    println!("{}", aograph_graph::summary(&renderer.plan, size));

    // 4. One frame, read back.
    renderer.render(0.0)?;
    let out = Path::new("out/custom");
    std::fs::create_dir_all(out)?;
    let ao_bytes: Vec<u8> = renderer
        .read_ao()?
        .iter()
        .map(|a| (a.clamp(0.0, 1.0) * 255.0).round() as u8)
        .collect();
    image::save_buffer(
        out.join("ao.png"),
        &ao_bytes,
        size.width,
        size.height,
        image::ColorType::L8,
    )?;
    let tint = tint
        .lock()
        .unwrap_or_else(|p| p.into_inner())
        .ok_or("the extension declared no tint pass")?;
    let tinted = renderer.exec.read_texture(&renderer.plan, tint)?;
    image::save_buffer(
        out.join("tint.png"),
        &tinted.bytes,
        size.width,
        size.height,
        image::ColorType::Rgba8,
    )?;
    print!("{}", renderer.timings()?.table());
    println!("wrote out/custom/ao.png and out/custom/tint.png");
    Ok(())
}
