//! `stairs`: a straight flight of twelve solid steps against a side wall, on a floor.
//! The inner step corners are a regular pattern of concave edges.
//!
//! Invariant: each step is a solid block from the floor up (18 cm rise, 28 cm tread); the
//! faces between neighbouring blocks are enclosed, so no ray from a visible surface reaches
//! them and no gap lets light through.

use super::{WALL_COLOR, floor};
use crate::camera::Camera;
use crate::model::Scene;
use crate::primitives::{cuboid, quad};
use crate::scene_builder::SceneBuilder;
use glam::{Mat4, Quat, Vec3};
use std::f32::consts::FRAC_PI_2;

const STEPS: u32 = 12;
const RISE: f32 = 0.18;
const TREAD: f32 = 0.28;
const WIDTH: f32 = 2.4;

pub(super) fn stairs() -> Scene {
    let mut builder = SceneBuilder::new();
    floor(&mut builder, 40.0);
    let stone = builder.material([0.7, 0.66, 0.6]);
    for i in 0..STEPS {
        let height = (i + 1) as f32 * RISE;
        builder.add(
            cuboid(Vec3::new(WIDTH, height, TREAD), stone),
            Mat4::from_translation(Vec3::new(0.0, 0.5 * height, -(i as f32) * TREAD)),
        );
    }
    let wall = builder.material(WALL_COLOR);
    // Side wall in the plane x = -WIDTH/2, facing +X.
    builder.add(
        quad(4.0, 6.0, wall),
        Mat4::from_rotation_translation(
            Quat::from_rotation_z(-FRAC_PI_2),
            Vec3::new(-0.5 * WIDTH, 2.0, -1.5),
        ),
    );
    builder.build(Camera::perspective(
        Vec3::new(2.8, 1.8, 3.0),
        Vec3::new(0.0, 0.9, -1.3),
        50f32.to_radians(),
        0.05,
        100.0,
    ))
}
