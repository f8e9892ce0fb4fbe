//! Simple mesh primitives for procedural scenes: quad (floor plane), box, UV sphere, cylinder.
//!
//! Invariants: every primitive is centred on the origin of its object space (the quad lies in
//! the XZ plane at y = 0), has counter-clockwise front faces seen from outside, unit vertex
//! normals pointing outwards, and no degenerate triangle (pole triangles of the sphere are left
//! out rather than collapsed). Tessellation counts are clamped to usable minimums.

use crate::model::Mesh;
use glam::Vec3;
use std::f32::consts::{PI, TAU};

/// Appends the quad `a b c d` (counter-clockwise seen from the side `normal` points to) as two
/// triangles with its own four vertices, so the quad has flat normals.
fn push_quad(mesh: &mut Mesh, corners: [Vec3; 4], normal: Vec3) {
    let base = mesh.positions.len() as u32;
    mesh.positions.extend(corners);
    mesh.normals.extend([normal; 4]);
    mesh.indices
        .extend([base, base + 1, base + 2, base, base + 2, base + 3]);
}

/// Appends the quad `corners` (a convex loop in either order) facing `normal`: the loop is
/// reversed if needed so the triangles are counter-clockwise seen from where `normal` points.
pub(crate) fn push_facing_quad(mesh: &mut Mesh, corners: [Vec3; 4], normal: Vec3) {
    let [a, b, c, d] = corners;
    if (b - a).cross(c - a).dot(normal) < 0.0 {
        push_quad(mesh, [a, d, c, b], normal);
    } else {
        push_quad(mesh, corners, normal);
    }
}

pub(crate) fn empty_mesh(name: &str, material: usize) -> Mesh {
    Mesh {
        name: name.to_owned(),
        material,
        ..Mesh::default()
    }
}

/// A `size_x` by `size_z` rectangle in the XZ plane facing +Y.
pub fn quad(size_x: f32, size_z: f32, material: usize) -> Mesh {
    let (x, z) = (0.5 * size_x, 0.5 * size_z);
    let mut mesh = empty_mesh("quad", material);
    push_quad(
        &mut mesh,
        [
            Vec3::new(-x, 0.0, -z),
            Vec3::new(-x, 0.0, z),
            Vec3::new(x, 0.0, z),
            Vec3::new(x, 0.0, -z),
        ],
        Vec3::Y,
    );
    mesh
}

/// An axis-aligned box with edge lengths `size`, flat-shaded (24 vertices, 12 triangles).
pub fn cuboid(size: Vec3, material: usize) -> Mesh {
    let half = size * 0.5;
    let mut mesh = empty_mesh("box", material);
    // (normal, u, v) with u x v = normal, so (-u,-v) (+u,-v) (+u,+v) (-u,+v) is counter-clockwise.
    let faces = [
        (Vec3::X, Vec3::NEG_Z, Vec3::Y),
        (Vec3::NEG_X, Vec3::Z, Vec3::Y),
        (Vec3::Y, Vec3::X, Vec3::NEG_Z),
        (Vec3::NEG_Y, Vec3::X, Vec3::Z),
        (Vec3::Z, Vec3::X, Vec3::Y),
        (Vec3::NEG_Z, Vec3::NEG_X, Vec3::Y),
    ];
    for (n, u, v) in faces {
        let centre = n * half;
        let (hu, hv) = (u * half, v * half);
        push_quad(
            &mut mesh,
            [
                centre - hu - hv,
                centre + hu - hv,
                centre + hu + hv,
                centre - hu + hv,
            ],
            n,
        );
    }
    mesh
}

/// A UV sphere of `radius` with `segments` around the equator (at least 3) and `rings` from
/// pole to pole (at least 2), smooth normals.
pub fn uv_sphere(radius: f32, segments: u32, rings: u32, material: usize) -> Mesh {
    let (segments, rings) = (segments.max(3), rings.max(2));
    let mut mesh = empty_mesh("sphere", material);
    for ring in 0..=rings {
        let phi = PI * ring as f32 / rings as f32;
        for segment in 0..=segments {
            let theta = TAU * segment as f32 / segments as f32;
            let n = Vec3::new(phi.sin() * theta.cos(), phi.cos(), phi.sin() * theta.sin());
            mesh.positions.push(n * radius);
            mesh.normals.push(n);
        }
    }
    let row = segments + 1;
    for ring in 0..rings {
        for segment in 0..segments {
            let a = ring * row + segment;
            let (b, c, d) = (a + row, a + row + 1, a + 1);
            if ring + 1 < rings {
                mesh.indices.extend([a, c, b]);
            }
            if ring > 0 {
                mesh.indices.extend([a, d, c]);
            }
        }
    }
    mesh
}

