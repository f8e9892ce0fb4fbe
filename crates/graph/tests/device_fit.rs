//! Plans checked against a device's limits and formats at compile (no GPU): WebGPU's default
//! profile refuses, by pass and limit, a pass with one storage texture too many, too much
//! workgroup memory, an r8unorm storage write or a ray query, and accepts the same passes
//! within the limits. The counts asserted are the shaders' own (known answers).

use aograph_graph::wgpu::TextureFormat;
use aograph_graph::*;

/// A compute pass writing `n` r32float storage textures, with `tile` f32s of workgroup memory
/// (0: none), and `format` for the first storage texture.
fn storage_shader(n: usize, tile: usize, format: &str) -> String {
    let mut s = String::new();
    for i in 0..n {
        let f = if i == 0 { format } else { "r32float" };
        s += &format!("@group(0) @binding({i}) var out{i}: texture_storage_2d<{f}, write>;\n");
    }
    if tile > 0 {
        s += &format!("var<workgroup> tile: array<f32, {tile}>;\n");
    }
    s +=
        "@compute @workgroup_size(8, 8)\nfn main(@builtin(global_invocation_id) id: vec3<u32>) {\n";
    if tile > 0 {
        s += "    tile[0] = 1.0;\n";
    }
    for i in 0..n {
        s += &format!("    textureStore(out{i}, vec2<i32>(id.xy), vec4<f32>(1.0));\n");
    }
    s += "}\n";
    s
}

/// The plan of one pass "many" running `source`, every storage texture exported.
fn compile_for(
    device: DeviceProfile,
    source: &str,
    n: usize,
    first: TextureFormat,
) -> GraphResult<()> {
    let lib = ShaderLibrary::inline_only();
    lib.add_inline("many.wgsl", source);
    let mut b = GraphBuilder::new();
    let textures: Vec<TextureHandle> = (0..n)
        .map(|i| {
            let format = if i == 0 {
                first
            } else {
                TextureFormat::R32Float
            };
            b.create_texture(&format!("t{i}"), TextureDesc::new(format, SizeClass::FULL))
        })
        .collect();
    let mut outs = Vec::new();
    {
        let mut p = b.compute_pass("many", "many.wgsl", "main");
        for (i, t) in textures.into_iter().enumerate() {
            outs.push(p.write_storage(&format!("out{i}"), t));
        }
        p.dispatch_over(outs[0]);
    }
    for o in outs {
        b.export(o);
    }
    GraphCompiler::for_device(device)
        .compile(b.build(), &lib, CompileOptions::default())
        .map(|_| ())
}

/// `err` is `OverDeviceLimit` for `pass` and `limit`, needing `needs` where `allows` are allowed.
fn assert_over(err: &GraphError, pass: &str, limit: &str, needs: u64, allows: u64) {
    match err {
        GraphError::OverDeviceLimit {
            pass: p,
            limit: l,
            needs: n,
            allows: a,
            ..
        } => assert_eq!(
            (p.as_str(), l.as_str(), *n, *a),
            (pass, limit, needs, allows)
        ),
        other => panic!("expected OverDeviceLimit, got {other:?}"),
    }
}

/// `err` is `DeviceLacks` for `pass`, naming something that starts with `what`.
fn assert_lacks(err: &GraphError, pass: &str, what: &str) {
    match err {
        GraphError::DeviceLacks {
            pass: p, what: w, ..
        } => {
            assert_eq!(p, pass);
            assert!(w.starts_with(what), "{w}");
        }
        other => panic!("expected DeviceLacks, got {other:?}"),
    }
}

#[test]
fn four_storage_textures_fit_webgpu_defaults_and_five_are_refused_by_name() {
    let fits = compile_for(
        DeviceProfile::webgpu_defaults(),
        &storage_shader(4, 0, "r32float"),
        4,
        TextureFormat::R32Float,
    );
    assert!(fits.is_ok(), "{fits:?}");
    let over = compile_for(
        DeviceProfile::webgpu_defaults(),
        &storage_shader(5, 0, "r32float"),
        5,
        TextureFormat::R32Float,
    )
    .unwrap_err();
    assert_over(&over, "many", "max_storage_textures_per_shader_stage", 5, 4);
    let text = over.to_string();
    assert!(
        text.contains("needs 5 storage textures in its compute stage") && text.contains("allows 4"),
        "{text}"
    );
}

#[test]
fn a_higher_limit_on_the_device_admits_the_fifth_storage_texture() {
    let mut limits = wgpu::Limits::defaults();
    limits.max_storage_textures_per_shader_stage = 8;
    let device = DeviceProfile::from_parts(
        "a device with 8 storage textures".into(),
        limits,
        wgpu::Features::empty(),
        |f| f.guaranteed_format_features(wgpu::Features::empty()),
    );
    let fits = compile_for(
        device,
        &storage_shader(5, 0, "r32float"),
        5,
        TextureFormat::R32Float,
    );
    assert!(fits.is_ok(), "{fits:?}");
}

