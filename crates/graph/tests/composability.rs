//! Composing the graph with a user's renderer: drawing onto an imported target keeps what
//! nothing drew over, explicit clear values, reversed-Z depth clears to 0, blend state on
//! full-screen passes, read-only depth attachments, usage checks on imported textures, and
//! duplicate import or history names as named errors. GPU results are read back from R32Float
//! targets and compared exactly (every value written is a multiple of 1/4).

use std::sync::Arc;

use aograph_graph::*;
use wgpu::TextureFormat::{Depth32Float, R32Float};

/// A full-screen triangle at depth `params.z` writing `params.value` into colour 0; pixels
/// with x below `params.discard_below_x` are discarded (nothing drawn there).
const DRAW: &str = r#"
struct Params { value: f32, z: f32, discard_below_x: f32, pad: f32 }
@group(0) @binding(0) var<uniform> params: Params;
@vertex
fn vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let uv = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(uv * 2.0 - 1.0, params.z, 1.0);
}
@fragment
fn fs(@builtin(position) p: vec4<f32>) -> @location(0) vec4<f32> {
    if (p.x < params.discard_below_x) { discard; }
    return vec4<f32>(params.value, 0.0, 0.0, 1.0);
}
"#;

/// A full-screen triangle at depth 0.3 writing the depth it samples from `depth` (which it
/// also tests against as a read-only attachment).
const SAMPLE_DEPTH: &str = r#"
@group(0) @binding(0) var depth: texture_depth_2d;
@vertex
fn vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let uv = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(uv * 2.0 - 1.0, 0.3, 1.0);
}
@fragment
fn fs(@builtin(position) p: vec4<f32>) -> @location(0) vec4<f32> {
    return vec4<f32>(textureLoad(depth, vec2<i32>(p.xy), 0), 0.0, 0.0, 1.0);
}
"#;

fn shaders() -> ShaderLibrary {
    let lib = ShaderLibrary::inline_only();
    lib.add_inline("draw.wgsl", DRAW);
    lib.add_inline("sample_depth.wgsl", SAMPLE_DEPTH);
    lib
}

fn params(value: f32, z: f32, discard_below_x: f32) -> Vec<u8> {
    [value, z, discard_below_x, 0.0]
        .iter()
        .flat_map(|f| f.to_le_bytes())
        .collect()
}

const W: u32 = 16;
const H: u32 = 8;

fn r32() -> TextureDesc {
    TextureDesc::new(R32Float, SizeClass::FULL)
}

/// A user's R32Float texture filled with `fill(x, y)`.
fn user_texture(
    gpu: &GpuContext,
    usage: wgpu::TextureUsages,
    fill: impl Fn(u32, u32) -> f32,
) -> wgpu::Texture {
    let tex = gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some("user target"),
        size: wgpu::Extent3d {
            width: W,
            height: H,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: R32Float,
        usage,
        view_formats: &[],
    });
    let data: Vec<u8> = (0..H)
        .flat_map(|y| (0..W).map(move |x| (x, y)))
        .flat_map(|(x, y)| fill(x, y).to_le_bytes())
        .collect();
    gpu.queue.write_texture(
        tex.as_image_copy(),
        &data,
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(W * 4),
            rows_per_image: None,
        },
        tex.size(),
    );
    tex
}

fn target_usage() -> wgpu::TextureUsages {
    wgpu::TextureUsages::RENDER_ATTACHMENT
        | wgpu::TextureUsages::COPY_DST
        | wgpu::TextureUsages::COPY_SRC
}

fn user_pattern(x: u32, y: u32) -> f32 {
    (x + 2 * y) as f32 * 0.25
}

/// Runs one frame of a graph drawing into the imported `target` with `color` (the target's
/// colour operations), reading back the result.
fn draw_onto_import(gpu: &Arc<GpuContext>, color: Option<ColorTarget>, draw: &[u8]) -> Vec<f32> {
    let mut b = GraphBuilder::new();
    let target = b.import_texture("user.target", r32());
    let mut p = b.fullscreen_pass("overlay", "draw.wgsl", "vs", "fs");
    p.uniform("params", draw);
    let out = match color {
        Some(c) => p.color_target(target, c),
        None => p.color_attachment(target),
    };
    b.export(out);
    let plan = Arc::new(compile(b.build(), &shaders(), CompileOptions::default()).unwrap());
    let mut exec = Executor::new(gpu.clone());
    exec.import_texture(
        "user.target",
        user_texture(gpu, target_usage(), user_pattern),
    );
    exec.execute(&plan, Extent::new(W, H)).unwrap();
    exec.read_texture(&plan, out).unwrap().to_f32().unwrap()
}

