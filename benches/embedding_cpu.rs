//! What the embedding API costs the CPU per frame, against aograph's own frame graph on the
//! same technique and size: `AmbientOcclusion::encode` (choose the plan, bind the application's
//! textures, write the View block, record the adapters, the technique and the output pass
//! into the application's encoder) plus the submit, against `Renderer::render` (write the View
//! block, record the g-buffer and the technique, submit), and the recordings alone (encode
//! against `Executor::encode` of the renderer's plan). Only the calls are timed; the GPU is
//! waited for outside the timed region, so the GPU's own time does not enter. Measured on
//! lavapipe (docs/guide/embedding.md, "In your own renderer"): encode 21-25 µs, the renderer's
//! recording 38 µs.
//!
//! gtao (the default preset) on `columns` at 320x180, reversed-Z Depth32Float depth and the
//! g-buffer's own normals handed over as an application would.

use std::sync::Arc;
use std::time::{Duration, Instant};

use aograph_ao_passes::{AoConfig, TechniqueRegistry};
use aograph_embed::{AmbientOcclusion, AoInputs, DepthInput};
use aograph_graph::{Extent, GpuContext, TimingMode};
use aograph_renderer::FrameOutputs;
use aograph_renderer::Renderer;
use criterion::Criterion;
use glam::Mat4;

const SIZE: Extent = Extent {
    width: 320,
    height: 180,
};

fn config(radius: f32) -> AoConfig {
    AoConfig {
        technique: "gtao".into(),
        radius: aograph_ao_passes::RadiusSetting::Units(
            aograph_ao_passes::Radius::new("R", radius).expect("a positive radius"),
        ),
        ..AoConfig::default()
    }
}

/// The application's depth: the g-buffer's linear depth through a reversed-Z infinite
/// projection, uploaded as R32Float and handed over as linear depth (what the adapters do
/// with a hardware buffer is one more compute pass; the CPU cost is the same).
fn application_depth(gpu: &GpuContext, lin: &[f32]) -> wgpu::Texture {
    let t = gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some("application depth"),
        size: wgpu::Extent3d {
            width: SIZE.width,
            height: SIZE.height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::R32Float,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    gpu.queue.write_texture(
        t.as_image_copy(),
        bytemuck::cast_slice(lin),
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(4 * SIZE.width),
            rows_per_image: Some(SIZE.height),
        },
        wgpu::Extent3d {
            width: SIZE.width,
            height: SIZE.height,
            depth_or_array_layers: 1,
        },
    );
    t
}

/// CPU time of `iters` calls of `call`, the GPU drained after each outside the timing.
fn cpu_only(gpu: &GpuContext, iters: u64, mut call: impl FnMut()) -> Duration {
    let mut total = Duration::ZERO;
    for _ in 0..iters {
        let started = Instant::now();
        call();
        total += started.elapsed();
        gpu.wait_idle().expect("device idle");
    }
    total
}

fn main() {
    let gpu = Arc::new(GpuContext::new().expect("a GPU adapter (lavapipe where there is none)"));
    let scene = aograph_scene::procedural_scene("columns").expect("a built-in scene");
    let radius = aograph_scene::suggested_radius(&scene).radius;
    let config = config(radius);
    let outputs = FrameOutputs {
        linear_depth: true,
        ..Default::default()
    };
    let mut renderer = Renderer::new(
        gpu.clone(),
        aograph::shader_library(),
        &TechniqueRegistry::with_builtins(),
        Arc::new(scene.clone()),
        &config,
        outputs,
        SIZE,
    )
    .expect("the frame graph builds");
    // Timing off: CPU-wall timing would wait per pass, which is not the frame graph's cost.
    renderer
        .exec
        .set_timing(TimingMode::Off)
        .expect("timing off");
    renderer.render(0.0).expect("frame renders");
    let lin = renderer.read_linear_depth().expect("linear depth");
    let depth = application_depth(&gpu, &lin);
    let camera = scene.camera_at(0.0);
    let aspect = SIZE.width as f32 / SIZE.height as f32;
    let proj = Mat4::perspective_infinite_reverse_rh(
        camera.fov_y().expect("a perspective camera"),
        aspect,
        camera.near(),
    );
    let view = camera.view();
    let mut ao = AmbientOcclusion::new(&gpu.adapter, &gpu.device, &gpu.queue, &config)
        .expect("the embedding builds");
    let inputs = AoInputs::new(DepthInput::Linear(&depth), proj, view);
    let mut embed_frame = || {
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        ao.encode(&mut encoder, &inputs).expect("frame encodes");
        gpu.queue.submit([encoder.finish()]);
    };
    embed_frame();

    let mut c = Criterion::default().configure_from_args().sample_size(20);
    c.bench_function(
        "frame graph: Renderer::render (g-buffer + gtao), CPU",
        |b| b.iter_custom(|iters| cpu_only(&gpu, iters, || renderer.render(0.0).expect("frame"))),
    );
    c.bench_function(
        "embedding: AmbientOcclusion::encode + submit (adapters + gtao), CPU",
        |b| b.iter_custom(|iters| cpu_only(&gpu, iters, &mut embed_frame)),
    );
    // The recordings alone: the submit (the driver's share) left out of the timing. aograph's
    // own frame recorded by the same executor call the embedding makes.
    c.bench_function(
        "frame graph: Executor::encode of the Renderer's plan alone, CPU",
        |b| {
            b.iter_custom(|iters| {
                let mut total = Duration::ZERO;
                for _ in 0..iters {
                    let mut encoder = gpu.device.create_command_encoder(&Default::default());
                    let started = Instant::now();
                    let plan = renderer.plan.clone();
                    renderer
                        .exec
                        .encode(&plan, SIZE, &mut encoder)
                        .expect("frame encodes");
                    total += started.elapsed();
                    gpu.queue.submit([encoder.finish()]);
                    gpu.wait_idle().expect("device idle");
                }
                total
            })
        },
    );
    c.bench_function("embedding: AmbientOcclusion::encode alone, CPU", |b| {
        b.iter_custom(|iters| {
            let mut total = Duration::ZERO;
            for _ in 0..iters {
                let mut encoder = gpu.device.create_command_encoder(&Default::default());
                let started = Instant::now();
                ao.encode(&mut encoder, &inputs).expect("frame encodes");
                total += started.elapsed();
                gpu.queue.submit([encoder.finish()]);
                gpu.wait_idle().expect("device idle");
            }
            total
        })
    });
    c.final_summary();
}
