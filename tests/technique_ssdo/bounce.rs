//! `ssdo`'s indirect bounce carries a wall's colour onto the floor (against the reference's
//! colour under the sky), and its accessibility stays within `ssao`'s error.

use aograph_ao_passes::TechniqueRegistry;
use aograph_graph::Extent;
use aograph_scene::procedural_scene;

use super::*;

/// Mean (red, green) of `ssdo_indirect` over floor pixels of the Cornell box with x in `xs`.
fn floor_indirect(run: &common::AoRun, xs: std::ops::Range<f32>) -> (f32, f32, usize) {
    let s = common::surfaces(run);
    let rgba = run
        .renderer
        .read_extra(aograph_ao_passes::techniques::ssdo::INDIRECT_OUTPUT)
        .unwrap();
    let (mut r, mut g, mut n) = (0.0f64, 0.0f64, 0usize);
    for i in common::cornell_floor_pixels(&s, xs) {
        r += rgba[i * 4] as f64;
        g += rgba[i * 4 + 1] as f64;
        n += 1;
    }
    (
        (r / n.max(1) as f64) as f32,
        (g / n.max(1) as f64) as f32,
        n,
    )
}

#[test]
fn cornell_box_bounce_carries_the_walls_colour_onto_the_floor() {
    let size = Extent::new(96, 96);
    // The paper's distance clamp (1 scene unit) and one scaled to this 2-unit room with R = 0.5.
    let mut first = None;
    for params in ["", "distance_clamp = 0.1"] {
        let Some(run) = common::render_ao(
            procedural_scene("cornell-box").unwrap(),
            &common::ao_config("ssdo", 0.5, params),
            size,
            1,
        ) else {
            return;
        };
        assert_valid(&run, "ssdo on cornell-box");
        let (red_r, red_g, n_red) = floor_indirect(&run, -1.0..-0.75);
        let (green_r, green_g, n_green) = floor_indirect(&run, 0.75..1.0);
        let (mid_r, mid_g, n_mid) = floor_indirect(&run, -0.15..0.15);
        println!(
            "ssdo_indirect on the cornell-box floor (R = 0.5, N = 8, 96x96, [{params}]), mean (red, green):"
        );
        println!(
            "  near the red wall   (x < -0.75, {n_red} px): ({red_r:.4}, {red_g:.4}), red/green {:.2}",
            red_r / red_g.max(1e-9)
        );
        println!(
            "  middle              (|x| < 0.15, {n_mid} px): ({mid_r:.4}, {mid_g:.4}), red/green {:.2}",
            mid_r / mid_g.max(1e-9)
        );
        println!(
            "  near the green wall (x > 0.75, {n_green} px): ({green_r:.4}, {green_g:.4}), red/green {:.2}",
            green_r / green_g.max(1e-9)
        );
        assert!(
            n_red >= 20 && n_green >= 20,
            "the floor near both walls is in view: {n_red}, {n_green} pixels"
        );
        // The colour of the bleed, as ratios with tolerances: measured red/green 1.89 and 1.97
        // near the red wall, 0.38 and 0.35 near the green wall, 1.07 in the middle (both
        // [params] sets). The bounds are those +-25% (the estimator's 8 samples per pixel
        // vary with the device's rounding); the middle sees both walls alike, so its ratio is
        // the floor's own albedo ratio (0.62 / 0.60 = 1.03) shifted a little by the nearer
        // walls: 0.9 to 1.25. A bounce that carried no colour (ratios near 1 everywhere) or
        // the wrong wall's fails.
        let ratio = |r: f32, g: f32| r / g.max(1e-9);
        let (near_red, middle, near_green) = (
            ratio(red_r, red_g),
            ratio(mid_r, mid_g),
            ratio(green_r, green_g),
        );
        assert!(
            red_r > 1e-4 && (1.45..=2.45).contains(&near_red),
            "[{params}] near the red wall red/green {near_red}"
        );
        assert!(
            (0.28..=0.48).contains(&near_green),
            "[{params}] near the green wall red/green {near_green}"
        );
        assert!(
            (0.9..=1.25).contains(&middle),
            "[{params}] middle red/green {middle}"
        );
        first.get_or_insert(run);
    }
    let Some(run) = first else { return };
    let Some(off) = common::render_ao(
        procedural_scene("cornell-box").unwrap(),
        &common::ao_config("ssdo", 0.5, "bounce = false"),
        size,
        1,
    ) else {
        return;
    };
    let indirect = off
        .renderer
        .read_extra(aograph_ao_passes::techniques::ssdo::INDIRECT_OUTPUT)
        .unwrap();
    assert!(
        indirect.chunks_exact(4).all(|px| px[..3] == [0.0; 3]),
        "bounce = false: the indirect term is exactly zero"
    );
    assert_eq!(
        off.ao, run.ao,
        "the bounce does not change the accessibility"
    );
    assert_eq!(
        off.renderer
            .read_extra(aograph_ao_passes::techniques::ssdo::DIRECT_OUTPUT)
            .unwrap(),
        run.renderer
            .read_extra(aograph_ao_passes::techniques::ssdo::DIRECT_OUTPUT)
            .unwrap(),
        "nor the direct term"
    );
}

