//! Composing a custom pipeline: a user AO technique registered beside the built-ins, chosen by
//! config like any other, and a user pass added after it in the same graph.
//!
//! Run: `cargo run --release --example custom_pipeline` (writes out/custom/ao.png and tint.png).

use std::sync::Arc;

use aograph::{FrameOutputs, images};
use aograph_ao::{AoConfig, TechniqueRegistry};
use aograph_graph::{
    CompileOptions, Executor, Extent, GpuContext, GraphCompiler, SizeClass, TextureDesc,
};

#[path = "custom_pipeline/unsharp_depth.rs"]
mod unsharp_depth;
use unsharp_depth::UnsharpDepth;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // 1. Register the user technique beside the built-ins and pick it by config.
    let mut registry = TechniqueRegistry::with_builtins();
    registry.register(UnsharpDepth);
    let config: toml::Table =
        "technique = \"unsharp-depth\"\nradius = 1.0\n[unsharp-depth]\nstrength = 6.0\n".parse()?;
    let ao = AoConfig::from_table(&config, &registry)?;

    // 2. The user's shaders live outside shaders/: register them inline.
    let shaders = aograph::shader_library();
    unsharp_depth::add_shader(&shaders);
    shaders.add_inline("examples/tint.wgsl", include_str!("shaders/tint.wgsl"));

    // 3. Declare the frame (g-buffer + technique), then add a user pass reading its output.
    let scene = Arc::new(aograph_scene::procedural_scene("columns")?);
    let size = Extent::new(320, 180);
    let mut fg =
        aograph::build_frame_graph(&registry, scene.clone(), &ao, FrameOutputs::default(), size)?;
    let mut builder = aograph_graph::GraphBuilder::from_decl(fg.decl.clone());
    let tint = {
        let target = builder.create_texture(
            "tint",
            TextureDesc::new(wgpu::TextureFormat::Rgba8Unorm, SizeClass::FULL),
        );
        let mut pass = builder.compute_pass("user.tint", "examples/tint.wgsl", "main");
        pass.sample("ao", fg.ao);
        let t = pass.write_storage("image", target);
        pass.dispatch_over(t);
        builder.export(t);
        t
    };
    fg.decl = builder.build();

    // 4. Compile (pure, no GPU) and run one frame.
    let plan = GraphCompiler::new().compile(fg.decl, &shaders, CompileOptions::default())?;
    println!("{}", aograph_graph::summary(&plan, size));
    let gpu = Arc::new(GpuContext::new()?);
    let mut exec = Executor::with_shaders(gpu.clone(), shaders);
    let view = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("view"),
        size: std::mem::size_of::<aograph_frame::ViewUniforms>() as u64,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let camera = scene.camera_at(0.0);
    let block = aograph_scene::view_block::view_uniforms(&aograph_scene::view_block::ViewFrame {
        camera,
        prev_camera: camera,
        output: size,
        frame_index: 0,
        history_valid: false,
        camera_cut: false,
        time: 0.0,
        dt: 0.0,
    });
    gpu.queue.write_buffer(&view, 0, block.bytes());
    exec.import_buffer(aograph_frame::VIEW_BUFFER, view);
    exec.execute(&plan, size)?;

    let out = std::path::Path::new("out/custom");
    images::prepare_output_dir(out)?;
    images::write_gray_png(
        &out.join("ao.png"),
        size.width,
        size.height,
        &exec.read_texture(&plan, fg.ao)?.channel(0)?,
    )?;
    images::write_rgba_png(
        &out.join("tint.png"),
        size.width,
        size.height,
        &exec.read_texture(&plan, tint)?.bytes,
    )?;
    print!("{}", exec.wait_timings()?.table());
    println!("wrote out/custom/ao.png and out/custom/tint.png");
    Ok(())
}
