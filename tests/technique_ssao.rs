//! `ssao` on the GPU: no self-occlusion on a plane from straight down to grazing, valid output
//! (finite, in [0, 1], sky exactly 1), occlusion at the sphere's contact, and the MAE against
//! the ray-traced reference on `sphere-on-plane`, bounded.

mod common;

use aograph_graph::Extent;
use aograph_scene::procedural_scene;

const RADIUS: f32 = 1.0;
/// Share of the reference's dark contact pixels (A < 0.9 at 96x96) the technique must darken
/// too: measured 490 of 1,740 = 28%; the bound leaves room for device differences. A technique returning 1
/// has none.
const MIN_DARK_SHARE: f32 = 0.2;

use common::plane_at;

#[test]
fn plane_is_unoccluded_from_straight_down_to_80_degrees() {
    for degrees in [0.0, 30.0, 60.0, 80.0] {
        let config = common::ao_config("ssao", RADIUS, "");
        let Some(run) = common::render_ao(plane_at(degrees), &config, Extent::new(64, 64), 1)
        else {
            return;
        };
        let what = format!("ssao on plane at {degrees} degrees");
        common::assert_valid_ao(&run.ao, &run.depth, &what);
        assert!(
            run.depth.iter().any(|&d| d > 0.0),
            "{what}: the camera sees the plane"
        );
        let min = run.ao.iter().copied().fold(1.0f32, f32::min);
        assert!(min >= 0.98, "{what}: darkest pixel {min}");
    }
}

#[test]
fn sample_counts_give_valid_output() {
    for samples in [4, 64] {
        let config = common::ao_config("ssao", RADIUS, &format!("samples = {samples}"));
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
            &format!("ssao samples = {samples} on columns"),
        );
    }
}

#[test]
fn huge_radius_stays_valid() {
    let config = common::ao_config("ssao", 1.0e6, "");
    let Some(run) = common::render_ao(
        procedural_scene("sphere-on-plane").unwrap(),
        &config,
        Extent::new(64, 64),
        1,
    ) else {
        return;
    };
    common::assert_valid_ao(&run.ao, &run.depth, "ssao with R = 1e6");
}

#[test]
fn sphere_on_plane_occludes_the_contact_and_tracks_the_reference() {
    let config = common::ao_config("ssao", RADIUS, "");
    let Some(run) = common::render_ao(
        procedural_scene("sphere-on-plane").unwrap(),
        &config,
        Extent::new(96, 96),
        1,
    ) else {
        return;
    };
    common::assert_valid_ao(&run.ao, &run.depth, "ssao on sphere-on-plane");
    // The dark region must be the reference's, not a stray pixel: count the pixels the
    // reference darkens below 0.9 (the contact ring) and require the technique to darken a
    // share of those very pixels.
    let reference = common::reference(&run, RADIUS, 256);
    let (dark, dark_ref, both) = common::dark_overlap(&run.ao, &reference, 0.9);
    eprintln!("ssao: {dark} pixels below 0.9, the reference {dark_ref}, both {both}");
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
    let mae = common::mae(&run.ao, &reference, &run.depth);
    let mae_of_one = common::mae(&vec![1.0; reference.len()], &reference, &run.depth);
    println!(
        "ssao (16 samples) on sphere-on-plane 96x96, R = {RADIUS}: MAE {mae:.4} against the reference (256 rays); accessibility 1 everywhere: {mae_of_one:.4}"
    );
    // Bounds. Sample-point SSAO under-occludes a binary reference by construction (a point at
    // distance d < R in front of the occluder is visible although the ray through it is
    // blocked within R), so it cannot get close; measured 0.054 against 0.071 for returning 1
    // (lavapipe). It must clearly beat returning 1 (0.9x leaves ~20% headroom over the
    // measurement for device differences), and stay under 0.1, below the paper-era
    // screen-space methods' 0.12 on Pyramid HBAO's simplest scene (Table 1a, Viking Room).
    assert!(
        mae < 0.9 * mae_of_one,
        "MAE {mae} does not beat accessibility 1 ({mae_of_one}) by 10%"
    );
    assert!(mae < 0.1, "MAE {mae}");
}
