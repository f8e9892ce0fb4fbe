//! `columns`: a Sponza-like arcade and the app's default scene. A nave along X with a row of
//! six columns and five arches on each side, an upper wall with a cornice, side aisles with
//! back walls and low ceilings, a closed far end, and a few props on the nave floor.
//!
//! Invariant: the default camera stands inside the open near end of the nave at eye height,
//! looking down its length, so the view shows every kind of AO feature: column bases on the
//! floor, the curved arch intrados, dark aisles under their ceilings, and props in contact.

use super::{FLOOR_COLOR, WALL_COLOR, arched_panel};
use crate::camera::Camera;
use crate::model::Scene;
use crate::primitives::{cuboid, cylinder, quad, uv_sphere};
use crate::scene_builder::SceneBuilder;
use glam::{Mat4, Quat, Vec3};
use std::f32::consts::{FRAC_PI_2, PI};

/// Column centres along X (4 m apart) and the two arcade rows along Z.
const COLUMN_X: [f32; 6] = [-10.0, -6.0, -2.0, 2.0, 6.0, 10.0];
const ROW_Z: [f32; 2] = [-3.0, 3.0];
/// Height of the springing line of the arches (top of the capitals).
const SPRING: f32 = 3.0;
/// Top of the arched panels; the upper wall continues from here.
const ARCH_TOP: f32 = 5.2;
/// Top of the upper wall.
const WALL_TOP: f32 = 7.0;
/// Thickness of the arcade (arches and upper wall).
const ARCADE_DEPTH: f32 = 0.5;
/// The aisles' back walls stand at z = +-AISLE_WALL_Z.
const AISLE_WALL_Z: f32 = 6.0;
/// The nave runs from x = -NAVE_HALF_LENGTH (closed end) to +NAVE_HALF_LENGTH (open end).
const NAVE_HALF_LENGTH: f32 = 12.0;

/// Adds one column (base, shaft, capital) standing on the floor at (x, z).
fn add_column(builder: &mut SceneBuilder, parts: &ColumnParts, x: f32, z: f32) {
    builder.place(parts.plinth, Mat4::from_translation(Vec3::new(x, 0.125, z)));
    builder.place(parts.shaft, Mat4::from_translation(Vec3::new(x, 1.5, z)));
    builder.place(
        parts.plinth,
        Mat4::from_translation(Vec3::new(x, SPRING - 0.125, z)),
    );
}

/// Mesh indices shared by every column.
struct ColumnParts {
    plinth: usize,
    shaft: usize,
}

