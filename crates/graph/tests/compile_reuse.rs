//! Compile: resource lifetimes and reuse of physical textures.

use aograph_graph::wgpu::TextureFormat;
use aograph_graph::*;

const HD: Extent = Extent::new(1920, 1080);

fn rgba(size: SizeClass) -> TextureDesc {
    TextureDesc::new(TextureFormat::Rgba16Float, size)
}

fn compile_with(b: GraphBuilder, reuse: bool) -> CompiledGraph {
    compile(
        b.build(),
        &ShaderLibrary::inline_only(),
        CompileOptions { reuse },
    )
    .expect("graph compiles")
}

/// a -> b -> c -> d, each writing its own texture of `desc`, d's output exported.
fn chain(n: usize, desc: TextureDesc) -> (GraphBuilder, Vec<TextureHandle>) {
    let mut b = GraphBuilder::new();
    let mut outs: Vec<TextureHandle> = Vec::new();
    for i in 0..n {
        let t = b.create_texture(&format!("t{i}"), desc);
        let mut p = b.custom_pass(&format!("p{i}"), NoopPass);
        if let Some(prev) = outs.last() {
            p.sample("src", *prev);
        }
        outs.push(p.write_storage("dst", t));
    }
    b.export(*outs.last().unwrap());
    (b, outs)
}

/// Side-effect passes that each write (only) their own texture: every lifetime is one step.
fn isolated(descs: &[TextureDesc]) -> (GraphBuilder, Vec<TextureHandle>) {
    let mut b = GraphBuilder::new();
    let mut outs = Vec::new();
    for (i, d) in descs.iter().enumerate() {
        let t = b.create_texture(&format!("t{i}"), *d);
        let mut p = b.custom_pass(&format!("p{i}"), NoopPass);
        p.side_effect();
        outs.push(p.write_storage("dst", t));
    }
    (b, outs)
}

#[test]
fn lifetimes_span_first_to_last_use_in_the_order() {
    let (mut b, outs) = chain(3, rgba(SizeClass::FULL));
    // A late reader of t0 extends its lifetime to position 3.
    b.custom_pass("late", NoopPass)
        .sample("src", outs[0])
        .sample("src2", outs[2])
        .side_effect();
    let plan = compile_with(b, true);
    assert_eq!(plan.pass_names(), vec!["p0", "p1", "p2", "late"]);
    let life = |h: TextureHandle| plan.lifetimes[h.resource_index()];
    assert_eq!(life(outs[0]), Some(Lifetime { first: 0, last: 3 }));
    assert_eq!(life(outs[1]), Some(Lifetime { first: 1, last: 2 }));
    assert_eq!(life(outs[2]), Some(Lifetime { first: 2, last: 3 }));
}

#[test]
fn exported_resource_lives_to_the_end_of_the_frame() {
    let mut b = GraphBuilder::new();
    let e = b.create_texture("early", rgba(SizeClass::FULL));
    let e1 = b.custom_pass("p0", NoopPass).write_storage("dst", e);
    b.export(e1);
    for i in 1..3 {
        let t = b.create_texture(&format!("t{i}"), rgba(SizeClass::FULL));
        b.custom_pass(&format!("p{i}"), NoopPass)
            .side_effect()
            .write_storage("dst", t);
    }
    let plan = compile_with(b, true);
    assert_eq!(
        plan.lifetimes[e.resource_index()],
        Some(Lifetime { first: 0, last: 2 })
    );
}

#[test]
fn unused_resource_has_no_lifetime_and_no_slot() {
    let (mut b, _) = chain(2, rgba(SizeClass::FULL));
    let spare = b.create_texture("spare", rgba(SizeClass::FULL));
    let plan = compile_with(b, true);
    assert_eq!(plan.lifetimes[spare.resource_index()], None);
    assert_eq!(plan.slot_of[spare.resource_index()], None);
}

#[test]
fn equal_descriptors_with_disjoint_lifetimes_share_a_texture() {
    let (b, outs) = chain(4, rgba(SizeClass::FULL));
    let plan = compile_with(b, true);
    // t0 [0,1] t1 [1,2] t2 [2,3] t3 [3,3]: two textures alternate.
    let slot = |i: usize| plan.slot_of[outs[i].resource_index()].unwrap();
    assert_eq!(plan.physical.len(), 2);
    assert_eq!(slot(0), slot(2));
    assert_eq!(slot(1), slot(3));
    assert_ne!(slot(0), slot(1));
    assert_eq!(
        plan.physical[slot(0)].resources,
        vec![outs[0].resource_index(), outs[2].resource_index()]
    );
    assert_eq!(plan.physical[slot(0)].desc, rgba(SizeClass::FULL));
}

