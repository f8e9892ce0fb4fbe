//! `thin-bars`: a fence of thin vertical bars with two rails, in front of a wall, on a floor.
//! Thin occluders are where screen-space AO goes wrong (depth buffers see only their front).
//!
//! Invariant: bars are 3 cm thick, 20 cm apart, 30 cm in front of the wall at z = -1.

use super::{WALL_COLOR, floor};
use crate::camera::Camera;
use crate::model::Scene;
use crate::primitives::{cuboid, quad};
use crate::scene_builder::SceneBuilder;
use glam::{Mat4, Quat, Vec3};
use std::f32::consts::FRAC_PI_2;

pub(super) fn thin_bars() -> Scene {
    let mut builder = SceneBuilder::new();
    floor(&mut builder, 40.0);
    let wall = builder.material(WALL_COLOR);
    builder.add(
        quad(8.0, 3.0, wall),
        Mat4::from_rotation_translation(
            Quat::from_rotation_x(FRAC_PI_2),
            Vec3::new(0.0, 1.5, -1.0),
        ),
    );
    let metal = builder.material([0.25, 0.25, 0.28]);
    let bar = builder.mesh(cuboid(Vec3::new(0.03, 2.0, 0.03), metal));
    for i in 0..21 {
        let x = -2.0 + 0.2 * i as f32;
        builder.place(bar, Mat4::from_translation(Vec3::new(x, 1.0, -0.7)));
    }
    let rail = builder.mesh(cuboid(Vec3::new(4.2, 0.04, 0.04), metal));
    for y in [0.15, 1.9] {
        builder.place(rail, Mat4::from_translation(Vec3::new(0.0, y, -0.7)));
    }
    builder.build(Camera::perspective(
        Vec3::new(0.6, 1.4, 3.0),
        Vec3::new(0.0, 1.0, -0.8),
        50f32.to_radians(),
        0.05,
        100.0,
    ))
}