pub(super) fn columns() -> Scene {
    let mut builder = SceneBuilder::new();
    let floor_material = builder.material(FLOOR_COLOR);
    let stone = builder.material([0.78, 0.74, 0.66]);
    let plaster = builder.material(WALL_COLOR);
    let bronze = builder.material([0.55, 0.42, 0.25]);
    let cloth = builder.material([0.55, 0.12, 0.1]);

    let length = 2.0 * NAVE_HALF_LENGTH;
    builder.add(
        quad(length + 2.0, 2.0 * AISLE_WALL_Z, floor_material),
        Mat4::IDENTITY,
    );

    let parts = ColumnParts {
        plinth: builder.mesh(cuboid(Vec3::new(0.7, 0.25, 0.7), stone)),
        shaft: builder.mesh(cylinder(0.22, 2.5, 32, stone)),
    };
    let spacing = COLUMN_X[1] - COLUMN_X[0];
    let arch = builder.mesh(arched_panel(
        spacing,
        ARCH_TOP - SPRING,
        0.5 * (spacing - 0.7),
        ARCADE_DEPTH,
        24,
        stone,
    ));
    let pier = builder.mesh(cuboid(
        Vec3::new(NAVE_HALF_LENGTH - COLUMN_X[5], ARCH_TOP, ARCADE_DEPTH),
        stone,
    ));
    let upper_wall = builder.mesh(cuboid(
        Vec3::new(length, WALL_TOP - ARCH_TOP, ARCADE_DEPTH),
        plaster,
    ));
    let cornice = builder.mesh(cuboid(Vec3::new(length, 0.15, ARCADE_DEPTH + 0.3), stone));
    let aisle_wall = builder.mesh(quad(length, WALL_TOP, plaster));
    let aisle_depth = AISLE_WALL_Z - ROW_Z[1] - 0.5 * ARCADE_DEPTH;
    let aisle_ceiling = builder.mesh(quad(length, aisle_depth, plaster));

    for (side, &z) in ROW_Z.iter().enumerate() {
        let outward = if side == 0 { -1.0 } else { 1.0 };
        for &x in &COLUMN_X {
            add_column(&mut builder, &parts, x, z);
        }
        for pair in COLUMN_X.windows(2) {
            let centre = 0.5 * (pair[0] + pair[1]);
            builder.place(arch, Mat4::from_translation(Vec3::new(centre, SPRING, z)));
        }
        let pier_x = 0.5 * (NAVE_HALF_LENGTH + COLUMN_X[5]);
        for x in [-pier_x, pier_x] {
            builder.place(
                pier,
                Mat4::from_translation(Vec3::new(x, 0.5 * ARCH_TOP, z)),
            );
        }
        builder.place(
            upper_wall,
            Mat4::from_translation(Vec3::new(0.0, 0.5 * (ARCH_TOP + WALL_TOP), z)),
        );
        builder.place(
            cornice,
            Mat4::from_translation(Vec3::new(0.0, ARCH_TOP + 0.075, z)),
        );
        // Aisle back wall facing the nave (the XZ quad turned to face -outward along Z).
        builder.place(
            aisle_wall,
            Mat4::from_rotation_translation(
                Quat::from_rotation_x(-outward * FRAC_PI_2),
                Vec3::new(0.0, 0.5 * WALL_TOP, outward * AISLE_WALL_Z),
            ),
        );
        // Aisle ceiling facing down.
        builder.place(
            aisle_ceiling,
            Mat4::from_rotation_translation(
                Quat::from_rotation_x(PI),
                Vec3::new(0.0, ARCH_TOP, outward * (AISLE_WALL_Z - 0.5 * aisle_depth)),
            ),
        );
    }
    // Closed far end, facing +X.
    builder.add(
        quad(WALL_TOP, 2.0 * AISLE_WALL_Z, plaster),
        Mat4::from_rotation_translation(
            Quat::from_rotation_z(-FRAC_PI_2),
            Vec3::new(-NAVE_HALF_LENGTH, 0.5 * WALL_TOP, 0.0),
        ),
    );

    // Props: two urns on pedestals, a low bench, a draped block against the far wall.
    let pedestal = builder.mesh(cuboid(Vec3::new(0.6, 0.9, 0.6), stone));
    let urn = builder.mesh(uv_sphere(0.35, 32, 16, bronze));
    for z in [-1.4, 1.4] {
        builder.place(pedestal, Mat4::from_translation(Vec3::new(-4.0, 0.45, z)));
        builder.place(urn, Mat4::from_translation(Vec3::new(-4.0, 1.2, z)));
    }
    builder.add(
        cuboid(Vec3::new(2.4, 0.45, 0.5), stone),
        Mat4::from_translation(Vec3::new(2.0, 0.225, 0.0)),
    );
    builder.add(
        cuboid(Vec3::new(0.8, 2.2, 4.0), cloth),
        Mat4::from_translation(Vec3::new(-NAVE_HALF_LENGTH + 0.4, 1.1, 0.0)),
    );

    let camera = Camera::perspective(
        Vec3::new(NAVE_HALF_LENGTH - 0.5, 1.7, 0.4),
        Vec3::new(-NAVE_HALF_LENGTH, 2.4, -0.3),
        60f32.to_radians(),
        0.05,
        200.0,
    );
    builder.build(camera)
}
