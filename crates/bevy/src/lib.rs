//! aograph's ambient occlusion in bevy: every technique aograph-embed offers, on a bevy
//! camera, in place of bevy's own SSAO.
//!
//! **Targets bevy 0.20.1** (wgpu 30, the same wgpu as aograph) and Rust 1.97.1 or newer.
//!
//! ```no_run
//! use bevy::prelude::*;
//! use aograph_bevy::{AographAo, AographAoPlugin};
//!
//! fn setup(mut commands: Commands) {
//!     // Any technique aograph-embed can feed from depth, normals and motion, with its
//!     // parameters; a bad name or value is an Err here, never a panic in the render world.
//!     let ao = AographAo::from_toml("technique = \"gtao\"\nradius = 0.5\n[gtao]\nresolution = \"half\"")
//!         .expect("valid settings");
//!     commands.spawn((Camera3d::default(), Msaa::Off, ao));
//! }
//!
//! App::new()
//!     .add_plugins((DefaultPlugins, AographAoPlugin))
//!     .add_systems(Startup, setup)
//!     .run();
//! ```
//!
//! How it meets bevy: the camera component brings bevy's depth, normal and motion prepasses
//! and bevy's `ScreenSpaceAmbientOcclusion` marker, so bevy's PBR shaders read AO from group 0
//! binding 17. In the render world the plugin puts aograph's AO texture (bevy's format,
//! R16Float or R32Float, the viewport's size) in `ScreenSpaceAmbientOcclusionResources`
//! before bevy makes the mesh view bind group, removes the pipeline id bevy's SSAO system
//! needs (so bevy's SSAO passes do not run), and records aograph's passes into the camera's
//! Core3d schedule between the prepass and the main pass. Direct light is untouched, as with
//! bevy's SSAO: AO scales the indirect diffuse and specular terms only.
//!
//! Layers: this crate is the bevy adapter over `aograph-embed` (an application's frame in, AO
//! out); it owns no technique, pass or shader of its own.

#![warn(missing_docs)]

mod camera_ao;
mod component;
mod error;
mod frame_inputs;
mod render_systems;
mod status;

use bevy::core_pipeline::schedule::{Core3d, Core3dSystems};
use bevy::prelude::*;
use bevy::render::extract_component::ExtractComponentPlugin;
use bevy::render::{Render, RenderApp, RenderSystems};

pub use component::AographAo;
pub use error::AographBevyError;
pub use frame_inputs::{BEVY_MOTION_UV_SCALE, ao_inputs};
pub use status::{AographAoStatus, CameraAoStatus};

/// The bevy version this crate is built for and tested with.
pub const BEVY_VERSION: &str = "0.20.1";

/// Adds aograph's AO for every `Camera3d` with an [`AographAo`] component. Add it after
/// `DefaultPlugins` (it needs bevy's PBR plugin, whose SSAO resources it fills).
pub struct AographAoPlugin;

impl Plugin for AographAoPlugin {
    fn build(&self, app: &mut App) {
        let status = AographAoStatus::default();
        app.add_plugins(ExtractComponentPlugin::<AographAo>::default())
            .insert_resource(status.clone());
        let Some(render_app) = app.get_sub_app_mut(RenderApp) else {
            return;
        };
        render_app
            .insert_resource(status)
            .init_resource::<render_systems::AographCameras>()
            .add_systems(
                Render,
                render_systems::refuse_msaa.in_set(RenderSystems::PrepareAssets),
            )
            .add_systems(
                Render,
                render_systems::hand_over_ao_texture
                    .in_set(RenderSystems::PrepareBindGroups)
                    .before(bevy::pbr::prepare_mesh_view_bind_groups),
            )
            .add_systems(
                Core3d,
                render_systems::encode_ao
                    .after(Core3dSystems::Prepass)
                    .before(Core3dSystems::MainPass),
            );
    }
}
