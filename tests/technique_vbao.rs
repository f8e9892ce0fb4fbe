//! `vbao` on the GPU, against closed forms first (docs/techniques/vbao.md §9, §11):
//! - an open plane is exactly 1 from straight down to 80 degrees, under both weightings and
//!   both rounding rules (no tap rises above the tangent plane, so no sector is set);
//! - a conical pit seen along its axis, walls at elevation β, gives 1 - 2β/π with uniform
//!   sectors and cos² β with cosine-weighted ones (V6), exactly where β is a whole number of
//!   sectors; with the /π of V2 dropped (the bug bevy shipped) the pit moves far from both;
//!
//! then thin occluders on `thin-bars` (light passes behind a slab of thickness T, against the
//! height-field limit and against gtao),
//! valid output at every preset, and the MAE against the reference, bounded.

mod common;

use aograph_graph::Extent;
use aograph_scene::procedural_scene;

use common::plane_at;

const RADIUS: f32 = 1.0;

#[test]
fn plane_is_exactly_open_from_straight_down_to_80_degrees() {
    for degrees in [0.0, 30.0, 60.0, 80.0] {
        for params in [
            "",
            "weighting = \"cosine\"",
            "rounding = \"ceil\"",
            "preset = \"low\"\nthickness = 100.0",
        ] {
            let config = common::ao_config("vbao", RADIUS, params);
            let Some(run) = common::render_ao(plane_at(degrees), &config, Extent::new(64, 64), 1)
            else {
                return;
            };
            let what = format!("vbao [{params}] on plane at {degrees} degrees");
            common::assert_valid_ao(&run.ao, &run.depth, &what);
            assert!(run.depth.iter().any(|&d| d > 0.0), "{what}: sees the plane");
            let min = run.ao.iter().copied().fold(1.0f32, f32::min);
            assert!(min >= 1.0 - 1e-6, "{what}: darkest pixel {min}");
        }
    }
}

#[test]
fn pit_gives_the_uniform_and_the_cosine_closed_forms() {
    let size = Extent::new(65, 65);
    // β = 22.5, 45, 67.5 degrees are 4, 8, 12 of 32 sectors of 5.625 degrees: the occluded arc
    // on each side, from the tangent plane up to β, is a whole number of sectors. The thickness
    // covers it (T = 2 R behind the nearest wall tap, 0.07 R away), MIP 0 only, no denoiser.
    let base = "denoise_passes = 0\ndepth_mip_offset = 6.0\nthickness = 2.0\nsteps = 4";
    for beta_deg in [22.5f32, 45.0, 67.5] {
        let beta = beta_deg.to_radians();
        for (weighting, want) in [
            ("uniform", 1.0 - 2.0 * beta / std::f32::consts::PI),
            ("cosine", beta.cos().powi(2)),
        ] {
            let p = format!("{base}\nweighting = \"{weighting}\"");
            let Some(run) = common::render_ao(
                common::cone_pit(beta, 0.05, 1.6, 0.0),
                &common::ao_config("vbao", RADIUS, &p),
                size,
                1,
            ) else {
                return;
            };
            let got = common::centre_value(&run.ao, size);
            println!("vbao {weighting} pit beta = {beta_deg}: {got:.5}, closed form {want:.5}");
            // f32 rounding of the sums only: the sector boundaries fall on whole sectors.
            assert!(
                (got - want).abs() <= 1e-4,
                "{weighting}, beta = {beta_deg}: centre {got}, closed form {want}"
            );
        }
    }
}

