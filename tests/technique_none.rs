//! `none` on the GPU: accessibility exactly 1 everywhere, the cost floor.

mod common;

use aograph_graph::Extent;

#[test]
fn none_is_exactly_one_everywhere() {
    let scene = aograph_scene::procedural_scene("columns").unwrap();
    let Some(run) = common::render_ao(
        scene,
        &common::ao_config("none", 1.0, ""),
        Extent::new(64, 48),
        1,
    ) else {
        return;
    };
    assert!(run.ao.iter().all(|&v| v == 1.0));
    assert!(
        run.depth.iter().any(|&d| d > 0.0),
        "the default camera sees geometry"
    );
}
