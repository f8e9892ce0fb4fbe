//! The application config: one TOML schema (annotated in configs/reference.toml) covering the
//! scene, output size, AO technique and parameters, and the reference. Unknown keys are
//! rejected with the nearest valid key suggested; values are range-checked with the allowed
//! range in the message. CLI flags override the file and are checked the same way.

use std::path::{Path, PathBuf};

use aograph_ao_passes::{AoConfig, TechniqueRegistry, unknown_key};
use aograph_scene::{ReferenceMode, ReferenceNormals, ReferenceTracer};

/// The scene rendered when none is given.
pub const DEFAULT_SCENE: &str = "columns";

use crate::camera_spec::{CameraParams, CameraSpec, NamedView};
use crate::error::{AppError, AppResult};

/// Where the scene comes from: a procedural name or a glTF file.
#[derive(Clone, Debug, PartialEq)]
pub enum SceneSource {
    /// A built-in scene by name (`aograph_scene::procedural_scene`), e.g. `columns` or `room`.
    Procedural(String),
    /// A glTF file (.gltf or .glb). A path from a config file is relative to that file's
    /// directory; one from the command line, to the working directory.
    File(PathBuf),
}

impl SceneSource {
    /// A name containing a path separator or ending in .gltf/.glb is a file; anything else is
    /// a procedural scene name.
    pub fn parse(s: &str) -> Self {
        let lower = s.to_ascii_lowercase();
        if lower.ends_with(".gltf")
            || lower.ends_with(".glb")
            || s.contains('/')
            || s.contains('\\')
        {
            SceneSource::File(PathBuf::from(s))
        } else {
            SceneSource::Procedural(s.to_string())
        }
    }
    /// The name reports and progress messages show: the procedural name, or the file's path as
    /// given.
    pub fn label(&self) -> String {
        match self {
            SceneSource::Procedural(n) => n.clone(),
            SceneSource::File(p) => p.display().to_string(),
        }
    }

    /// A short name for file names: the procedural name, or the file's name without its
    /// directories and extension.
    pub fn short_name(&self) -> String {
        match self {
            SceneSource::Procedural(n) => n.clone(),
            SceneSource::File(p) => p
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_else(|| p.display().to_string()),
        }
    }
}

/// How R is chosen: `auto` or a number (`[ao] radius`, `--radius`), checked in one place.
pub use aograph_ao_passes::RadiusSetting;

/// Everything `aograph render` and friends need.
#[derive(Clone, Debug, PartialEq)]
pub struct AppConfig {
    /// The scene to render (`[scene] name` or `file`; default [`DEFAULT_SCENE`]).
    pub scene: SceneSource,
    /// Output width in pixels (`[output] width`, 1 to `MAX_SIDE`; default 1280).
    pub width: u32,
    /// Output height in pixels (`[output] height`, 1 to `MAX_SIDE`; default 720).
    pub height: u32,
    /// Technique, parameters and how R is chosen (`ao.radius`: `auto` unless the config or
    /// `--radius` gives a number; the prepared scene holds the number).
    pub ao: AoConfig,
    /// The camera: `[camera]` or `--camera`; `None` = the scene's own.
    pub camera: Option<CameraSpec>,
    /// Named viewpoints (`[[views]]`).
    pub views: Vec<NamedView>,
    /// Rays per pixel of the ray-traced reference (`[reference] rays`, 1 to 2^20; default 256).
    pub reference_rays: u32,
    /// How a reference ray's hit becomes occlusion (`[reference] mode`): `binary` (a hit
    /// within R occludes fully; the default) or `obscurance` (weighted by distance).
    pub reference_mode: ReferenceMode,
    /// The normal that orients the reference's hemisphere (geometric unless set).
    pub reference_normals: ReferenceNormals,
    /// CPU or GPU reference tracer (auto unless set).
    pub reference_tracer: ReferenceTracer,
    /// Frames to render (temporal techniques converge over frames).
    pub frames: u32,
    /// Seconds of scene time per frame (0 = a still frame).
    pub frame_time: f32,
}

