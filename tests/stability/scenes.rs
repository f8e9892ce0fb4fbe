//! The stability scenes (floors, boxes, a degenerate mesh) and the cameras the cases use.

use aograph_scene::primitives::{cuboid, quad};
use aograph_scene::{Camera, Mesh, Projection, Scene, SceneBuilder};
use glam::{Mat4, Vec3};

use super::*;

// ---- Scenes -------------------------------------------------------------------------------

/// A floor of `size` x `size` at y = 0, centred on `centre`, made of `cells` x `cells` quads so
/// no triangle is much larger than the view (interpolation stays exact to f32's precision).
pub(crate) fn floor(b: &mut SceneBuilder, centre: Vec3, size: f32, cells: u32) {
    let cell = size / cells as f32;
    let m = b.mesh(quad(cell, cell, 0));
    for i in 0..cells {
        for j in 0..cells {
            let c = centre
                + Vec3::new(
                    (i as f32 + 0.5) * cell - 0.5 * size,
                    0.0,
                    (j as f32 + 0.5) * cell - 0.5 * size,
                );
            b.place(m, Mat4::from_translation(c));
        }
    }
}

/// `box-on-plane` at `scale`, moved by `offset`: a 200 x 200 floor, a unit box and a 1 x 3 x 1
/// column at the origin; with `island`, a second, empty 200 x 200 floor at x = [`JUMP`].
pub(crate) fn box_scene(scale: f32, offset: Vec3, island: bool, reversed: bool) -> Scene {
    let mut b = SceneBuilder::new();
    b.material([0.6, 0.6, 0.6]);
    floor(&mut b, offset, 200.0 * scale, 4);
    b.add(
        cuboid(Vec3::splat(scale), 0),
        Mat4::from_translation(offset + Vec3::new(0.0, 0.5, 0.0) * scale),
    );
    b.add(
        cuboid(Vec3::new(1.0, 3.0, 1.0) * scale, 0),
        Mat4::from_translation(offset + Vec3::new(-1.5, 1.5, -1.0) * scale),
    );
    if island {
        floor(&mut b, offset + Vec3::X * JUMP * scale, 200.0 * scale, 4);
    }
    let mut camera = Camera::perspective(
        offset + Vec3::new(0.0, 3.0, 8.0) * scale,
        offset + Vec3::Y * 0.5 * scale,
        50f32.to_radians(),
        0.05 * scale,
        1000.0 * scale,
    );
    if reversed {
        camera.projection = Projection::Perspective {
            fov_y: 50f32.to_radians(),
            near: 0.05 * scale,
            far: 0.0,
            reversed_z_infinite: true,
        };
    }
    b.build(camera)
}

