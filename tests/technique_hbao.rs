//! `hbao` on the GPU: no self-occlusion on a plane from straight down to grazing, valid output
//! (finite, in [0, 1], sky exactly 1) for the paper's (D, S) rows and with the blur off,
//! occlusion at the sphere's contact (so a shader returning 1 fails), and the MAE against the
//! ray-traced reference on `sphere-on-plane`, bounded.

mod common;

use aograph_graph::Extent;
use aograph_scene::procedural_scene;

const RADIUS: f32 = 1.0;
/// Share of the reference's dark contact pixels (A < 0.9 at 96x96) the technique must darken
/// too: measured 48 of 1,740 = 2.8%: HBAO under-occludes by design, W taken at the horizon sample; the bound leaves room for device differences. A technique returning 1
/// has none.
const MIN_DARK_SHARE: f32 = 0.02;

use common::plane_at;

#[test]
fn plane_is_unoccluded_from_straight_down_to_80_degrees() {
    for degrees in [0.0, 30.0, 60.0, 80.0] {
        let config = common::ao_config("hbao", RADIUS, "");
        let Some(run) = common::render_ao(plane_at(degrees), &config, Extent::new(64, 64), 1)
        else {
            return;
        };
        let what = format!("hbao on plane at {degrees} degrees");
        common::assert_valid_ao(&run.ao, &run.depth, &what);
        assert!(
            run.depth.iter().any(|&d| d > 0.0),
            "{what}: the camera sees the plane"
        );
        // Exactly 1 up to the blur's normalisation (a weighted mean of ones, rounded in f32):
        // the g-buffer normals' rounding is not occlusion (shaders/common/horizon.wgsl).
        let min = run.ao.iter().copied().fold(1.0f32, f32::min);
        assert!(min >= 1.0 - 1e-6, "{what}: darkest pixel {min}");
    }
}

#[test]
fn paper_rows_and_unblurred_output_are_valid() {
    for params in [
        "directions = 16\nsteps = 20",
        "directions = 1\nsteps = 1",
        "blur = false",
    ] {
        let config = common::ao_config("hbao", RADIUS, params);
        let Some(run) = common::render_ao(
            procedural_scene("columns").unwrap(),
            &config,
            Extent::new(64, 48),
            1,
        ) else {
            return;
        };
        common::assert_valid_ao(
            &run.ao,
            &run.depth,
            &format!("hbao [{}] on columns", params.replace('\n', ", ")),
        );
    }
}

#[test]
fn huge_radius_stays_valid() {
    let config = common::ao_config("hbao", 1.0e6, "");
    let Some(run) = common::render_ao(
        procedural_scene("sphere-on-plane").unwrap(),
        &config,
        Extent::new(64, 64),
        1,
    ) else {
        return;
    };
    common::assert_valid_ao(&run.ao, &run.depth, "hbao with R = 1e6");
}

#[test]
fn d8_s10_occludes_near_the_contact() {
    let config = common::ao_config("hbao", RADIUS, "directions = 8\nsteps = 10");
    let Some(run) = common::render_ao(
        procedural_scene("sphere-on-plane").unwrap(),
        &config,
        Extent::new(96, 96),
        1,
    ) else {
        return;
    };
    common::assert_valid_ao(&run.ao, &run.depth, "hbao (8, 10) on sphere-on-plane");
    // The dark region must be the reference's, not a stray pixel: count the pixels the
    // reference darkens below 0.9 (the contact ring) and require the technique to darken a
    // share of those very pixels.
    let reference = common::reference(&run, RADIUS, 256);
    let (dark, dark_ref, both) = common::dark_overlap(&run.ao, &reference, 0.9);
    eprintln!("hbao: {dark} pixels below 0.9, the reference {dark_ref}, both {both}");
    assert!(
        dark_ref > 50,
        "the reference's contact ring: {dark_ref} pixels"
    );
    assert!(
        both as f32 >= MIN_DARK_SHARE * dark_ref as f32,
        "only {both} of the reference's {dark_ref} dark pixels are dark here"
    );
    // And where it is dark, the reference is too (measured: all of them): bounded noise or a
    // misplaced kernel darkens pixels the reference leaves open.
    assert!(
        both as f32 >= 0.9 * dark as f32,
        "{dark} dark pixels, only {both} of them where the reference is dark"
    );
}