#[test]
fn workgroup_memory_over_16_kib_is_refused_with_its_byte_count() {
    // 4096 f32s = 16384 bytes, WebGPU's default exactly; one more f32 rounds up to 16400.
    let at = compile_for(
        DeviceProfile::webgpu_defaults(),
        &storage_shader(1, 4096, "r32float"),
        1,
        TextureFormat::R32Float,
    );
    assert!(at.is_ok(), "{at:?}");
    let over = compile_for(
        DeviceProfile::webgpu_defaults(),
        &storage_shader(1, 4097, "r32float"),
        1,
        TextureFormat::R32Float,
    )
    .unwrap_err();
    assert_over(
        &over,
        "many",
        "max_compute_workgroup_storage_size",
        16400,
        16384,
    );
}

#[test]
fn r8unorm_storage_writes_are_not_core_webgpu() {
    let err = compile_for(
        DeviceProfile::webgpu_defaults(),
        &storage_shader(1, 0, "r8unorm"),
        1,
        TextureFormat::R8Unorm,
    )
    .unwrap_err();
    assert_lacks(
        &err,
        "many",
        "R8Unorm storage textures with WriteOnly access",
    );
}

/// A custom pass (no shader: a raster the application records) writing one colour target of
/// each format.
fn raster_with_targets(formats: &[TextureFormat]) -> GraphResult<()> {
    let lib = ShaderLibrary::inline_only();
    let mut b = GraphBuilder::new();
    let targets: Vec<TextureHandle> = formats
        .iter()
        .enumerate()
        .map(|(i, f)| {
            b.create_texture(&format!("target{i}"), TextureDesc::new(*f, SizeClass::FULL))
        })
        .collect();
    let mut outs = Vec::new();
    {
        let mut p = b.custom_pass("raster", NoopPass);
        for t in targets {
            outs.push(p.color_attachment(t));
        }
    }
    for o in outs {
        b.export(o);
    }
    GraphCompiler::for_device(DeviceProfile::webgpu_defaults())
        .compile(b.build(), &lib, CompileOptions::default())
        .map(|_| ())
}

#[test]
fn colour_bytes_per_sample_follow_webgpus_alignment_rule_for_custom_passes_too() {
    use TextureFormat as F;
    // WebGPU's count: R8Unorm 1; R32Float aligned to 4 -> 4 + 4 = 8; Rgba32Float -> 24;
    // Rgba16Float (align 2) -> 32. A plain sum is 29: one more R8Unorm (30 summed) is 33 by the
    // rule, over the default 32.
    let at_limit = [F::R8Unorm, F::R32Float, F::Rgba32Float, F::Rgba16Float];
    assert!(raster_with_targets(&at_limit).is_ok());
    let mut over = at_limit.to_vec();
    over.push(F::R8Unorm);
    let err = raster_with_targets(&over).unwrap_err();
    assert_over(
        &err,
        "raster",
        "max_color_attachment_bytes_per_sample",
        33,
        32,
    );
}

const RAY_QUERY: &str = "enable wgpu_ray_query;
@group(0) @binding(0) var scene: acceleration_structure;
@group(0) @binding(1) var dst: texture_storage_2d<r32float, write>;
@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    var rq: ray_query;
    rayQueryInitialize(&rq, scene, RayDesc(0u, 0xffu, 0.0, 1.0, vec3<f32>(0.0), vec3<f32>(0.0, 0.0, 1.0)));
    rayQueryProceed(&rq);
    let hit = rayQueryGetCommittedIntersection(&rq);
    textureStore(dst, vec2<i32>(id.xy), vec4<f32>(f32(hit.kind)));
}
";

fn ray_query_plan(device: DeviceProfile) -> GraphResult<()> {
    let lib = ShaderLibrary::inline_only();
    lib.add_inline("rq.wgsl", RAY_QUERY);
    let mut b = GraphBuilder::new();
    let tlas = b.import_acceleration_structure("scene.tlas");
    let out = b.create_texture(
        "out",
        TextureDesc::new(TextureFormat::R32Float, SizeClass::FULL),
    );
    let out = {
        let mut p = b.compute_pass("trace", "rq.wgsl", "main");
        p.read_acceleration_structure("scene", tlas);
        let out = p.write_storage("dst", out);
        p.dispatch_over(out);
        out
    };
    b.export(out);
    GraphCompiler::for_device(device)
        .compile(b.build(), &lib, CompileOptions::default())
        .map(|_| ())
}

#[test]
fn a_ray_query_needs_the_feature_and_is_named_without_it() {
    let err = ray_query_plan(DeviceProfile::webgpu_defaults()).unwrap_err();
    assert_lacks(&err, "trace", "ray queries (`scene`");
    let with_rq = DeviceProfile::from_parts(
        "a device with ray queries".into(),
        wgpu::Limits::defaults(),
        wgpu::Features::EXPERIMENTAL_RAY_QUERY,
        |f| f.guaranteed_format_features(wgpu::Features::empty()),
    );
    let fits = ray_query_plan(with_rq);
    assert!(fits.is_ok(), "{fits:?}");
}

#[test]
fn sixteen_bit_norm_storage_is_not_core_webgpu() {
    let err = compile_for(
        DeviceProfile::webgpu_defaults(),
        &storage_shader(1, 0, "r16unorm"),
        1,
        TextureFormat::R16Unorm,
    )
    .unwrap_err();
    assert_lacks(&err, "many", "R16Unorm storage textures");
}
