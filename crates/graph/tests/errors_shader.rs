//! Errors found by checking a pass's uses against its shader's reflected bindings.

use aograph_graph::wgpu::TextureFormat;
use aograph_graph::*;

const FILTER: &str = "struct Params { strength: f32, pad: vec3<f32> }\n\
@group(0) @binding(0) var src: texture_2d<f32>;\n\
@group(0) @binding(1) var dst: texture_storage_2d<r32float, write>;\n\
@group(0) @binding(2) var<uniform> params: Params;\n\
@group(0) @binding(3) var linear_clamp: sampler;\n\
@compute @workgroup_size(8, 8, 1)\n\
fn main(@builtin(global_invocation_id) id: vec3<u32>) {\n\
    let uv = (vec2<f32>(id.xy) + 0.5) / vec2<f32>(textureDimensions(dst));\n\
    let v = textureSampleLevel(src, linear_clamp, uv, 0.0).x * params.strength;\n\
    textureStore(dst, vec2<i32>(id.xy), vec4<f32>(v));\n\
}\n";

const INPLACE: &str = "@group(0) @binding(0) var img: texture_storage_2d<r32float, read_write>;\n\
@compute @workgroup_size(8, 8, 1)\n\
fn main(@builtin(global_invocation_id) id: vec3<u32>) {\n\
    let p = vec2<i32>(id.xy);\n\
    textureStore(img, p, textureLoad(img, p) * 0.5);\n\
}\n";

fn library() -> ShaderLibrary {
    let lib = ShaderLibrary::inline_only();
    lib.add_inline("filter.wgsl", FILTER);
    lib.add_inline("inplace.wgsl", INPLACE);
    lib.add_inline(
        "bad.wgsl",
        "@compute @workgroup_size(1)\nfn main() {\n    let x = ;\n}\n",
    );
    lib
}

fn r32() -> TextureDesc {
    TextureDesc::new(TextureFormat::R32Float, SizeClass::FULL)
}