#[test]
fn drawing_onto_an_imported_target_keeps_what_nothing_drew_over() {
    let Some(gpu) = test_gpu() else { return };
    // Draws 9.0 on the right half (x >= 8); the left half is discarded.
    let got = draw_onto_import(&gpu, None, &params(9.0, 0.5, 8.0));
    for y in 0..H {
        for x in 0..W {
            let want = if x >= 8 { 9.0 } else { user_pattern(x, y) };
            assert_eq!(got[(y * W + x) as usize], want, "({x}, {y})");
        }
    }
    assert!(gpu.take_errors().is_empty());
}

#[test]
fn an_explicit_clear_value_clears_an_imported_target() {
    let Some(gpu) = test_gpu() else { return };
    let got = draw_onto_import(
        &gpu,
        Some(ColorTarget::clear([0.75, 0.0, 0.0, 1.0])),
        &params(9.0, 0.5, 8.0),
    );
    for (i, v) in got.iter().enumerate() {
        let x = i as u32 % W;
        assert_eq!(*v, if x >= 8 { 9.0 } else { 0.75 }, "pixel {i}");
    }
}

#[test]
fn blend_state_on_a_fullscreen_pass_adds_onto_the_target() {
    let Some(gpu) = test_gpu() else { return };
    let additive = wgpu::BlendState {
        color: wgpu::BlendComponent {
            src_factor: wgpu::BlendFactor::One,
            dst_factor: wgpu::BlendFactor::One,
            operation: wgpu::BlendOperation::Add,
        },
        alpha: wgpu::BlendComponent::OVER,
    };
    let got = draw_onto_import(
        &gpu,
        Some(ColorTarget::load().blend(additive)),
        &params(0.5, 0.5, 0.0),
    );
    for y in 0..H {
        for x in 0..W {
            assert_eq!(
                got[(y * W + x) as usize],
                user_pattern(x, y) + 0.5,
                "({x}, {y})"
            );
        }
    }
}

/// `passes` full-screen draws into one colour texture (cleared to 0) sharing a depth buffer:
/// each draws `value` at depth `z` with its depth use. Returns the colour read back.
fn depth_sequence(
    gpu: &Arc<GpuContext>,
    first: DepthTarget,
    passes: &[(f32, f32, bool, wgpu::CompareFunction)],
) -> Vec<f32> {
    let mut b = GraphBuilder::new();
    let mut color = b.create_texture("color", r32());
    let mut depth = b.create_texture("depth", TextureDesc::new(Depth32Float, SizeClass::FULL));
    for (i, &(value, z, read_only, compare)) in passes.iter().enumerate() {
        let mut p = b.fullscreen_pass(&format!("draw{i}"), "draw.wgsl", "vs", "fs");
        p.uniform("params", &params(value, z, 0.0));
        color = p.color_attachment(color);
        if i == 0 {
            depth = p.depth_target(depth, first);
        } else if read_only {
            p.depth_read_with(depth, compare);
        } else {
            depth = p.depth_target(
                depth,
                DepthTarget {
                    load: None,
                    compare,
                },
            );
        }
    }
    b.export(color);
    let plan = Arc::new(compile(b.build(), &shaders(), CompileOptions::default()).unwrap());
    let mut exec = Executor::new(gpu.clone());
    exec.execute(&plan, Extent::new(W, H)).unwrap();
    assert!(gpu.take_errors().is_empty());
    exec.read_texture(&plan, color).unwrap().to_f32().unwrap()
}

