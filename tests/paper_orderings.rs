//! The orderings the papers report, checked against our reference on the same frames.

mod common;

use aograph_graph::Extent;

/// Pyramid HBAO paper, Table 1: Pyramid HBAO at L = 4 is at least as accurate as HBAO with
/// D = 8, S = 10.
#[test]
fn pyramid_hbao_l4_is_no_worse_than_hbao_8x10_on_sphere_on_plane() {
    let size = Extent::new(96, 96);
    let scene = || aograph_scene::procedural_scene("sphere-on-plane").unwrap();
    let Some(pyramid) = common::render_ao(
        scene(),
        &common::ao_config("pyramid-hbao", 1.0, "levels = 4"),
        size,
        1,
    ) else {
        return;
    };
    let Some(hbao) = common::render_ao(
        scene(),
        &common::ao_config("hbao", 1.0, "directions = 8\nsteps = 10"),
        size,
        1,
    ) else {
        return;
    };
    let reference = common::reference(&pyramid, 1.0, 256);
    let (mp, mh) = (
        common::mae(&pyramid.ao, &reference, &pyramid.depth),
        common::mae(&hbao.ao, &reference, &hbao.depth),
    );
    println!("sphere-on-plane 96x96 MAE: pyramid-hbao L=4 {mp:.4}, hbao 8x10 {mh:.4}");
    assert!(mp <= mh, "pyramid-hbao {mp} > hbao {mh}");
}
