//! Techniques reach R at any resolution: at 1280x720 on the floor-wall corner (`wall`, whose
//! binary accessibility is known in closed form), the darkened band along the crease of
//! `mssao` and `pyramid-hbao` with `levels = "auto"` must reach to within 20% of the distance
//! the reference's band reaches (at least 80% of it), and the same techniques at a fixed level
//! count too small for this view (the negative control) must fall short.
//!
//! Band reach: floor pixels are binned by their distance d to the wall (from the g-buffer's
//! own points, R/40 per bin, at least 20 pixels each), and the band ends at the first bin past
//! 0.05 R whose mean darkening 1 - A(d) is below 0.003: the edge of the support, well above
//! the bins' noise. A threshold relative to each profile's own crease darkening would measure
//! the shape of the falloff instead of the reach: the techniques weigh occluders by distance
//! (MSSAO's rho, Pyramid HBAO's W = 1 - r/R), so their darkening decays faster than the binary
//! reference's. For the reference the rule gives the closed form's d = 0.967 R
//! (1 - A = (acos a - a sqrt(1 - a^2)) / pi, a = d / R, falls to 0.003 there). A band may also
//! run past the reference's: MSSAO's coarse levels are upsampled over 2^l pixels, so its
//! darkening bleeds beyond R; the test prints the overshoot and does not bound it.

mod common;

use aograph_graph::Extent;
use aograph_scene::procedural::wall_accessibility;
use aograph_scene::{Camera, procedural_scene};
use glam::Vec3;

const SIZE: Extent = Extent {
    width: 1280,
    height: 720,
};
const RADIUS: f32 = 1.0;
/// Bins of the profile per R, out to 1.5 R.
const BINS_PER_R: usize = 40;

/// A view along the crease: the wall (x = 0) on the right, the floor in front.
fn corner_scene() -> aograph_scene::Scene {
    let mut scene = procedural_scene("wall").unwrap();
    scene.camera = Camera::perspective(
        Vec3::new(-2.2, 1.6, 3.0),
        Vec3::new(0.0, 0.0, -0.5),
        50f32.to_radians(),
        0.05,
        3000.0,
    );
    scene
}

/// Mean accessibility per distance bin over the floor (y = 0, x < 0) pixels.
fn profile(ao: &[f32], points: &[Vec3], valid: &[bool]) -> Vec<Option<f32>> {
    let bins = BINS_PER_R * 3 / 2;
    let mut sum = vec![(0.0f64, 0usize); bins];
    for ((a, p), v) in ao.iter().zip(points).zip(valid) {
        if !v || p.y.abs() > 1e-3 || p.x >= 0.0 {
            continue;
        }
        let bin = (-p.x / RADIUS * BINS_PER_R as f32) as usize;
        if let Some(b) = sum.get_mut(bin) {
            b.0 += f64::from(*a);
            b.1 += 1;
        }
    }
    sum.into_iter()
        .map(|(s, n)| (n >= 20).then(|| (s / n as f64) as f32))
        .collect()
}

/// Darkening below which a bin counts as unoccluded.
const SUPPORT_EPSILON: f32 = 0.003;

/// Where the band ends (module docs), in units of R.
fn band_reach(profile: &[Option<f32>]) -> f32 {
    assert!(
        profile[..BINS_PER_R / 20].iter().any(Option::is_some),
        "no floor pixels next to the crease"
    );
    for (i, a) in profile.iter().enumerate().skip(BINS_PER_R / 20) {
        if let Some(a) = a
            && 1.0 - a < SUPPORT_EPSILON
        {
            return i as f32 / BINS_PER_R as f32;
        }
    }
    profile.len() as f32 / BINS_PER_R as f32
}

/// The band reach of `technique` with `params` at 1280x720.
fn technique_reach(technique: &str, params: &str) -> Option<f32> {
    let run = common::render_ao(
        corner_scene(),
        &common::ao_config(technique, RADIUS, params),
        SIZE,
        1,
    )?;
    let s = common::surfaces(&run);
    Some(band_reach(&profile(&run.ao, &s.points, &s.valid)))
}

/// The reference's band reach by the same rule, from the closed form (binned alike).
fn reference_reach() -> f32 {
    let profile: Vec<Option<f32>> = (0..BINS_PER_R * 3 / 2)
        .map(|i| {
            Some(wall_accessibility(
                (i as f32 + 0.5) / BINS_PER_R as f32,
                1.0,
            ))
        })
        .collect();
    band_reach(&profile)
}

#[test]
fn the_closed_form_band_ends_just_short_of_r() {
    let reach = reference_reach();
    assert!((reach - 0.967).abs() <= 1.0 / BINS_PER_R as f32, "{reach}");
}

#[test]
fn auto_levels_reach_the_reference_band_and_fixed_small_pyramids_do_not() {
    let reference = reference_reach();
    let mut failures = Vec::new();
    for (technique, auto_note, short) in [
        ("mssao", "levels = \"auto\"", "levels = 3"),
        ("pyramid-hbao", "levels = \"auto\"", "levels = 2"),
    ] {
        let (Some(auto), Some(cut)) = (
            technique_reach(technique, auto_note),
            technique_reach(technique, short),
        ) else {
            return;
        };
        eprintln!(
            "{technique}: band reaches {auto:.3} R with {auto_note}, {cut:.3} R with {short} (reference {reference:.3} R)"
        );
        if auto < 0.8 * reference {
            failures.push(format!(
                "{technique} ({auto_note}): the band reaches {auto:.3} R, the reference's {reference} R"
            ));
        }
        if cut >= 0.8 * reference {
            failures.push(format!(
                "{technique} ({short}) reaches {cut:.3} R: the negative control should fall short"
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