#[test]
fn reversed_z_depth_clears_to_zero() {
    let Some(gpu) = test_gpu() else { return };
    use wgpu::CompareFunction::GreaterEqual;
    // Reversed Z: the clear is 0 (far), so a draw at z = 0.25 passes GreaterEqual.
    let got = depth_sequence(
        &gpu,
        DepthTarget::reversed_z(),
        &[(1.0, 0.25, false, GreaterEqual)],
    );
    assert!(got.iter().all(|&v| v == 1.0), "{:?}", &got[..4]);
    // Cleared to 1 (the standard far value) the same test fails everywhere.
    let standard_clear = DepthTarget {
        load: None,
        compare: GreaterEqual,
    }
    .clear(1.0);
    let got = depth_sequence(&gpu, standard_clear, &[(1.0, 0.25, false, GreaterEqual)]);
    assert!(got.iter().all(|&v| v == 0.0), "{:?}", &got[..4]);
    // The builder resolves the automatic clear of a reversed-Z target to 0.0.
    let mut b = GraphBuilder::new();
    let d = b.create_texture("d", TextureDesc::new(Depth32Float, SizeClass::FULL));
    b.fullscreen_pass("p", "draw.wgsl", "vs", "fs")
        .depth_target(d, DepthTarget::reversed_z());
    let decl = b.build();
    assert_eq!(
        decl.passes[0].textures[0].attachment,
        Some(AttachmentOps::Depth {
            load: LoadOp::Clear(0.0),
            compare: GreaterEqual,
            read_only: false,
        })
    );
}

#[test]
fn a_read_only_depth_attachment_is_tested_but_not_written() {
    let Some(gpu) = test_gpu() else { return };
    use wgpu::CompareFunction::LessEqual;
    // Pass 0 writes depth 0.5. Pass 1 (read-only) draws at 0.3: passes, and must not write 0.3.
    // Pass 2 (read-only) draws at 0.4: passes only if the depth is still 0.5.
    let got = depth_sequence(
        &gpu,
        DepthTarget::standard(),
        &[
            (1.0, 0.5, false, LessEqual),
            (2.0, 0.3, true, LessEqual),
            (3.0, 0.4, true, LessEqual),
        ],
    );
    assert!(got.iter().all(|&v| v == 3.0), "{:?}", &got[..4]);
    // The same with pass 1 writing depth: pass 2 fails and pass 1's value stays.
    let got = depth_sequence(
        &gpu,
        DepthTarget::standard(),
        &[
            (1.0, 0.5, false, LessEqual),
            (2.0, 0.3, false, LessEqual),
            (3.0, 0.4, true, LessEqual),
        ],
    );
    assert!(got.iter().all(|&v| v == 2.0), "{:?}", &got[..4]);
}

#[test]
fn a_read_only_depth_attachment_can_be_sampled_in_the_same_pass() {
    let Some(gpu) = test_gpu() else { return };
    let mut b = GraphBuilder::new();
    let color = b.create_texture("color", r32());
    let depth = b.create_texture("depth", TextureDesc::new(Depth32Float, SizeClass::FULL));
    let mut p = b.fullscreen_pass("write depth", "draw.wgsl", "vs", "fs");
    p.uniform("params", &params(1.0, 0.5, 0.0));
    let color = p.color_attachment(color);
    let depth = p.depth_attachment(depth);
    let mut q = b.fullscreen_pass("test and sample", "sample_depth.wgsl", "vs", "fs");
    q.depth_read(depth).sample("depth", depth);
    let color = q.color_attachment(color);
    b.export(color);
    let plan = Arc::new(compile(b.build(), &shaders(), CompileOptions::default()).unwrap());
    let mut exec = Executor::new(gpu.clone());
    exec.execute(&plan, Extent::new(W, H)).unwrap();
    let got = exec.read_texture(&plan, color).unwrap().to_f32().unwrap();
    assert!(got.iter().all(|&v| v == 0.5), "{:?}", &got[..4]);
    assert!(gpu.take_errors().is_empty());
}

#[test]
fn an_imported_texture_missing_a_needed_usage_is_a_named_error() {
    let Some(gpu) = test_gpu() else { return };
    let mut b = GraphBuilder::new();
    let target = b.import_texture("user.target", r32());
    let mut p = b.fullscreen_pass("overlay", "draw.wgsl", "vs", "fs");
    p.uniform("params", &params(1.0, 0.5, 0.0));
    let out = p.color_attachment(target);
    b.export(out);
    let plan = Arc::new(compile(b.build(), &shaders(), CompileOptions::default()).unwrap());
    let mut exec = Executor::new(gpu.clone());
    // Created for sampling only: cannot be a render target.
    let usage = wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST;
    exec.import_texture("user.target", user_texture(&gpu, usage, user_pattern));
    let err = exec.execute(&plan, Extent::new(W, H)).unwrap_err();
    match &err {
        GraphError::ImportUsage {
            resource, missing, ..
        } => {
            assert_eq!(resource, "user.target");
            assert!(missing.contains("RENDER_ATTACHMENT"), "{missing}");
        }
        other => panic!("expected ImportUsage, got {other:?}"),
    }
    assert!(
        err.to_string().contains("add it to the texture's usage"),
        "{err}"
    );
    assert!(gpu.take_errors().is_empty(), "caught before wgpu saw it");
}

