//! `dynamic`: objects moving along simple paths over a floor, seen by an orbiting camera.
//! It exercises motion vectors, temporal reprojection and history invalidation.
//!
//! Invariant: every motion is periodic (orbit 6 s, oscillation 4 s, spin 5 s, camera 20 s), so
//! any time t is valid and the scene at t and t + 60 s is the same.

use super::{WALL_COLOR, floor};
use crate::animation::{AnimatedTransform, Animation};
use crate::camera::{Camera, CameraMotion};
use crate::model::Scene;
use crate::primitives::{cuboid, cylinder, quad, uv_sphere};
use crate::scene_builder::SceneBuilder;
use glam::{Mat4, Quat, Vec3};
use std::f32::consts::FRAC_PI_2;

pub(super) fn dynamic() -> Scene {
    let mut builder = SceneBuilder::new();
    floor(&mut builder, 60.0);
    let wall = builder.material(WALL_COLOR);
    let blue = builder.material([0.2, 0.35, 0.7]);
    let orange = builder.material([0.85, 0.45, 0.15]);
    let grey = builder.material([0.6, 0.6, 0.6]);

    // Static context: a back wall and a central pillar.
    builder.add(
        quad(12.0, 3.0, wall),
        Mat4::from_rotation_translation(
            Quat::from_rotation_x(FRAC_PI_2),
            Vec3::new(0.0, 1.5, -4.0),
        ),
    );
    builder.add(
        cylinder(0.4, 2.5, 32, grey),
        Mat4::from_translation(Vec3::new(0.0, 1.25, 0.0)),
    );

    let sphere = builder.mesh(uv_sphere(0.5, 48, 24, orange));
    builder.place_animated(
        sphere,
        Animation::new(vec![AnimatedTransform::Orbit {
            centre: Vec3::new(0.0, 0.5, 0.0),
            radius: 2.2,
            period: 6.0,
            phase: 0.0,
        }]),
    );
    let sliding_box = builder.mesh(cuboid(Vec3::new(0.8, 0.8, 0.8), blue));
    builder.place_animated(
        sliding_box,
        Animation::new(vec![AnimatedTransform::Oscillate {
            from: Vec3::new(-3.0, 0.4, 2.5),
            to: Vec3::new(3.0, 0.4, 2.5),
            period: 4.0,
        }]),
    );
    let spinner = builder.mesh(cuboid(Vec3::new(1.6, 0.3, 0.3), grey));
    builder.place_animated(
        spinner,
        Animation::new(vec![
            AnimatedTransform::Static(Mat4::from_translation(Vec3::new(3.0, 0.15, -2.0))),
            AnimatedTransform::Spin {
                axis: Vec3::Y,
                period: 5.0,
            },
        ]),
    );

    let centre = Vec3::new(0.0, 0.5, 0.0);
    let (radius, height) = (8.0, 3.5);
    let mut scene = builder.build(Camera::perspective(
        centre + Vec3::new(0.0, height, radius),
        centre,
        50f32.to_radians(),
        0.05,
        200.0,
    ));
    scene.camera_motion = Some(CameraMotion::Orbit {
        centre,
        radius,
        height,
        period: 20.0,
    });
    scene
}
