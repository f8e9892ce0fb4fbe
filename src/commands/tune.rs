//! `aograph tune`: runs a sweep on one scene and prints, as a ready config file, the most
//! accurate technique and parameters (lowest MAE against the reference) whose median AO time
//! fits a budget on this device. The budget is for the technique's passes, the same "AO ms"
//! `aograph bench` reports: the g-buffer is every technique's and is not counted. Without
//! `--sweep`, the built-in configs/sweeps/quick.toml is used, over every registered technique.
//! `--search` runs XeGTAO's auto-tune instead (src/commands/tune_search.rs).

use std::path::PathBuf;

use aograph_ao_passes::TechniqueRegistry;

use super::bench::{RunFlags, scenes, techniques};
use super::gpu;
use crate::shader_library;
use aograph_app_config::config::SceneSource;
use aograph_app_config::error::{AppError, AppResult};
use aograph_bench::images::write_atomic;
use aograph_bench::metrics::nonfinite::format as num;
use aograph_bench::{BenchContext, BenchPlan, RunRecord, Sweep, plan_param_sets, run_bench};

/// The built-in sweep used when `--sweep` is not given.
pub const DEFAULT_SWEEP: &str = include_str!("../../configs/sweeps/quick.toml");

/// Flags of `aograph tune`.
#[derive(clap::Args, Clone, Debug)]
pub struct TuneArgs {
    /// The scene to tune for: a procedural name or a .gltf/.glb file.
    #[arg(long, default_value = "columns")]
    pub scene: String,
    /// Budget in milliseconds for the AO passes (median time on this device).
    #[arg(long, required_unless_present = "search")]
    pub budget_ms: Option<f64>,
    /// Instead of a budget: search each technique's parameters (configs/tune/search.toml)
    /// like XeGTAO's auto-tune, with training and held-out scores (`tune_search`).
    #[arg(long)]
    pub search: bool,
    /// --search: the parameter ranges (TOML). Default: the built-in configs/tune/search.toml.
    #[arg(long)]
    pub space: Option<PathBuf>,
    /// --search: training scenes, comma-separated. Default: columns, cornell-box, stairs,
    /// thin-bars.
    #[arg(long, value_delimiter = ',')]
    pub train: Vec<String>,
    /// --search: held-out scenes, comma-separated. Default: sphere-on-plane, corner, room,
    /// node-transforms, dynamic.
    #[arg(long, value_delimiter = ',')]
    pub held_out: Vec<String>,
    /// --search: the views of each scene (as bench's --views).
    #[arg(long, value_delimiter = ',', default_value = "default")]
    pub views: Vec<String>,
    /// --search: values per parameter and pass (XeGTAO: 10).
    #[arg(long, default_value_t = 5)]
    pub steps: usize,
    /// --search: narrowing passes (XeGTAO: 6).
    #[arg(long, default_value_t = 3)]
    pub passes: usize,
    /// Parameter grids (TOML). Default: the built-in configs/sweeps/quick.toml.
    #[arg(long)]
    pub sweep: Option<PathBuf>,
    /// `all` (default) or techniques comma-separated.
    #[arg(long, value_delimiter = ',')]
    pub techniques: Vec<String>,
    /// The view to tune for: a view name or inline "pos=x,y,z target=x,y,z fov=60".
    #[arg(long)]
    pub camera: Option<String>,
    #[command(flatten)]
    pub run: RunFlags,
    /// Also write the config to this file.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// The most accurate run within `budget_ms` (ties: the faster), if any.
pub fn choose(records: &[RunRecord], budget_ms: f64) -> Option<&RunRecord> {
    records
        .iter()
        .filter(|r| r.times.total_ms.median <= budget_ms && r.metrics.mae.is_finite())
        .min_by(|a, b| {
            a.metrics
                .mae
                .total_cmp(&b.metrics.mae)
                .then(a.times.total_ms.median.total_cmp(&b.times.total_ms.median))
        })
}

/// A config file (crates/app-config/src/config.rs's schema) for `r` on `scene`, with a comment header.
pub fn config_text(r: &RunRecord, scene: &SceneSource, device: &str, budget_ms: f64) -> String {
    let q = |s: &str| toml::Value::String(s.to_string()).to_string();
    let scene_line = match scene {
        SceneSource::Procedural(n) => format!("name = {}", q(n)),
        SceneSource::File(p) => format!("file = {}", q(&p.display().to_string())),
    };
    let mut s = format!(
        "# aograph tune: the most accurate setting within {budget_ms} ms of AO time on {device}.\n# Measured on {} at {}x{}: AO {} ms median ([{}, {}]), MAE {}, SSIM {}, signed error {}.\n\n[scene]\n{scene_line}\n\n[output]\nwidth = {}\nheight = {}\n\n[ao]\ntechnique = {}\nradius = {}\n",
        r.scene,
        r.width,
        r.height,
        num(r.times.total_ms.median, 3),
        num(r.times.total_ms.min, 3),
        num(r.times.total_ms.max, 3),
        num(r.metrics.mae, 4),
        num(r.metrics.ssim, 4),
        num(r.metrics.signed_error, 4),
        r.width,
        r.height,
        q(&r.technique),
        toml::Value::Float(r.radius as f64),
    );
    if !r.params.is_empty() {
        s.push_str(&format!("\n[ao.{}]\n", r.technique));
        for (k, v) in &r.params {
            s.push_str(&format!("{k} = {v}\n"));
        }
    }
    s
}

/// `aograph tune --budget-ms`: the sweep and the pick (`commands::tune` sends `--search` to
/// tune_search.rs instead).
pub fn tune_budget(args: &TuneArgs) -> AppResult<()> {
    let budget_ms = args.budget_ms.unwrap_or(f64::NAN);
    if !(budget_ms.is_finite() && budget_ms > 0.0) {
        return Err(AppError::InvalidArgument {
            name: "--budget-ms".into(),
            value: budget_ms.to_string(),
            allowed: "a number of milliseconds greater than 0".into(),
        });
    }
    let registry = TechniqueRegistry::with_builtins();
    let settings = args
        .run
        .settings(aograph_bench::metrics::DEFAULT_EDGE_BAND)?;
    let sweep = match &args.sweep {
        Some(p) => Sweep::load(p)?,
        None => Sweep::parse(DEFAULT_SWEEP, "configs/sweeps/quick.toml (built in)")?,
    };
    let techniques = techniques(&registry, &args.techniques, Some(&sweep), true)?;
    let sets = plan_param_sets(&registry, &techniques, Some(&sweep))?;
    let scene = scenes(std::slice::from_ref(&args.scene))?.remove(0);
    let plan = BenchPlan {
        scenes: vec![scene.clone()],
        views: super::bench::view_choice(&[], args.camera.as_deref(), None, &registry)?,
        sets,
        settings,
        sizes: Vec::new(),
    };
    let ctx = BenchContext {
        gpu: gpu()?,
        shaders: shader_library(),
        registry,
        peaks: None,
    };
    let records = run_bench(&ctx, &plan, None, !args.run.quiet)?;
    let device = format!(
        "{}{}",
        ctx.gpu.describe(),
        if ctx.gpu.is_software() {
            ", a software device (CPU times)"
        } else {
            ""
        }
    );
    let Some(best) = choose(&records, budget_ms) else {
        let fastest = records
            .iter()
            .map(|r| r.times.total_ms.median)
            .fold(f64::INFINITY, f64::min);
        return Err(AppError::InvalidArgument {
            name: "--budget-ms".into(),
            value: budget_ms.to_string(),
            allowed: format!(
                "at least {} ms: the fastest of {} settings measured on {device}",
                num(fastest, 3),
                records.len()
            ),
        });
    };
    let fits = records
        .iter()
        .filter(|r| r.times.total_ms.median <= budget_ms)
        .count();
    eprintln!(
        "{} of {} settings fit {} ms on {device}; the most accurate is {} {}",
        fits,
        records.len(),
        budget_ms,
        best.technique,
        best.label
    );
    let text = config_text(best, &scene, &device, budget_ms);
    print!("{text}");
    if let Some(p) = &args.out {
        write_atomic(p, text.as_bytes())?;
        eprintln!("wrote {}", p.display());
    }
    Ok(())
}
