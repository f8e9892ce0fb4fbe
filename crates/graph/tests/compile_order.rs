//! Compile: topological order, stable by declaration order, and its edges.

use aograph_graph::wgpu::TextureFormat;
use aograph_graph::*;

fn desc() -> TextureDesc {
    TextureDesc::new(TextureFormat::Rgba16Float, SizeClass::FULL)
}

fn compile_ok(b: GraphBuilder) -> CompiledGraph {
    compile(
        b.build(),
        &ShaderLibrary::inline_only(),
        CompileOptions::default(),
    )
    .expect("graph compiles")
}

/// A side-effect pass writing its own fresh texture and reading `inputs`; returns (id, output).
fn pass(b: &mut GraphBuilder, name: &str, inputs: &[TextureHandle]) -> (PassId, TextureHandle) {
    let t = b.create_texture(&format!("{name}.out"), desc());
    let mut p = b.custom_pass(name, NoopPass);
    for (i, h) in inputs.iter().enumerate() {
        p.sample(&format!("in{i}"), *h);
    }
    let out = p.write_storage("out", t);
    (p.id(), out)
}

#[test]
fn independent_passes_keep_declaration_order() {
    let mut b = GraphBuilder::new();
    for name in ["e", "b", "d", "a", "c"] {
        let (id, _) = pass(&mut b, name, &[]);
        b.pass(id).side_effect();
    }
    let plan = compile_ok(b);
    assert_eq!(plan.pass_names(), vec!["e", "b", "d", "a", "c"]);
    assert!(plan.edges.is_empty());
    assert!(plan.culled.is_empty());
}

#[test]
fn linear_chain_runs_in_dependency_order() {
    let mut b = GraphBuilder::new();
    let (a, ta) = pass(&mut b, "a", &[]);
    let (bb, tb) = pass(&mut b, "b", &[ta]);
    let (c, tc) = pass(&mut b, "c", &[tb]);
    b.export(tc);
    let plan = compile_ok(b);
    assert_eq!(plan.order, vec![a, bb, c]);
    assert_eq!(plan.edges, vec![(a, bb), (bb, c)]);
}

#[test]
fn pass_declared_first_moves_after_the_later_pass_it_reads() {
    let mut b = GraphBuilder::new();
    let (consumer, _) = pass(&mut b, "consumer", &[]);
    let (producer, tp) = pass(&mut b, "producer", &[]);
    b.pass(consumer).sample("late", tp).side_effect();
    let plan = compile_ok(b);
    assert_eq!(plan.pass_names(), vec!["producer", "consumer"]);
    assert_eq!(plan.edges, vec![(producer, consumer)]);
}

#[test]
fn reopened_pass_waits_but_unrelated_passes_keep_their_place() {
    // x (declared first) reads z's output; y is independent. Lowest-index-first topological
    // order: y and z are ready, x after z.
    let mut b = GraphBuilder::new();
    let (x, tx) = pass(&mut b, "x", &[]);
    let (_, ty) = pass(&mut b, "y", &[]);
    let (z, tz) = pass(&mut b, "z", &[]);
    b.pass(x).sample("z", tz);
    b.export(tx);
    b.export(ty);
    let plan = compile_ok(b);
    assert_eq!(plan.pass_names(), vec!["y", "z", "x"]);
    assert_eq!(plan.edges, vec![(z, x)]);
}

#[test]
fn diamond_orders_join_after_both_branches() {
    let mut b = GraphBuilder::new();
    let (top, t) = pass(&mut b, "top", &[]);
    let (l, tl) = pass(&mut b, "left", &[t]);
    let (r, tr) = pass(&mut b, "right", &[t]);
    let (j, tj) = pass(&mut b, "join", &[tl, tr]);
    b.export(tj);
    let plan = compile_ok(b);
    assert_eq!(plan.order, vec![top, l, r, j]);
    assert_eq!(plan.edges, vec![(top, l), (top, r), (l, j), (r, j)]);
}

#[test]
fn reversed_declaration_built_by_reopening_runs_reversed() {
    // Declare d, c, b, a; then reopen so that a -> b -> c -> d.
    let mut b = GraphBuilder::new();
    let ids: Vec<(PassId, TextureHandle)> = ["d", "c", "b", "a"]
        .iter()
        .map(|n| pass(&mut b, n, &[]))
        .collect();
    for w in ids.windows(2) {
        // w[0] (declared earlier) reads w[1]'s output.
        b.pass(w[0].0).sample("prev", w[1].1);
    }
    b.export(ids[0].1);
    let plan = compile_ok(b);
    assert_eq!(plan.pass_names(), vec!["a", "b", "c", "d"]);
}

#[test]
fn reader_of_old_version_runs_before_the_overwrite() {
    // w overwrites t (write-only) after a wrote it; r, declared after w, still reads a's
    // version, so it must run before w (write-after-read ordering).
    let mut b = GraphBuilder::new();
    let t = b.create_texture("t", desc());
    let t1 = b.custom_pass("a", NoopPass).write_storage("out", t);
    let t2 = b.custom_pass("w", NoopPass).write_storage("out", t1);
    b.custom_pass("r", NoopPass).sample("old", t1).side_effect();
    b.export(t2);
    let plan = compile_ok(b);
    assert_eq!(plan.pass_names(), vec!["a", "r", "w"]);
    let (a, r) = (
        plan.decl.pass_by_name("a").unwrap(),
        plan.decl.pass_by_name("r").unwrap(),
    );
    assert_eq!(
        plan.edges,
        vec![(a, r)],
        "edges lists only producer -> consumer data edges"
    );
}

