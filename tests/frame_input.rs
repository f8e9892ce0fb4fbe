//! A frame input added from outside aograph's crates, as docs/guide/writing-a-technique.md
//! walks through it: a per-frame exposure (a uniform the application writes), declared by a
//! test technique that outputs it as its accessibility, and bound by whoever owns the frame
//! (the renderer with `Renderer::bind_input`, the embedding with
//! `AmbientOcclusion::bind_input`). The whole input is this file and the WGSL below: its type,
//! the technique that reads it, and the owners' calls that bind it.

mod common;

use std::sync::Arc;

use aograph_ao_passes::{
    AoBuildContext, AoOutput, AoResult, AoTechnique, ParamDesc, TechniqueRegistry,
};
use aograph_frame::{BufferBlock, BufferInput, GBufferChannels};
use aograph_graph::{BufferAccess, Extent, ShaderMount, test_gpu};
use serde::{Deserialize, Serialize};

/// The input's block, `Exposure` in the WGSL: one buffer the application fills, so the
/// input is `BufferInput<ExposureBlock>` (a frame input needing more than one buffer
/// implements `FrameInput` itself, as the scene's BVH does).
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct ExposureBlock {
    value: f32,
    pad: [f32; 3],
}

impl BufferBlock for ExposureBlock {
    const NAME: &'static str = "the exposure";
    const IMPORT: &'static str = "exposure";
}

/// The input.
type Exposure = BufferInput<ExposureBlock>;

const SHADER: &str = "tests/exposed.wgsl";
const WGSL: &str = "
struct Exposure { value: f32, pad0: f32, pad1: f32, pad2: f32 }
@group(0) @binding(0) var<uniform> exposure: Exposure;
@group(0) @binding(1) var ao: texture_storage_2d<r32float, write>;
@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(ao);
    if (id.x >= size.x || id.y >= size.y) { return; }
    textureStore(ao, vec2<i32>(id.xy), vec4<f32>(clamp(exposure.value, 0.0, 1.0), 0.0, 0.0, 0.0));
}
";

/// A technique whose accessibility is the exposure, everywhere.
struct Exposed;

#[derive(Clone, Debug, Default, Serialize, Deserialize)]
struct NoParams {}

impl AoTechnique for Exposed {
    type Params = NoParams;
    const NAME: &'static str = "exposed";
    fn description(&self) -> &'static str {
        "the frame's exposure as accessibility (a frame input's test)"
    }
    fn params(&self) -> Vec<ParamDesc> {
        Vec::new()
    }
    fn channels(&self, _: &NoParams) -> GBufferChannels {
        GBufferChannels::none()
    }
    fn build(&self, ctx: &mut AoBuildContext<'_>, _: &NoParams) -> AoResult<AoOutput> {
        let exposure = ctx.input::<Exposure>();
        let out = ctx.accessibility_texture("exposed.ao");
        let mut pass = ctx.builder.compute_pass("exposed.ao", SHADER, "main");
        pass.read_buffer("exposure", BufferAccess::Uniform, exposure);
        let out = pass.write_storage("ao", out);
        pass.dispatch_over(out);
        Ok(AoOutput::new(out))
    }
}

fn registry() -> TechniqueRegistry {
    let mut r = TechniqueRegistry::with_builtins();
    r.register(Exposed);
    r
}

fn mount() -> ShaderMount {
    ShaderMount::new("frame-input-test").with_file(SHADER, WGSL)
}

fn exposure_buffer(gpu: &aograph_graph::GpuContext, value: f32) -> wgpu::Buffer {
    let buffer = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("exposure"),
        size: 16,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    gpu.queue.write_buffer(
        &buffer,
        0,
        bytemuck::bytes_of(&ExposureBlock {
            value,
            pad: [0.0; 3],
        }),
    );
    buffer
}

#[test]
fn the_renderer_binds_an_applications_frame_input_and_names_it_when_unbound() {
    let Some(gpu) = test_gpu() else { return };
    let shaders = aograph::shader_library();
    shaders.mount(mount()).unwrap();
    let scene = Arc::new(aograph_scene::procedural_scene("columns").unwrap());
    let mut r = aograph_renderer::Renderer::new(
        gpu.clone(),
        shaders,
        &registry(),
        scene,
        &common::ao_config("exposed", 1.0, ""),
        Default::default(),
        Extent::new(37, 21),
    )
    .unwrap();
    // Declared by the technique, and nothing supplies it yet: the frame names it.
    assert!(r.graph.declared.contains::<Exposure>());
    let e = r.render(0.0).unwrap_err().to_string();
    assert!(
        e.contains("the exposure") && e.contains("bind_input"),
        "{e}"
    );
    // Bound: the frame reads it; rewritten between frames: the next frame reads the new value.
    let buffer = exposure_buffer(&gpu, 0.25);
    r.bind_input::<Exposure>(buffer.clone());
    r.render(0.0).unwrap();
    assert!(r.read_ao().unwrap().iter().all(|&a| a == 0.25));
    gpu.queue
        .write_buffer(&buffer, 0, bytemuck::cast_slice(&[0.75f32, 0.0, 0.0, 0.0]));
    r.render(0.0).unwrap();
    assert!(r.read_ao().unwrap().iter().all(|&a| a == 0.75));
}

#[test]
fn the_embedding_refuses_a_technique_whose_input_is_unbound_when_it_is_chosen() {
    let Some(gpu) = test_gpu() else { return };
    let registry = registry();
    let mut ao = aograph_embed::AmbientOcclusion::with_registry(
        &gpu.adapter,
        &gpu.device,
        &gpu.queue,
        &common::ao_config("gtao", 0.5, ""),
        registry,
        Some(mount()),
    )
    .unwrap();
    let exposed = common::ao_config("exposed", 0.5, "");
    let e = ao.set_config(&exposed).unwrap_err().to_string();
    assert!(
        e.contains("exposed") && e.contains("the exposure") && e.contains("bind_input"),
        "{e}"
    );
    assert_eq!(ao.config().technique, "gtao", "the settings in use stay");
    ao.bind_input::<Exposure>(exposure_buffer(&gpu, 0.5))
        .unwrap();
    ao.set_config(&exposed).unwrap();
    assert_eq!(ao.config().technique, "exposed");
}
