//! Compile: the GraphCompiler cache keyed by the declaration's structure hash: a hit carries
//! the new declaration, uniform values are not structure, and the cache is LRU-bounded.

use std::sync::Arc;

use aograph_graph::wgpu::TextureFormat;
use aograph_graph::*;

#[path = "common/test_passes.rs"]
mod test_passes;
use test_passes::KeyedPass;

const BLUR: &str = "struct Params { radius: f32, strength: f32, pad0: f32, pad1: f32 }\n\
@group(0) @binding(0) var src: texture_2d<f32>;\n\
@group(0) @binding(1) var dst: texture_storage_2d<r32float, write>;\n\
@group(0) @binding(2) var<uniform> params: Params;\n\
@compute @workgroup_size(8, 8, 1)\n\
fn main(@builtin(global_invocation_id) id: vec3<u32>) {\n\
    let v = textureLoad(src, vec2<i32>(id.xy), 0).x * params.strength;\n\
    textureStore(dst, vec2<i32>(id.xy), vec4<f32>(v));\n\
}\n";

fn library() -> ShaderLibrary {
    let lib = ShaderLibrary::inline_only();
    lib.add_inline("blur.wgsl", BLUR);
    lib
}

fn r32() -> TextureDesc {
    TextureDesc::new(TextureFormat::R32Float, SizeClass::FULL)
}

/// import -> blur (with a uniform) -> exported output; `extra` adds one more blur.
fn declare(uniform: &[u8], extra: bool) -> GraphDecl {
    let mut b = GraphBuilder::new();
    let src = b.import_texture("src", r32());
    let mut cur = src;
    for i in 0..(1 + extra as usize) {
        let t = b.create_texture(&format!("blurred{i}"), r32());
        let mut p = b.compute_pass(&format!("blur{i}"), "blur.wgsl", "main");
        p.sample("src", cur);
        p.uniform("params", uniform);
        let out = p.write_storage("dst", t);
        p.dispatch_over(out);
        cur = out;
    }
    b.export(cur);
    b.build()
}

fn params(radius: f32, strength: f32) -> Vec<u8> {
    [radius, strength, 0.0, 0.0]
        .iter()
        .flat_map(|f| f.to_le_bytes())
        .collect()
}

#[test]
fn identical_declaration_compiles_once() {
    let lib = library();
    let mut c = GraphCompiler::new();
    let a = c
        .compile(
            declare(&params(1.0, 1.0), false),
            &lib,
            CompileOptions::default(),
        )
        .unwrap();
    let b = c
        .compile(
            declare(&params(1.0, 1.0), false),
            &lib,
            CompileOptions::default(),
        )
        .unwrap();
    assert_eq!(c.compile_count(), 1);
    assert_eq!(a.key(), b.key());
    assert_eq!(a.order, b.order);
    assert_eq!(a.physical, b.physical);
    assert_eq!(a.pass_names(), vec!["blur0"]);
    assert!(
        !Arc::ptr_eq(&a.decl, &b.decl),
        "a hit carries the declaration it was asked for, not the cached one"
    );
}

#[test]
fn changing_a_uniform_value_hits_the_cache_and_carries_the_new_value() {
    // Uniform contents are not structure: a changed parameter value costs a hash, and the
    // plan returned carries the new contents (the executor writes them, rebuilding nothing).
    let lib = library();
    let mut c = GraphCompiler::new();
    let a = c
        .compile(
            declare(&params(1.0, 1.0), false),
            &lib,
            CompileOptions::default(),
        )
        .unwrap();
    let b = c
        .compile(
            declare(&params(4.0, 0.5), false),
            &lib,
            CompileOptions::default(),
        )
        .unwrap();
    assert_eq!(c.compile_count(), 1);
    assert_eq!(a.hash, b.hash);
    assert_eq!(a.decl.uniforms[0].initial, params(1.0, 1.0));
    assert_eq!(b.decl.uniforms[0].initial, params(4.0, 0.5));
    assert_eq!(
        declare(&params(1.0, 1.0), false).structure_hash(),
        declare(&params(4.0, 0.5), false).structure_hash()
    );
}