impl Default for AppConfig {
    fn default() -> Self {
        Self {
            scene: SceneSource::Procedural(DEFAULT_SCENE.into()),
            width: 1280,
            height: 720,
            ao: AoConfig::default(),
            camera: None,
            views: Vec::new(),
            reference_rays: 256,
            reference_mode: ReferenceMode::Binary,
            reference_normals: ReferenceNormals::Geometric,
            reference_tracer: ReferenceTracer::Auto,
            frames: 1,
            frame_time: 1.0 / 30.0,
        }
    }
}

const TOP_KEYS: &[&str] = &[
    "scene",
    "output",
    "ao",
    "camera",
    "views",
    "reference",
    "render",
];
const SCENE_KEYS: &[&str] = &["name", "file"];
const OUTPUT_KEYS: &[&str] = &["width", "height"];
const REFERENCE_KEYS: &[&str] = &["rays", "mode", "normals", "tracer"];
const RENDER_KEYS: &[&str] = &["frames", "frame_time"];

/// Largest output side accepted (wgpu's default 2D texture limit).
pub use aograph_renderer::MAX_SIDE;

fn err(path: &str, message: String) -> AppError {
    AppError::Config {
        path: path.into(),
        message,
    }
}

fn table<'a>(path: &str, v: &'a toml::Value, section: &str) -> AppResult<&'a toml::Table> {
    v.as_table()
        .ok_or_else(|| err(path, format!("[{section}] must be a table")))
}

fn uint(path: &str, key: &str, v: &toml::Value, lo: u32, hi: u32) -> AppResult<u32> {
    let i = v
        .as_integer()
        .ok_or_else(|| err(path, format!("`{key}` must be an integer")))?;
    if i < lo as i64 || i > hi as i64 {
        return Err(err(
            path,
            format!("`{key}` = {i} is out of range (allowed {lo} to {hi})"),
        ));
    }
    Ok(i as u32)
}

impl AppConfig {
    /// Reads and validates a config file.
    pub fn load(path: &Path, registry: &TechniqueRegistry) -> AppResult<Self> {
        let text =
            std::fs::read_to_string(path).map_err(|e| AppError::io("read config", path, e))?;
        Self::parse(&text, &path.display().to_string(), registry)
    }

