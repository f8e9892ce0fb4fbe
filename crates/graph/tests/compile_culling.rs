//! Compile: culling keeps exactly the passes an export, history write or side effect needs.

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
fn culls_pass_whose_output_is_unused() {
    let mut b = GraphBuilder::new();
    let (_, ta) = pass(&mut b, "used", &[]);
    let (unused, _) = pass(&mut b, "unused", &[]);
    b.export(ta);
    let plan = compile_ok(b);
    assert_eq!(plan.pass_names(), vec!["used"]);
    assert_eq!(plan.culled_names(), vec!["unused"]);
    assert_eq!(plan.culled.len(), 1);
    assert_eq!(plan.culled[0].pass, unused);
    assert!(
        plan.culled[0].reason.contains("no exported output"),
        "reason: {}",
        plan.culled[0].reason
    );
    assert!(!plan.is_kept(unused));
}

#[test]
fn culls_a_branch_that_feeds_nothing_exported() {
    let mut b = GraphBuilder::new();
    let (_, src) = pass(&mut b, "src", &[]);
    let (_, keep) = pass(&mut b, "keep", &[src]);
    let (_, dead1) = pass(&mut b, "dead1", &[src]);
    let (_, _dead2) = pass(&mut b, "dead2", &[dead1, keep]);
    let (_, out) = pass(&mut b, "out", &[keep]);
    b.export(out);
    let plan = compile_ok(b);
    assert_eq!(plan.pass_names(), vec!["src", "keep", "out"]);
    assert_eq!(plan.culled_names(), vec!["dead1", "dead2"]);
}

#[test]
fn nothing_exported_culls_everything() {
    let mut b = GraphBuilder::new();
    let (_, a) = pass(&mut b, "a", &[]);
    pass(&mut b, "b", &[a]);
    let plan = compile_ok(b);
    assert!(plan.order.is_empty());
    assert_eq!(plan.culled_names(), vec!["a", "b"]);
    assert!(plan.physical.is_empty());
    assert!(plan.lifetimes.iter().all(Option::is_none));
}

#[test]
fn side_effect_pass_and_its_inputs_are_kept() {
    let mut b = GraphBuilder::new();
    let (_, a) = pass(&mut b, "a", &[]);
    let (_, _) = pass(&mut b, "other", &[]);
    b.custom_pass("present", NoopPass)
        .sample("src", a)
        .side_effect();
    let plan = compile_ok(b);
    assert_eq!(plan.pass_names(), vec!["a", "present"]);
    assert_eq!(plan.culled_names(), vec!["other"]);
}

#[test]
fn history_write_keeps_its_writer_without_export() {
    let mut b = GraphBuilder::new();
    let h = b.history_texture("accum", desc());
    let (_, a) = pass(&mut b, "a", &[]);
    {
        let mut p = b.custom_pass("accumulate", NoopPass);
        p.sample("prev", h.previous).sample("cur", a);
        p.write_storage("out", h.current);
    }
    pass(&mut b, "unrelated", &[h.previous]);
    let plan = compile_ok(b);
    assert_eq!(plan.pass_names(), vec!["a", "accumulate"]);
    assert_eq!(plan.culled_names(), vec!["unrelated"]);
    assert_eq!(
        plan.slot_of[h.current.resource_index()],
        None,
        "history is not pooled"
    );
    assert_eq!(
        plan.slot_of[h.previous.resource_index()],
        None,
        "history is not pooled"
    );
}

#[test]
fn write_only_overwrite_of_exported_texture_culls_the_earlier_writer() {
    let mut b = GraphBuilder::new();
    let t = b.create_texture("t", desc());
    let t1 = b.custom_pass("first", NoopPass).write_storage("out", t);
    let t2 = b.custom_pass("second", NoopPass).write_storage("out", t1);
    b.export(t2);
    let plan = compile_ok(b);
    assert_eq!(plan.pass_names(), vec!["second"]);
    assert_eq!(plan.culled_names(), vec!["first"]);
}

#[test]
fn read_write_chain_keeps_every_pass() {
    let mut b = GraphBuilder::new();
    let t = b.create_texture("t", desc());
    let t1 = b.custom_pass("init", NoopPass).write_storage("out", t);
    let t2 = b.custom_pass("rw1", NoopPass).read_write_storage("rw", t1);
    let t3 = b
        .custom_pass("rw2", NoopPass)
        .write_texture(TextureAccess::StorageReadWrite, t2);
    b.export(t3);
    let plan = compile_ok(b);
    assert_eq!(plan.pass_names(), vec!["init", "rw1", "rw2"]);
    assert!(plan.culled.is_empty());
}

#[test]
fn loading_colour_attachment_keeps_the_clearing_pass() {
    let mut b = GraphBuilder::new();
    let t = b.create_texture("color", desc());
    let t1 = b.custom_pass("opaque", NoopPass).color_attachment(t);
    let t2 = b.custom_pass("transparent", NoopPass).color_attachment(t1);
    b.export(t2);
    let plan = compile_ok(b);
    assert_eq!(plan.pass_names(), vec!["opaque", "transparent"]);
}

#[test]
fn exporting_an_intermediate_version_keeps_its_final_writer_chain() {
    // export() marks the resource: what counts is its final version.
    let mut b = GraphBuilder::new();
    let t = b.create_texture("t", desc());
    let t1 = b.custom_pass("init", NoopPass).write_storage("out", t);
    let _t2 = b
        .custom_pass("update", NoopPass)
        .read_write_storage("rw", t1);
    b.export(t1);
    let plan = compile_ok(b);
    assert_eq!(plan.pass_names(), vec!["init", "update"]);
}

#[test]
fn reader_of_culled_version_does_not_keep_the_overwritten_writer() {
    // a writes v1, r reads v1 (culled, no side effect), w overwrites; export keeps w only.
    let mut b = GraphBuilder::new();
    let t = b.create_texture("t", desc());
    let t1 = b.custom_pass("a", NoopPass).write_storage("out", t);
    pass(&mut b, "r", &[t1]);
    let t2 = b.custom_pass("w", NoopPass).write_storage("out", t1);
    b.export(t2);
    let plan = compile_ok(b);
    assert_eq!(plan.pass_names(), vec!["w"]);
    assert_eq!(plan.culled_names(), vec!["a", "r"]);
}

#[test]
fn culled_pass_with_broken_shader_is_not_checked() {
    // Shaders are checked for kept passes only, so a dead compute pass without a shader
    // does not fail compile.
    let mut b = GraphBuilder::new();
    let (_, a) = pass(&mut b, "a", &[]);
    let t = b.create_texture("dead", desc());
    b.compute_pass("dead", "missing.wgsl", "main")
        .write_storage("dst", t);
    b.export(a);
    let plan = compile_ok(b);
    assert_eq!(plan.culled_names(), vec!["dead"]);
    assert!(plan.shaders.iter().all(Option::is_none));
}