#[test]
fn changing_uniform_size_recompiles() {
    let lib = library();
    let mut c = GraphCompiler::new();
    let a = c
        .compile(
            declare(&params(1.0, 1.0), false),
            &lib,
            CompileOptions::default(),
        )
        .unwrap();
    let mut bigger = params(1.0, 1.0);
    bigger.extend_from_slice(&[0; 16]);
    let b = c
        .compile(declare(&bigger, false), &lib, CompileOptions::default())
        .unwrap();
    assert!(!Arc::ptr_eq(&a, &b));
    assert_eq!(c.compile_count(), 2);
}

#[test]
fn changing_structure_recompiles() {
    let lib = library();
    let mut c = GraphCompiler::new();
    let a = c
        .compile(
            declare(&params(1.0, 1.0), false),
            &lib,
            CompileOptions::default(),
        )
        .unwrap();
    let b = c
        .compile(
            declare(&params(1.0, 1.0), true),
            &lib,
            CompileOptions::default(),
        )
        .unwrap();
    assert!(!Arc::ptr_eq(&a, &b));
    assert_ne!(a.hash, b.hash);
    assert_eq!(c.compile_count(), 2);
    assert_eq!(b.pass_names(), vec!["blur0", "blur1"]);
    // Going back to the first structure hits the cache again.
    let a2 = c
        .compile(
            declare(&params(1.0, 1.0), false),
            &lib,
            CompileOptions::default(),
        )
        .unwrap();
    assert_eq!(a.key(), a2.key());
    assert_eq!(c.compile_count(), 2);
}

#[test]
fn changing_compile_options_recompiles() {
    let lib = library();
    let mut c = GraphCompiler::new();
    let a = c
        .compile(
            declare(&params(1.0, 1.0), true),
            &lib,
            CompileOptions { reuse: true },
        )
        .unwrap();
    let b = c
        .compile(
            declare(&params(1.0, 1.0), true),
            &lib,
            CompileOptions { reuse: false },
        )
        .unwrap();
    assert!(!Arc::ptr_eq(&a, &b));
    assert_eq!(a.hash, b.hash, "same declaration, different options");
    assert_eq!(c.compile_count(), 2);
}

#[test]
fn changing_an_export_changes_the_hash() {
    let build = |export: bool| {
        let mut b = GraphBuilder::new();
        let t = b.create_texture("t", r32());
        let t1 = b
            .custom_pass("p", NoopPass)
            .side_effect()
            .write_storage("dst", t);
        if export {
            b.export(t1);
        }
        b.build()
    };
    assert_eq!(build(true).structure_hash(), build(true).structure_hash());
    assert_ne!(build(true).structure_hash(), build(false).structure_hash());
}

#[test]
fn custom_pass_cache_key_enters_the_hash() {
    let build = |key: u64| {
        let mut b = GraphBuilder::new();
        b.custom_pass("p", KeyedPass(key)).side_effect();
        b.build()
    };
    assert_eq!(build(1).structure_hash(), build(1).structure_hash());
    assert_ne!(build(1).structure_hash(), build(2).structure_hash());
    let mut nb = GraphBuilder::new();
    nb.custom_pass("p", NoopPass).side_effect();
    assert_ne!(
        nb.build().structure_hash(),
        build(0).structure_hash(),
        "kind name enters the hash"
    );
}

#[test]
fn failed_compile_is_not_cached() {
    let lib = ShaderLibrary::inline_only();
    let mut c = GraphCompiler::new();
    let decl = declare(&params(1.0, 1.0), false);
    assert!(matches!(
        c.compile(decl, &lib, CompileOptions::default()),
        Err(GraphError::ShaderFile { .. })
    ));
    assert_eq!(c.compile_count(), 0);
    lib.add_inline("blur.wgsl", BLUR);
    let plan = c
        .compile(
            declare(&params(1.0, 1.0), false),
            &lib,
            CompileOptions::default(),
        )
        .unwrap();
    assert_eq!(c.compile_count(), 1);
    assert_eq!(plan.pass_names(), vec!["blur0"]);
}