#[test]
fn overlapping_lifetimes_never_share() {
    let (b, outs) = chain(2, rgba(SizeClass::FULL));
    let plan = compile_with(b, true);
    // p1 reads t0 and writes t1 at the same position.
    assert_ne!(
        plan.slot_of[outs[0].resource_index()],
        plan.slot_of[outs[1].resource_index()]
    );
    assert_eq!(plan.physical.len(), 2);
}

#[test]
fn different_formats_or_size_classes_never_share() {
    let full = rgba(SizeClass::FULL);
    let r32 = TextureDesc::new(TextureFormat::R32Float, SizeClass::FULL);
    let half = rgba(SizeClass::half_pow(1));
    let mipped = rgba(SizeClass::FULL).with_mips(2);
    let (b, outs) = isolated(&[full, r32, half, mipped, full, r32, half]);
    let plan = compile_with(b, true);
    let slot = |i: usize| plan.slot_of[outs[i].resource_index()].unwrap();
    assert_eq!(plan.physical.len(), 4);
    assert_eq!(slot(0), slot(4));
    assert_eq!(slot(1), slot(5));
    assert_eq!(slot(2), slot(6));
    let distinct: std::collections::BTreeSet<usize> = [slot(0), slot(1), slot(2), slot(3)].into();
    assert_eq!(distinct.len(), 4);
    for p in &plan.physical {
        for &r in &p.resources {
            assert_eq!(plan.decl.resources[r].texture_desc(), Some(&p.desc));
        }
    }
}

#[test]
fn exported_resource_is_never_reused_by_a_later_resource() {
    let (mut b, outs) = isolated(&[rgba(SizeClass::FULL); 3]);
    b.export(outs[0]);
    let plan = compile_with(b, true);
    let slot = |i: usize| plan.slot_of[outs[i].resource_index()].unwrap();
    assert_eq!(
        plan.physical[slot(0)].resources,
        vec![outs[0].resource_index()]
    );
    assert_ne!(slot(1), slot(0));
    assert_ne!(slot(2), slot(0));
    assert_eq!(slot(1), slot(2), "the non-exported ones still share");
}

#[test]
fn reuse_disabled_gives_one_texture_per_transient() {
    let (b, outs) = chain(5, rgba(SizeClass::FULL));
    let plan = compile_with(b, false);
    assert_eq!(plan.options, CompileOptions { reuse: false });
    assert_eq!(plan.physical.len(), 5);
    for (i, h) in outs.iter().enumerate() {
        let s = plan.slot_of[h.resource_index()].unwrap();
        assert_eq!(plan.physical[s].resources, vec![outs[i].resource_index()]);
    }
}

#[test]
fn texture_bytes_with_reuse_are_exact_and_at_most_without() {
    let (b, _) = chain(4, rgba(SizeClass::FULL));
    let plan = compile_with(b, true);
    let one = 1920 * 1080 * 8;
    assert_eq!(texture_bytes(&plan, HD), (2 * one, 4 * one));

    let (b, _) = chain(4, rgba(SizeClass::FULL));
    let no_reuse = compile_with(b, false);
    assert_eq!(texture_bytes(&no_reuse, HD), (4 * one, 4 * one));
}

#[test]
fn texture_bytes_count_imported_and_history_in_both_totals() {
    let mut b = GraphBuilder::new();
    let depth = b.import_texture(
        "depth",
        TextureDesc::new(TextureFormat::R32Float, SizeClass::FULL),
    );
    let h = b.history_texture("hist", rgba(SizeClass::half_pow(1)));
    let t = b.create_texture("t", rgba(SizeClass::FULL));
    {
        let mut p = b.custom_pass("p", NoopPass);
        p.sample("depth", depth).sample("prev", h.previous);
        p.write_storage("dst", t);
        p.write_storage("hist", h.current);
    }
    let plan = compile_with(b, true);
    let persistent = 1920 * 1080 * 4 + 2 * 960 * 540 * 8;
    let transient = 1920 * 1080 * 8;
    assert_eq!(
        texture_bytes(&plan, HD),
        (persistent + transient, persistent + transient)
    );
}

#[test]
fn every_used_transient_texture_has_a_slot_with_its_descriptor() {
    let (mut b, outs) = chain(3, rgba(SizeClass::half_pow(2)));
    let extra = b.create_texture(
        "extra",
        TextureDesc::new(TextureFormat::R32Float, SizeClass::FULL),
    );
    {
        let mut p = b.custom_pass("extra", NoopPass);
        p.sample("src", outs[1]).side_effect();
        p.write_storage("dst", extra);
    }
    let plan = compile_with(b, true);
    for (r, res) in plan.decl.resources.iter().enumerate() {
        if plan.lifetimes[r].is_some() && res.origin == ResourceOrigin::Transient {
            let s = plan.slot_of[r].expect("slot");
            assert_eq!(Some(&plan.physical[s].desc), res.texture_desc());
            assert!(plan.physical[s].resources.contains(&r));
        }
    }
}