/// An imported input, an output of `out_desc`, and a "filter" compute pass set up by `f`.
fn filter_graph(
    out_desc: TextureDesc,
    f: impl FnOnce(&mut PassBuilder<'_>, TextureHandle, TextureHandle) -> TextureHandle,
) -> GraphBuilder {
    let mut b = GraphBuilder::new();
    let src = b.import_texture("input", r32());
    let dst = b.create_texture("filtered", out_desc);
    let out = {
        let mut p = b.compute_pass("filter", "filter.wgsl", "main");
        p.sampler("linear_clamp", SamplerDesc::LINEAR_CLAMP);
        f(&mut p, src, dst)
    };
    b.export(out);
    b
}

fn params() -> Vec<u8> {
    vec![0; 32]
}

fn compile_result(b: GraphBuilder) -> GraphResult<CompiledGraph> {
    compile(b.build(), &library(), CompileOptions::default())
}

fn invalid_pass(b: GraphBuilder) -> (String, String) {
    match compile_result(b) {
        Err(GraphError::InvalidPass { pass, message }) => (pass, message),
        Err(other) => panic!("expected InvalidPass, got {other:?}"),
        Ok(plan) => panic!("expected InvalidPass, compiled {:?}", plan.pass_names()),
    }
}

#[test]
fn fully_supplied_compute_pass_compiles() {
    let b = filter_graph(r32(), |p, src, dst| {
        p.sample("src", src);
        p.uniform("params", &params());
        let out = p.write_storage("dst", dst);
        p.dispatch_over(out);
        out
    });
    let plan = compile_result(b).expect("compiles");
    assert_eq!(plan.pass_names(), vec!["filter"]);
    assert_eq!(
        plan.shaders[0]
            .as_ref()
            .unwrap()
            .entry("main")
            .unwrap()
            .workgroup_size,
        [8, 8, 1]
    );
}

#[test]
fn compute_pass_without_dispatch_is_invalid() {
    let b = filter_graph(r32(), |p, src, dst| {
        p.sample("src", src);
        p.uniform("params", &params());
        p.write_storage("dst", dst)
    });
    let (pass, message) = invalid_pass(b);
    assert_eq!(pass, "filter");
    assert!(message.contains("dispatch"), "{message}");
}

#[test]
fn shader_binding_not_supplied_names_the_binding() {
    let b = filter_graph(r32(), |p, _src, dst| {
        p.uniform("params", &params());
        let out = p.write_storage("dst", dst);
        p.dispatch_over(out);
        out
    });
    let (pass, message) = invalid_pass(b);
    assert_eq!(pass, "filter");
    assert!(
        message.contains("`src`") && message.contains("filter.wgsl"),
        "{message}"
    );
    assert!(message.contains("supplies nothing"), "{message}");
}

#[test]
fn uniform_not_supplied_names_the_binding() {
    let b = filter_graph(r32(), |p, src, dst| {
        p.sample("src", src);
        let out = p.write_storage("dst", dst);
        p.dispatch_over(out);
        out
    });
    let (_, message) = invalid_pass(b);
    assert!(message.contains("`params`"), "{message}");
}

#[test]
fn named_binding_missing_from_shader_lists_what_the_shader_has() {
    let b = filter_graph(r32(), |p, src, dst| {
        p.sample("src", src).sample("extra_input", src);
        p.uniform("params", &params());
        let out = p.write_storage("dst", dst);
        p.dispatch_over(out);
        out
    });
    let (pass, message) = invalid_pass(b);
    assert_eq!(pass, "filter");
    assert_eq!(
        message,
        "shader `filter.wgsl` has no binding `extra_input`; it has: src, dst, params, linear_clamp"
    );
}

#[test]
fn misnamed_uniform_is_reported() {
    let b = filter_graph(r32(), |p, src, dst| {
        p.sample("src", src);
        p.uniform("params", &params());
        p.uniform("paramz", &params());
        let out = p.write_storage("dst", dst);
        p.dispatch_over(out);
        out
    });
    let (_, message) = invalid_pass(b);
    assert!(message.contains("no binding `paramz`"), "{message}");
}

#[test]
fn storage_format_differing_from_shader_is_a_format_mismatch() {
    let b = filter_graph(
        TextureDesc::new(TextureFormat::Rgba16Float, SizeClass::FULL),
        |p, src, dst| {
            p.sample("src", src);
            p.uniform("params", &params());
            let out = p.write_storage("dst", dst);
            p.dispatch_over(out);
            out
        },
    );
    let e = compile_result(b).unwrap_err();
    match &e {
        GraphError::FormatMismatch {
            pass,
            resource,
            expected,
            found,
        } => {
            assert_eq!(pass, "filter");
            assert_eq!(resource, "filtered");
            assert!(
                expected.contains("R32Float") && expected.contains("`dst`"),
                "{expected}"
            );
            assert_eq!(*found, TextureFormat::Rgba16Float);
        }
        other => panic!("expected FormatMismatch, got {other:?}"),
    }
    assert!(e.to_string().contains("`filter`") && e.to_string().contains("`filtered`"));
}

#[test]
fn storage_access_differing_from_shader_is_invalid() {
    // The shader's `img` is read_write; declaring a write-only use is a mistake.
    let mut b = GraphBuilder::new();
    let t = b.create_texture("img", r32());
    let t1 = b.custom_pass("init", NoopPass).write_storage("dst", t);
    let t2 = {
        let mut p = b.compute_pass("halve", "inplace.wgsl", "main");
        let h = p.write_storage("img", t1);
        p.dispatch_over(h);
        h
    };
    b.export(t2);
    let (pass, message) = invalid_pass(b);
    assert_eq!(pass, "halve");
    assert!(
        message.contains("`img`")
            && message.contains("ReadWrite")
            && message.contains("StorageWrite"),
        "{message}"
    );
}

#[test]
fn in_place_storage_use_matches_read_write_shader() {
    let mut b = GraphBuilder::new();
    let t = b.create_texture("img", r32());
    let t1 = b.custom_pass("init", NoopPass).write_storage("dst", t);
    let t2 = {
        let mut p = b.compute_pass("halve", "inplace.wgsl", "main");
        let h = p.read_write_storage("img", t1);
        p.dispatch_workgroups(4, 4, 1);
        h
    };
    b.export(t2);
    let plan = compile_result(b).expect("compiles");
    assert_eq!(plan.pass_names(), vec!["init", "halve"]);
}

#[test]
fn sampled_binding_supplied_as_storage_is_invalid() {
    let b = filter_graph(r32(), |p, src, dst| {
        p.read_storage("src", src);
        p.uniform("params", &params());
        let out = p.write_storage("dst", dst);
        p.dispatch_over(out);
        out
    });
    let (_, message) = invalid_pass(b);
    assert!(
        message.contains("`src` is a sampled texture") && message.contains("StorageRead"),
        "{message}"
    );
}

#[test]
fn uniform_smaller_than_shader_type_is_invalid() {
    let b = filter_graph(r32(), |p, src, dst| {
        p.sample("src", src);
        p.uniform("params", &[0; 8]);
        let out = p.write_storage("dst", dst);
        p.dispatch_over(out);
        out
    });
    let (_, message) = invalid_pass(b);
    assert!(
        message.contains("uniform `params` has 8 bytes") && message.contains("32"),
        "{message}"
    );
}

#[test]
fn missing_entry_point_lists_the_shader_entries() {
    let mut b = GraphBuilder::new();
    let t = b.create_texture("img", r32());
    let t1 = b.custom_pass("init", NoopPass).write_storage("dst", t);
    let t2 = {
        let mut p = b.compute_pass("halve", "inplace.wgsl", "mian");
        let h = p.read_write_storage("img", t1);
        p.dispatch_workgroups(1, 1, 1);
        h
    };
    b.export(t2);
    let (pass, message) = invalid_pass(b);
    assert_eq!(pass, "halve");
    assert!(
        message.contains("`mian`") && message.contains("main (Compute)"),
        "{message}"
    );
}

#[test]
fn fullscreen_pass_with_compute_entry_is_invalid() {
    let mut b = GraphBuilder::new();
    let t = b.create_texture(
        "out",
        TextureDesc::new(TextureFormat::Rgba8Unorm, SizeClass::FULL),
    );
    let t1 = b
        .fullscreen_pass("show", "inplace.wgsl", "main", "main")
        .color_attachment(t);
    b.export(t1);
    let (pass, message) = invalid_pass(b);
    assert_eq!(pass, "show");
    assert!(message.contains("Vertex"), "{message}");
}

#[test]
fn syntax_error_in_a_pass_shader_fails_compile_with_file_and_line() {
    let mut b = GraphBuilder::new();
    let t = b.create_texture("out", r32());
    let t1 = {
        let mut p = b.compute_pass("broken", "bad.wgsl", "main");
        let h = p.write_storage("dst", t);
        p.dispatch_workgroups(1, 1, 1);
        h
    };
    b.export(t1);
    let e = compile_result(b).unwrap_err();
    assert!(
        matches!(&e, GraphError::Shader { file, line: 3, .. } if file == "bad.wgsl"),
        "{e:?}"
    );
}

#[test]
fn missing_shader_file_fails_compile() {
    let mut b = GraphBuilder::new();
    let t = b.create_texture("out", r32());
    let t1 = {
        let mut p = b.compute_pass("ghost", "ghost.wgsl", "main");
        let h = p.write_storage("dst", t);
        p.dispatch_workgroups(1, 1, 1);
        h
    };
    b.export(t1);
    assert!(
        matches!(compile_result(b), Err(GraphError::ShaderFile { file, .. }) if file == "ghost.wgsl")
    );
}

#[test]
fn shader_sampler_without_a_declaration_names_the_pass_binding_and_call() {
    let mut b = GraphBuilder::new();
    let src = b.import_texture("input", r32());
    let dst = b.create_texture("filtered", r32());
    let out = {
        let mut p = b.compute_pass("filter", "filter.wgsl", "main");
        p.sample("src", src);
        p.uniform("params", &params());
        let out = p.write_storage("dst", dst);
        p.dispatch_over(out);
        out
    };
    b.export(out);
    let e = compile_result(b).unwrap_err();
    match &e {
        GraphError::Sampler {
            pass,
            binding,
            message,
        } => {
            assert_eq!(
                (pass.as_str(), binding.as_str()),
                ("filter", "linear_clamp")
            );
            assert!(
                message.contains("filter.wgsl")
                    && message.contains("PassBuilder::sampler(\"linear_clamp\""),
                "{message}"
            );
        }
        other => panic!("expected a Sampler error, got {other:?}"),
    }
    assert!(
        e.to_string()
            .starts_with("pass `filter`, sampler `linear_clamp`:"),
        "{e}"
    );
}

#[test]
fn sampler_declaration_naming_no_sampler_binding_is_an_error() {
    for name in ["linear_clmap", "src"] {
        let b = filter_graph(r32(), |p, src, dst| {
            p.sample("src", src);
            p.uniform("params", &params());
            p.sampler(name, SamplerDesc::NEAREST_CLAMP);
            let out = p.write_storage("dst", dst);
            p.dispatch_over(out);
            out
        });
        match compile_result(b) {
            Err(GraphError::Sampler {
                pass,
                binding,
                message,
            }) => {
                assert_eq!((pass.as_str(), binding.as_str()), ("filter", name));
                assert!(
                    message.contains("no sampler binding") && message.contains("linear_clamp"),
                    "{message}"
                );
            }
            other => panic!("{name}: expected a Sampler error, got {other:?}"),
        }
    }
}

#[test]
fn sampler_declared_on_a_pass_without_a_shader_is_an_error() {
    let mut b = GraphBuilder::new();
    let t = b.create_texture("img", r32());
    let t = {
        let mut p = b.custom_pass("draw", NoopPass);
        p.sampler("s", SamplerDesc::LINEAR_CLAMP);
        p.write_storage("dst", t)
    };
    b.export(t);
    assert!(
        matches!(compile_result(b), Err(GraphError::Sampler { pass, binding, .. }) if pass == "draw" && binding == "s")
    );
}

#[test]
fn a_declared_sampler_decides_the_layout_filtering() {
    // Filtering follows the declaration, not the WGSL name: `linear_clamp` declared nearest.
    let b = filter_graph(r32(), |p, src, dst| {
        p.sample("src", src);
        p.uniform("params", &params());
        p.sampler("linear_clamp", SamplerDesc::NEAREST_CLAMP);
        let out = p.write_storage("dst", dst);
        p.dispatch_over(out);
        out
    });
    let plan = compile_result(b).expect("compiles");
    assert_eq!(plan.samplers, vec![SamplerDesc::NEAREST_CLAMP]);
    assert_eq!(
        SamplerDesc::NEAREST_CLAMP.binding_type(),
        wgpu::SamplerBindingType::NonFiltering
    );
    assert_eq!(
        SamplerDesc::LINEAR_CLAMP.binding_type(),
        wgpu::SamplerBindingType::Filtering
    );
}
