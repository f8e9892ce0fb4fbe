//! Binding slots (no GPU): compile resolves each shader binding of a kept pass to the use that
//! supplies it, once, so that binding a frame compares no names. The uses below are declared
//! in another order than the shader's bindings, so a slot that took the wrong use (or the
//! wrong resource, mip or sampler) fails here.

use aograph_graph::wgpu::{AddressMode, FilterMode, TextureFormat};
use aograph_graph::*;

const WIDE: &str = "struct Params { k: f32, pad: vec3<f32> }
@group(0) @binding(0) var color: texture_2d<f32>;
@group(0) @binding(1) var depth: texture_2d<f32>;
@group(0) @binding(2) var out_img: texture_storage_2d<r32float, write>;
@group(0) @binding(3) var<uniform> params: Params;
@group(0) @binding(4) var soft: sampler;
@group(1) @binding(0) var<storage, read> weights: array<vec4<f32>, 4>;
@group(1) @binding(1) var crisp: sampler;
@group(1) @binding(2) var<storage, read_write> counters: array<u32, 8>;
@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let uv = vec2<f32>(id.xy) / 8.0;
    let a = textureSampleLevel(color, soft, uv, 0.0).r;
    let b = textureSampleLevel(depth, crisp, uv, 0.0).r;
    textureStore(out_img, vec2<i32>(id.xy), vec4<f32>(a + b * params.k + weights[0].x));
    counters[0] = 1u;
}
";

const ONE_SAMPLER: &str = "@group(0) @binding(0) var src: texture_2d<f32>;
@group(0) @binding(1) var blur: sampler;
@group(0) @binding(2) var dst: texture_storage_2d<r32float, write>;
@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let v = textureSampleLevel(src, blur, vec2<f32>(id.xy) / 8.0, 0.0);
    textureStore(dst, vec2<i32>(id.xy), v);
}
";

fn library() -> ShaderLibrary {
    let lib = ShaderLibrary::inline_only();
    lib.add_inline("wide.wgsl", WIDE);
    lib.add_inline("one_sampler.wgsl", ONE_SAMPLER);
    lib
}

const NEAREST_REPEAT: SamplerDesc = SamplerDesc {
    filter: FilterMode::Nearest,
    address: AddressMode::Repeat,
};

struct Declared {
    decl: GraphDecl,
    color: TextureHandle,
    depth: TextureHandle,
    out: TextureHandle,
    weights: BufferHandle,
    counters: BufferHandle,
    params: UniformHandle,
}

/// Pass "wide" (uses declared out of binding order), pass "second" (one sampler, the same
/// description as `soft`), and a pass "unused" that is culled.
fn declare() -> Declared {
    let mut b = GraphBuilder::new();
    let r32 = TextureDesc::new(TextureFormat::R32Float, SizeClass::FULL);
    let color = b.import_texture("color", r32);
    let depth = b.import_texture("depth", r32.with_mips(3));
    let weights = b.import_buffer("weights", BufferDesc { size: 64 });
    let counters = b.create_buffer("counters", BufferDesc { size: 32 });
    let out = b.create_texture("out", r32);
    let (out, params, counters) = {
        let mut p = b.compute_pass("wide", "wide.wgsl", "main");
        let counters = p.write_buffer("counters", counters);
        p.sampler("crisp", NEAREST_REPEAT);
        p.sample_mip("depth", depth, 2);
        p.read_buffer("weights", BufferAccess::StorageRead, weights);
        let out = p.write_storage("out_img", out);
        p.sampler("soft", SamplerDesc::NEAREST_CLAMP);
        // Declared again: the last description counts.
        p.sampler("soft", SamplerDesc::LINEAR_CLAMP);
        let params = p.uniform("params", &[0; 32]);
        p.sample("color", color);
        p.dispatch_over(out);
        (out, params, counters)
    };
    let second = b.create_texture("second", r32);
    let second = {
        let mut p = b.compute_pass("second", "one_sampler.wgsl", "main");
        p.sampler("blur", SamplerDesc::LINEAR_CLAMP);
        p.sample("src", out);
        let s = p.write_storage("dst", second);
        p.dispatch_over(s);
        s
    };
    let unused = b.create_texture("unused", r32);
    {
        let mut p = b.compute_pass("unused", "one_sampler.wgsl", "main");
        p.sampler("blur", NEAREST_REPEAT);
        p.sample("src", color);
        let u = p.write_storage("dst", unused);
        p.dispatch_over(u);
    }
    b.export(second);
    Declared {
        decl: b.build(),
        color,
        depth,
        out,
        weights,
        counters,
        params,
    }
}