/// A floor with zero-area geometry on and above it: triangles with repeated indices, collinear
/// triangles, a box whose 24 vertices all coincide, a floor piece built of coincident
/// (unwelded) vertices with zero-length normals, and a sliver 1e-6 wide.
pub(crate) fn degenerate_scene() -> Scene {
    let mut b = SceneBuilder::new();
    b.material([0.6, 0.6, 0.6]);
    floor(&mut b, Vec3::ZERO, 200.0, 4);
    // Repeated indices and collinear vertices, lying on the floor and standing above it.
    let p = vec![
        Vec3::new(-1.0, 0.0, 0.0),
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
        Vec3::new(0.0, 2.0, 0.0),
        Vec3::new(0.5, 0.5, 0.5),
    ];
    let degenerate = Mesh {
        name: "degenerate".into(),
        normals: vec![Vec3::Y; p.len()],
        positions: p,
        indices: vec![0, 0, 1, 2, 2, 2, 0, 1, 2, 2, 3, 4, 5, 5, 3, 1, 1, 1],
        material: 0,
        skin_weights: Vec::new(),
    };
    b.add(degenerate, Mat4::from_translation(Vec3::new(0.0, 0.0, 0.0)));
    // A box collapsed to one point (every vertex coincides), above the floor.
    let mut collapsed = cuboid(Vec3::ONE, 0);
    collapsed
        .positions
        .iter_mut()
        .for_each(|p| *p = Vec3::new(0.3, 0.7, 0.2));
    b.add(collapsed, Mat4::IDENTITY);
    // A raised platform (0.02 above the floor, 4 x 4) of unwelded quads: every corner is four
    // coincident vertices, normals zero-length (the g-buffer must derive them).
    let mut platform = Mesh {
        name: "platform".into(),
        material: 0,
        ..Mesh::default()
    };
    for i in 0..4 {
        for j in 0..4 {
            let o = Vec3::new(i as f32 - 2.0, 0.02, j as f32 - 2.0);
            let base = platform.positions.len() as u32;
            platform
                .positions
                .extend([o, o + Vec3::Z, o + Vec3::X + Vec3::Z, o + Vec3::X]);
            platform.normals.extend([Vec3::ZERO; 4]);
            platform
                .indices
                .extend([base, base + 1, base + 2, base, base + 2, base + 3]);
        }
    }
    b.add(platform, Mat4::from_translation(Vec3::new(20.0, 0.0, 0.0)));
    // A sliver: two vertices 1e-6 apart, standing up.
    let sliver = Mesh {
        name: "sliver".into(),
        positions: vec![
            Vec3::ZERO,
            Vec3::new(1e-6, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        ],
        normals: vec![Vec3::Z; 3],
        indices: vec![0, 1, 2],
        material: 0,
        skin_weights: Vec::new(),
    };
    b.add(sliver, Mat4::from_translation(Vec3::new(-0.7, 0.0, 0.3)));
    b.build(Camera::perspective(
        Vec3::new(0.0, 3.0, 8.0),
        Vec3::new(0.0, 0.5, 0.0),
        50f32.to_radians(),
        0.05,
        1000.0,
    ))
}

// ---- Cameras ------------------------------------------------------------------------------

pub(crate) fn perspective(position: Vec3, target: Vec3, near: f32, far: f32) -> Camera {
    Camera::perspective(position, target, 50f32.to_radians(), near, far)
}

/// The view of the box and column at `scale`, moved by `offset`.
pub(crate) fn occluders(scale: f32, offset: Vec3) -> Camera {
    // Close enough that the box's contact and the column's foot span several pixels at 32x32
    // (from 8 units away they were 4 pixels wide and a 5-tap blur diluted them to 0.92).
    perspective(
        offset + Vec3::new(0.6, 2.2, 4.5) * scale,
        offset + Vec3::new(-0.6, 0.6, -0.5) * scale,
        0.05 * scale,
        1000.0 * scale,
    )
}

/// A view of open floor 40 units (times `scale`) from the box: only the plane, the box far
/// outside the view (at 32x32).
pub(crate) fn open_floor(scale: f32, offset: Vec3) -> Camera {
    perspective(
        offset + Vec3::new(40.0, 3.0, 8.0) * scale,
        offset + Vec3::new(40.0, 0.0, 0.0) * scale,
        0.05 * scale,
        1000.0 * scale,
    )
}

/// The floor at 89.9 degrees to the central ray (grazing by 0.1 degree) from 0.1 above it
/// (times `scale`): the central ray meets it 57 units ahead; the box is out of view at 32x32.
pub(crate) fn grazing(scale: f32, offset: Vec3) -> Camera {
    let pitch = 0.1f32.to_radians();
    let eye = offset + Vec3::new(40.0, 0.1, 50.0) * scale;
    perspective(
        eye,
        eye + Vec3::new(0.0, -pitch.sin(), -pitch.cos()) * scale,
        0.01 * scale,
        1000.0 * scale,
    )
}

/// A view of the empty island floor (scale 1): only the plane at any aspect ratio.
pub(crate) fn island_view() -> Camera {
    perspective(
        Vec3::new(JUMP, 3.0, 8.0),
        Vec3::new(JUMP, 0.0, 0.0),
        0.05,
        1000.0,
    )
}

pub(crate) fn reversed(mut c: Camera) -> Camera {
    if let Projection::Perspective { fov_y, near, .. } = c.projection {
        c.projection = Projection::Perspective {
            fov_y,
            near,
            far: 0.0,
            reversed_z_infinite: true,
        };
    }
    c
}

pub(crate) fn with_planes(mut c: Camera, near: f32, far: f32) -> Camera {
    if let Projection::Perspective {
        fov_y,
        reversed_z_infinite,
        ..
    } = c.projection
    {
        c.projection = Projection::Perspective {
            fov_y,
            near,
            far,
            reversed_z_infinite,
        };
    }
    c
}
