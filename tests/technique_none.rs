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

#[test]
fn a_gbuffer_only_frame_runs_no_technique_and_draws_the_same_gbuffer() {
    let scene = aograph_scene::procedural_scene("columns").unwrap();
    let size = Extent::new(67, 37); // odd, non-square
    let Some(none) = common::render_ao(scene.clone(), &common::ao_config("none", 1.0, ""), size, 1)
    else {
        return;
    };
    let outputs = aograph_renderer::FrameOutputs {
        linear_depth: true,
        ..Default::default()
    };
    let mut r = aograph_renderer::Renderer::gbuffer_only(
        none.renderer.gpu.clone(),
        aograph::shader_library(),
        std::sync::Arc::new(scene),
        outputs,
        size,
    )
    .unwrap();
    r.render(0.0).unwrap();
    // The g-buffer is the one the `none` technique's frame draws, texel for texel.
    assert_eq!(r.read_linear_depth().unwrap(), none.depth);
    // No technique's pass is in the plan (the `none` frame has one), and there is no
    // accessibility to read.
    let with_none = none.renderer.plan.pass_names();
    assert!(
        with_none.iter().any(|p| p.starts_with("none")),
        "{with_none:?}"
    );
    let passes = r.plan.pass_names();
    assert!(!passes.iter().any(|p| p.starts_with("none")), "{passes:?}");
    assert_eq!(r.graph.ao, None);
    let err = r.read_ao().unwrap_err().to_string();
    assert!(err.contains("a g-buffer-only frame"), "{err}");
    // A technique later makes it an AO renderer.
    r.set_ao(&common::ao_config("none", 1.0, "")).unwrap();
    r.render(0.0).unwrap();
    assert!(r.read_ao().unwrap().iter().all(|&v| v == 1.0));
}
