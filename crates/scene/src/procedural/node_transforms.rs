//! `node-transforms`: the node transforms real glTF files carry and a model matrix alone gets
//! wrong for normals, on a floor. Built to check the g-buffer against the CPU (issue: normals
//! under every node transform) and usable as any other scene:
//! - a smooth sphere under a node scaled [1, 8, 1] (a tall ellipsoid: a model-matrix normal
//!   would lean almost along its surface);
//! - a mirrored node (scale -1 in X, so the determinant is negative and the winding flips)
//!   holding a tilted, squashed sphere and a box;
//! - a sheared nested pair: a parent scaled [1, 2.5, 1] over children turned 45 degrees about
//!   Z (a box, and a sphere squashed in its own frame), whose product is a shear no single TRS
//!   node can hold.
//!
//! Invariant: every piece rests on or above the floor y = 0, and all meshes have smooth vertex
//! normals (spheres) or per-face normals (boxes), so both normal kinds are exercised.

use super::floor;
use crate::camera::Camera;
use crate::model::Scene;
use crate::primitives::{cuboid, uv_sphere};
use crate::scene_builder::SceneBuilder;
use glam::{Mat4, Vec3};
use std::f32::consts::FRAC_PI_4;

pub(super) fn node_transforms() -> Scene {
    let mut b = SceneBuilder::new();
    floor(&mut b, 40.0);
    let clay = b.material([0.72, 0.62, 0.55]);
    let stone = b.material([0.6, 0.64, 0.7]);

    // A node scaled [1, 8, 1]: a sphere of radius 0.3 becomes 0.6 wide and 4.8 tall.
    b.add(
        uv_sphere(0.3, 48, 32, clay),
        Mat4::from_translation(Vec3::new(-2.2, 2.4, -0.5))
            * Mat4::from_scale(Vec3::new(1.0, 8.0, 1.0)),
    );

    // A mirrored node (negative determinant) with two children.
    let mirrored = Mat4::from_translation(Vec3::new(2.0, 0.0, 0.0))
        * Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0));
    b.add(
        uv_sphere(0.7, 48, 32, stone),
        mirrored
            * Mat4::from_translation(Vec3::new(0.3, 0.75, 0.2))
            * Mat4::from_rotation_z(0.5)
            * Mat4::from_scale(Vec3::new(1.6, 0.7, 1.0)),
    );
    b.add(
        cuboid(Vec3::new(0.8, 1.2, 0.6), clay),
        mirrored * Mat4::from_translation(Vec3::new(-0.9, 0.6, -0.9)) * Mat4::from_rotation_y(0.6),
    );

    // A sheared nested pair: parent scale [1, 2.5, 1], child turned 45 degrees about Z.
    let parent = Mat4::from_translation(Vec3::new(0.0, 0.0, 0.6))
        * Mat4::from_scale(Vec3::new(1.0, 2.5, 1.0));
    let child = Mat4::from_translation(Vec3::new(0.0, 0.5, 0.0)) * Mat4::from_rotation_z(FRAC_PI_4);
    b.add(cuboid(Vec3::new(0.7, 0.7, 0.7), stone), parent * child);
    b.add(
        uv_sphere(0.45, 48, 32, clay),
        parent
            * Mat4::from_translation(Vec3::new(-0.9, 0.55, -1.2))
            * Mat4::from_rotation_z(FRAC_PI_4)
            * Mat4::from_scale(Vec3::new(1.5, 0.6, 1.0)),
    );

    b.build(Camera::perspective(
        Vec3::new(0.5, 3.2, 7.5),
        Vec3::new(0.0, 1.3, 0.0),
        50f32.to_radians(),
        0.05,
        200.0,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_scene_has_a_stretched_a_mirrored_and_a_sheared_instance() {
        let scene = node_transforms();
        let linear: Vec<glam::Mat3> = scene
            .instances
            .iter()
            .map(|i| glam::Mat3::from_mat4(i.transform))
            .collect();
        assert!(
            linear.iter().any(|m| m.y_axis.length() > 7.9),
            "no [1, 8, 1] node"
        );
        assert!(
            linear.iter().filter(|m| m.determinant() < 0.0).count() == 2,
            "no mirrored node"
        );
        // Shear: the images of two perpendicular axes are no longer perpendicular.
        let sheared = |m: &glam::Mat3| m.x_axis.normalize().dot(m.y_axis.normalize()).abs() > 0.5;
        assert!(
            linear.iter().filter(|m| sheared(m)).count() >= 2,
            "no sheared node"
        );
        let lowest = scene
            .world_triangles(0.0)
            .iter()
            .flatten()
            .map(|v| v.y)
            .fold(f32::INFINITY, f32::min);
        assert!(lowest >= -1e-5, "a vertex below the floor: y = {lowest}");
    }
}
