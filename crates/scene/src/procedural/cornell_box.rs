//! `cornell-box`: the classic box with a red left wall, a green right wall, white floor,
//! ceiling and back wall, and two boxes inside; the front is open towards the camera.
//!
//! Invariant: the room spans x in [-1, 1], y in [0, 2], z in [-1, 1], and every wall faces
//! the inside.

use crate::camera::Camera;
use crate::model::Scene;
use crate::primitives::{cuboid, quad};
use crate::scene_builder::SceneBuilder;
use glam::{Mat4, Quat, Vec3};
use std::f32::consts::{FRAC_PI_2, PI};

const WHITE: [f32; 3] = [0.725, 0.71, 0.68];
const RED: [f32; 3] = [0.63, 0.065, 0.05];
const GREEN: [f32; 3] = [0.14, 0.45, 0.091];

pub(super) fn cornell_box() -> Scene {
    let mut builder = SceneBuilder::new();
    let white = builder.material(WHITE);
    let red = builder.material(RED);
    let green = builder.material(GREEN);
    let walls = [
        // floor, facing +Y
        (white, Quat::IDENTITY, Vec3::ZERO),
        // ceiling, facing -Y
        (white, Quat::from_rotation_x(PI), Vec3::new(0.0, 2.0, 0.0)),
        // back wall, facing +Z
        (
            white,
            Quat::from_rotation_x(FRAC_PI_2),
            Vec3::new(0.0, 1.0, -1.0),
        ),
        // left wall, facing +X
        (
            red,
            Quat::from_rotation_z(-FRAC_PI_2),
            Vec3::new(-1.0, 1.0, 0.0),
        ),
        // right wall, facing -X
        (
            green,
            Quat::from_rotation_z(FRAC_PI_2),
            Vec3::new(1.0, 1.0, 0.0),
        ),
    ];
    for (material, rotation, translation) in walls {
        builder.add(
            quad(2.0, 2.0, material),
            Mat4::from_rotation_translation(rotation, translation),
        );
    }
    builder.add(
        cuboid(Vec3::new(0.6, 1.2, 0.6), white),
        Mat4::from_rotation_translation(
            Quat::from_rotation_y(17f32.to_radians()),
            Vec3::new(-0.35, 0.6, -0.3),
        ),
    );
    builder.add(
        cuboid(Vec3::splat(0.6), white),
        Mat4::from_rotation_translation(
            Quat::from_rotation_y(-17f32.to_radians()),
            Vec3::new(0.35, 0.3, 0.35),
        ),
    );
    builder.build(Camera::perspective(
        Vec3::new(0.0, 1.0, 3.6),
        Vec3::new(0.0, 1.0, 0.0),
        40f32.to_radians(),
        0.05,
        20.0,
    ))
}
