//! One minimal bad graph per structural error; each error names the pass/resource at fault.

use aograph_graph::wgpu::TextureFormat;
use aograph_graph::*;

fn rgba(size: SizeClass) -> TextureDesc {
    TextureDesc::new(TextureFormat::Rgba16Float, size)
}

fn compile_err(b: GraphBuilder) -> GraphError {
    match compile(
        b.build(),
        &ShaderLibrary::inline_only(),
        CompileOptions::default(),
    ) {
        Ok(plan) => panic!("expected an error, compiled {:?}", plan.pass_names()),
        Err(e) => e,
    }
}

fn assert_names(e: &GraphError, names: &[&str]) {
    let msg = e.to_string();
    for n in names {
        assert!(
            msg.contains(&format!("`{n}`")),
            "message {msg:?} should name `{n}`"
        );
    }
}

#[test]
fn cycle_between_two_reopened_passes() {
    let mut b = GraphBuilder::new();
    let ta = b.create_texture("ta", rgba(SizeClass::FULL));
    let tb = b.create_texture("tb", rgba(SizeClass::FULL));
    let pa = b.custom_pass("pa", NoopPass).id();
    let pb = b.custom_pass("pb", NoopPass).id();
    let ta1 = b.pass(pa).write_storage("out", ta);
    let tb1 = b.pass(pb).write_storage("out", tb);
    b.pass(pa).sample("in", tb1);
    b.pass(pb).sample("in", ta1);
    b.export(ta1);
    let e = compile_err(b);
    match &e {
        GraphError::Cycle { pass } => assert!(pass == "pa" || pass == "pb", "cycle names {pass}"),
        other => panic!("expected Cycle, got {other:?}"),
    }
    let GraphError::Cycle { pass } = &e else {
        unreachable!()
    };
    assert_names(&e, &[pass]);
    assert!(e.to_string().contains("cycle"));
}

#[test]
fn cycle_through_a_longer_loop_is_found_even_when_culled() {
    // a -> b -> c -> a, nothing exported: still an error, not silently culled.
    let mut b = GraphBuilder::new();
    let ids: Vec<PassId> = ["a", "b", "c"]
        .iter()
        .map(|n| b.custom_pass(n, NoopPass).id())
        .collect();
    let outs: Vec<TextureHandle> = ids
        .iter()
        .enumerate()
        .map(|(i, &id)| {
            let t = b.create_texture(&format!("t{i}"), rgba(SizeClass::FULL));
            b.pass(id).write_storage("out", t)
        })
        .collect();
    for i in 0..3 {
        b.pass(ids[(i + 1) % 3]).sample("in", outs[i]);
    }
    assert!(matches!(compile_err(b), GraphError::Cycle { .. }));
}

#[test]
fn read_of_never_written_transient() {
    let mut b = GraphBuilder::new();
    let t = b.create_texture("gbuffer", rgba(SizeClass::FULL));
    b.custom_pass("shade", NoopPass)
        .sample("src", t)
        .side_effect();
    let e = compile_err(b);
    assert_eq!(
        e,
        GraphError::ReadOfUnwritten {
            pass: "shade".into(),
            resource: "gbuffer".into()
        }
    );
    assert_names(&e, &["shade", "gbuffer"]);
}

#[test]
fn read_of_unwritten_is_reported_even_for_a_culled_pass() {
    let mut b = GraphBuilder::new();
    let t = b.create_texture("never", rgba(SizeClass::FULL));
    b.custom_pass("dead", NoopPass).sample("src", t);
    assert!(matches!(compile_err(b), GraphError::ReadOfUnwritten { pass, .. } if pass == "dead"));
}

#[test]
fn writing_a_stale_handle_is_a_conflicting_write() {
    let mut b = GraphBuilder::new();
    let t = b.create_texture("accum", rgba(SizeClass::FULL));
    let t1 = b.custom_pass("first", NoopPass).write_storage("out", t);
    // Writes version 0 again although `first` already produced version 1.
    b.custom_pass("second", NoopPass).write_storage("out", t);
    b.export(t1);
    let e = compile_err(b);
    assert_eq!(
        e,
        GraphError::ConflictingWrites {
            resource: "accum".into(),
            first: "first".into(),
            second: "second".into()
        }
    );
    assert_names(&e, &["accum", "first", "second"]);
}

