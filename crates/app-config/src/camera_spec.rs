//! Choosing the camera: `[camera]` and `[[views]]` in a config, and `--camera` on every
//! command that renders.
//!
//! `--camera` takes, in this order of lookup: an inline camera (`pos=x,y,z target=x,y,z
//! fov=60`, any text containing `=`), a `[[views]]` name from the config, or a view of the
//! scene (`aograph_scene::views::find_view`: `default`, a glTF camera's name or index,
//! `outside`, `outside-2`, `interior-1`, `interior-2`). An unknown name is an error listing
//! every name the scene and config offer.
//!
//! A camera table or inline camera has: `position` (`pos`), `target` or `yaw` and `pitch`
//! (degrees; yaw 0 looks along -Z, positive yaw turns left, positive pitch looks up), `up`
//! (default +Y), `fov` (vertical, degrees, default 60), `near` and `far` (default 1e-3 and 100
//! times the scene's diagonal), and `orthographic` (the view volume's height in scene units; a
//! perspective camera when absent).

use aograph_scene::views::{SceneView, find_view, view_names};
use aograph_scene::{Camera, Projection, Scene};
use glam::Vec3;

use crate::error::{AppError, AppResult};

/// Where the camera looks.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Look {
    /// Looks at this world-space point (`target`); it must differ from the position.
    Target(Vec3),
    /// Yaw and pitch in degrees.
    YawPitch(f32, f32),
}

/// A camera written out in a config or on the command line.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraParams {
    /// Camera position in world space, scene units (`position` or `pos`).
    pub position: Vec3,
    /// Where the camera looks: a target point, or yaw and pitch from -Z.
    pub look: Look,
    /// World-space up vector, normalized (`up`; default +Y).
    pub up: Vec3,
    /// Vertical field of view in degrees, 0 < fov < 180 (`fov`; default 60); unused by an
    /// orthographic camera.
    pub fov_degrees: f32,
    /// Near plane distance in scene units (> 0); `None`: 1e-3 times the scene's diagonal.
    pub near: Option<f32>,
    /// Far plane distance in scene units (> near when both are given); `None`: 100 times the
    /// scene's diagonal. The camera raises it to at least twice the near distance.
    pub far: Option<f32>,
    /// The orthographic view height; `None` for perspective.
    pub orthographic: Option<f32>,
}

/// A camera choice: a name to look up or a camera written out.
#[derive(Clone, Debug, PartialEq)]
pub enum CameraSpec {
    /// A name looked up by [`CameraSpec::resolve`]: a config `[[views]]` entry first, then a
    /// view of the scene or a glTF camera (by name or index).
    Named(String),
    /// A camera written out: inline `pos=x,y,z target=x,y,z fov=60` or a `[camera]` table.
    Inline(CameraParams),
}

/// A `[[views]]` entry.
#[derive(Clone, Debug, PartialEq)]
pub struct NamedView {
    /// The view's name: non-empty and unique among the config's views; `--camera` and
    /// `--views` pick it by this name (picked by name, it wins over a scene view of the same
    /// name).
    pub name: String,
    /// The camera the entry writes out.
    pub params: CameraParams,
}

const KEYS: &[&str] = &[
    "position",
    "target",
    "yaw",
    "pitch",
    "up",
    "fov",
    "near",
    "far",
    "orthographic",
];

fn finite_positive(key: &str, v: f32) -> Result<f32, String> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(format!("`{key}` = {v}: must be a finite number > 0"))
    }
}