#[test]
fn thin_bars_let_light_behind_a_slab_and_vbao_beats_gtao_there() {
    let size = Extent::new(128, 96);
    let scene = || procedural_scene("thin-bars").unwrap();
    let Some(gtao) = common::render_ao(scene(), &common::ao_config("gtao", RADIUS, ""), size, 1)
    else {
        return;
    };
    let render = |params: &str| {
        common::render_ao(scene(), &common::ao_config("vbao", RADIUS, params), size, 1).unwrap()
    };
    // thickness = 100 R: every sample is a height field, as under gtao.
    let (slab, height_field) = (render(""), render("thickness = 100.0"));
    let reference = common::reference(&gtao, RADIUS, 256);
    let depth = &gtao.depth;
    let signed = |ao: &[f32]| {
        let (s, n) = ao
            .iter()
            .zip(&reference)
            .zip(depth)
            .filter(|(_, d)| **d > 0.0)
            .fold((0.0f64, 0usize), |(s, n), ((a, r), _)| {
                (s + (*a - *r) as f64, n + 1)
            });
        (s / n.max(1) as f64) as f32
    };
    let score = |ao: &[f32]| (common::mae(ao, &reference, depth), signed(ao));
    let (g, v, h) = (score(&gtao.ao), score(&slab.ao), score(&height_field.ao));
    println!(
        "thin-bars {size}, R = {RADIUS}: MAE / signed: gtao {:.4} / {:+.4}, vbao {:.4} / {:+.4}, vbao as a height field {:.4} / {:+.4}",
        g.0, g.1, v.0, v.1, h.0, h.1
    );
    // A height field fills everything below a bar's top; a slab of thickness T = 0.5 R lets
    // light pass behind it, so the slab is lighter (measured +0.0142 against +0.0099). At the
    // defaults vbao is already too light here, so the height field's MAE is the lower one
    // (0.0581 against 0.0619): thickness is a tuning parameter, not a free gain.
    assert!(v.1 > h.1 + 1e-3, "slab {v:?} against height field {h:?}");
    // gtao's height field and falloff over R' = 1.457 R over-occlude the bars (-0.0642);
    // vbao's hard R and uniform sectors do not (MAE 0.0619 against 0.0921).
    assert!(v.1 > g.1 && v.0 < g.0, "vbao {v:?} against gtao {g:?}");
}

#[test]
fn every_preset_and_option_gives_valid_output() {
    for params in [
        "preset = \"low\"",
        "preset = \"medium\"",
        "preset = \"ultra\"",
        "sectors = 1",
        "sectors = 7\nrounding = \"ceil\"",
        "weighting = \"cosine\"\nclip_to_radius = false",
        "thickness = 0.01\ndenoise_passes = 3",
    ] {
        let Some(run) = common::render_ao(
            procedural_scene("columns").unwrap(),
            &common::ao_config("vbao", RADIUS, params),
            Extent::new(64, 48),
            1,
        ) else {
            return;
        };
        common::assert_valid_ao(
            &run.ao,
            &run.depth,
            &format!("vbao [{}] on columns", params.replace('\n', ", ")),
        );
    }
    let Some(run) = common::render_ao(
        procedural_scene("sphere-on-plane").unwrap(),
        &common::ao_config("vbao", 1.0e6, ""),
        Extent::new(64, 64),
        1,
    ) else {
        return;
    };
    common::assert_valid_ao(&run.ao, &run.depth, "vbao with R = 1e6");
}

#[test]
fn sphere_on_plane_tracks_the_reference() {
    let size = Extent::new(96, 96);
    let Some(first) = common::render_ao(
        procedural_scene("sphere-on-plane").unwrap(),
        &common::ao_config("vbao", RADIUS, ""),
        size,
        1,
    ) else {
        return;
    };
    let reference = common::reference(&first, RADIUS, 256);
    let mae_of_one = common::mae(&vec![1.0; reference.len()], &reference, &first.depth);
    let (dark, dark_ref, both) = common::dark_overlap(&first.ao, &reference, 0.9);
    println!("vbao: {dark} pixels below 0.9, the reference {dark_ref}, both {both}");
    assert!(
        dark_ref > 50,
        "the reference's contact ring: {dark_ref} pixels"
    );
    // Measured 459 of 1,740 (26%): uniform sectors under-count the deep occlusion near the
    // contact (1 - 2β/π > cos² β past 45 degrees, spec §9); a technique returning 1 has none.
    assert!(
        both as f32 >= 0.2 * dark_ref as f32,
        "only {both} of the reference's {dark_ref} dark pixels are dark here"
    );
    // Where it is dark, the reference is too (measured: all of them).
    assert!(
        both as f32 >= 0.9 * dark as f32,
        "{dark} dark pixels, only {both} of them where the reference is dark"
    );
    // Bounds: the measured MAE (256-ray reference, lavapipe) plus about 15%, each below
    // accessibility 1's 0.0706. The sphere is thicker than T = 0.5 R, so light leaks behind its
    // front taps: vbao at its defaults sits between none and gtao (0.0248) here.
    for (params, bound) in [
        ("", 0.062),
        ("weighting = \"cosine\"", 0.051),
        ("rounding = \"ceil\"", 0.061),
        ("preset = \"low\"", 0.068),
    ] {
        let run = common::render_ao(
            procedural_scene("sphere-on-plane").unwrap(),
            &common::ao_config("vbao", RADIUS, params),
            size,
            1,
        )
        .unwrap();
        let mae = common::mae(&run.ao, &reference, &run.depth);
        println!("vbao [{params}] on sphere-on-plane 96x96: MAE {mae:.4} (none: {mae_of_one:.4})");
        assert!(mae < bound, "vbao [{params}]: MAE {mae}, bound {bound}");
    }
}
