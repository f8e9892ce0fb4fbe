//! Procedural test scenes and their registry, looked up by name.
//!
//! Every scene comes with a default camera, the default directional light and ambient, and is
//! built only from the primitives in [`crate::primitives`] (plus the arched panel of the
//! arcade). Invariant: [`PROCEDURAL_SCENE_NAMES`] lists exactly the names
//! [`procedural_scene`] accepts, and every scene it returns has triangles and finite geometry.

mod analytic;
mod arch;
mod columns;
mod cornell_box;
mod dynamic;
mod instanced_field;
mod node_transforms;
mod room;
mod stairs;
mod thin_bars;

pub use analytic::{
    SPHERE_ON_PLANE_CENTRE, SPHERE_ON_PLANE_RADIUS, WALL_HALF_EXTENT, WALL_PLANE_X,
    sphere_on_plane_accessibility, wall_accessibility,
};
pub use arch::arched_panel;
pub use instanced_field::instanced_field;
pub use room::{ROOM_HALF_X, ROOM_HALF_Z, ROOM_HEIGHT};

use crate::error::SceneError;
use crate::model::Scene;
use crate::primitives::quad;
use crate::scene_builder::SceneBuilder;
use glam::Mat4;

/// The names [`procedural_scene`] knows, in a sensible display order.
pub const PROCEDURAL_SCENE_NAMES: &[&str] = &[
    "plane",
    "sphere-on-plane",
    "wall",
    "corner",
    "cornell-box",
    "thin-bars",
    "stairs",
    "columns",
    "dynamic",
    "node-transforms",
    "room",
];

/// The scene the app opens when none is given.
pub const DEFAULT_SCENE_NAME: &str = "columns";

/// Builds the procedural scene called `name` (one of [`PROCEDURAL_SCENE_NAMES`]).
pub fn procedural_scene(name: &str) -> Result<Scene, SceneError> {
    Ok(match name {
        "plane" => analytic::plane(),
        "sphere-on-plane" => analytic::sphere_on_plane(),
        "wall" => analytic::wall(),
        "corner" => analytic::corner(),
        "cornell-box" => cornell_box::cornell_box(),
        "thin-bars" => thin_bars::thin_bars(),
        "stairs" => stairs::stairs(),
        "columns" => columns::columns(),
        "dynamic" => dynamic::dynamic(),
        "node-transforms" => node_transforms::node_transforms(),
        "room" => room::room(),
        _ => {
            return Err(SceneError::UnknownScene {
                name: name.to_owned(),
                known: PROCEDURAL_SCENE_NAMES.join(", "),
            });
        }
    })
}

/// Light grey floor colour shared by the scenes.
pub(crate) const FLOOR_COLOR: [f32; 3] = [0.62, 0.6, 0.57];
/// Off-white wall colour shared by the scenes.
pub(crate) const WALL_COLOR: [f32; 3] = [0.8, 0.78, 0.74];

/// Adds a square floor of edge `size` centred on the origin at y = 0, as a backdrop (it stands
/// in for an unbounded ground plane: `Instance::backdrop`).
pub(crate) fn floor(builder: &mut SceneBuilder, size: f32) {
    let material = builder.material(FLOOR_COLOR);
    builder.add_backdrop(quad(size, size, material), Mat4::IDENTITY);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_listed_scene_builds_with_triangles_and_finite_bounds() {
        for name in PROCEDURAL_SCENE_NAMES {
            let scene = procedural_scene(name).unwrap();
            assert!(scene.triangle_count() > 0, "{name} has no triangles");
            let b = scene.bounds();
            assert!(
                b.min.is_finite() && b.max.is_finite(),
                "{name} bounds {b:?}"
            );
        }
    }

    #[test]
    fn unknown_scene_lists_the_known_names() {
        let message = procedural_scene("sponza").unwrap_err().to_string();
        assert!(message.contains("sponza"), "{message}");
        for name in PROCEDURAL_SCENE_NAMES {
            assert!(message.contains(name), "{message}");
        }
    }

    #[test]
    fn only_dynamic_scene_moves() {
        for name in PROCEDURAL_SCENE_NAMES {
            let scene = procedural_scene(name).unwrap();
            assert_eq!(scene.is_static(), *name != "dynamic", "{name}");
        }
    }
}
