//! Declare phase: versioned handles, history, export, inferred usage flags.

use aograph_graph::wgpu::{TextureFormat, TextureUsages};
use aograph_graph::*;

fn rgba(size: SizeClass) -> TextureDesc {
    TextureDesc::new(TextureFormat::Rgba16Float, size)
}

fn compile_noop(b: GraphBuilder) -> CompiledGraph {
    compile(
        b.build(),
        &ShaderLibrary::inline_only(),
        CompileOptions::default(),
    )
    .expect("graph compiles")
}

#[test]
fn handle_version_increases_on_each_write() {
    let mut b = GraphBuilder::new();
    let t = b.create_texture("t", rgba(SizeClass::FULL));
    assert_eq!(t.version(), 0);
    let v1 = b
        .custom_pass("a", NoopPass)
        .write_texture(TextureAccess::StorageWrite, t);
    assert_eq!(v1.version(), 1);
    let v2 = b.custom_pass("b", NoopPass).read_write_storage("rw", v1);
    assert_eq!(v2.version(), 2);
    let v3 = b.copy_pass("c", v2, v2);
    assert_eq!(v3.version(), 3);
    for h in [v1, v2, v3] {
        assert_eq!(h.resource_index(), t.resource_index());
    }
    let decl = b.build();
    let res = &decl.resources[t.resource_index()];
    assert_eq!(res.latest_version(), 3);
    assert_eq!(res.producer(0), None);
    assert_eq!(res.producer(1), decl.pass_by_name("a"));
    assert_eq!(res.producer(2), decl.pass_by_name("b"));
    assert_eq!(res.producer(3), decl.pass_by_name("c"));
    assert_eq!(res.producer(4), None);
}

#[test]
fn reads_do_not_bump_versions() {
    let mut b = GraphBuilder::new();
    let t = b.create_texture("t", rgba(SizeClass::FULL));
    let v1 = b
        .custom_pass("w", NoopPass)
        .write_texture(TextureAccess::StorageWrite, t);
    b.custom_pass("r1", NoopPass)
        .sample("src", v1)
        .read_storage("src2", v1)
        .depth_read(v1);
    b.custom_pass("r2", NoopPass)
        .read_texture(TextureAccess::CopySrc, v1);
    let decl = b.build();
    assert_eq!(decl.resources[t.resource_index()].latest_version(), 1);
    let r1 = &decl.passes[decl.pass_by_name("r1").unwrap().index()];
    assert_eq!(r1.textures.len(), 3);
    assert!(
        r1.textures
            .iter()
            .all(|u| u.read == Some(v1) && u.written.is_none())
    );
}

#[test]
fn writes_return_distinct_handles_per_resource() {
    let mut b = GraphBuilder::new();
    let a = b.create_texture("a", rgba(SizeClass::FULL));
    let c = b.create_texture("c", rgba(SizeClass::FULL));
    let (a1, c1) = {
        let mut p = b.custom_pass("p", NoopPass);
        (
            p.write_texture(TextureAccess::StorageWrite, a),
            p.write_texture(TextureAccess::StorageWrite, c),
        )
    };
    assert_ne!(a1, c1);
    assert_eq!((a1.resource_index(), a1.version()), (0, 1));
    assert_eq!((c1.resource_index(), c1.version()), (1, 1));
}

#[test]
fn second_colour_attachment_write_loads_the_previous_version() {
    let mut b = GraphBuilder::new();
    let t = b.create_texture("t", rgba(SizeClass::FULL));
    let v1 = b.custom_pass("clear", NoopPass).color_attachment(t);
    let v2 = b.custom_pass("draw", NoopPass).color_attachment(v1);
    let decl = b.build();
    let clear = &decl.passes[0].textures[0];
    assert_eq!(clear.read, None, "first write clears, it does not read");
    assert_eq!(clear.written, Some(v1));
    let draw = &decl.passes[1].textures[0];
    assert_eq!(
        draw.read,
        Some(v1),
        "a later attachment write loads the old contents"
    );
    assert_eq!(draw.written, Some(v2));
}

#[test]
fn write_only_storage_does_not_read_previous_version() {
    let mut b = GraphBuilder::new();
    let t = b.create_texture("t", rgba(SizeClass::FULL));
    let v1 = b.custom_pass("a", NoopPass).write_storage("dst", t);
    b.custom_pass("b", NoopPass).write_storage("dst", v1);
    let decl = b.build();
    assert_eq!(decl.passes[1].textures[0].read, None);
    assert_eq!(
        decl.passes[1].textures[0].written.map(|h| h.version()),
        Some(2)
    );
}