/// Builds camera parameters from (key, value) pairs already split, checking every value.
fn from_pairs<'a>(
    pairs: impl IntoIterator<Item = (&'a str, Value)>,
) -> Result<CameraParams, String> {
    let (mut position, mut target, mut yaw, mut pitch) = (None, None, None, None);
    let mut p = CameraParams {
        position: Vec3::ZERO,
        look: Look::YawPitch(0.0, 0.0),
        up: Vec3::Y,
        fov_degrees: 60.0,
        near: None,
        far: None,
        orthographic: None,
    };
    for (key, value) in pairs {
        let key = if key == "pos" { "position" } else { key };
        match key {
            "position" => position = Some(value.vec3(key)?),
            "target" => target = Some(value.vec3(key)?),
            "up" => {
                p.up = value
                    .vec3(key)?
                    .try_normalize()
                    .ok_or("`up` must not be zero")?
            }
            "yaw" => yaw = Some(value.number(key)?),
            "pitch" => {
                let v = value.number(key)?;
                if v.abs() >= 90.0 {
                    return Err(format!("`pitch` = {v}: allowed -90 < pitch < 90 degrees"));
                }
                pitch = Some(v)
            }
            "fov" => {
                let v = value.number(key)?;
                if !(v > 0.0 && v < 180.0) {
                    return Err(format!("`fov` = {v}: allowed 0 < fov < 180 degrees"));
                }
                p.fov_degrees = v
            }
            "near" => p.near = Some(finite_positive(key, value.number(key)?)?),
            "far" => p.far = Some(finite_positive(key, value.number(key)?)?),
            "orthographic" => p.orthographic = Some(finite_positive(key, value.number(key)?)?),
            other => {
                return Err(aograph_ao_passes::unknown_key("camera", other, KEYS));
            }
        }
    }
    p.position = position.ok_or("`position` is missing (e.g. position = [0, 2, 5])")?;
    p.look = match (target, yaw, pitch) {
        (Some(t), None, None) => {
            if t == p.position {
                return Err("`target` equals `position`: the camera looks nowhere".into());
            }
            Look::Target(t)
        }
        (None, y, pt) if y.is_some() || pt.is_some() => {
            Look::YawPitch(y.unwrap_or(0.0), pt.unwrap_or(0.0))
        }
        (None, _, _) => return Err("give `target`, or `yaw` and `pitch`".into()),
        _ => return Err("give `target` or `yaw`/`pitch`, not both".into()),
    };
    if let (Some(n), Some(f)) = (p.near, p.far)
        && n >= f
    {
        return Err(format!("`near` = {n} must be less than `far` = {f}"));
    }
    Ok(p)
}

/// A value of a camera key: a number or a 3-vector.
enum Value {
    Number(f32),
    Vec3(Vec3),
    Bad(String),
}

impl Value {
    fn shown(&self) -> String {
        match self {
            Value::Number(v) => v.to_string(),
            Value::Vec3(v) => format!("{},{},{}", v.x, v.y, v.z),
            Value::Bad(text) => text.clone(),
        }
    }
    fn number(&self, key: &str) -> Result<f32, String> {
        match self {
            Value::Number(v) if v.is_finite() => Ok(*v),
            _ => Err(format!(
                "`{key}` = {} must be a finite number",
                self.shown()
            )),
        }
    }
    fn vec3(&self, key: &str) -> Result<Vec3, String> {
        match self {
            Value::Vec3(v) if v.is_finite() => Ok(*v),
            _ => Err(format!(
                "`{key}` = {} must be three finite numbers, x,y,z",
                self.shown()
            )),
        }
    }
    fn from_text(text: &str) -> Value {
        let parts: Vec<&str> = text.split(',').map(str::trim).collect();
        let numbers: Option<Vec<f32>> = parts.iter().map(|s| s.parse::<f32>().ok()).collect();
        match numbers.as_deref() {
            Some([v]) => Value::Number(*v),
            Some([x, y, z]) => Value::Vec3(Vec3::new(*x, *y, *z)),
            _ => Value::Bad(text.to_string()),
        }
    }
    fn from_toml(v: &toml::Value) -> Value {
        let num = |v: &toml::Value| v.as_float().or_else(|| v.as_integer().map(|i| i as f64));
        match v {
            toml::Value::Array(a) => {
                let n: Option<Vec<f64>> = a.iter().map(num).collect();
                match n.as_deref() {
                    Some([x, y, z]) => Value::Vec3(Vec3::new(*x as f32, *y as f32, *z as f32)),
                    _ => Value::Bad(v.to_string()),
                }
            }
            other => num(other).map_or(Value::Bad(other.to_string()), |f| Value::Number(f as f32)),
        }
    }
}

