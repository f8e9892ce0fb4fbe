//! The reference ray tracer against scenes whose accessibility is known in closed form.
//!
//! Tolerances come from the estimator's own noise: each pixel reports its standard error s_i
//! (the i.i.d. formula, an upper bound for the stratified Sobol estimate), so a pixel more than
//! 5 s_i (plus the scene's tessellation error) from the closed form is a bug, not bad luck
//! (P(|z| > 5) = 6e-7 per pixel). The mean signed error must stay within 5 standard errors of
//! the mean, sqrt(sum s_i^2) / n, so a biased tracer fails even when each pixel looks plausible.

use aograph_scene::procedural::{
    SPHERE_ON_PLANE_CENTRE, SPHERE_ON_PLANE_RADIUS, WALL_PLANE_X, sphere_on_plane_accessibility,
    wall_accessibility,
};
use aograph_scene::reference::ProgressMode;
use aograph_scene::{
    ReferenceMode, ReferenceParams, SurfaceBuffer, TriangleBvh, primary_hits, procedural_scene,
    trace_reference,
};
use glam::Vec3;

fn params(radius: f32, rays_per_pixel: u32) -> ReferenceParams {
    ReferenceParams {
        radius,
        rays_per_pixel,
        mode: ReferenceMode::Binary,
        progress: ProgressMode::Never,
    }
}

#[test]
fn flat_plane_reference_is_exactly_one() {
    let scene = procedural_scene("plane").unwrap();
    let surfaces = primary_hits(&scene, &scene.camera, 32, 32, 0.0);
    assert!(
        surfaces.valid_count() > 32 * 16,
        "the floor should fill most of the view"
    );
    let bvh = TriangleBvh::new(&scene.world_triangles(0.0));
    for mode in [ReferenceMode::Binary, ReferenceMode::Obscurance] {
        let image = trace_reference(
            &bvh,
            &surfaces,
            &ReferenceParams {
                mode,
                ..params(5.0, 64)
            },
        )
        .unwrap();
        assert!(image.accessibility.iter().all(|&a| a == 1.0), "{mode:?}");
        assert!(image.std_error.iter().all(|&e| e == 0.0), "{mode:?}");
    }
}

#[test]
fn sphere_on_plane_reference_matches_closed_form() {
    let scene = procedural_scene("sphere-on-plane").unwrap();
    let mut surfaces = primary_hits(&scene, &scene.camera, 48, 48, 0.0);
    // Keep only floor pixels where the closed form holds; the rest become sky (not traced).
    let expected: Vec<Option<f32>> = (0..surfaces.valid.len())
        .map(|i| {
            let on_floor = surfaces.valid[i] && surfaces.normals[i].y > 0.999;
            on_floor
                .then(|| sphere_on_plane_accessibility(surfaces.points[i], surfaces.normals[i]))
                .flatten()
        })
        .collect();
    for (valid, closed_form) in surfaces.valid.iter_mut().zip(&expected) {
        *valid = closed_form.is_some();
    }
    let count = surfaces.valid_count();
    assert!(count > 500, "only {count} floor pixels to test");
    // R must contain the sphere from every tested point.
    let farthest = surfaces
        .points
        .iter()
        .zip(&surfaces.valid)
        .filter(|(_, v)| **v)
        .map(|(p, _)| p.distance(SPHERE_ON_PLANE_CENTRE) + SPHERE_ON_PLANE_RADIUS)
        .fold(0.0f32, f32::max);
    let bvh = TriangleBvh::new(&scene.world_triangles(0.0));
    let image = trace_reference(&bvh, &surfaces, &params(farthest * 1.01, 4096)).unwrap();
    // The 128 x 64 sphere's facets sit up to r (1 - cos(pi / 128)) = 3e-4 inside the true
    // sphere: its solid angle, and so the closed form, is off by about 1e-3 at most.
    let check = check_against_closed_form(&image, &expected, 1e-3);
    eprintln!("sphere-on-plane, 4096 rays: {check}");
    check.assert_within(5.0);
}

