//! The reference ray tracer against scenes whose accessibility is known in closed form.

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
    let (mut total_error, mut max_error) = (0.0f64, 0.0f32);
    for (i, closed_form) in expected.iter().enumerate() {
        if let Some(closed_form) = closed_form {
            let error = (image.accessibility[i] - closed_form).abs();
            total_error += f64::from(error);
            max_error = max_error.max(error);
        }
    }
    let mean_error = total_error / count as f64;
    eprintln!(
        "sphere-on-plane: {count} pixels, mean abs error {mean_error:.5}, max {max_error:.5}"
    );
    assert!(mean_error < 0.01, "mean absolute error {mean_error}");
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
        for &a in &image.accessibility {
            assert!(
                (a - 0.5).abs() < 0.01,
                "d = {distance}: A = {a}, expected about 0.5"
            );
            assert!(
                (a - closed_form).abs() < 0.005,
                "d = {distance}: A = {a}, closed form {closed_form}"
            );
        }
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
        for (d, a) in distances.iter().zip(&image.accessibility) {
            let expected = wall_accessibility(*d, 1.0);
            assert!(
                (a - expected).abs() < 0.02,
                "scale {scale}, distance {d} R: A = {a}, expected {expected}"
            );
        }
    }
}
