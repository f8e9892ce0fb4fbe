//! Scenes with closed-form accessibility: `plane`, `sphere-on-plane`, `wall`, `corner`.
//!
//! Invariant: the geometry matches the constants and closed forms exported here (sphere centre
//! and radius, wall plane), and the flat pieces are much larger than any radius the tests use,
//! so their edges never show up in the reference. The closed forms are for binary mode.

use super::{FLOOR_COLOR, WALL_COLOR, floor};
use crate::camera::Camera;
use crate::model::Scene;
use crate::primitives::{quad, uv_sphere};
use crate::scene_builder::SceneBuilder;
use glam::{Mat4, Quat, Vec3};
use std::f32::consts::{FRAC_PI_2, PI};

/// Centre of the sphere in `sphere-on-plane` (it rests on the floor y = 0).
pub const SPHERE_ON_PLANE_CENTRE: Vec3 = Vec3::new(0.0, 1.0, 0.0);
/// Radius of the sphere in `sphere-on-plane`.
pub const SPHERE_ON_PLANE_RADIUS: f32 = 1.0;
/// The wall of `wall` is the plane x = WALL_PLANE_X; the floor is y = 0, on both sides.
pub const WALL_PLANE_X: f32 = 0.0;
/// Half the extent of the `wall` scene's floor and wall (they reach this far from the origin).
pub const WALL_HALF_EXTENT: f32 = 1000.0;

/// `plane`: one large floor and nothing else; accessibility 1 everywhere.
pub(super) fn plane() -> Scene {
    let mut builder = SceneBuilder::new();
    floor(&mut builder, 1000.0);
    builder.build(Camera::perspective(
        Vec3::new(0.0, 2.0, 6.0),
        Vec3::ZERO,
        50f32.to_radians(),
        0.05,
        2000.0,
    ))
}

/// `sphere-on-plane`: a sphere (see [`SPHERE_ON_PLANE_CENTRE`], [`SPHERE_ON_PLANE_RADIUS`])
/// resting on a floor, tessellated finely (128 x 64) so the closed form holds to ~1e-3.
pub(super) fn sphere_on_plane() -> Scene {
    let mut builder = SceneBuilder::new();
    floor(&mut builder, 200.0);
    let sphere_material = builder.material([0.7, 0.7, 0.75]);
    builder.add(
        uv_sphere(SPHERE_ON_PLANE_RADIUS, 128, 64, sphere_material),
        Mat4::from_translation(SPHERE_ON_PLANE_CENTRE),
    );
    builder.build(Camera::perspective(
        Vec3::new(0.0, 2.2, 4.2),
        Vec3::new(0.0, 0.5, 0.0),
        50f32.to_radians(),
        0.05,
        500.0,
    ))
}

/// Closed-form accessibility of a receiver at `point` with unit `normal` next to the
/// `sphere-on-plane` sphere, for a radius that contains the sphere: 1 - cos(theta) (r/d)^2,
/// theta between the normal and the direction to the centre, d the distance to the centre.
/// `None` where it does not hold: the sphere crosses the receiver's tangent plane, or the
/// point is inside the sphere.
pub fn sphere_on_plane_accessibility(point: Vec3, normal: Vec3) -> Option<f32> {
    let to_centre = SPHERE_ON_PLANE_CENTRE - point;
    let d = to_centre.length();
    let r = SPHERE_ON_PLANE_RADIUS;
    let height = to_centre.dot(normal);
    if d <= r || height < r - 1e-5 {
        return None;
    }
    let cos_theta = height / d;
    Some(1.0 - cos_theta * (r / d).powi(2))
}

/// `wall`: a floor and one perpendicular wall in the plane x = [`WALL_PLANE_X`], both
/// reaching [`WALL_HALF_EXTENT`] from the origin.
pub(super) fn wall() -> Scene {
    let mut builder = SceneBuilder::new();
    floor(&mut builder, 2.0 * WALL_HALF_EXTENT);
    let wall_material = builder.material(WALL_COLOR);
    // The XZ quad turned about Z by +90 degrees faces -X: towards the camera side.
    builder.add_backdrop(
        quad(WALL_HALF_EXTENT, 2.0 * WALL_HALF_EXTENT, wall_material),
        Mat4::from_rotation_translation(
            Quat::from_rotation_z(FRAC_PI_2),
            Vec3::new(WALL_PLANE_X, 0.5 * WALL_HALF_EXTENT, 0.0),
        ),
    );
    builder.build(Camera::perspective(
        Vec3::new(-6.0, 3.0, 6.0),
        Vec3::new(0.0, 0.5, 0.0),
        50f32.to_radians(),
        0.05,
        3000.0,
    ))
}

/// Binary-mode accessibility of a floor point at `distance` from an infinite wall, with
/// occlusion radius `radius`: 1 - (acos(a) - a sqrt(1 - a^2)) / pi, a = min(1, distance/radius)
/// (cosine-weighted directions project uniformly onto the unit disk; those within reach of the
/// wall are the disk segment beyond a). It tends to 0.5 as the radius grows.
pub fn wall_accessibility(distance: f32, radius: f32) -> f32 {
    let a = (distance / radius).clamp(0.0, 1.0);
    1.0 - (a.acos() - a * (1.0 - a * a).sqrt()) / PI
}

/// `corner`: a floor and two walls meeting at right angles at the origin; the room is the
/// quadrant x > 0, z > 0.
pub(super) fn corner() -> Scene {
    const SIZE: f32 = 30.0;
    let mut builder = SceneBuilder::new();
    let floor_material = builder.material(FLOOR_COLOR);
    builder.add_backdrop(
        quad(SIZE, SIZE, floor_material),
        Mat4::from_translation(Vec3::new(0.5 * SIZE, 0.0, 0.5 * SIZE)),
    );
    let wall_material = builder.material(WALL_COLOR);
    // Plane x = 0 facing +X.
    builder.add_backdrop(
        quad(SIZE, SIZE, wall_material),
        Mat4::from_rotation_translation(
            Quat::from_rotation_z(-FRAC_PI_2),
            Vec3::new(0.0, 0.5 * SIZE, 0.5 * SIZE),
        ),
    );
    // Plane z = 0 facing +Z.
    builder.add_backdrop(
        quad(SIZE, SIZE, wall_material),
        Mat4::from_rotation_translation(
            Quat::from_rotation_x(FRAC_PI_2),
            Vec3::new(0.5 * SIZE, 0.5 * SIZE, 0.0),
        ),
    );
    builder.build(Camera::perspective(
        Vec3::new(8.0, 5.0, 8.0),
        Vec3::new(0.0, 0.5, 0.0),
        55f32.to_radians(),
        0.05,
        200.0,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wall_closed_form_tends_to_one_half() {
        assert!((wall_accessibility(0.0, 1.0) - 0.5).abs() < 1e-6);
        assert!((wall_accessibility(1.0, 1.0) - 1.0).abs() < 1e-6);
        assert!((wall_accessibility(0.01, 1.0) - 0.50637).abs() < 1e-4);
    }

    #[test]
    fn sphere_closed_form_holds_only_above_the_tangent_plane() {
        let a = sphere_on_plane_accessibility(Vec3::new(2.0, 0.0, 0.0), Vec3::Y).unwrap();
        let d2 = 5.0f32; // (2, -1, 0) from the centre
        let expected = 1.0 - (1.0 / d2.sqrt()) * (1.0 / d2);
        assert!((a - expected).abs() < 1e-6);
        assert!(sphere_on_plane_accessibility(Vec3::new(0.0, 1.5, 3.0), Vec3::Y).is_none());
    }
}
