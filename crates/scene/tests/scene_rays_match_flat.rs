//! The two-level `SceneRays` answers exactly what the flat `TriangleBvh` over
//! `Scene::world_triangles` answers: the same distance for every ray (bit for bit), the same
//! any-hit answer, the same triangle and vertex normals for every index, hence the same CPU
//! g-buffer and the same reference image. Checked on scenes whose shared meshes are
//! rotated, scaled non-uniformly, mirrored, sheared, flattened to zero thickness and moved far
//! from the origin, next to meshes placed once and a skinned one.

mod common;

use aograph_scene::primitives::{cuboid, uv_sphere};
use aograph_scene::procedural::instanced_field;
use aograph_scene::{
    BruteForceTracer, Camera, CpuGBuffer, ReferenceMode, ReferenceNormals, ReferenceParams, Scene,
    SceneBuilder, SceneRays, TriangleBvh, load_scene, test_scene, trace_reference,
};
use common::Lcg;
use glam::{Mat4, Quat, Vec3};

/// One box mesh placed under every kind of transform, a sphere placed twice, a sphere placed
/// once, and a ground.
fn transformed_copies() -> Scene {
    let mut b = SceneBuilder::new();
    let m = b.material([0.6; 3]);
    let cube = b.mesh(cuboid(Vec3::new(1.0, 0.6, 0.8), m));
    let sphere = b.mesh(uv_sphere(0.5, 12, 8, m));
    let transforms = [
        Mat4::IDENTITY,
        Mat4::from_rotation_translation(Quat::from_rotation_y(0.7), Vec3::new(2.0, 0.0, 0.3)),
        Mat4::from_scale_rotation_translation(
            Vec3::new(0.3, 2.5, 1.0),
            Quat::from_rotation_z(0.4),
            Vec3::new(-2.0, 0.5, 0.0),
        ),
        // Mirrored.
        Mat4::from_translation(Vec3::new(0.0, 0.0, 2.5))
            * Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0)),
        // Sheared.
        Mat4::from_translation(Vec3::new(0.0, 1.5, -2.0))
            * Mat4::from_cols_array(&[
                1.0, 0.0, 0.0, 0.0, 0.8, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0,
            ]),
        // Flattened to zero thickness: singular, so placed in world space.
        Mat4::from_translation(Vec3::new(3.0, 0.0, -2.0))
            * Mat4::from_scale(Vec3::new(1.0, 0.0, 1.0)),
        // Tiny and far from the origin.
        Mat4::from_scale_rotation_translation(
            Vec3::splat(1e-3),
            Quat::from_rotation_x(1.1),
            Vec3::new(0.0, 0.2, 40.0),
        ),
    ];
    for t in transforms {
        b.place(cube, t);
    }
    b.place(sphere, Mat4::from_translation(Vec3::new(1.0, 1.2, 1.0)));
    b.place(sphere, Mat4::from_translation(Vec3::new(-1.0, 1.2, 1.0)));
    b.add(
        uv_sphere(0.4, 9, 6, m),
        Mat4::from_translation(Vec3::new(0.0, 2.0, 0.0)),
    );
    b.add(
        cuboid(Vec3::new(12.0, 0.1, 12.0), m),
        Mat4::from_translation(Vec3::new(0.0, -0.4, 0.0)),
    );
    b.build(Camera::perspective(
        Vec3::new(4.0, 3.0, 6.0),
        Vec3::ZERO,
        0.9,
        0.05,
        100.0,
    ))
}

/// The scenes compared: copies under every transform, a field of spheres, and a skinned man
/// standing in that field (one skinned instance, placed in world space).
fn scenes() -> Vec<(&'static str, Scene)> {
    let mut out = vec![
        ("transformed copies", transformed_copies()),
        ("instanced field", instanced_field(30, 300)),
    ];
    if let Some(path) = test_scene("scene_rays_match_flat", "CesiumMan.glb") {
        out.push(("skinned", load_scene(path).unwrap()));
    }
    out
}