fn slot(group: u32, binding: u32, source: BindingSource) -> BindingSlot {
    BindingSlot {
        group,
        binding,
        source,
    }
}

fn check_slots(plan: &CompiledGraph, d: &Declared) {
    let wide = plan.decl.pass_by_name("wide").unwrap().index();
    let pass = &plan.decl.passes[wide];
    let use_of = |binding: &str| {
        pass.textures
            .iter()
            .position(|u| u.binding.as_deref() == Some(binding))
            .unwrap()
    };
    let buffer_use_of = |binding: &str| {
        pass.buffers
            .iter()
            .position(|u| u.binding.as_deref() == Some(binding))
            .unwrap()
    };
    // Two distinct samplers in the plan: the culled pass's third one is not among them.
    assert_eq!(
        plan.samplers,
        vec![SamplerDesc::LINEAR_CLAMP, NEAREST_REPEAT],
        "`soft` (bound first) and `crisp`, interned in binding order"
    );
    use BindingSource as S;
    assert_eq!(
        plan.binding_slots[wide],
        vec![
            slot(
                0,
                0,
                S::SampledTexture {
                    texture_use: use_of("color"),
                    resource: d.color.resource_index(),
                    mip: None,
                },
            ),
            slot(
                0,
                1,
                S::SampledTexture {
                    texture_use: use_of("depth"),
                    resource: d.depth.resource_index(),
                    mip: Some(2),
                },
            ),
            slot(
                0,
                2,
                S::StorageTexture {
                    texture_use: use_of("out_img"),
                    resource: d.out.resource_index(),
                    mip: 0,
                },
            ),
            slot(0, 3, S::Uniform(d.params)),
            slot(0, 4, S::Sampler { sampler: 0 }),
            slot(
                1,
                0,
                S::Buffer {
                    buffer_use: buffer_use_of("weights"),
                    resource: d.weights.resource_index(),
                },
            ),
            slot(1, 1, S::Sampler { sampler: 1 }),
            slot(
                1,
                2,
                S::Buffer {
                    buffer_use: buffer_use_of("counters"),
                    resource: d.counters.resource_index(),
                },
            ),
        ]
    );
    // The uses are declared out of binding order, so indices are not positions.
    assert_ne!(use_of("color"), 0);
    assert_ne!(buffer_use_of("weights"), 0);

    let second = plan.decl.pass_by_name("second").unwrap().index();
    assert_eq!(
        plan.binding_slots[second],
        vec![
            slot(
                0,
                0,
                S::SampledTexture {
                    texture_use: 0,
                    resource: d.out.resource_index(),
                    mip: None,
                },
            ),
            slot(0, 1, S::Sampler { sampler: 0 }),
            slot(
                0,
                2,
                S::StorageTexture {
                    texture_use: 1,
                    resource: plan.decl.resource_by_name("second").unwrap(),
                    mip: 0,
                },
            ),
        ],
        "the same description as `soft` is the same sampler"
    );
    let unused = plan.decl.pass_by_name("unused").unwrap();
    assert!(!plan.is_kept(unused));
    assert!(plan.binding_slots[unused.index()].is_empty(), "culled");
    // Each slot is its shader binding's, in the shader's order.
    for p in &plan.order {
        let info = plan.shaders[p.index()].as_ref().unwrap();
        let at: Vec<_> = info.bindings.iter().map(|b| (b.group, b.binding)).collect();
        let slots: Vec<_> = plan.binding_slots[p.index()]
            .iter()
            .map(|s| (s.group, s.binding))
            .collect();
        assert_eq!(at, slots);
    }
}

#[test]
fn slots_point_at_the_uses_that_supply_each_binding() {
    let d = declare();
    let plan = compile(d.decl.clone(), &library(), CompileOptions::default()).expect("compiles");
    check_slots(&plan, &d);
}

#[test]
fn a_compile_cache_hit_keeps_the_slots() {
    let mut compiler = GraphCompiler::new();
    let lib = library();
    let d = declare();
    let first = compiler
        .compile(d.decl.clone(), &lib, CompileOptions::default())
        .unwrap();
    let again = compiler
        .compile(declare().decl, &lib, CompileOptions::default())
        .unwrap();
    assert_eq!(compiler.compile_count(), 1, "the second compile is a hit");
    assert_eq!(first.binding_slots, again.binding_slots);
    check_slots(&again, &d);
}

