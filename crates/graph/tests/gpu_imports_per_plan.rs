//! GPU tests of imports bound per plan: two plans that import a texture under the same name
//! each read the texture bound to their own handle (`Executor::bind_import_texture`), a plan's
//! own binding wins over one made by name for every plan, and a handle that is no import of
//! the plan is refused with a message. Skips (saying so) only when no adapter exists and
//! AOGRAPH_REQUIRE_GPU is unset.

use std::sync::Arc;

use aograph_graph::wgpu::TextureFormat;
use aograph_graph::*;

/// dst = src + offset, texel by texel.
const ADD: &str = "struct Params { offset: f32, pad0: f32, pad1: f32, pad2: f32 }
@group(0) @binding(0) var src: texture_2d<f32>;
@group(0) @binding(1) var<uniform> params: Params;
@group(0) @binding(2) var dst: texture_storage_2d<r32float, write>;
@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(dst);
    if (id.x >= size.x || id.y >= size.y) { return; }
    let v = textureLoad(src, vec2<i32>(id.xy), 0).r + params.offset;
    textureStore(dst, vec2<i32>(id.xy), vec4<f32>(v, 0.0, 0.0, 0.0));
}
";

const SIDE: u32 = 5;

/// A plan importing `input` and writing input + `offset` (plans with different offsets have
/// different structures, so the executor keeps them apart).
fn plan(offset: f32) -> (Arc<CompiledGraph>, TextureHandle, TextureHandle) {
    let shaders = ShaderLibrary::inline_only();
    shaders.add_inline("add.wgsl", ADD);
    let mut b = GraphBuilder::new();
    let desc = TextureDesc::new(TextureFormat::R32Float, SizeClass::FULL);
    let input = b.import_texture("input", desc);
    let out = b.create_texture("out", desc);
    let mut p = b.compute_pass(&format!("add{offset}"), "add.wgsl", "main");
    p.sample("src", input);
    let params: Vec<u8> = [offset, 0.0, 0.0, 0.0]
        .iter()
        .flat_map(|f| f.to_le_bytes())
        .collect();
    p.uniform("params", &params);
    let out = p.write_storage("dst", out);
    p.dispatch_over(out);
    b.export(out);
    let plan = compile(b.build(), &shaders, CompileOptions::default()).expect("compiles");
    (Arc::new(plan), input, out)
}

/// A SIDE x SIDE R32Float texture holding `value` everywhere.
fn filled(gpu: &GpuContext, value: f32) -> wgpu::Texture {
    let size = wgpu::Extent3d {
        width: SIDE,
        height: SIDE,
        depth_or_array_layers: 1,
    };
    let texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some("filled"),
        size,
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: TextureFormat::R32Float,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    let texels: Vec<u8> = (0..SIDE * SIDE).flat_map(|_| value.to_le_bytes()).collect();
    gpu.queue.write_texture(
        texture.as_image_copy(),
        &texels,
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(4 * SIDE),
            rows_per_image: Some(SIDE),
        },
        size,
    );
    texture
}

#[test]
fn two_plans_bind_different_textures_to_imports_of_one_name() {
    let Some(gpu) = test_gpu() else { return };
    let (a, a_in, a_out) = plan(0.5);
    let (b, b_in, b_out) = plan(0.25);
    assert_ne!(a.key(), b.key());
    let mut exec = Executor::new(gpu.clone());
    // By name for every plan; then plan b binds its own.
    exec.import_texture("input", filled(&gpu, 1.0));
    exec.bind_import_texture(&b, b_in, filled(&gpu, 2.0))
        .expect("b's import");
    let size = Extent::new(SIDE, SIDE);
    for _ in 0..2 {
        exec.execute(&a, size).expect("frame of a");
        exec.execute(&b, size).expect("frame of b");
    }
    let read =
        |exec: &Executor, p: &CompiledGraph, h| exec.read_texture(p, h).unwrap().to_f32().unwrap();
    let n = (SIDE * SIDE) as usize;
    assert_eq!(
        read(&exec, &a, a_out),
        vec![1.5; n],
        "a reads the texture imported by name"
    );
    assert_eq!(
        read(&exec, &b, b_out),
        vec![2.25; n],
        "b reads its own binding"
    );
    // Binding a's handle now changes a alone.
    exec.bind_import_texture(&a, a_in, filled(&gpu, 3.0))
        .expect("a's import");
    exec.execute(&a, size).expect("frame of a");
    exec.execute(&b, size).expect("frame of b");
    assert_eq!(read(&exec, &a, a_out), vec![3.5; n]);
    assert_eq!(read(&exec, &b, b_out), vec![2.25; n]);
    assert!(gpu.take_errors().is_empty());
}

#[test]
fn a_handle_that_is_no_import_of_the_plan_is_refused() {
    let Some(gpu) = test_gpu() else { return };
    let (a, _, a_out) = plan(0.5);
    let mut exec = Executor::new(gpu.clone());
    let e = exec
        .bind_import_texture(&a, a_out, filled(&gpu, 1.0))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("out") && e.contains("not an imported texture"),
        "{e}"
    );
    // Nothing bound and nothing imported by name: the frame names what to call.
    let e = exec
        .execute(&a, Extent::new(SIDE, SIDE))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("input") && e.contains("bind_import_texture"),
        "{e}"
    );
}
