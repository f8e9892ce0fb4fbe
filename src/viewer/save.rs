//! Saving the viewer's settings as a config that `aograph render --config` reads (the schema of
//! configs/reference.toml): the scene, the render size, the technique with every parameter the
//! user set, R as the number in use, the intermediate format, the camera written out, and the
//! frame count.
//!
//! Invariant: floats are written as the f64 of their f32, which TOML prints in full, so they
//! read back to the same f32; the field of view is stored in degrees, which can move its
//! radians by an ulp (a change far below one 8-bit level of the picture).

use std::fmt::Write;
use std::path::Path;

use aograph_scene::Projection;

use super::session::Session;
use aograph_app_config::config::SceneSource;
use aograph_app_config::error::AppResult;

impl Session {
    /// The settings as a config `aograph render --config` renders the same picture from.
    pub fn config_text(&self) -> String {
        config_text(self)
    }

    /// Writes [`Session::config_text`] to `path` (atomically).
    pub fn save_config(&self, path: &Path) -> AppResult<()> {
        aograph_bench::images::write_atomic(path, self.config_text().as_bytes())
    }
}

/// The config text (see the module docs).
fn config_text(s: &Session) -> String {
    let mut t = String::new();
    let set = &s.settings;
    let _ = writeln!(
        t,
        "# Saved by `aograph view`: `aograph render --config <this file>` renders the picture the\n\
         # viewer showed (technique {}, view as the camera was when saved).",
        set.ao.technique
    );
    t.push_str("\n[scene]\n");
    match &set.scene {
        SceneSource::Procedural(name) => {
            let _ = writeln!(t, "name = {}", toml::Value::from(name.as_str()));
        }
        SceneSource::File(path) => {
            let abs = std::fs::canonicalize(path).unwrap_or_else(|_| path.clone());
            let _ = writeln!(t, "file = {}", toml::Value::from(abs.display().to_string()));
        }
    }
    let size = s.size();
    let _ = writeln!(
        t,
        "\n[output]\nwidth = {}\nheight = {}",
        size.width, size.height
    );
    let _ = writeln!(
        t,
        "\n[ao]\ntechnique = {}\nradius = {}\nintermediate_format = {}",
        toml::Value::from(set.ao.technique.as_str()),
        float(s.radius()),
        toml::Value::from(match set.ao.intermediate_format {
            aograph_ao_passes::IntermediateFormat::R16Float => "r16float",
            aograph_ao_passes::IntermediateFormat::R32Float => "r32float",
        })
    );
    for (technique, params) in &set.ao.params {
        if params.is_empty() {
            continue;
        }
        let _ = writeln!(t, "\n[ao.{technique}]");
        for (k, v) in params {
            let _ = writeln!(t, "{k} = {v}");
        }
    }
    let c = s.camera.camera();
    let v3 = |v: glam::Vec3| format!("[{}, {}, {}]", float(v.x), float(v.y), float(v.z));
    let _ = writeln!(
        t,
        "\n[camera]\nposition = {}\ntarget = {}\nup = {}",
        v3(c.position),
        v3(c.target),
        v3(c.up)
    );
    match c.projection {
        Projection::Perspective {
            fov_y, near, far, ..
        } => {
            let _ = writeln!(
                t,
                "fov = {}\nnear = {}\nfar = {}",
                float(fov_y.to_degrees()),
                float(near),
                float(far)
            );
        }
        Projection::Orthographic { height, near, far } => {
            let _ = writeln!(
                t,
                "orthographic = {}\nnear = {}\nfar = {}",
                float(height),
                float(near),
                float(far)
            );
        }
    }
    let temporal = set
        .ao
        .resolve(&s.registry)
        .is_ok_and(|tech| tech.is_temporal());
    let _ = writeln!(
        t,
        "\n[render]\n# A still frame at scene time 0; a technique with history converges over {}.\nframes = {}\nframe_time = 0.0",
        if temporal {
            "these frames"
        } else {
            "one frame"
        },
        if temporal { 30 } else { 1 }
    );
    t
}

/// An f32 as TOML prints its f64: exact, and read back to the same f32.
fn float(v: f32) -> toml::Value {
    toml::Value::Float(v as f64)
}