#[test]
fn sphere_on_plane_accessibility_is_within_the_error_of_ssao() {
    let size = Extent::new(96, 96);
    let registry = TechniqueRegistry::with_builtins();
    for samples in [8, 16] {
        let Some(run) = common::render_ao(
            procedural_scene("sphere-on-plane").unwrap(),
            &common::ao_config("ssdo", RADIUS, &format!("samples = {samples}")),
            size,
            1,
        ) else {
            return;
        };
        assert_valid(&run, "ssdo on sphere-on-plane");
        assert!(run.ao.iter().any(|&a| a < 0.9), "the contact is occluded");
        let reference = common::reference(&run, RADIUS, 256);
        let mae = common::mae(&run.ao, &reference, &run.depth);
        assert!(
            registry.get("ssao").is_ok(),
            "ssao is a built-in technique: the comparison needs it"
        );
        if registry.get("ssao").is_ok() {
            let ssao = common::render_ao(
                procedural_scene("sphere-on-plane").unwrap(),
                &common::ao_config("ssao", RADIUS, &format!("samples = {samples}")),
                size,
                1,
            )
            .unwrap();
            let ssao_mae = common::mae(
                &ssao.ao,
                &common::reference(&ssao, RADIUS, 256),
                &ssao.depth,
            );
            println!(
                "sphere-on-plane 96x96, R = {RADIUS}, N = {samples}: MAE against the reference (256 rays): ssdo {mae:.4}, ssao {ssao_mae:.4}"
            );
            assert!(
                mae <= ssao_mae * 1.1 + 0.005,
                "N = {samples}: ssdo MAE {mae} is not within ssao's {ssao_mae}"
            );
        } else {
            println!(
                "sphere-on-plane 96x96, R = {RADIUS}, N = {samples}: ssdo MAE {mae:.4} (ssao not registered)"
            );
            assert!(mae < 0.1, "MAE {mae}");
        }
    }
}

/// Mean RGB of `rgb(i)` over the Cornell box's floor pixels with x in `xs` (as
/// [`floor_indirect`] picks them).
fn floor_mean(
    s: &aograph_scene::SurfaceBuffer,
    xs: std::ops::Range<f32>,
    rgb: impl Fn(usize) -> glam::Vec3,
) -> glam::Vec3 {
    let picked = common::cornell_floor_pixels(s, xs.clone());
    assert!(
        picked.len() >= 20,
        "{} floor pixels in {xs:?}",
        picked.len()
    );
    picked.iter().map(|&i| rgb(i)).sum::<glam::Vec3>() / picked.len() as f32
}

#[test]
fn cornell_box_bounce_under_the_sky_has_the_references_colour() {
    // SSDO under the built-in sky against the radiance reference (one diffuse bounce from
    // geometry within R, the same sky): the bounce's colour on the floor, as red / green, near
    // each coloured wall. Its strength is E2's business (sender patches, the distance clamp:
    // 0.1 for this 2-unit room, see cornell_box_bounce_carries_the_walls_colour_onto_the_floor);
    // the colour must be the walls'.
    let size = Extent::new(96, 96);
    let Some(run) = common::render_ao(
        procedural_scene("cornell-box").unwrap(),
        &common::ao_config("ssdo", 0.5, "environment = \"sky\"\ndistance_clamp = 0.1"),
        size,
        1,
    ) else {
        return;
    };
    assert_valid(&run, "ssdo under the sky");
    let truth = aograph_renderer::frame_reference::radiance_reference(
        run.renderer.gpu.clone(),
        run.renderer.shaders.clone(),
        &aograph_renderer::frame_reference::FrameView::of(&run.renderer),
        &aograph_renderer::ReferenceSettings::new(0.5, 256),
    )
    .expect("radiance reference traces");
    let s = common::surfaces(&run);
    let gpu = run
        .renderer
        .read_extra(aograph_ao_passes::techniques::ssdo::INDIRECT_OUTPUT)
        .unwrap();
    let px = |i: usize| glam::Vec3::new(gpu[4 * i], gpu[4 * i + 1], gpu[4 * i + 2]);
    let ratio = |c: glam::Vec3| c.x / c.y.max(1e-9);
    for (wall, xs) in [("red", -1.0..-0.75), ("green", 0.75..1.0)] {
        let ours = floor_mean(&s, xs.clone(), px);
        let reference = floor_mean(&s, xs, |i| truth.indirect[i]);
        println!(
            "near the {wall} wall: ssdo indirect {ours} (red/green {:.2}), reference {reference} (red/green {:.2})",
            ratio(ours),
            ratio(reference)
        );
        // 25%: the reference's 256 rays and SSDO's 8 samples per pixel, averaged over the
        // band; a bounce of the wrong wall's colour, or of none, is off by 2x or more.
        let off = ratio(ours) / ratio(reference);
        assert!(
            (0.75..=1.33).contains(&off),
            "{wall}: ratio off by {off:.2}"
        );
    }
}