/// How a traced image compares with per-pixel closed forms.
struct ClosedFormCheck {
    count: usize,
    mean_abs: f64,
    mean_signed: f64,
    /// Standard error of the mean: sqrt(sum s_i^2) / n.
    mean_std_error: f64,
    /// The worst |error| / (s_i + model error), and that pixel's error and s_i.
    worst_z: f64,
    worst: (f32, f32),
    max_abs: f32,
    model_error: f32,
}

impl std::fmt::Display for ClosedFormCheck {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} pixels, mean |error| {:.5}, mean signed {:+.5} (standard error {:.5}), max |error| {:.5}, worst pixel {:.5} at s = {:.5} ({:.2} s)",
            self.count,
            self.mean_abs,
            self.mean_signed,
            self.mean_std_error,
            self.max_abs,
            self.worst.0,
            self.worst.1,
            self.worst_z
        )
    }
}

impl ClosedFormCheck {
    /// Every pixel within `k` of its standard error (plus the model error) and the mean
    /// signed error within `k` standard errors of the mean (plus the model error).
    fn assert_within(&self, k: f64) {
        assert!(self.count > 0, "no pixel compared");
        assert!(
            self.worst_z <= k,
            "a pixel is {:.2} standard errors off: {self}",
            self.worst_z
        );
        assert!(
            self.mean_signed.abs() <= k * self.mean_std_error + f64::from(self.model_error),
            "biased: {self}"
        );
    }
}

/// Compares `image` with `expected` where it is `Some`; `model_error` bounds how far the
/// scene's geometry (tessellation) moves the closed form.
fn check_against_closed_form(
    image: &aograph_scene::ReferenceImage,
    expected: &[Option<f32>],
    model_error: f32,
) -> ClosedFormCheck {
    let mut c = ClosedFormCheck {
        count: 0,
        mean_abs: 0.0,
        mean_signed: 0.0,
        mean_std_error: 0.0,
        worst_z: 0.0,
        worst: (0.0, 0.0),
        max_abs: 0.0,
        model_error,
    };
    let mut variance = 0.0f64;
    for (i, closed_form) in expected.iter().enumerate() {
        let Some(closed_form) = closed_form else {
            continue;
        };
        let error = image.accessibility[i] - closed_form;
        let s = image.std_error[i];
        c.count += 1;
        c.mean_abs += f64::from(error.abs());
        c.mean_signed += f64::from(error);
        variance += f64::from(s) * f64::from(s);
        c.max_abs = c.max_abs.max(error.abs());
        // A pixel whose estimate is exactly 0 or 1 reports s = 0; one ray's worth of
        // resolution (1 / N) stands in for it.
        let scale = f64::from(s.max(1.0 / 4096.0) + model_error);
        let z = f64::from(error.abs()) / scale;
        if z > c.worst_z {
            c.worst_z = z;
            c.worst = (error, s);
        }
    }
    let n = c.count.max(1) as f64;
    c.mean_abs /= n;
    c.mean_signed /= n;
    c.mean_std_error = variance.sqrt() / n;
    c
}

#[test]
fn wall_floor_points_near_the_wall_see_one_half() {
    let scene = procedural_scene("wall").unwrap();
    let bvh = TriangleBvh::new(&scene.world_triangles(0.0));
    for distance in [0.001f32, 0.05, 2.0] {
        let points: Vec<Vec3> = (0..8)
            .map(|k| Vec3::new(WALL_PLANE_X - distance, 0.0, k as f32 * 3.0 - 10.0))
            .collect();
        let surfaces = SurfaceBuffer {
            width: points.len() as u32,
            height: 1,
            normals: vec![Vec3::Y; points.len()],
            valid: vec![true; points.len()],
            points,
        };
        let radius = 100.0 * distance;
        let image = trace_reference(&bvh, &surfaces, &params(radius, 1024)).unwrap();
        let closed_form = wall_accessibility(distance, radius);
        assert!((closed_form - 0.5).abs() < 0.01, "{closed_form}");
        // The wall reaches 1000 units: the scene is the closed form's, no model error.
        let check = check_against_closed_form(&image, &[Some(closed_form); 8], 0.0);
        eprintln!("wall at d = {distance}, 1024 rays: {check}");
        check.assert_within(5.0);
        // Sobol stratification does far better than the i.i.d. bound (s = 0.0156 here): a
        // plane splits the hemisphere's disk along a line, which every 2^k prefix samples
        // evenly. A tracer that lost the stratification would exceed this.
        assert!(check.max_abs < 0.005, "{check}");
    }
}