#[test]
fn in_place_updates_run_in_write_order() {
    let mut b = GraphBuilder::new();
    let t = b.create_texture("t", desc());
    let t1 = b.custom_pass("init", NoopPass).write_storage("out", t);
    let t2 = b.custom_pass("add1", NoopPass).read_write_storage("rw", t1);
    let t3 = b.custom_pass("add2", NoopPass).read_write_storage("rw", t2);
    b.export(t3);
    let plan = compile_ok(b);
    assert_eq!(plan.pass_names(), vec!["init", "add1", "add2"]);
    assert_eq!(plan.edges.len(), 2);
}

#[test]
fn compiled_order_respects_every_edge() {
    let mut b = GraphBuilder::new();
    let (p0, t0) = pass(&mut b, "p0", &[]);
    let (p1, t1) = pass(&mut b, "p1", &[]);
    let (p2, t2) = pass(&mut b, "p2", &[t1]);
    b.pass(p0).sample("late", t2);
    let (_, t3) = pass(&mut b, "p3", &[t0, t1]);
    b.export(t3);
    let plan = compile_ok(b);
    let pos = |p: PassId| plan.order.iter().position(|&o| o == p).unwrap();
    assert_eq!(plan.edges.len(), 4);
    for &(from, to) in &plan.edges {
        assert!(
            pos(from) < pos(to),
            "{from:?} before {to:?} in {:?}",
            plan.pass_names()
        );
    }
    assert_eq!(plan.pass_names(), vec!["p1", "p2", "p0", "p3"]);
    let _ = (p1, p2);
}

#[test]
fn compute_and_fullscreen_passes_get_their_reflected_shader() {
    let lib = ShaderLibrary::inline_only();
    lib.add_inline(
        "fill.wgsl",
        "@group(0) @binding(0) var dst: texture_storage_2d<r32float, write>;\n\
         @compute @workgroup_size(8, 8, 1)\n\
         fn main(@builtin(global_invocation_id) id: vec3<u32>) {\n\
             textureStore(dst, vec2<i32>(id.xy), vec4<f32>(1.0));\n\
         }\n",
    );
    lib.add_inline(
        "show.wgsl",
        "@group(0) @binding(0) var src: texture_2d<f32>;\n\
         @vertex fn vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {\n\
             return vec4<f32>(f32(i), 0.0, 0.0, 1.0);\n\
         }\n\
         @fragment fn fs(@builtin(position) p: vec4<f32>) -> @location(0) vec4<f32> {\n\
             return textureLoad(src, vec2<i32>(p.xy), 0);\n\
         }\n",
    );
    let mut b = GraphBuilder::new();
    let ao = b.create_texture(
        "ao",
        TextureDesc::new(TextureFormat::R32Float, SizeClass::FULL),
    );
    let ao1 = {
        let mut p = b.compute_pass("fill", "fill.wgsl", "main");
        let h = p.write_storage("dst", ao);
        p.dispatch_over(h);
        h
    };
    let out = b.create_texture(
        "out",
        TextureDesc::new(TextureFormat::Rgba8Unorm, SizeClass::FULL),
    );
    let out1 = {
        let mut p = b.fullscreen_pass("show", "show.wgsl", "vs", "fs");
        p.sample("src", ao1);
        p.color_attachment(out)
    };
    let (side, _) = pass(&mut b, "custom", &[out1]);
    b.pass(side).side_effect();
    let plan = compile(b.build(), &lib, CompileOptions::default()).expect("compiles");
    assert_eq!(plan.pass_names(), vec!["fill", "show", "custom"]);
    assert_eq!(
        plan.shaders[0].as_ref().map(|s| s.name.as_str()),
        Some("fill.wgsl")
    );
    assert_eq!(
        plan.shaders[1].as_ref().map(|s| s.name.as_str()),
        Some("show.wgsl")
    );
    assert!(plan.shaders[2].is_none(), "custom passes have no shader");
}

#[test]
fn reader_of_old_version_runs_before_a_later_kept_overwrite_when_the_next_writer_is_culled() {
    // w1 writes v1, w2 overwrites it (v2, culled: w3 overwrites again), w3 writes v3 (exported).
    // `late` is declared last but reads v1: it must run before w3 although its direct
    // write-after-read successor w2 is culled.
    let mut b = GraphBuilder::new();
    let t = b.create_texture("t", desc());
    let v1 = b.custom_pass("w1", NoopPass).write_storage("out", t);
    let v2 = b.custom_pass("w2", NoopPass).write_storage("out", v1);
    let v3 = b.custom_pass("w3", NoopPass).write_storage("out", v2);
    b.custom_pass("late", NoopPass)
        .sample("old", v1)
        .side_effect();
    b.export(v3);
    let plan = compile_ok(b);
    assert_eq!(plan.culled_names(), vec!["w2"]);
    assert_eq!(plan.pass_names(), vec!["w1", "late", "w3"]);
}

#[test]
fn in_place_update_after_culled_overwrites_still_follows_the_stale_reader() {
    // Like above but the kept overwrite is an in-place update of a culled pass's version chain.
    let mut b = GraphBuilder::new();
    let t = b.create_texture("t", desc());
    let v1 = b.custom_pass("w1", NoopPass).write_storage("out", t);
    let v2 = b.custom_pass("w2", NoopPass).write_storage("out", v1);
    let v3 = b.custom_pass("w3", NoopPass).write_storage("out", v2);
    let v4 = b.custom_pass("rw", NoopPass).read_write_storage("rw", v3);
    b.custom_pass("late", NoopPass)
        .sample("old", v1)
        .side_effect();
    b.export(v4);
    let plan = compile_ok(b);
    assert_eq!(plan.culled_names(), vec!["w2"]);
    assert_eq!(plan.pass_names(), vec!["w1", "late", "w3", "rw"]);
}