#[test]
fn two_writes_of_the_same_version_conflict() {
    let mut b = GraphBuilder::new();
    let t = b.create_texture("t", rgba(SizeClass::FULL));
    let t1 = b.custom_pass("a", NoopPass).write_storage("out", t);
    let _t2 = b.custom_pass("b", NoopPass).read_write_storage("rw", t1);
    b.custom_pass("c", NoopPass).read_write_storage("rw", t1);
    let e = compile_err(b);
    assert_eq!(
        e,
        GraphError::ConflictingWrites {
            resource: "t".into(),
            first: "b".into(),
            second: "c".into()
        }
    );
}

#[test]
fn colour_attachments_of_different_size_classes_mismatch() {
    let mut b = GraphBuilder::new();
    let full = b.create_texture("full_rt", rgba(SizeClass::FULL));
    let half = b.create_texture("half_rt", rgba(SizeClass::half_pow(1)));
    let out = {
        let mut p = b.custom_pass("mrt", NoopPass);
        let o = p.color_attachment(full);
        p.color_attachment(half);
        o
    };
    b.export(out);
    let e = compile_err(b);
    assert_eq!(
        e,
        GraphError::SizeMismatch {
            pass: "mrt".into(),
            resource: "half_rt".into(),
            expected: "full (the size of `full_rt`)".into(),
            found: "1/2".into()
        }
    );
    assert_names(&e, &["mrt", "half_rt", "full_rt"]);
}

#[test]
fn fullscreen_pass_with_mismatched_attachments_is_a_size_mismatch() {
    let mut b = GraphBuilder::new();
    let a = b.create_texture("a", rgba(SizeClass::FULL));
    let c = b.create_texture("c", rgba(SizeClass::fixed(64, 64)));
    let out = {
        let mut p = b.fullscreen_pass("composite", "composite.wgsl", "vs", "fs");
        let o = p.color_attachment(a);
        p.color_attachment(c);
        o
    };
    b.export(out);
    let e = compile_err(b);
    assert!(
        matches!(&e, GraphError::SizeMismatch { pass, resource, found, .. } if pass == "composite" && resource == "c" && found == "fixed 64x64"),
        "{e:?}"
    );
}

#[test]
fn depth_attachment_of_different_size_is_a_size_mismatch() {
    let mut b = GraphBuilder::new();
    let color = b.create_texture("color", rgba(SizeClass::FULL));
    let depth = b.create_texture(
        "depth",
        TextureDesc::new(TextureFormat::Depth32Float, SizeClass::half_pow(1)),
    );
    let out = {
        let mut p = b.custom_pass("draw", NoopPass);
        let o = p.color_attachment(color);
        p.depth_attachment(depth);
        o
    };
    b.export(out);
    assert!(
        matches!(compile_err(b), GraphError::SizeMismatch { pass, resource, .. } if pass == "draw" && resource == "depth")
    );
}

#[test]
fn copy_between_different_sizes_is_a_size_mismatch() {
    let mut b = GraphBuilder::new();
    let src = b.create_texture("src", rgba(SizeClass::FULL));
    let dst = b.create_texture("dst", rgba(SizeClass::half_pow(1)));
    let src1 = b.custom_pass("fill", NoopPass).write_storage("out", src);
    let dst1 = b.copy_pass("downcopy", src1, dst);
    b.export(dst1);
    let e = compile_err(b);
    assert_eq!(
        e,
        GraphError::SizeMismatch {
            pass: "downcopy".into(),
            resource: "dst".into(),
            expected: "full (the size of `src`)".into(),
            found: "1/2".into()
        }
    );
}

#[test]
fn copy_between_different_formats_is_a_format_mismatch() {
    let mut b = GraphBuilder::new();
    let src = b.create_texture("src", rgba(SizeClass::FULL));
    let dst = b.create_texture(
        "dst",
        TextureDesc::new(TextureFormat::R32Float, SizeClass::FULL),
    );
    let src1 = b.custom_pass("fill", NoopPass).write_storage("out", src);
    let dst1 = b.copy_pass("copy", src1, dst);
    b.export(dst1);
    let e = compile_err(b);
    assert!(
        matches!(&e, GraphError::FormatMismatch { pass, resource, found, .. } if pass == "copy" && resource == "dst" && *found == TextureFormat::R32Float),
        "{e:?}"
    );
}

