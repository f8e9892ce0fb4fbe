//! Every technique fed a g-buffer with NaN and infinite texels: the output stays finite and in
//! [0, 1] (extra outputs, SSDO's radiance, finite), and a pixel whose own depth is NaN reads as
//! accessibility 1 (it occludes nothing and is occluded by nothing), exactly as sky does.
//!
//! The g-buffer is a real frame of `columns` (rendered, read back as raw bytes) with poison
//! written into it: NaN linear depth in a block of pixels, +infinity depth at others, NaN
//! normals (garbage codes in the compact normals) and NaN positions elsewhere. Each technique's own graph is then built on imported
//! copies of those channels and run for three frames (the temporal ones accumulate), so the
//! poison reaches every pass: kernels that sample it, blurs that average it, histories that
//! keep it. The shaders detect non-finite values by their bit pattern (shaders/common/
//! finite.wgsl), not with `a == a`, which WGSL allows a compiler to fold to true.

mod common;

use std::sync::Arc;

use aograph_ao_passes::{AoBuildContext, AoConfig, TechniqueRegistry, TracingSupport};
use aograph_frame::{GBufferChannel, GBufferTextures, VIEW_BUFFER, ViewUniforms};
use aograph_frame::{
    LIGHTING_BUFFER, LightingUniforms, SceneAcceleration, SceneAccelerationResources, SceneBvh,
    SceneBvhBuffers,
};
use aograph_graph::{
    BufferDesc, CompileOptions, Executor, Extent, GraphBuilder, SizeClass, TextureDesc, compile,
    test_gpu,
};
use aograph_renderer::FrameOutputs;
use aograph_renderer::Renderer;
use aograph_scene::ReferenceNormals;
use aograph_scene::view_block::{ViewFrame, view_uniforms};
use aograph_tracing::gpu::{GpuSceneBvh, HardwareSceneAs};

const SIZE: Extent = Extent {
    width: 64,
    height: 48,
};

/// Where the poison goes: (x range, y range) of the blocks.
const NAN_DEPTH: (std::ops::Range<u32>, std::ops::Range<u32>) = (20..26, 20..26);
const INF_DEPTH: (std::ops::Range<u32>, std::ops::Range<u32>) = (40..44, 10..14);
const NAN_NORMAL: (std::ops::Range<u32>, std::ops::Range<u32>) = (8..12, 30..34);
const NAN_POSITION: (std::ops::Range<u32>, std::ops::Range<u32>) = (50..54, 30..34);

fn in_block(i: usize, block: &(std::ops::Range<u32>, std::ops::Range<u32>)) -> bool {
    let (x, y) = ((i as u32) % SIZE.width, (i as u32) / SIZE.width);
    block.0.contains(&x) && block.1.contains(&y)
}

/// Writes the bit pattern `bits` (one texel component of `size` bytes) into every channel
/// `components` of texel `i`.
fn poison(
    bytes: &mut [u8],
    i: usize,
    texel: usize,
    components: std::ops::Range<usize>,
    bits: &[u8],
) {
    for c in components {
        let at = i * texel + c * bits.len();
        bytes[at..at + bits.len()].copy_from_slice(bits);
    }
}

/// The poisoned raw bytes of `channel`: `r`'s last frame for depth, normals and positions;
/// for the colour channels (which the frame graph keeps internal), a constant grey albedo and
/// a constant direct light of 0.5 with a NaN block.
fn poisoned(r: &Renderer, channel: GBufferChannel) -> Vec<u8> {
    let n = (SIZE.width * SIZE.height) as usize;
    let texel = channel.format().block_copy_size(None).unwrap() as usize;
    let mut bytes = match channel {
        GBufferChannel::Albedo => [200u8, 200, 200, 255].repeat(n),
        GBufferChannel::DirectLight => [0x3800u16, 0x3800, 0x3800, 0x3c00]
            .iter()
            .flat_map(|h| h.to_le_bytes())
            .collect::<Vec<u8>>()
            .repeat(n),
        // The compact normals of the source's normals (the source frame writes the wide
        // encoding); no code is NaN, so the poisoned block gets the codes of the square's
        // corners and of -1 in both components, which decode to the seams of the map.
        GBufferChannel::NormalsOct => {
            let h = r.graph.gbuffer.normals.expect("the source renders normals");
            let wide = r.exec.read_texture(&r.plan, h).expect("reads back");
            let wide = wide.to_f32().expect("Rgba16Float");
            (0..n)
                .flat_map(|i| {
                    let code = if in_block(i, &NAN_NORMAL) {
                        [0xffff_ffffu32, 0x8000_8000, 0x7fff_7fff][i % 3]
                    } else {
                        let v = &wide[i * 4..i * 4 + 3];
                        aograph_frame::normal_oct::encode([v[0], v[1], v[2]])
                    };
                    code.to_le_bytes()
                })
                .collect()
        }
        c => {
            let h = r
                .graph
                .gbuffer
                .get(c)
                .expect("the source renders the channel");
            r.exec.read_texture(&r.plan, h).expect("reads back").bytes
        }
    };
    let (f32_nan, f32_inf) = (f32::NAN.to_le_bytes(), f32::INFINITY.to_le_bytes());
    let f16_nan = 0x7e00u16.to_le_bytes();
    for i in 0..n {
        match channel {
            GBufferChannel::LinearDepth if in_block(i, &NAN_DEPTH) => {
                poison(&mut bytes, i, texel, 0..1, &f32_nan)
            }
            GBufferChannel::LinearDepth if in_block(i, &INF_DEPTH) => {
                poison(&mut bytes, i, texel, 0..1, &f32_inf)
            }
            GBufferChannel::Normals if in_block(i, &NAN_NORMAL) => {
                poison(&mut bytes, i, texel, 0..3, &f16_nan)
            }
            GBufferChannel::Positions if in_block(i, &NAN_POSITION) || in_block(i, &NAN_DEPTH) => {
                poison(&mut bytes, i, texel, 0..3, &f32_nan)
            }
            GBufferChannel::DirectLight if in_block(i, &NAN_NORMAL) => {
                poison(&mut bytes, i, texel, 0..3, &f16_nan)
            }
            _ => {}
        }
    }
    bytes
}