    /// Parses config text; `path` names it in messages.
    pub fn parse(text: &str, path: &str, registry: &TechniqueRegistry) -> AppResult<Self> {
        let doc: toml::Table = text
            .parse()
            .map_err(|e: toml::de::Error| err(path, e.to_string().trim().to_string()))?;
        let mut c = AppConfig::default();
        for (k, v) in &doc {
            match k.as_str() {
                "scene" => {
                    for (sk, sv) in table(path, v, "scene")? {
                        let s = sv
                            .as_str()
                            .ok_or_else(|| err(path, format!("[scene] `{sk}` must be a string")))?;
                        c.scene = match sk.as_str() {
                            "name" => SceneSource::Procedural(s.to_string()),
                            "file" => SceneSource::File(resolve(path, s)),
                            _ => return Err(err(path, unknown_key("scene", sk, SCENE_KEYS))),
                        };
                    }
                }
                "output" => {
                    for (ok, ov) in table(path, v, "output")? {
                        match ok.as_str() {
                            "width" => c.width = uint(path, "width", ov, 1, MAX_SIDE)?,
                            "height" => c.height = uint(path, "height", ov, 1, MAX_SIDE)?,
                            _ => return Err(err(path, unknown_key("output", ok, OUTPUT_KEYS))),
                        }
                    }
                }
                "ao" => {
                    let ao = table(path, v, "ao")?;
                    c.ao =
                        AoConfig::from_table(ao, registry).map_err(|e| err(path, e.to_string()))?
                }
                "camera" => {
                    c.camera = Some(CameraSpec::Inline(
                        CameraParams::from_table(table(path, v, "camera")?)
                            .map_err(|m| err(path, format!("[camera]: {m}")))?,
                    ))
                }
                "views" => {
                    let list = v.as_array().ok_or_else(|| {
                        err(path, "`views` must be an array of tables: [[views]]".into())
                    })?;
                    for (i, entry) in list.iter().enumerate() {
                        let t = entry.as_table().ok_or_else(|| {
                            err(path, format!("[[views]] entry {i} must be a table"))
                        })?;
                        let name = t
                            .get("name")
                            .and_then(|n| n.as_str())
                            .filter(|n| !n.trim().is_empty())
                            .ok_or_else(|| {
                                err(path, format!("[[views]] entry {i} needs a `name` string"))
                            })?
                            .to_string();
                        if c.views.iter().any(|v| v.name == name) {
                            return Err(err(
                                path,
                                format!("[[views]] name `{name}` is used twice"),
                            ));
                        }
                        let params = CameraParams::from_table(t)
                            .map_err(|m| err(path, format!("[[views]] `{name}`: {m}")))?;
                        c.views.push(NamedView { name, params });
                    }
                }
                "reference" => {
                    for (rk, rv) in table(path, v, "reference")? {
                        match rk.as_str() {
                            "rays" => c.reference_rays = uint(path, "rays", rv, 1, 1 << 20)?,
                            "mode" => {
                                c.reference_mode = parse_mode(rv.as_str().unwrap_or(""))
                                    .map_err(|m| err(path, m))?
                            }
                            "normals" => {
                                c.reference_normals =
                                    ReferenceNormals::parse(rv.as_str().unwrap_or(""))
                                        .map_err(|m| err(path, m))?
                            }
                            "tracer" => {
                                c.reference_tracer =
                                    ReferenceTracer::parse(rv.as_str().unwrap_or(""))
                                        .map_err(|m| err(path, m))?
                            }
                            _ => {
                                return Err(err(
                                    path,
                                    unknown_key("reference", rk, REFERENCE_KEYS),
                                ));
                            }
                        }
                    }
                }
                "render" => {
                    for (rk, rv) in table(path, v, "render")? {
                        match rk.as_str() {
                            "frames" => c.frames = uint(path, "frames", rv, 1, 1_000_000)?,
                            "frame_time" => {
                                let f = rv
                                    .as_float()
                                    .or_else(|| rv.as_integer().map(|i| i as f64))
                                    .ok_or_else(|| {
                                        err(path, "`frame_time` must be a number of seconds".into())
                                    })?;
                                if !(f.is_finite() && (0.0..=10.0).contains(&f)) {
                                    return Err(err(
                                        path,
                                        format!(
                                            "`frame_time` = {f} is out of range (allowed 0 to 10 seconds)"
                                        ),
                                    ));
                                }
                                c.frame_time = f as f32;
                            }
                            _ => return Err(err(path, unknown_key("render", rk, RENDER_KEYS))),
                        }
                    }
                }
                _ => return Err(err(path, unknown_key("top level", k, TOP_KEYS))),
            }
        }
        Ok(c)
    }

    /// Checks values that flags may also set.
    pub fn validate(&self, registry: &TechniqueRegistry) -> AppResult<()> {
        check_size("--width", self.width)?;
        check_size("--height", self.height)?;
        self.ao.validate(registry)?;
        Ok(())
    }
}

/// Output sides must be 1..=MAX_SIDE (aograph_renderer::check_size).
pub fn check_size(name: &str, v: u32) -> AppResult<()> {
    Ok(aograph_renderer::check_size(name, v)?)
}

/// Parses a reference mode name, `binary` or `obscurance`; the error message lists both.
pub fn parse_mode(s: &str) -> Result<ReferenceMode, String> {
    match s {
        "binary" => Ok(ReferenceMode::Binary),
        "obscurance" => Ok(ReferenceMode::Obscurance),
        _ => Err(format!(
            "reference mode `{s}` is not known (allowed: binary, obscurance)"
        )),
    }
}

/// A scene file path in a config is relative to the config file.
fn resolve(config_path: &str, file: &str) -> PathBuf {
    let p = PathBuf::from(file);
    if p.is_absolute() {
        return p;
    }
    Path::new(config_path)
        .parent()
        .map(|d| d.join(&p))
        .unwrap_or(p)
}