impl CameraParams {
    /// An inline camera: `pos=x,y,z target=x,y,z fov=60` (space-separated key=value pairs).
    pub fn parse_inline(text: &str) -> Result<CameraParams, String> {
        let mut pairs = Vec::new();
        for word in text.split_whitespace() {
            let (k, v) = word
                .split_once('=')
                .ok_or_else(|| format!("`{word}` is not key=value"))?;
            pairs.push((k, Value::from_text(v)));
        }
        from_pairs(pairs)
    }

    /// A `[camera]` or `[[views]]` table (`name` is skipped: the caller reads it).
    pub fn from_table(t: &toml::Table) -> Result<CameraParams, String> {
        from_pairs(
            t.iter()
                .filter(|(k, _)| k.as_str() != "name")
                .map(|(k, v)| (k.as_str(), Value::from_toml(v))),
        )
    }

    /// The camera in `scene` (near and far default to 1e-3 and 100 times its diagonal).
    pub fn camera(&self, scene: &Scene) -> Camera {
        let d = scene.bounds().diagonal();
        let d = if d.is_finite() && d > 0.0 { d } else { 1.0 };
        let near = self.near.unwrap_or(1e-3 * d);
        let far = self.far.unwrap_or(100.0 * d).max(near * 2.0);
        let target = match self.look {
            Look::Target(t) => t,
            Look::YawPitch(yaw, pitch) => {
                let (y, p) = (yaw.to_radians(), pitch.to_radians());
                self.position + Vec3::new(-y.sin() * p.cos(), p.sin(), -y.cos() * p.cos())
            }
        };
        let projection = match self.orthographic {
            Some(height) => Projection::Orthographic { height, near, far },
            None => Projection::Perspective {
                fov_y: self.fov_degrees.to_radians(),
                near,
                far,
                reversed_z_infinite: false,
            },
        };
        Camera {
            position: self.position,
            target,
            up: self.up,
            projection,
        }
    }
}

impl CameraSpec {
    /// `--camera`'s text: inline when it contains `=`, else a name.
    pub fn parse(text: &str) -> AppResult<CameraSpec> {
        let text = text.trim();
        if text.contains('=') {
            CameraParams::parse_inline(text)
                .map(CameraSpec::Inline)
                .map_err(|e| AppError::InvalidArgument {
                    name: "--camera".into(),
                    value: text.into(),
                    allowed: format!("{e}; e.g. \"pos=0,2,5 target=0,0,0 fov=60\""),
                })
        } else if text.is_empty() {
            Err(AppError::InvalidArgument {
                name: "--camera".into(),
                value: String::new(),
                allowed: "a view or glTF camera name, an index, or pos=x,y,z target=x,y,z".into(),
            })
        } else {
            Ok(CameraSpec::Named(text.to_string()))
        }
    }

    /// The view this spec picks in `scene`, with `views` from the config.
    pub fn resolve(&self, scene: &Scene, views: &[NamedView]) -> AppResult<SceneView> {
        match self {
            CameraSpec::Inline(p) => Ok(SceneView {
                name: "inline".into(),
                camera: p.camera(scene),
                motion: None,
            }),
            CameraSpec::Named(name) => {
                if let Some(v) = views.iter().find(|v| &v.name == name) {
                    return Ok(SceneView {
                        name: v.name.clone(),
                        camera: v.params.camera(scene),
                        motion: None,
                    });
                }
                find_view(scene, name).ok_or_else(|| {
                    let mut known: Vec<String> = views.iter().map(|v| v.name.clone()).collect();
                    known.extend(view_names(scene));
                    AppError::InvalidArgument {
                        name: "--camera".into(),
                        value: name.clone(),
                        allowed: format!(
                            "{}, or an inline camera \"pos=x,y,z target=x,y,z fov=60\"{}",
                            known.join(", "),
                            aograph_graph::did_you_mean(name, known.iter().map(String::as_str))
                        ),
                    }
                })
            }
        }
    }
}