#[test]
fn single_mip_write_of_a_mipped_texture_reads_previous_version() {
    let mut b = GraphBuilder::new();
    let t = b.create_texture("pyr", rgba(SizeClass::FULL).with_mips(3));
    let v1 = b
        .custom_pass("mip0", NoopPass)
        .write_storage_mip("dst", t, 0);
    let v2 = b
        .custom_pass("mip1", NoopPass)
        .write_storage_mip("dst", v1, 1);
    let decl = b.build();
    let u = &decl.passes[1].textures[0];
    assert_eq!(u.mip, Some(1));
    assert_eq!(
        u.read,
        Some(v1),
        "mip 1 write keeps mip 0, so it depends on it"
    );
    assert_eq!(u.written, Some(v2));
}

#[test]
fn history_texture_gives_previous_and_current() {
    let mut b = GraphBuilder::new();
    let h = b.history_texture("accum", rgba(SizeClass::FULL));
    assert_ne!(h.previous.resource_index(), h.current.resource_index());
    assert_eq!(h.previous.version(), 0);
    assert_eq!(h.current.version(), 0);
    assert_eq!(b.texture_desc(h.previous), Some(rgba(SizeClass::FULL)));
    assert_eq!(b.texture_desc(h.current), Some(rgba(SizeClass::FULL)));
    let decl = b.build();
    let prev = &decl.resources[h.previous.resource_index()];
    let cur = &decl.resources[h.current.resource_index()];
    assert_eq!(prev.name, "accum.previous");
    assert_eq!(cur.name, "accum");
    assert_eq!(
        prev.origin,
        ResourceOrigin::HistoryPrevious {
            history: "accum".into()
        }
    );
    assert_eq!(
        cur.origin,
        ResourceOrigin::HistoryCurrent {
            history: "accum".into()
        }
    );
    assert!(prev.readable_before_write());
    assert!(!cur.readable_before_write());
}

#[test]
fn imported_texture_is_readable_without_a_writer() {
    let mut b = GraphBuilder::new();
    let depth = b.import_texture(
        "depth",
        TextureDesc::new(TextureFormat::R32Float, SizeClass::FULL),
    );
    let out = b.create_texture("out", rgba(SizeClass::FULL));
    let out1 = {
        let mut p = b.custom_pass("shade", NoopPass);
        p.sample("depth", depth);
        p.write_storage("dst", out)
    };
    b.export(out1);
    let plan = compile_noop(b);
    assert_eq!(plan.pass_names(), vec!["shade"]);
    assert_eq!(
        plan.decl.resources[depth.resource_index()].origin,
        ResourceOrigin::Imported
    );
    assert_eq!(
        plan.slot_of[depth.resource_index()],
        None,
        "imported textures are not pooled"
    );
    assert!(plan.slot_of[out.resource_index()].is_some());
}

#[test]
fn export_marks_only_that_resource() {
    let mut b = GraphBuilder::new();
    let a = b.create_texture("a", rgba(SizeClass::FULL));
    let c = b.create_texture("c", rgba(SizeClass::FULL));
    let a1 = b.custom_pass("p", NoopPass).write_storage("dst", a);
    b.custom_pass("q", NoopPass).write_storage("dst", c);
    b.export(a1);
    let decl = b.build();
    assert!(decl.resources[a.resource_index()].exported);
    assert!(!decl.resources[c.resource_index()].exported);
}

#[test]
fn usage_flags_are_inferred_from_accesses() {
    let mut b = GraphBuilder::new();
    let t = b.create_texture("t", rgba(SizeClass::FULL));
    let depth = b.create_texture(
        "depth",
        TextureDesc::new(TextureFormat::Depth32Float, SizeClass::FULL),
    );
    let (t1, d1) = {
        let mut p = b.custom_pass("raster", NoopPass);
        (p.color_attachment(t), p.depth_attachment(depth))
    };
    let u = b.create_texture("u", rgba(SizeClass::FULL));
    let u1 = {
        let mut p = b.custom_pass("post", NoopPass);
        p.sample("color", t1).depth_read(d1);
        p.write_storage("dst", u)
    };
    let c = b.create_texture("copy", rgba(SizeClass::FULL));
    let c1 = b.copy_pass("copy", u1, c);
    b.export(c1);
    let plan = compile_noop(b);
    assert_eq!(plan.pass_names(), vec!["raster", "post", "copy"]);
    let usage = |h: TextureHandle| plan.usage[h.resource_index()];
    assert_eq!(
        usage(t),
        TextureUsages::RENDER_ATTACHMENT | TextureUsages::TEXTURE_BINDING
    );
    assert_eq!(usage(depth), TextureUsages::RENDER_ATTACHMENT);
    assert_eq!(
        usage(u),
        TextureUsages::STORAGE_BINDING | TextureUsages::COPY_SRC
    );
    assert_eq!(
        usage(c),
        TextureUsages::COPY_DST | TextureUsages::COPY_SRC,
        "exported adds COPY_SRC for read-back"
    );
    for h in [t, depth, u, c] {
        let slot = plan.slot_of[h.resource_index()].expect("transient used texture has a slot");
        assert!(
            plan.physical[slot].usage.contains(usage(h)),
            "physical usage covers every resource in it"
        );
    }
}

