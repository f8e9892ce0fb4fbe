//! `room`: a closed interior, 10 x 3 x 6 units, with furniture: the scene an outside camera
//! can only see as a box. It checks the interior-view heuristics (`crate::views`) and gives
//! the bench an enclosed scene: a table on four legs, a bookshelf against the back wall, a sofa
//! in the corner, stacked crates and a pillar, all resting on the floor.
//!
//! Invariant: the shell is closed (floor, ceiling and four walls are solid slabs 0.2 thick
//! whose ends overlap), so no ray from inside escapes, and every piece of furniture lies inside
//! it, clear of the walls by at least 1 cm.

use crate::camera::Camera;
use crate::model::Scene;
use crate::primitives::cuboid;
use crate::scene_builder::SceneBuilder;
use glam::{Mat4, Vec3};

/// Inner half-extent of the room along x: the inside faces of the side walls are at
/// x = +-`ROOM_HALF_X` (scene units; the room is centred on the origin).
pub const ROOM_HALF_X: f32 = 5.0;
/// Inner half-extent of the room along z: the inside faces of the front and back walls are at
/// z = +-`ROOM_HALF_Z`.
pub const ROOM_HALF_Z: f32 = 3.0;
/// Inner height of the room: the floor's top face is at y = 0, the ceiling's underside at
/// y = `ROOM_HEIGHT`.
pub const ROOM_HEIGHT: f32 = 3.0;
const SLAB: f32 = 0.2;

fn block(b: &mut SceneBuilder, size: Vec3, centre: Vec3, material: usize) {
    b.add(cuboid(size, material), Mat4::from_translation(centre));
}

pub(super) fn room() -> Scene {
    let mut b = SceneBuilder::new();
    let plaster = b.material([0.82, 0.8, 0.76]);
    let wood = b.material([0.55, 0.4, 0.28]);
    let fabric = b.material([0.35, 0.42, 0.55]);
    let (hx, hz, h) = (ROOM_HALF_X, ROOM_HALF_Z, ROOM_HEIGHT);
    let (outer_x, outer_z) = (2.0 * (hx + SLAB), 2.0 * (hz + SLAB));
    // Shell: floor, ceiling, walls at +-x and +-z.
    block(
        &mut b,
        Vec3::new(outer_x, SLAB, outer_z),
        Vec3::new(0.0, -0.5 * SLAB, 0.0),
        plaster,
    );
    block(
        &mut b,
        Vec3::new(outer_x, SLAB, outer_z),
        Vec3::new(0.0, h + 0.5 * SLAB, 0.0),
        plaster,
    );
    for side in [-1.0f32, 1.0] {
        block(
            &mut b,
            Vec3::new(SLAB, h, outer_z),
            Vec3::new(side * (hx + 0.5 * SLAB), 0.5 * h, 0.0),
            plaster,
        );
        block(
            &mut b,
            Vec3::new(outer_x, h, SLAB),
            Vec3::new(0.0, 0.5 * h, side * (hz + 0.5 * SLAB)),
            plaster,
        );
    }
    // A table: top 1.6 x 0.05 x 0.9 at 0.75, four legs.
    let table = Vec3::new(0.8, 0.0, -0.4);
    block(
        &mut b,
        Vec3::new(1.6, 0.05, 0.9),
        table + Vec3::new(0.0, 0.75, 0.0),
        wood,
    );
    for (dx, dz) in [(-0.7, -0.35), (0.7, -0.35), (-0.7, 0.35), (0.7, 0.35)] {
        block(
            &mut b,
            Vec3::new(0.06, 0.725, 0.06),
            table + Vec3::new(dx, 0.3625, dz),
            wood,
        );
    }
    // A bookshelf against the back wall (z = -hz).
    block(
        &mut b,
        Vec3::new(1.2, 2.0, 0.35),
        Vec3::new(-2.5, 1.0, -hz + 0.185),
        wood,
    );
    // A sofa in the (-x, +z) corner: seat and back.
    block(
        &mut b,
        Vec3::new(2.0, 0.45, 0.9),
        Vec3::new(-3.6, 0.225, 2.1),
        fabric,
    );
    block(
        &mut b,
        Vec3::new(2.0, 0.5, 0.2),
        Vec3::new(-3.6, 0.7, 2.54),
        fabric,
    );
    // Crates stacked by the +x wall, and a pillar.
    block(
        &mut b,
        Vec3::new(0.6, 0.6, 0.6),
        Vec3::new(4.5, 0.3, 2.2),
        wood,
    );
    block(
        &mut b,
        Vec3::new(0.6, 0.6, 0.6),
        Vec3::new(4.5, 0.9, 2.2),
        wood,
    );
    block(
        &mut b,
        Vec3::new(0.6, 0.6, 0.6),
        Vec3::new(3.85, 0.3, 2.3),
        wood,
    );
    block(
        &mut b,
        Vec3::new(0.4, h, 0.4),
        Vec3::new(2.5, 0.5 * h, 1.2),
        plaster,
    );
    b.build(Camera::perspective(
        Vec3::new(-4.2, 1.6, 2.2),
        Vec3::new(1.5, 0.8, -1.2),
        60f32.to_radians(),
        0.02,
        50.0,
    ))
}