/// `scene` seen through `view` (its motion kept, so an animated glTF camera still moves).
pub fn apply_view(scene: &Scene, view: &SceneView) -> Scene {
    Scene {
        camera: view.camera,
        camera_motion: view.motion.clone(),
        ..scene.clone()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scene() -> Scene {
        aograph_scene::procedural_scene("room").unwrap()
    }

    #[test]
    fn inline_camera_with_target_and_fov() {
        let p = CameraParams::parse_inline("pos=1,2,3 target=0,0.5,0 fov=45").unwrap();
        let c = p.camera(&scene());
        assert_eq!(c.position, Vec3::new(1.0, 2.0, 3.0));
        assert_eq!(c.target, Vec3::new(0.0, 0.5, 0.0));
        let Projection::Perspective {
            fov_y, near, far, ..
        } = c.projection
        else {
            panic!("perspective expected");
        };
        assert!((fov_y - 45f32.to_radians()).abs() < 1e-6);
        assert!(near > 0.0 && far > near);
    }

    #[test]
    fn yaw_and_pitch_turn_from_minus_z() {
        let p = CameraParams::parse_inline("pos=0,1,0 yaw=90 pitch=0").unwrap();
        let f = p.camera(&scene()).forward();
        assert!(
            (f - Vec3::NEG_X).length() < 1e-6,
            "yaw 90 turns left to -X: {f}"
        );
        let p = CameraParams::parse_inline("pos=0,1,0 yaw=0 pitch=30").unwrap();
        let f = p.camera(&scene()).forward();
        assert!((f.y - 0.5).abs() < 1e-6 && f.z < 0.0, "{f}");
    }

    #[test]
    fn a_config_table_and_orthographic() {
        let t: toml::Table =
            "position = [0, 5, 0]\ntarget = [0, 0, 0.001]\nup = [0, 0, -1]\northographic = 8\nnear = 0.5\nfar = 50"
                .parse()
                .unwrap();
        let c = CameraParams::from_table(&t).unwrap().camera(&scene());
        assert_eq!(
            c.projection,
            Projection::Orthographic {
                height: 8.0,
                near: 0.5,
                far: 50.0
            }
        );
    }

    #[test]
    fn bad_cameras_are_errors_that_name_the_problem() {
        for (text, needle) in [
            ("target=0,0,0", "`position` is missing"),
            ("pos=0,0,0 target=0,0,0", "looks nowhere"),
            ("pos=1,2 target=0,0,0", "three finite numbers"),
            ("pos=0,0,1 target=0,0,0 fov=0", "0 < fov < 180"),
            ("pos=0,0,1 target=0,0,0 zoom=2", "unknown key `zoom`"),
            ("pos=0,0,1 target=0,0,0 yaw=3", "not both"),
            ("pos=0,0,1 pitch=95", "-90 < pitch < 90"),
            ("pos=0,0,1 target=0,0,0 near=2 far=1", "less than `far`"),
            ("pos=0,0,1 target", "not key=value"),
        ] {
            let e = CameraParams::parse_inline(text).unwrap_err();
            assert!(e.contains(needle), "{text}: {e}");
        }
        let e = CameraSpec::Named("attic".into())
            .resolve(&scene(), &[])
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("attic") && e.contains("interior-1") && e.contains("default"),
            "{e}"
        );
    }

    #[test]
    fn config_views_come_before_the_scene_s_own() {
        let params = CameraParams::parse_inline("pos=0,1,2 target=0,1,0").unwrap();
        let views = [NamedView {
            name: "outside".into(),
            params,
        }];
        let v = CameraSpec::Named("outside".into())
            .resolve(&scene(), &views)
            .unwrap();
        assert_eq!(v.camera.position, Vec3::new(0.0, 1.0, 2.0));
        let auto = CameraSpec::Named("interior-1".into())
            .resolve(&scene(), &views)
            .unwrap();
        assert_eq!(auto.name, "interior-1");
    }
}