#[test]
fn two_imports_with_one_name_are_a_named_error() {
    let mut b = GraphBuilder::new();
    let a = b.import_texture("gbuffer.depth", r32());
    let c = b.import_texture("gbuffer.depth", r32());
    let t = b.create_texture("t", r32());
    let mut p = b.custom_pass("p", NoopPass);
    p.read_texture(TextureAccess::Sampled, a)
        .read_texture(TextureAccess::Sampled, c);
    let t = p.write_texture(TextureAccess::StorageWrite, t);
    b.export(t);
    let err = compile(b.build(), &shaders(), CompileOptions::default()).unwrap_err();
    assert_eq!(
        err,
        GraphError::DuplicateName {
            kind: "import".into(),
            name: "gbuffer.depth".into()
        }
    );
}

#[test]
fn two_histories_with_one_name_are_a_named_error() {
    let mut b = GraphBuilder::new();
    for i in 0..2 {
        let h = b.history_texture("ao.history", r32());
        let mut p = b.custom_pass(&format!("p{i}"), NoopPass);
        p.read_texture(TextureAccess::Sampled, h.previous);
        p.write_texture(TextureAccess::StorageWrite, h.current);
    }
    let err = compile(b.build(), &shaders(), CompileOptions::default()).unwrap_err();
    assert_eq!(
        err,
        GraphError::DuplicateName {
            kind: "history".into(),
            name: "ao.history".into()
        }
    );
    assert!(err.to_string().contains("give each its own name"));
}

#[test]
fn attachment_loads_follow_the_rule_unless_chosen() {
    let mut b = GraphBuilder::new();
    let imported = b.import_texture("user", r32());
    let owned = b.create_texture("owned", r32());
    let d = b.create_texture("d", TextureDesc::new(Depth32Float, SizeClass::FULL));
    let mut p = b.fullscreen_pass("first", "draw.wgsl", "vs", "fs");
    let imported = p.color_attachment(imported);
    let owned = p.color_attachment(owned);
    let d = p.depth_attachment(d);
    let mut q = b.fullscreen_pass("second", "draw.wgsl", "vs", "fs");
    q.color_attachment(owned);
    q.color_target(imported, ColorTarget::clear([0.5, 0.0, 0.0, 0.0]));
    q.depth_read(d);
    let decl = b.build();
    let ops: Vec<_> = decl
        .passes
        .iter()
        .flat_map(|p| p.textures.iter().map(|u| u.attachment))
        .collect();
    use wgpu::CompareFunction::LessEqual;
    assert_eq!(
        ops,
        [
            // imported: loads; graph-owned: clears to 0; depth: clears to far (1.0)
            Some(AttachmentOps::Color {
                load: LoadOp::Load,
                blend: None
            }),
            Some(AttachmentOps::Color {
                load: LoadOp::Clear([0.0; 4]),
                blend: None
            }),
            Some(AttachmentOps::Depth {
                load: LoadOp::Clear(1.0),
                compare: LessEqual,
                read_only: false
            }),
            // later versions load; an explicit clear wins; read-only depth loads
            Some(AttachmentOps::Color {
                load: LoadOp::Load,
                blend: None
            }),
            Some(AttachmentOps::Color {
                load: LoadOp::Clear([0.5, 0.0, 0.0, 0.0]),
                blend: None
            }),
            Some(AttachmentOps::Depth {
                load: LoadOp::Load,
                compare: LessEqual,
                read_only: true
            }),
        ]
    );
    // A clear is not a read: the second pass does not depend on the first through `imported`.
    assert!(decl.passes[1].textures[1].read.is_none());
    assert!(decl.passes[1].textures[0].read.is_some());
}
