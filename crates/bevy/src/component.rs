//! The camera component a bevy user writes: [`AographAo`], aograph's `[ao]` settings checked
//! when they are made, so a bad technique name or parameter is an `Err` in the user's code and
//! never a failure in the render world.
//!
//! Invariant: an `AographAo` always holds settings that passed every check aograph can make
//! without a device; it is cheap to clone (the render world gets a copy every frame), and a
//! changed component is a new `Arc`, which is how the render world sees a change.

use std::sync::Arc;

use aograph_embed::AoConfig;
use bevy::core_pipeline::prepass::{DepthPrepass, MotionVectorPrepass, NormalPrepass};
use bevy::pbr::ScreenSpaceAmbientOcclusion;
use bevy::prelude::*;
use bevy::render::RenderApp;
use bevy::render::extract_component::ExtractComponent;

use crate::error::AographBevyError;

/// aograph's ambient occlusion on a `Camera3d`, in place of bevy's own SSAO.
///
/// It brings the depth, normal and motion-vector prepasses aograph reads, and bevy's
/// [`ScreenSpaceAmbientOcclusion`] marker: bevy's PBR shaders read AO only where that marker
/// is, from the texture this plugin fills (bevy's own SSAO passes do not run for the camera).
/// As for bevy's SSAO, put `Msaa::Off` on the camera (`Camera3d` brings `Msaa::Sample4`, and
/// that wins over a requirement here): with MSAA on, an error in [`crate::AographAoStatus`]
/// says so, and the camera gets no AO.
///
/// Change the component (insert a new one) to switch technique or parameters: settings whose
/// plan the camera holds for its current size switch at once, without a new pipeline; others
/// are prepared on bevy's async compute pool, not on the render thread, and the camera's AO
/// texture keeps the last frame's AO until they are ready. Removing the component gives the
/// camera back to bevy's own SSAO.
#[derive(Component, Clone, Debug, ExtractComponent)]
#[extract_app(RenderApp)]
#[require(
    ScreenSpaceAmbientOcclusion,
    DepthPrepass,
    NormalPrepass,
    MotionVectorPrepass
)]
pub struct AographAo {
    settings: Arc<AoSettings>,
}

/// One set of settings, as the user wrote them and as aograph parsed them.
#[derive(Debug, PartialEq)]
pub(crate) struct AoSettings {
    pub(crate) text: String,
    pub(crate) config: AoConfig,
}

impl AographAo {
    /// The `[ao]` settings as TOML text, the keys of aograph's config files at the top level:
    /// `technique = "gtao"`, `radius = 0.5` (in world units, bevy's metres), and a table per
    /// technique (`[gtao]` with `resolution = "half"`, `temporal = true`, ...). Refused, with
    /// what is allowed, when the technique or a parameter is unknown or out of range, the
    /// radius is not a positive number, or the technique needs more than the camera's depth,
    /// normals and motion.
    pub fn from_toml(text: &str) -> Result<Self, AographBevyError> {
        let config = aograph_embed::check_settings_toml(text)?;
        Ok(Self {
            settings: Arc::new(AoSettings {
                text: text.to_owned(),
                config,
            }),
        })
    }

    /// The technique's registry name.
    pub fn technique(&self) -> &str {
        &self.settings.config.technique
    }

    /// The parsed settings.
    pub fn config(&self) -> &AoConfig {
        &self.settings.config
    }

    /// The settings' text, as given to [`AographAo::from_toml`].
    pub fn toml(&self) -> &str {
        &self.settings.text
    }

    pub(crate) fn settings(&self) -> &Arc<AoSettings> {
        &self.settings
    }
}
