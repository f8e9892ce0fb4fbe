//! The arched panel used by the `columns` arcade: a slab with a semicircular opening.
//!
//! Invariant: the mesh is a closed solid in object space x in [-width/2, width/2], y in
//! [0, height], z in [-depth/2, depth/2], with the opening's centre at the origin (the springing
//! line is y = 0); all faces are counter-clockwise seen from outside, flat normals per face
//! (smooth normals on the curved intrados).

use crate::model::Mesh;
use crate::primitives::{empty_mesh, push_facing_quad};
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// Where the ray from the origin at `angle` (radians, 0 = +X, in [0, pi]) leaves the
/// rectangle x in [-half_width, half_width], y in [0, height].
fn outline_point(angle: f32, half_width: f32, height: f32) -> Vec2 {
    let dir = Vec2::new(angle.cos(), angle.sin());
    let mut t = f32::INFINITY;
    if dir.x.abs() > 1e-6 {
        t = t.min(half_width / dir.x.abs());
    }
    if dir.y > 1e-6 {
        t = t.min(height / dir.y);
    }
    dir * t
}

/// A `width` x `height` x `depth` panel with a semicircular opening of `radius` (clamped below
/// half the width and the height) tessellated with `segments` steps (at least 4).
pub fn arched_panel(
    width: f32,
    height: f32,
    radius: f32,
    depth: f32,
    segments: u32,
    material: usize,
) -> Mesh {
    let (hw, hd) = (0.5 * width, 0.5 * depth);
    let radius = radius.min(0.98 * hw).min(0.98 * height);
    let segments = segments.max(4);
    // Arc angles from pi (left) down to 0 (right), plus the two top corners of the outline so
    // the outline between consecutive angles is a straight segment.
    let mut angles: Vec<f32> = (0..=segments)
        .map(|i| PI * (1.0 - i as f32 / segments as f32))
        .collect();
    angles.push(height.atan2(-hw));
    angles.push(height.atan2(hw));
    angles.sort_by(|a, b| b.total_cmp(a));
    angles.dedup_by(|a, b| (*a - *b).abs() < 1e-5);

    let mut mesh = empty_mesh("arched panel", material);
    let at = |p: Vec2, z: f32| Vec3::new(p.x, p.y, z);
    for pair in angles.windows(2) {
        let (a0, a1) = (pair[0], pair[1]);
        let inner0 = Vec2::new(a0.cos(), a0.sin()) * radius;
        let inner1 = Vec2::new(a1.cos(), a1.sin()) * radius;
        let outer0 = outline_point(a0, hw, height);
        let outer1 = outline_point(a1, hw, height);
        for (z, normal) in [(hd, Vec3::Z), (-hd, Vec3::NEG_Z)] {
            push_facing_quad(
                &mut mesh,
                [at(inner0, z), at(inner1, z), at(outer1, z), at(outer0, z)],
                normal,
            );
        }
        // Intrados: faces the opening's axis. Smooth normals across segments.
        let base = mesh.positions.len() as u32;
        let n0 = -Vec3::new(a0.cos(), a0.sin(), 0.0);
        let n1 = -Vec3::new(a1.cos(), a1.sin(), 0.0);
        mesh.positions.extend([
            at(inner0, hd),
            at(inner1, hd),
            at(inner1, -hd),
            at(inner0, -hd),
        ]);
        mesh.normals.extend([n0, n1, n1, n0]);
        let (b, c, d) = (base + 1, base + 2, base + 3);
        let face = (mesh.positions[b as usize] - mesh.positions[base as usize])
            .cross(mesh.positions[c as usize] - mesh.positions[base as usize]);
        if face.dot(n0 + n1) >= 0.0 {
            mesh.indices.extend([base, b, c, base, c, d]);
        } else {
            mesh.indices.extend([base, c, b, base, d, c]);
        }
    }
    let corner = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
    let outline_faces = [
        // top
        (
            [
                corner(-hw, height, -hd),
                corner(hw, height, -hd),
                corner(hw, height, hd),
                corner(-hw, height, hd),
            ],
            Vec3::Y,
        ),
        // sides
        (
            [
                corner(-hw, 0.0, -hd),
                corner(-hw, height, -hd),
                corner(-hw, height, hd),
                corner(-hw, 0.0, hd),
            ],
            Vec3::NEG_X,
        ),
        (
            [
                corner(hw, 0.0, -hd),
                corner(hw, height, -hd),
                corner(hw, height, hd),
                corner(hw, 0.0, hd),
            ],
            Vec3::X,
        ),
        // the two ledges under the springing line, either side of the opening
        (
            [
                corner(-hw, 0.0, -hd),
                corner(-radius, 0.0, -hd),
                corner(-radius, 0.0, hd),
                corner(-hw, 0.0, hd),
            ],
            Vec3::NEG_Y,
        ),
        (
            [
                corner(radius, 0.0, -hd),
                corner(hw, 0.0, -hd),
                corner(hw, 0.0, hd),
                corner(radius, 0.0, hd),
            ],
            Vec3::NEG_Y,
        ),
    ];
    for (corners, normal) in outline_faces {
        push_facing_quad(&mut mesh, corners, normal);
    }
    mesh
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arched_panel_triangles_agree_with_their_normals() {
        let mesh = arched_panel(4.0, 2.2, 1.65, 0.5, 16, 0);
        for tri in mesh.indices.chunks_exact(3) {
            let [a, b, c] = [0, 1, 2].map(|k| mesh.positions[tri[k] as usize]);
            let n = (b - a).cross(c - a);
            assert!(n.length() > 1e-9, "degenerate triangle");
            let vertex_normal = mesh.normals[tri[0] as usize];
            assert!(
                n.dot(vertex_normal) > 0.0,
                "triangle {tri:?} faces the wrong way"
            );
        }
        let bounds = mesh.bounds();
        assert!((bounds.min - Vec3::new(-2.0, 0.0, -0.25)).length() < 1e-5);
        assert!((bounds.max - Vec3::new(2.0, 2.2, 0.25)).length() < 1e-5);
    }
}