#[test]
fn sphere_on_plane_tracks_the_reference() {
    let Some(first) = common::render_ao(
        procedural_scene("sphere-on-plane").unwrap(),
        &common::ao_config("hbao", RADIUS, ""),
        Extent::new(96, 96),
        1,
    ) else {
        return;
    };
    let reference = common::reference(&first, RADIUS, 256);
    let mae_of_one = common::mae(&vec![1.0; reference.len()], &reference, &first.depth);
    println!(
        "accessibility 1 everywhere on sphere-on-plane 96x96, R = {RADIUS}: MAE {mae_of_one:.4}"
    );
    for params in ["", "blur = false", "directions = 16\nsteps = 20"] {
        let run = common::render_ao(
            procedural_scene("sphere-on-plane").unwrap(),
            &common::ao_config("hbao", RADIUS, params),
            Extent::new(96, 96),
            1,
        )
        .unwrap();
        let mae = common::mae(&run.ao, &reference, &run.depth);
        println!(
            "hbao [{}] on sphere-on-plane 96x96, R = {RADIUS}: MAE {mae:.4} against the reference (256 rays)",
            params.replace('\n', ", ")
        );
        // Bounds. Eq. 5 weights sin h by W at the horizon sample, which is usually the farthest
        // sample that still lies within R, so W is small and HBAO under-occludes a binary
        // reference (measured 0.065 against 0.071 for returning 1, lavapipe). It must beat
        // returning 1 by 5% (about half the measured margin, for device differences) and stay
        // under 0.1, below the paper's own HBAO (8, 10) MAE of 0.12 on its simplest scene
        // (Table 1a, Viking Room).
        assert!(
            mae < 0.95 * mae_of_one,
            "[{params}] MAE {mae} does not beat accessibility 1 ({mae_of_one}) by 5%"
        );
        assert!(mae < 0.1, "[{params}] MAE {mae}");
    }
}

/// Per-sample attenuation (Bavoil et al. 2008) weighs each rise of the horizon by W at the
/// sample that raised it, where the Pyramid paper's Eq. 5 takes W once at the horizon sample,
/// the farthest rise: marching outwards, the earlier rises are nearer and weigh more, so the
/// original HBAO occludes more where occluders rise gradually (the sphere's contact). Measured
/// at 96x96 on sphere-on-plane against the reference (blur off, so the estimators alone): the
/// per-sample form is darker on average and closer to the reference.
#[test]
fn per_sample_attenuation_occludes_more_and_tracks_the_reference_closer() {
    let size = Extent::new(96, 96);
    let run = |params: &str| {
        common::render_ao(
            procedural_scene("sphere-on-plane").unwrap(),
            &common::ao_config("hbao", RADIUS, params),
            size,
            1,
        )
    };
    let (Some(horizon), Some(per_sample)) = (
        run("blur = false"),
        run("blur = false\nattenuation = \"per-sample\""),
    ) else {
        return;
    };
    let reference = common::reference(&horizon, RADIUS, 256);
    let mean = |v: &[f32]| common::mae(v, &vec![0.0; v.len()], &horizon.depth);
    let (mh, mp) = (mean(&horizon.ao), mean(&per_sample.ao));
    let (eh, ep) = (
        common::mae(&horizon.ao, &reference, &horizon.depth),
        common::mae(&per_sample.ao, &reference, &horizon.depth),
    );
    eprintln!(
        "mean accessibility: horizon {mh:.4}, per-sample {mp:.4}; MAE {eh:.4} against {ep:.4}"
    );
    assert!(mp < mh - 0.002, "per-sample {mp} against horizon {mh}");
    assert!(ep < eh, "per-sample MAE {ep} against horizon {eh}");
}

/// The original's preset (per-sample, 10-degree bias) on an open plane: the bias only raises
/// the starting horizon, so nothing occludes from straight down to grazing.
#[test]
fn bavoil_preset_leaves_an_open_plane_unoccluded() {
    for degrees in [0.0, 60.0, 85.0] {
        let config = common::ao_config("hbao", RADIUS, "preset = \"bavoil-2008\"");
        let Some(run) = common::render_ao(plane_at(degrees), &config, Extent::new(64, 64), 1)
        else {
            return;
        };
        common::assert_valid_ao(&run.ao, &run.depth, "bavoil-2008 on the plane");
        let min = run.ao.iter().copied().fold(1.0f32, f32::min);
        assert!(min >= 0.99, "{degrees} degrees: darkest pixel {min}");
    }
}