#[test]
fn reference_is_deterministic_finite_and_in_range() {
    let scene = procedural_scene("columns").unwrap();
    let surfaces = primary_hits(&scene, &scene.camera, 24, 16, 0.0);
    let bvh = TriangleBvh::new(&scene.world_triangles(0.0));
    let p = ReferenceParams {
        mode: ReferenceMode::Obscurance,
        ..params(1.0, 16)
    };
    let first = trace_reference(&bvh, &surfaces, &p).unwrap();
    let second = trace_reference(&bvh, &surfaces, &p).unwrap();
    assert_eq!(first, second);
    assert!(
        first
            .accessibility
            .iter()
            .all(|a| a.is_finite() && (0.0..=1.0).contains(a))
    );
    assert!(first.std_error.iter().all(|e| e.is_finite() && *e >= 0.0));
    assert!(
        first.accessibility.iter().any(|&a| a < 0.9),
        "the arcade should have some occlusion"
    );
}

/// A floor (y = 0) and a wall (x = 0), `100 * scale` in extent, moved by `shift`.
fn floor_and_wall(scale: f32, shift: Vec3) -> Vec<[Vec3; 3]> {
    let b = 100.0 * scale;
    let quads = [
        [
            Vec3::new(-b, 0.0, -b),
            Vec3::new(-b, 0.0, b),
            Vec3::new(b, 0.0, b),
            Vec3::new(b, 0.0, -b),
        ],
        [
            Vec3::new(0.0, 0.0, -b),
            Vec3::new(0.0, b, -b),
            Vec3::new(0.0, b, b),
            Vec3::new(0.0, 0.0, b),
        ],
    ];
    quads
        .iter()
        .flat_map(|[a, b, c, d]| [[*a, *b, *c], [*a, *c, *d]])
        .map(|tri| tri.map(|v| v + shift))
        .collect()
}

#[test]
fn reference_works_at_scales_from_a_thousandth_to_ten_thousand() {
    for scale in [1e-3f32, 1.0, 1e4] {
        let shift = Vec3::new(3.0, 2.0, -5.0) * scale;
        let bvh = TriangleBvh::new(&floor_and_wall(scale, shift));
        // Floor points 0.01 and 0.3 radii from the wall, one next to the crease (1e-5 R) and one
        // far away. (A point exactly on the wall's plane is ambiguous: its rays start on the
        // wall.)
        let distances = [0.01f32, 0.3, 1e-5, 50.0];
        let points: Vec<Vec3> = distances
            .iter()
            .map(|d| Vec3::new(-d * scale, 0.0, 0.4 * scale) + shift)
            .collect();
        let surfaces = SurfaceBuffer {
            width: points.len() as u32,
            height: 1,
            normals: vec![Vec3::Y; points.len()],
            valid: vec![true; points.len()],
            points,
        };
        let image = trace_reference(&bvh, &surfaces, &params(scale, 1024)).unwrap();
        let expected: Vec<Option<f32>> = distances
            .iter()
            .map(|d| Some(wall_accessibility(*d, 1.0)))
            .collect();
        let check = check_against_closed_form(&image, &expected, 0.0);
        eprintln!("floor and wall at scale {scale}: {check}");
        check.assert_within(5.0);
    }
}