/// A custom pass carrying per-declaration state (as the g-buffer's clock is), which does not
/// enter the hash.
#[allow(dead_code)]
struct StatefulPass(u32);

impl CustomPass for StatefulPass {
    fn kind_name(&self) -> &str {
        "stateful"
    }
    fn record(&self, _ctx: &mut PassContext<'_>) -> GraphResult<()> {
        Ok(())
    }
}

#[test]
fn a_cache_hit_keeps_the_new_declarations_custom_pass() {
    let build = |value: u32| {
        let mut b = GraphBuilder::new();
        b.custom_pass("p", StatefulPass(value)).side_effect();
        b.build()
    };
    let lib = ShaderLibrary::inline_only();
    let mut c = GraphCompiler::new();
    let first = c
        .compile(build(1), &lib, CompileOptions::default())
        .unwrap();
    let second = c
        .compile(build(2), &lib, CompileOptions::default())
        .unwrap();
    assert_eq!(c.compile_count(), 1, "same structure: a hit");
    let pass_of = |plan: &CompiledGraph| match &plan.decl.passes[0].kind {
        PassKind::Custom(p) => Arc::as_ptr(p) as *const u8,
        other => panic!("not a custom pass: {other:?}"),
    };
    assert_ne!(
        pass_of(&first),
        pass_of(&second),
        "the hit must not return the first declaration's pass object"
    );
}

#[test]
fn the_cache_evicts_the_least_recently_used_plan_beyond_its_capacity() {
    let lib = library();
    let mut c = GraphCompiler::with_capacity(2);
    let one = || declare(&params(1.0, 1.0), false);
    let two = || declare(&params(1.0, 1.0), true);
    let three = || {
        let mut b = GraphBuilder::new();
        b.custom_pass("p", NoopPass).side_effect();
        b.build()
    };
    let opts = CompileOptions::default();
    c.compile(one(), &lib, opts).unwrap();
    c.compile(two(), &lib, opts).unwrap();
    c.compile(one(), &lib, opts).unwrap(); // hit: `one` is now the most recent
    assert_eq!((c.compile_count(), c.cached_plans()), (2, 2));
    c.compile(three(), &lib, opts).unwrap(); // miss: evicts `two`, the least recent
    assert_eq!((c.compile_count(), c.cached_plans()), (3, 2));
    c.compile(one(), &lib, opts).unwrap(); // still cached
    assert_eq!(c.compile_count(), 3);
    c.compile(two(), &lib, opts).unwrap(); // was evicted: compiled again
    assert_eq!((c.compile_count(), c.cached_plans()), (4, 2));
}

#[test]
fn a_replaced_shader_or_another_library_is_compiled_again() {
    let lib = library();
    let mut c = GraphCompiler::new();
    let options = CompileOptions::default();
    c.compile(declare(&params(1.0, 1.0), false), &lib, options)
        .unwrap();
    // The same sources in another library: its own plan (its modules are its own).
    let other = library();
    c.compile(declare(&params(1.0, 1.0), false), &other, options)
        .unwrap();
    assert_eq!(c.compile_count(), 2);
    // The blur without its uniform: the pass's `params` binds nothing in the new source, which
    // compile must see rather than serve the plan of the old one.
    let without_uniform = BLUR
        .replace("@group(0) @binding(2) var<uniform> params: Params;\n", "")
        .replace(" * params.strength", "");
    lib.add_inline("blur.wgsl", &without_uniform);
    let e = c
        .compile(declare(&params(1.0, 1.0), false), &lib, options)
        .unwrap_err()
        .to_string();
    assert!(e.contains("params"), "{e}");
    // Put back, it compiles again (a new revision, not the first plan).
    lib.add_inline("blur.wgsl", BLUR);
    c.compile(declare(&params(1.0, 1.0), false), &lib, options)
        .unwrap();
    assert_eq!(c.compile_count(), 3);
}