#[test]
fn every_ray_hits_at_the_same_distance_as_in_the_flattened_scene() {
    let mut rng = Lcg(0x2_1e7e1);
    for (name, scene) in scenes() {
        let t = 0.3;
        let flat_triangles = scene.world_triangles(t);
        let flat = TriangleBvh::new(&flat_triangles);
        let brute = BruteForceTracer::new(&flat_triangles);
        let rays = SceneRays::new(&scene, t);
        assert_eq!(rays.triangle_count(), flat_triangles.len(), "{name}");
        let bounds = scene.bounds_at(t);
        let (mut hits, mut shared_hits) = (0, 0);
        for i in 0..4000 {
            // Origins inside and around the scene's box, some on its geometry's scale.
            let origin = bounds.min
                + (bounds.max - bounds.min) * Vec3::new(rng.next(), rng.next(), rng.next()) * 1.4
                - (bounds.max - bounds.min) * 0.2;
            // Every other ray aims at a point of a random triangle, so most rays meet geometry.
            let direction = if i % 2 == 0 {
                let [a, b, c] = flat_triangles
                    [(rng.next() * flat_triangles.len() as f32) as usize % flat_triangles.len()];
                let (u, v) = (rng.next(), rng.next());
                let (u, v) = if u + v > 1.0 {
                    (1.0 - u, 1.0 - v)
                } else {
                    (u, v)
                };
                (a + (b - a) * u + (c - a) * v - origin)
                    .try_normalize()
                    .unwrap_or(Vec3::Y)
            } else {
                rng.direction()
            };
            let t_max = if i % 3 == 0 {
                f32::INFINITY
            } else {
                bounds.diagonal() * rng.next()
            };
            let expected = flat.closest_hit(origin, direction, 0.0, t_max);
            let got = rays.closest_hit(origin, direction, 0.0, t_max);
            // The flat BVH is itself held to testing every triangle (it once lost hits in
            // subtrees flat along an axis, such as the squashed box's).
            assert_eq!(
                expected.map(|h| h.distance.to_bits()),
                brute
                    .closest_hit(origin, direction, 0.0, t_max)
                    .map(|h| h.distance.to_bits()),
                "{name}: flat BVH against brute force, ray {i} from {origin} along {direction}"
            );
            assert_eq!(
                got.map(|h| h.distance.to_bits()),
                expected.map(|h| h.distance.to_bits()),
                "{name}: ray {i} from {origin} along {direction} to {t_max}"
            );
            if let (Some(got), Some(expected)) = (got, expected) {
                hits += 1;
                // The same triangle, unless two lie at exactly that distance.
                let same_place = got.triangle == expected.triangle
                    || flat_triangles[got.triangle] == flat_triangles[expected.triangle]
                    || TriangleBvh::new(&[flat_triangles[got.triangle]])
                        .closest_hit(origin, direction, 0.0, t_max)
                        .is_some_and(|h| h.distance == got.distance);
                assert!(
                    same_place,
                    "{name}: ray {i} reports triangle {} for {}",
                    got.triangle, expected.triangle
                );
                shared_hits += usize::from(got.triangle != expected.triangle);
            }
            assert_eq!(
                rays.any_hit(origin, direction, 0.0, t_max),
                flat.any_hit(origin, direction, 0.0, t_max),
                "{name}: any-hit of ray {i}"
            );
        }
        // Enough rays met geometry for the comparison to mean something.
        assert!(
            hits > 400,
            "{name}: only {hits} of 4000 rays hit ({shared_hits} ties)"
        );
    }
}

#[test]
fn every_triangle_and_vertex_normal_is_the_flattened_one() {
    for (name, scene) in scenes() {
        let t = 0.3;
        let rays = SceneRays::new(&scene, t);
        let normals = scene.world_vertex_normals(t);
        for (i, triangle) in scene.world_triangles(t).iter().enumerate() {
            assert_eq!(
                rays.triangle(i).as_ref(),
                Some(triangle),
                "{name}: triangle {i}"
            );
            assert_eq!(
                rays.vertex_normals(i),
                normals[i],
                "{name}: normals of triangle {i}"
            );
        }
        assert_eq!(
            rays.triangle(normals.len()),
            None,
            "{name}: one past the end"
        );
    }
}

#[test]
fn the_g_buffer_and_reference_are_those_of_the_flattened_scene() {
    for (name, scene) in scenes() {
        let (w, h) = (37, 23);
        let camera = scene.camera;
        let triangles = scene.world_triangles(0.0);
        let flat = TriangleBvh::new(&triangles);
        let flat_g = CpuGBuffer::trace_with_bvh(
            &flat,
            &triangles,
            &scene.world_vertex_normals(0.0),
            &camera,
            w,
            h,
            glam::Vec2::ZERO,
        );
        let rays = SceneRays::new(&scene, 0.0);
        let g = CpuGBuffer::trace_rays(&rays, &camera, w, h);
        // Compared pixel by pixel, so a failure names the pixel rather than printing both.
        assert_eq!((g.width, g.height), (flat_g.width, flat_g.height));
        for i in 0..(w * h) as usize {
            let pixel = |g: &CpuGBuffer| {
                (
                    g.points[i],
                    g.geometric_normals[i],
                    g.shading_normals[i],
                    // Not the triangle: the squashed box's top and bottom lie at the same
                    // distance, and either may be reported.
                    g.distances[i],
                    g.valid[i],
                )
            };
            assert_eq!(pixel(&g), pixel(&flat_g), "{name}: g-buffer pixel {i}");
        }
        let surfaces = g.surfaces(ReferenceNormals::Geometric);
        for mode in [ReferenceMode::Binary, ReferenceMode::Obscurance] {
            let params = ReferenceParams {
                radius: scene.bounds().diagonal() / 9.0,
                rays_per_pixel: 16,
                mode,
                ..Default::default()
            };
            let expected = trace_reference(&flat, &surfaces, &params).unwrap();
            let got = trace_reference(&rays, &surfaces, &params).unwrap();
            assert_eq!(
                got.accessibility, expected.accessibility,
                "{name}: {mode:?} reference"
            );
            assert_eq!(
                got.std_error, expected.std_error,
                "{name}: {mode:?} standard errors"
            );
        }
    }
}