/// A closed cylinder of `radius` and `height` around the Y axis, from y = -height/2 to
/// +height/2, with `segments` sides (at least 3), smooth sides and flat caps.
pub fn cylinder(radius: f32, height: f32, segments: u32, material: usize) -> Mesh {
    let segments = segments.max(3);
    let half = 0.5 * height;
    let mut mesh = empty_mesh("cylinder", material);
    for segment in 0..=segments {
        let theta = TAU * segment as f32 / segments as f32;
        let n = Vec3::new(theta.cos(), 0.0, theta.sin());
        mesh.positions
            .extend([n * radius + Vec3::Y * half, n * radius - Vec3::Y * half]);
        mesh.normals.extend([n, n]);
    }
    for segment in 0..segments {
        let top = 2 * segment;
        let (bottom, next_top, next_bottom) = (top + 1, top + 2, top + 3);
        mesh.indices
            .extend([top, next_top, next_bottom, top, next_bottom, bottom]);
    }
    for (y, normal) in [(half, Vec3::Y), (-half, Vec3::NEG_Y)] {
        let centre = mesh.positions.len() as u32;
        mesh.positions.push(Vec3::Y * y);
        mesh.normals.push(normal);
        for segment in 0..segments {
            let theta = TAU * segment as f32 / segments as f32;
            mesh.positions
                .push(Vec3::new(theta.cos() * radius, y, theta.sin() * radius));
            mesh.normals.push(normal);
        }
        for segment in 0..segments {
            let a = centre + 1 + segment;
            let b = centre + 1 + (segment + 1) % segments;
            if normal.y > 0.0 {
                mesh.indices.extend([centre, b, a]);
            } else {
                mesh.indices.extend([centre, a, b]);
            }
        }
    }
    mesh
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every triangle of a convex, origin-centred mesh faces away from the origin and is not
    /// degenerate; every normal is unit length and points away from the origin.
    fn assert_outward(mesh: &Mesh) {
        for tri in mesh.triangles() {
            let n = (tri[1] - tri[0]).cross(tri[2] - tri[0]);
            assert!(
                n.length() > 1e-9,
                "{}: degenerate triangle {tri:?}",
                mesh.name
            );
            let centroid = (tri[0] + tri[1] + tri[2]) / 3.0;
            assert!(
                n.dot(centroid) > 0.0,
                "{}: inward triangle {tri:?}",
                mesh.name
            );
        }
        assert_eq!(mesh.normals.len(), mesh.positions.len());
        for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
            assert!((n.length() - 1.0).abs() < 1e-5);
            assert!(n.dot(*p) >= -1e-6, "{}: inward normal at {p}", mesh.name);
        }
    }

    #[test]
    fn convex_primitives_face_outwards() {
        assert_outward(&cuboid(Vec3::new(1.0, 2.0, 3.0), 0));
        assert_outward(&uv_sphere(2.0, 16, 8, 0));
        assert_outward(&cylinder(0.5, 3.0, 12, 0));
    }

    #[test]
    fn quad_faces_up() {
        let q = quad(2.0, 4.0, 0);
        for tri in q.triangles() {
            assert!((tri[1] - tri[0]).cross(tri[2] - tri[0]).y > 0.0);
        }
        assert_eq!(q.bounds().size(), Vec3::new(2.0, 0.0, 4.0));
    }

    #[test]
    fn sphere_has_expected_triangle_count() {
        // Two triangles per cell, minus one per segment at each pole.
        assert_eq!(
            uv_sphere(1.0, 16, 8, 0).triangle_count(),
            16 * 8 * 2 - 2 * 16
        );
    }
}