#[test]
fn passes_without_a_shader_have_no_slots() {
    let mut b = GraphBuilder::new();
    let t = b.create_texture(
        "t",
        TextureDesc::new(TextureFormat::R32Float, SizeClass::FULL),
    );
    let t = b.custom_pass("draw", NoopPass).write_storage("dst", t);
    let c = b.create_texture(
        "c",
        TextureDesc::new(TextureFormat::R32Float, SizeClass::FULL),
    );
    let c = b.copy_pass("copy", t, c);
    b.export(c);
    let plan = compile(b.build(), &library(), CompileOptions::default()).unwrap();
    assert_eq!(plan.order.len(), 2);
    assert!(plan.binding_slots.iter().all(Vec::is_empty));
    assert!(plan.samplers.is_empty());
}

#[test]
fn samplers_enter_the_structure_hash() {
    let a = declare().decl;
    let wide = a.pass_by_name("wide").unwrap();
    let mut b = GraphBuilder::from_decl(declare().decl);
    b.pass(wide).sampler("crisp", SamplerDesc::LINEAR_CLAMP);
    assert_ne!(a.structure_hash(), b.build().structure_hash());
}

const RAY_QUERY: &str = "enable wgpu_ray_query;
@group(0) @binding(0) var<storage, read> rows: array<u32>;
@group(0) @binding(1) var scene: acceleration_structure;
@group(0) @binding(2) var dst: texture_storage_2d<r32float, write>;
@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    var rq: ray_query;
    rayQueryInitialize(&rq, scene, RayDesc(0u, 0xffu, 0.0, 1.0, vec3<f32>(0.0), vec3<f32>(0.0, 0.0, 1.0)));
    rayQueryProceed(&rq);
    let hit = rayQueryGetCommittedIntersection(&rq);
    textureStore(dst, vec2<i32>(id.xy), vec4<f32>(f32(hit.kind) + f32(rows[0])));
}
";

/// A ray-query pass: the scene's TLAS (imported) and a table, with `bind` choosing how the
/// pass supplies the `acceleration_structure` and storage globals.
fn ray_query_plan(
    bind: impl FnOnce(&mut PassBuilder<'_>, AccelerationStructureHandle, BufferHandle),
) -> GraphResult<(CompiledGraph, AccelerationStructureHandle)> {
    let lib = ShaderLibrary::inline_only();
    lib.add_inline("ray_query.wgsl", RAY_QUERY);
    let mut b = GraphBuilder::new();
    let r32 = TextureDesc::new(TextureFormat::R32Float, SizeClass::FULL);
    let tlas = b.import_acceleration_structure("scene.tlas");
    let rows = b.import_buffer("scene.rows", BufferDesc { size: 16 });
    let out = b.create_texture("out", r32);
    let out = {
        let mut p = b.compute_pass("trace", "ray_query.wgsl", "main");
        bind(&mut p, tlas, rows);
        let out = p.write_storage("dst", out);
        p.dispatch_over(out);
        out
    };
    b.export(out);
    compile(b.build(), &lib, CompileOptions::default()).map(|plan| (plan, tlas))
}

#[test]
fn an_acceleration_structure_binding_takes_the_imported_structure() {
    let (plan, tlas) = ray_query_plan(|p, tlas, rows| {
        p.read_buffer("rows", BufferAccess::StorageRead, rows);
        p.read_acceleration_structure("scene", tlas);
    })
    .expect("compiles");
    let pass = plan.order[0].index();
    let slot = plan.binding_slots[pass]
        .iter()
        .find(|s| s.binding == 1)
        .expect("slot 1");
    assert_eq!(
        slot.source,
        BindingSource::AccelerationStructure {
            buffer_use: 1,
            resource: tlas.resource_index(),
        }
    );
    assert_eq!(
        plan.decl.resources[tlas.resource_index()].kind,
        ResourceKind::AccelerationStructure
    );
}

#[test]
fn an_acceleration_structure_binding_without_one_is_named() {
    let e = ray_query_plan(|p, _, rows| {
        p.read_buffer("rows", BufferAccess::StorageRead, rows);
    })
    .unwrap_err()
    .to_string();
    assert!(e.contains("scene") && e.contains("supplies nothing"), "{e}");
    let e = ray_query_plan(|p, _, rows| {
        p.read_buffer("rows", BufferAccess::StorageRead, rows);
        p.read_buffer("scene", BufferAccess::StorageRead, rows);
    })
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("acceleration structure") && e.contains("read_acceleration_structure"),
        "{e}"
    );
    // And a structure bound where the shader has a storage buffer.
    let e = ray_query_plan(|p, tlas, _| {
        p.read_acceleration_structure("scene", tlas);
        p.read_acceleration_structure("rows", tlas);
    })
    .unwrap_err()
    .to_string();
    assert!(e.contains("rows") && e.contains("storage buffer"), "{e}");
}
