//! Debugging output of a compiled plan: DOT graph and text summary.

use aograph_graph::wgpu::TextureFormat;
use aograph_graph::*;

const HD: Extent = Extent::new(1920, 1080);

fn rgba() -> TextureDesc {
    TextureDesc::new(TextureFormat::Rgba16Float, SizeClass::FULL)
}

/// gbuffer (imported) -> ao -> blur -> composite (exported); "debug_view" is culled.
fn plan(reuse: bool) -> CompiledGraph {
    let mut b = GraphBuilder::new();
    let depth = b.import_texture(
        "depth",
        TextureDesc::new(TextureFormat::R32Float, SizeClass::FULL),
    );
    let ao = b.create_texture("ao_raw", rgba());
    let ao1 = {
        let mut p = b.custom_pass("ao", NoopPass);
        p.sample("depth", depth);
        p.write_storage("dst", ao)
    };
    let blur = b.create_texture("ao_blurred", rgba());
    let blur1 = {
        let mut p = b.custom_pass("blur", NoopPass);
        p.sample("src", ao1);
        p.write_storage("dst", blur)
    };
    let dbg = b.create_texture("debug", rgba());
    {
        let mut p = b.custom_pass("debug_view", NoopPass);
        p.sample("src", ao1);
        p.write_storage("dst", dbg);
    }
    let out = b.create_texture("final", rgba());
    let out1 = {
        let mut p = b.custom_pass("composite", NoopPass);
        p.sample("ao", blur1);
        p.write_storage("dst", out)
    };
    b.export(out1);
    compile(
        b.build(),
        &ShaderLibrary::inline_only(),
        CompileOptions { reuse },
    )
    .unwrap()
}

fn node_line<'a>(dot: &'a str, name: &str) -> &'a str {
    let label = format!("label = \"{name}\"");
    dot.lines()
        .find(|l| l.contains(&label))
        .unwrap_or_else(|| panic!("no node {name} in\n{dot}"))
}

#[test]
fn dot_is_a_digraph_with_every_pass_and_resource() {
    let p = plan(true);
    let dot = to_dot(&p);
    assert!(dot.trim_start().starts_with("digraph"), "{dot}");
    assert!(dot.trim_end().ends_with('}'));
    for name in [
        "ao",
        "blur",
        "debug_view",
        "composite",
        "depth",
        "ao_raw",
        "ao_blurred",
        "debug",
        "final",
    ] {
        node_line(&dot, name);
    }
}

#[test]
fn dot_draws_culled_passes_grey_and_kept_ones_not() {
    let p = plan(true);
    assert_eq!(p.culled_names(), vec!["debug_view"]);
    let dot = to_dot(&p);
    let culled = node_line(&dot, "debug_view");
    assert!(
        culled.contains("fillcolor=lightgrey") && culled.contains("shape=box"),
        "{culled}"
    );
    for kept in ["ao", "blur", "composite"] {
        let l = node_line(&dot, kept);
        assert!(!l.contains("grey"), "{l}");
        assert!(l.contains("shape=box"), "{l}");
    }
    assert!(node_line(&dot, "ao_raw").contains("shape=ellipse"));
    assert_eq!(dot.matches("lightgrey").count(), 1);
}

#[test]
fn dot_has_one_edge_per_read_and_write() {
    let p = plan(true);
    let dot = to_dot(&p);
    // 4 passes: ao (1 read, 1 write), blur (1+1), debug_view (1+1), composite (1+1).
    assert_eq!(dot.matches(" -> ").count(), 8, "{dot}");
    assert!(dot.contains("Sampled") && dot.contains("StorageWrite"));
}

#[test]
fn summary_lists_order_culled_passes_and_bytes() {
    let p = plan(true);
    let s = summary(&p, HD);
    assert!(
        s.contains("3 passes kept, 1 culled, output 1920x1080"),
        "{s}"
    );
    let pos = |needle: &str| {
        s.find(needle)
            .unwrap_or_else(|| panic!("{needle:?} missing from\n{s}"))
    };
    assert!(pos("  0. ao [custom noop]") < pos("  1. blur [custom noop]"));
    assert!(pos("  1. blur [custom noop]") < pos("  2. composite [custom noop]"));
    assert!(
        s.contains("culled:\n     - debug_view: no exported output"),
        "{s}"
    );
    assert!(
        s.contains("reads  depth Sampled 1920x1080 R32Float (imported)"),
        "{s}"
    );
    assert!(
        s.contains("writes ao_raw StorageWrite 1920x1080 Rgba16Float -> texture 0"),
        "{s}"
    );
    let (with, without) = texture_bytes(&p, HD);
    let one = 1920 * 1080 * 8;
    let depth = 1920 * 1080 * 4;
    // ao_raw [0,1], ao_blurred [1,2], final [2,2] exported: ao_raw and final share.
    assert_eq!((with, without), (2 * one + depth, 3 * one + depth));
    assert!(
        s.contains("with reuse, ") && s.contains(&format!("without ({with} / {without} bytes)")),
        "{s}"
    );
    assert!(
        s.contains("physical textures: 2 for 3 transient resources"),
        "{s}"
    );
}

#[test]
fn summary_without_reuse_reports_equal_totals() {
    let p = plan(false);
    let s = summary(&p, HD);
    let (with, without) = texture_bytes(&p, HD);
    assert_eq!(with, without);
    assert!(s.contains(&format!("({with} / {without} bytes)")), "{s}");
    assert!(
        s.contains("physical textures: 3 for 3 transient resources"),
        "{s}"
    );
}

#[test]
fn summary_omits_culled_section_when_nothing_is_culled() {
    let mut b = GraphBuilder::new();
    let t = b.create_texture("t", rgba());
    let t1 = b.custom_pass("only", NoopPass).write_storage("dst", t);
    b.export(t1);
    let p = compile(
        b.build(),
        &ShaderLibrary::inline_only(),
        CompileOptions::default(),
    )
    .unwrap();
    let s = summary(&p, Extent::new(4, 4));
    assert!(!s.contains("culled:"), "{s}");
    assert!(s.contains("1 passes kept, 0 culled"));
    assert!(s.contains("(128 / 128 bytes)"), "{s}");
}
