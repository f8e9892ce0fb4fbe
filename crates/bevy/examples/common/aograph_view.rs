//! The camera and radius aograph's own tools (`aograph render`, `aograph bench`) use for a glTF
//! file, as a bevy `Transform` and `Projection`, so that bevy and aograph see one view of it:
//! the "default" view (the file's first camera, else one placed to frame its content) and
//! `radius = "auto"`.

use std::error::Error;
use std::path::Path;

use aograph_app_config::{PreparedScene, RadiusSetting};
use bevy::prelude::*;

/// aograph's view of a file.
pub struct AographView {
    /// The scene as aograph loaded it, with the view's camera.
    pub prepared: PreparedScene,
    /// The camera at time 0.
    pub camera: aograph_scene::Camera,
    /// R in the file's units (bevy's metres).
    pub radius: f32,
}

impl AographView {
    /// Loads `file` with aograph's importer and chooses its default view and radius.
    pub fn of(file: &Path) -> Result<Self, Box<dyn Error>> {
        let scene = aograph_scene::load_scene(file)?;
        let view = aograph_scene::views::find_view(&scene, "default").ok_or("no default view")?;
        let prepared = PreparedScene::new(&scene, &view, RadiusSetting::Auto);
        let camera = prepared.scene.camera_at(0.0);
        let radius = prepared.radius.get();
        Ok(Self {
            prepared,
            camera,
            radius,
        })
    }

    /// Where bevy's camera goes (aograph's and bevy's view spaces are both right-handed,
    /// looking down -Z, Y up).
    pub fn transform(&self) -> Transform {
        let v = |a: [f32; 3]| Vec3::from_array(a);
        Transform::from_translation(v(self.camera.position.to_array())).looking_at(
            v(self.camera.target.to_array()),
            v(self.camera.up.to_array()),
        )
    }

    /// bevy's projection with aograph's vertical field of view and near plane (bevy's far plane
    /// is at infinity, which moves no pixel), for `aspect` = width / height.
    pub fn projection(&self, aspect: f32) -> Result<Projection, Box<dyn Error>> {
        let fov = self
            .camera
            .fov_y()
            .ok_or("the file's view is orthographic; these examples place perspective cameras")?;
        Ok(Projection::Perspective(PerspectiveProjection {
            fov,
            near: self.camera.near(),
            aspect_ratio: aspect,
            ..default()
        }))
    }
}
