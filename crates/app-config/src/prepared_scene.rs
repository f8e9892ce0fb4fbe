//! A scene made ready for a command: loaded, seen through the chosen camera, with the radius
//! R resolved for that view. Every command that renders goes through
//! [`AppConfig::prepare_scene`], so the camera (`[camera]`, `--camera`) and the radius (`auto`,
//! `auto-view` or a number) mean the same thing in
//! `render`, `reference`, `montage`, `graph`, `bench` and `tune`, and every one can print the R
//! it used and where it came from.

use std::sync::Arc;

use aograph_ao_passes::{AoConfig, Radius, RadiusSetting};
use aograph_scene::Scene;
use aograph_scene::views::SceneView;

use crate::camera_spec::apply_view;
use crate::config::AppConfig;
use crate::error::AppResult;

/// A scene, its view and its radius.
#[derive(Clone)]
pub struct PreparedScene {
    /// The scene with the chosen camera as its camera.
    pub scene: Arc<Scene>,
    /// The view's name ("default" when no camera was chosen).
    pub view: String,
    /// The shared radius R in scene units.
    pub radius: Radius,
    /// Where R came from: "set to 2 units" or the automatic rule's derivation.
    pub radius_note: String,
}

impl PreparedScene {
    /// `scene` through `view` with R from `setting`.
    pub fn new(scene: &Scene, view: &SceneView, setting: RadiusSetting) -> Self {
        // R of what this view sees (`auto` is the view rule for an interior view).
        let viewed = apply_view(scene, view);
        let (radius, radius_note) = resolve_radius(&viewed, setting);
        PreparedScene {
            scene: Arc::new(viewed),
            view: view.name.clone(),
            radius,
            radius_note,
        }
    }

    /// `ao` with R pinned to this scene's resolved number (so the graph and the reference
    /// use the same R whatever the setting was).
    pub fn ao(&self, ao: &AoConfig) -> AoConfig {
        AoConfig {
            radius: RadiusSetting::Units(self.radius),
            ..ao.clone()
        }
    }

    /// "R = 0.98 (auto: ...)" for output headers.
    pub fn radius_line(&self) -> String {
        format!("R = {} ({})", short(self.radius.get()), self.radius_note)
    }
}

pub use aograph_renderer::{resolve_radius, short};

impl AppConfig {
    /// Loads the config's scene, applies `[camera]`/`--camera` and resolves the radius.
    pub fn prepare_scene(&self) -> AppResult<PreparedScene> {
        let scene = crate::load_scene(&self.scene)?;
        let view = match &self.camera {
            Some(spec) => spec.resolve(&scene, &self.views)?,
            None => SceneView {
                name: "default".into(),
                camera: scene.camera,
                motion: scene.camera_motion.clone(),
            },
        };
        Ok(PreparedScene::new(&scene, &view, self.ao.radius))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn radii_print_with_four_significant_digits() {
        assert_eq!(short(0.98294), "0.9829");
        assert_eq!(short(1.0), "1.000");
        assert_eq!(short(123.456), "123.5");
        assert_eq!(short(0.0012345), "0.001234");
        assert_eq!(short(0.0), "0");
        assert_eq!(short(-2.5), "-2.500");
    }
}
