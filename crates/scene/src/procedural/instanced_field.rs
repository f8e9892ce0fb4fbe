//! A field of many copies of one mesh: the shape of scenes made with EXT_mesh_gpu_instancing
//! (forests, crowds, rubble), for measuring what instancing costs the CPU paths. Not in the
//! registry: at its full size it has millions of triangles.
//! Invariant: instance `i` is placed deterministically from `i` alone (a grid cell, a turn
//! about Y and a uniform scale in 0.6..1.2), so the scene is the same on every machine.

use crate::camera::Camera;
use crate::model::Scene;
use crate::primitives::{quad, uv_sphere};
use crate::scene_builder::SceneBuilder;
use glam::{Mat4, Quat, Vec3};

/// `instances` copies of a UV sphere of about `triangles` triangles (at least 4 rings) on a
/// square-ish grid over a ground quad, seen from above one corner.
pub fn instanced_field(instances: usize, triangles: usize) -> Scene {
    let mut builder = SceneBuilder::new();
    let material = builder.material([0.7, 0.7, 0.7]);
    // A UV sphere of s segments and r rings has s (2 r - 2) triangles; r = s / 1.25.
    let segments = ((triangles as f32 * 0.625).sqrt().round() as u32).max(4);
    let rings = (triangles as u32 / (2 * segments) + 1).max(4);
    let mesh = builder.mesh(uv_sphere(1.0, segments, rings, material));
    let columns = (instances as f32).sqrt().ceil().max(1.0) as usize;
    let spacing = 2.5;
    for i in 0..instances {
        let (x, z) = ((i % columns) as f32, (i / columns) as f32);
        // A fixed scramble of i (Knuth's multiplicative hash) for turn and scale.
        let h = (i as u32).wrapping_mul(2_654_435_761);
        let turn = (h >> 16) as f32 / 65_536.0 * std::f32::consts::TAU;
        let scale = 0.6 + 0.6 * (h & 0xffff) as f32 / 65_536.0;
        let transform = Mat4::from_scale_rotation_translation(
            Vec3::splat(scale),
            Quat::from_rotation_y(turn),
            Vec3::new(x * spacing, scale, z * spacing),
        );
        builder.place(mesh, transform);
    }
    let extent = columns as f32 * spacing;
    let centre = Vec3::new(extent / 2.0, 0.0, extent / 2.0);
    builder.add_backdrop(
        quad(extent * 1.5, extent * 1.5, material),
        Mat4::from_translation(centre),
    );
    let camera = Camera::perspective(
        Vec3::new(-0.2 * extent, 0.4 * extent, -0.2 * extent),
        centre,
        60f32.to_radians(),
        0.1,
        10.0 * extent,
    );
    builder.build(camera)
}