#[test]
fn nan_and_infinite_gbuffer_texels_give_finite_accessibility_for_every_technique() {
    let Some(gpu) = test_gpu() else {
        return;
    };
    let registry = TechniqueRegistry::with_builtins();
    let scene = Arc::new(aograph_scene::procedural_scene("columns").unwrap());
    // The source frame: every channel a technique may read.
    let mut source = Renderer::new(
        gpu.clone(),
        aograph::shader_library(),
        &registry,
        scene.clone(),
        &AoConfig {
            technique: "none".into(),
            ..AoConfig::default()
        },
        FrameOutputs {
            surfaces: true,
            surface_normals: ReferenceNormals::Shading,
            linear_depth: true,
            ..Default::default()
        },
        SIZE,
    )
    .expect("source renderer");
    source.render(0.0).expect("source frame");
    let view = view_uniforms(&ViewFrame {
        camera: scene.camera,
        prev_camera: scene.camera,
        output: SIZE,
        frame_index: 0,
        history_valid: false,
        camera_cut: true,
        time: 0.0,
        dt: 0.0,
    });
    let channels = [
        GBufferChannel::LinearDepth,
        GBufferChannel::Normals,
        GBufferChannel::NormalsOct,
        GBufferChannel::Positions,
        GBufferChannel::Albedo,
        GBufferChannel::DirectLight,
    ];
    let data: Vec<(GBufferChannel, Vec<u8>)> = channels
        .iter()
        .map(|c| (*c, poisoned(&source, *c)))
        .collect();
    let mut failures = Vec::new();
    // Every technique at its defaults, and those with a denoiser also without it, so the raw
    // AO pass's own output is checked (a blur that treats a NaN depth as sky hides it); a
    // technique that traces rays on each backend the device runs (the rays start from the
    // poisoned points and normals, and the hardware one's ray queries must not see NaN).
    let mut variants: Vec<(String, toml::Table)> = Vec::new();
    for name in registry.names() {
        variants.push((name.clone(), toml::Table::new()));
        let t = registry.get(&name).unwrap();
        if t.parameters().iter().any(|p| p.name == "blur") {
            variants.push((name.clone(), "blur = false".parse().unwrap()));
        }
        if t.parameters().iter().any(|p| p.name == "tracer") {
            for tracer in common::ray_tracers(&gpu) {
                let params = format!("tracer = \"{tracer}\"").parse().unwrap();
                variants.push((name.clone(), params));
            }
        }
    }
    for (name, params) in variants {
        let technique = registry
            .get(&name)
            .unwrap()
            .clone()
            .configure(&params)
            .unwrap();
        let name = if params.is_empty() {
            name
        } else {
            format!("{name} [{}]", params.to_string().trim())
        };
        let mut b = GraphBuilder::new();
        let view_h = b.import_buffer(
            VIEW_BUFFER,
            BufferDesc {
                size: std::mem::size_of::<ViewUniforms>() as u64,
            },
        );
        let mut g = GBufferTextures::default();
        for c in channels {
            g.set(
                c,
                b.import_texture(c.name(), TextureDesc::new(c.format(), SizeClass::FULL)),
            );
        }
        let mut ctx = AoBuildContext {
            builder: &mut b,
            gbuffer: g,
            view: view_h,
            radius: 1.0,
            intermediate_format: wgpu::TextureFormat::R16Float,
            technique: technique.name(),
            radius_pixels: None,
            declared: Default::default(),
            tracing: TracingSupport::of(&gpu),
        };
        let out = technique.build(&mut ctx).expect("builds");
        let declared = ctx.declared;
        b.export(out.accessibility);
        out.extra.iter().for_each(|(_, h)| b.export(*h));
        let plan = Arc::new(
            compile(
                b.build(),
                &aograph::shader_library(),
                CompileOptions::default(),
            )
            .expect("compiles"),
        );
        let mut exec = Executor::with_shaders(gpu.clone(), aograph::shader_library());
        let buffer = |label: &str, bytes: &[u8]| {
            let buf = gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: bytes.len() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            gpu.queue.write_buffer(&buf, 0, bytes);
            buf
        };
        exec.import_buffer(VIEW_BUFFER, buffer("view", bytemuck::bytes_of(&view)));
        let l = &scene.light;
        let lighting = LightingUniforms::new(
            l.direction.into(),
            l.color.map(|c| c * l.intensity),
            scene.ambient,
        );
        exec.import_buffer(LIGHTING_BUFFER, buffer("lighting", lighting.bytes()));
        // A technique that declared the scene's BVH (rtao) gets the scene's, as the renderer
        // would give it: the rays start from the poisoned points and normals.
        if declared.contains::<SceneBvh>() {
            let bvh = GpuSceneBvh::new(gpu.clone(), &scene, 0.0).expect("the BVH fits");
            let buffers = SceneBvhBuffers {
                nodes: bvh.nodes.clone(),
                instances: bvh.instances.clone(),
                triangles: bvh.triangles.clone(),
            };
            (declared.bind::<SceneBvh>(&mut exec, &plan, &buffers)).expect("binds");
        }
        // And the acceleration structures to one that declared them (rtao on ray queries).
        if declared.contains::<SceneAcceleration>() {
            let a = HardwareSceneAs::build(&gpu, &scene, 0.0).expect("the structures build");
            let resources = SceneAccelerationResources {
                tlas: a.tlas.clone(),
                instances: a.instances.clone(),
                primitives: a.primitives.clone(),
            };
            (declared.bind::<SceneAcceleration>(&mut exec, &plan, &resources)).expect("binds");
        }
        for (c, bytes) in &data {
            let tex = gpu.device.create_texture(&wgpu::TextureDescriptor {
                label: Some(c.name()),
                size: wgpu::Extent3d {
                    width: SIZE.width,
                    height: SIZE.height,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: c.format(),
                usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
                view_formats: &[],
            });
            let row = SIZE.width * c.format().block_copy_size(None).unwrap();
            gpu.queue.write_texture(
                tex.as_image_copy(),
                bytes,
                wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(row),
                    rows_per_image: None,
                },
                wgpu::Extent3d {
                    width: SIZE.width,
                    height: SIZE.height,
                    depth_or_array_layers: 1,
                },
            );
            exec.import_texture(c.name(), tex);
        }
        for _ in 0..3 {
            exec.execute(&plan, SIZE).expect("executes");
        }
        let ao = exec
            .read_texture(&plan, out.accessibility)
            .and_then(|t| t.channel(0))
            .expect("reads back");
        let bad: Vec<usize> = (0..ao.len())
            .filter(|&i| !(ao[i].is_finite() && (0.0..=1.0).contains(&ao[i])))
            .collect();
        if !bad.is_empty() {
            failures.push(format!(
                "{name}: {} pixels not finite in [0, 1], e.g. pixel {} = {}",
                bad.len(),
                bad[0],
                ao[bad[0]]
            ));
        }
        let nan_pixels: Vec<usize> = (0..ao.len()).filter(|&i| in_block(i, &NAN_DEPTH)).collect();
        let not_one = nan_pixels.iter().filter(|&&i| ao[i] != 1.0).count();
        if not_one > 0 {
            failures.push(format!(
                "{name}: {not_one} of {} NaN-depth pixels are not exactly 1",
                nan_pixels.len()
            ));
        }
        // Extra outputs (SSDO's radiance) must stay finite too.
        for (extra, h) in &out.extra {
            let values = exec
                .read_texture(&plan, *h)
                .and_then(|t| t.to_f32())
                .expect("reads back");
            let non_finite = values.iter().filter(|v| !v.is_finite()).count();
            if non_finite > 0 {
                failures.push(format!("{name}: {non_finite} non-finite values in {extra}"));
            }
        }
        let errors = gpu.take_errors();
        if !errors.is_empty() {
            failures.push(format!("{name}: wgpu errors {}", errors.join("; ")));
        }
        eprintln!(
            "{name}: {} poisoned channels in; {} non-finite or out-of-range outputs; NaN-depth pixels {}",
            data.len(),
            bad.len(),
            if not_one == 0 { "exactly 1" } else { "NOT 1" }
        );
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