#[test]
fn physical_texture_usage_is_the_union_of_its_resources() {
    // a (storage) and b (sampled + copy src) share one texture: disjoint lifetimes, same desc.
    let mut b = GraphBuilder::new();
    let a = b.create_texture("a", rgba(SizeClass::FULL));
    let x = b.create_texture(
        "x",
        TextureDesc::new(TextureFormat::R32Float, SizeClass::FULL),
    );
    let a1 = b.custom_pass("p0", NoopPass).write_storage("dst", a);
    let x1 = {
        let mut p = b.custom_pass("p1", NoopPass);
        p.sample("src", a1);
        p.write_storage("dst", x)
    };
    let c = b.create_texture("c", rgba(SizeClass::FULL));
    let c1 = {
        let mut p = b.custom_pass("p2", NoopPass);
        p.sample("src", x1);
        p.color_attachment(c)
    };
    let y = b.create_texture(
        "y",
        TextureDesc::new(TextureFormat::R32Float, SizeClass::FULL),
    );
    let y1 = {
        let mut p = b.custom_pass("p3", NoopPass);
        p.sample("src", c1);
        p.write_storage("dst", y)
    };
    b.export(y1);
    let plan = compile_noop(b);
    let sa = plan.slot_of[a.resource_index()].unwrap();
    assert_eq!(plan.slot_of[c.resource_index()], Some(sa));
    assert_eq!(
        plan.physical[sa].resources,
        vec![a.resource_index(), c.resource_index()]
    );
    assert_eq!(
        plan.physical[sa].usage,
        TextureUsages::STORAGE_BINDING
            | TextureUsages::TEXTURE_BINDING
            | TextureUsages::RENDER_ATTACHMENT
    );
}

#[test]
fn buffer_versions_increase_on_write_only() {
    let mut b = GraphBuilder::new();
    let buf = b.create_buffer("counts", BufferDesc { size: 256 });
    let v1 = b.custom_pass("fill", NoopPass).write_buffer("out", buf);
    assert_eq!(v1.version(), 1);
    b.custom_pass("use", NoopPass)
        .read_buffer("inp", BufferAccess::StorageRead, v1);
    let decl = b.build();
    assert_eq!(decl.resources[buf.resource_index()].latest_version(), 1);
    assert_eq!(
        decl.resources[buf.resource_index()].kind,
        ResourceKind::Buffer(BufferDesc { size: 256 })
    );
}

#[test]
fn dispatch_over_uses_the_size_class_and_mip_written() {
    let mut b = GraphBuilder::new();
    let t = b.create_texture("pyr", rgba(SizeClass::half_pow(1)).with_mips(4));
    let v1 = b
        .custom_pass("seed", NoopPass)
        .write_storage_mip("dst", t, 0);
    let id = {
        let mut p = b.compute_pass("down", "down.wgsl", "main");
        p.write_storage_mip("dst", v1, 2);
        p.dispatch_over(t);
        p.id()
    };
    let decl = b.build();
    match &decl.passes[id.index()].kind {
        PassKind::Compute {
            dispatch,
            shader,
            entry,
        } => {
            assert_eq!(shader, "down.wgsl");
            assert_eq!(entry, "main");
            assert_eq!(
                *dispatch,
                Some(Dispatch::Threads {
                    size: SizeClass::half_pow(1),
                    mip: 2
                })
            );
        }
        other => panic!("expected compute, got {other:?}"),
    }
}

#[test]
fn first_mip_write_of_a_fresh_transient_reads_nothing_but_of_an_import_keeps_it() {
    let mut b = GraphBuilder::new();
    let t = b.create_texture("fresh", rgba(SizeClass::FULL).with_mips(3));
    let imp = b.import_texture("imported", rgba(SizeClass::FULL).with_mips(3));
    {
        let mut p = b.custom_pass("p", NoopPass);
        p.write_storage_mip("a", t, 0);
        p.write_storage_mip("b", imp, 1);
    }
    let decl = b.build();
    let uses = &decl.passes[0].textures;
    assert_eq!(
        uses[0].read, None,
        "version 0 of a transient holds nothing to keep"
    );
    assert_eq!(
        uses[1].read,
        Some(imp),
        "other mips of an import are kept, so it is read"
    );
}
