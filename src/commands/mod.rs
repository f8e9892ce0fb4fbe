//! The commands behind the `aograph` binary, callable from tests. Each resolves the config
//! (file, then flags), does its work and prints where its files went.

mod bench;
pub mod docs;
mod docs_tables;
mod graph;
mod montage;
mod reference;
mod render;
mod scene_info;
mod tune;
mod tune_search;
mod webgpu_fit;

use std::path::PathBuf;
use std::sync::Arc;

use aograph_ao_passes::TechniqueRegistry;
use aograph_graph::GpuContext;

pub use bench::{BenchArgs, bench};
pub use docs::docs;
pub use graph::graph;
pub use montage::montage;
pub use reference::reference;
pub use render::{RenderArgs, render};
pub use scene_info::{scene_info, scene_info_text};
pub use tune::{DEFAULT_SWEEP, TuneArgs, choose, config_text};
pub use webgpu_fit::webgpu_fit_lines;

use aograph_app_config::camera_spec::CameraSpec;
use aograph_app_config::config::{AppConfig, RadiusSetting, SceneSource, check_size};
use aograph_app_config::error::AppResult;

/// Flags shared by several commands; each overrides the config file.
#[derive(Clone, Debug, Default)]
pub struct CommonArgs {
    pub config: Option<PathBuf>,
    pub scene: Option<String>,
    pub technique: Option<String>,
    pub width: Option<u32>,
    pub height: Option<u32>,
    /// `auto` or a number of scene units.
    pub radius: Option<String>,
    /// `--camera`: a view name, a glTF camera name or index, or an inline camera.
    pub camera: Option<String>,
}

impl CommonArgs {
    /// The config file (or defaults) with the flags applied, validated.
    pub fn resolve(&self, registry: &TechniqueRegistry) -> AppResult<AppConfig> {
        let mut c = match &self.config {
            Some(p) => AppConfig::load(p, registry)?,
            None => AppConfig::default(),
        };
        if let Some(s) = &self.scene {
            c.scene = SceneSource::parse(s);
        }
        if let Some(t) = &self.technique {
            registry.get(t)?;
            c.ao.technique = t.clone();
        }
        if let Some(w) = self.width {
            check_size("--width", w)?;
            c.width = w;
        }
        if let Some(h) = self.height {
            check_size("--height", h)?;
            c.height = h;
        }
        if let Some(r) = &self.radius {
            c.ao.radius = RadiusSetting::parse("--radius", r)?;
        }
        if let Some(text) = &self.camera {
            c.camera = Some(CameraSpec::parse(text)?);
        }
        c.validate(registry)?;
        Ok(c)
    }
}

/// `aograph tune`: the most accurate setting within `--budget-ms` (src/commands/tune.rs), or with
/// `--search` XeGTAO's auto-tune (src/commands/tune_search.rs).
pub fn tune(args: &TuneArgs) -> AppResult<()> {
    if args.search {
        return tune_search::tune_search(args);
    }
    tune::tune_budget(args)
}

/// The GPU, or an error that says how to get one.
pub fn gpu() -> AppResult<Arc<GpuContext>> {
    Ok(Arc::new(GpuContext::new()?))
}

/// `aograph techniques`.
pub fn techniques(markdown: bool, webgpu_limits: bool) -> AppResult<()> {
    let registry = TechniqueRegistry::with_builtins();
    if webgpu_limits {
        println!(
            "each technique's plan (64x64, R = 0.5, r32float intermediates unless named) against \
             WebGPU's default limits and core formats:"
        );
        for line in webgpu_fit_lines(&registry)? {
            println!("{line}");
        }
        return Ok(());
    }
    for t in registry.iter() {
        if markdown {
            println!("## `{}`\n\n{}\n", t.name(), t.description());
            println!("{}", docs::parameter_table(&registry, t.name())?);
            continue;
        }
        println!("{}: {}", t.name(), t.description());
        for p in t.parameters() {
            println!(
                "    {:<22} default {:<10} allowed {:<24} {}",
                p.name,
                p.default_text(),
                p.allowed(),
                p.doc
            );
        }
    }
    Ok(())
}

/// `aograph scene export SCENE FILE`: a procedural scene, or a glTF file's t = 0 pose (skinned
/// meshes baked in world space, animations dropped: see `aograph_scene::gltf_export`).
pub fn scene_export(scene: &str, file: &std::path::Path) -> AppResult<()> {
    let scene =
        aograph_app_config::load_scene(&aograph_app_config::config::SceneSource::parse(scene))?;
    aograph_scene::export_glb(&scene, file)?;
    println!("wrote {}", file.display());
    Ok(())
}