#[test]
fn depth_attachment_with_colour_format_is_a_format_mismatch() {
    let mut b = GraphBuilder::new();
    let t = b.create_texture("not_depth", rgba(SizeClass::FULL));
    let t1 = b.custom_pass("zprepass", NoopPass).depth_attachment(t);
    b.export(t1);
    let e = compile_err(b);
    assert_eq!(
        e,
        GraphError::FormatMismatch {
            pass: "zprepass".into(),
            resource: "not_depth".into(),
            expected: "a depth format".into(),
            found: TextureFormat::Rgba16Float
        }
    );
    assert_names(&e, &["zprepass", "not_depth"]);
    assert!(e.to_string().contains("Rgba16Float"));
}

#[test]
fn colour_attachment_with_depth_format_is_a_format_mismatch() {
    let mut b = GraphBuilder::new();
    let t = b.create_texture(
        "depth",
        TextureDesc::new(TextureFormat::Depth32Float, SizeClass::FULL),
    );
    let t1 = b.custom_pass("draw", NoopPass).color_attachment(t);
    b.export(t1);
    assert!(
        matches!(compile_err(b), GraphError::FormatMismatch { expected, resource, .. } if expected == "a colour format" && resource == "depth")
    );
}

#[test]
fn history_read_but_never_written() {
    let mut b = GraphBuilder::new();
    let h = b.history_texture("taa", rgba(SizeClass::FULL));
    let out = b.create_texture("out", rgba(SizeClass::FULL));
    let out1 = {
        let mut p = b.custom_pass("resolve", NoopPass);
        p.sample("prev", h.previous);
        p.write_storage("out", out)
    };
    b.export(out1);
    let e = compile_err(b);
    assert_eq!(
        e,
        GraphError::HistoryNeverWritten {
            resource: "taa".into()
        }
    );
    assert_names(&e, &["taa"]);
}

#[test]
fn mip_out_of_range_is_an_invalid_pass() {
    let mut b = GraphBuilder::new();
    let t = b.create_texture("pyramid", rgba(SizeClass::FULL).with_mips(2));
    let t1 = b.custom_pass("fill", NoopPass).write_storage("out", t);
    let out = b.create_texture("out", rgba(SizeClass::FULL));
    let out1 = {
        let mut p = b.custom_pass("reader", NoopPass);
        p.sample_mip("src", t1, 2);
        p.write_storage("out", out)
    };
    b.export(out1);
    let e = compile_err(b);
    match &e {
        GraphError::InvalidPass { pass, message } => {
            assert_eq!(pass, "reader");
            assert!(
                message.contains("mip 2")
                    && message.contains("`pyramid`")
                    && message.contains("0..2"),
                "{message}"
            );
        }
        other => panic!("expected InvalidPass, got {other:?}"),
    }
}

#[test]
fn first_write_of_a_mip_of_a_fresh_mipped_texture_compiles() {
    // Building a mip chain: mip 0 is written first (nothing to keep yet), then each level.
    let mut b = GraphBuilder::new();
    let t = b.create_texture("pyramid", rgba(SizeClass::FULL).with_mips(3));
    let mut cur = b
        .custom_pass("mip0", NoopPass)
        .write_storage_mip("dst", t, 0);
    for m in 1..3 {
        let mut p = b.custom_pass(&format!("mip{m}"), NoopPass);
        p.sample_mip("src", cur, m - 1);
        cur = p.write_storage_mip("dst", cur, m);
    }
    b.export(cur);
    let plan = compile(
        b.build(),
        &ShaderLibrary::inline_only(),
        CompileOptions::default(),
    )
    .expect("a mip chain compiles");
    assert_eq!(plan.pass_names(), vec!["mip0", "mip1", "mip2"]);
}

#[test]
fn writing_a_mip_out_of_range_of_a_fresh_texture_is_an_invalid_pass() {
    let mut b = GraphBuilder::new();
    let t = b.create_texture("pyramid", rgba(SizeClass::FULL).with_mips(4));
    let t1 = b
        .custom_pass("writer", NoopPass)
        .write_storage_mip("dst", t, 4);
    b.export(t1);
    assert!(
        matches!(compile_err(b), GraphError::InvalidPass { pass, message } if pass == "writer" && message.contains("mip 4"))
    );
}

#[test]
fn handle_from_another_graph_is_an_invalid_pass_not_a_panic() {
    let mut other = GraphBuilder::new();
    for i in 0..3 {
        other.create_texture(&format!("o{i}"), rgba(SizeClass::FULL));
    }
    let foreign = other.create_texture("foreign", rgba(SizeClass::FULL));
    let mut b = GraphBuilder::new();
    b.custom_pass("p", NoopPass)
        .sample("src", foreign)
        .side_effect();
    assert!(matches!(compile_err(b), GraphError::InvalidPass { pass, .. } if pass == "p"));
}
