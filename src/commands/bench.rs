//! `aograph bench`: runs techniques and parameter sets against the reference on a list of
//! scenes and writes the speed/accuracy tables, the Pareto plot and per-run images (see the
//! `bench` module); `--scaling` times resolution and radius scaling instead.

use std::path::PathBuf;

use aograph_ao_passes::TechniqueRegistry;

use super::gpu;
use crate::shader_library;
use aograph_app_config::camera_spec::CameraSpec;
use aograph_app_config::config::{RadiusSetting, SceneSource, check_size};
use aograph_app_config::error::{AppError, AppResult};
use aograph_bench::metrics::MetricOptions;
use aograph_bench::motion::{MotionKind, MotionSettings, run_motion_bench};
use aograph_bench::{
    BenchContext, BenchPlan, BenchSettings, Sweep, ViewChoice, plan_param_sets, scaling,
};

/// Flags of `aograph bench`.
#[derive(clap::Args, Clone, Debug)]
pub struct BenchArgs {
    /// Scenes, comma-separated: procedural names (`aograph scene list`) or .gltf/.glb files.
    #[arg(long, value_delimiter = ',', default_value = "columns")]
    pub scenes: Vec<String>,
    /// `all`, or techniques comma-separated. Default: the sweep's techniques, else all.
    #[arg(long, value_delimiter = ',')]
    pub techniques: Vec<String>,
    /// Parameter grids per technique (TOML; see configs/sweeps/).
    #[arg(long)]
    pub sweep: Option<PathBuf>,
    /// Views of each scene, comma-separated: default, outside, outside-2, interior-1,
    /// interior-2, a glTF camera's name or index, a `[[views]]` name from --config, or `all`.
    #[arg(long, value_delimiter = ',', default_value = "default")]
    pub views: Vec<String>,
    /// One view instead of --views: a name as there, or inline "pos=x,y,z target=x,y,z fov=60".
    #[arg(long)]
    pub camera: Option<String>,
    /// A config whose `[[views]]` --views and --camera may name.
    #[arg(long)]
    pub config: Option<PathBuf>,
    #[command(flatten)]
    pub run: RunFlags,
    /// Output sizes, comma-separated WIDTHxHEIGHT (e.g. 256x144,640x360,1280x720): every run
    /// at each size against a reference at that size, and report.md's table by size. Replaces
    /// --width and --height.
    #[arg(long, value_delimiter = ',')]
    pub sizes: Vec<String>,
    /// Half-width in pixels of the depth-edge band of the edge MAE.
    #[arg(long, default_value_t = aograph_bench::metrics::DEFAULT_EDGE_BAND)]
    pub edge_band: u32,
    /// Output directory.
    #[arg(long, default_value = "bench-out")]
    pub out: PathBuf,
    /// Time resolution and radius scaling instead (no reference): writes scaling.csv.
    #[arg(long)]
    pub scaling: bool,
    /// Square sides for --scaling, comma-separated.
    // The default as text, so --help shows the comma form it accepts (a list default prints
    // space-separated, which the flag refused); `scaling::DEFAULT_SIDES` says the same.
    #[arg(long, value_delimiter = ',', default_value = "128,256,512,1024")]
    pub scaling_sizes: Vec<u32>,
    /// Radii (world units) for --scaling, comma-separated. Default: R times 0.5, 1, 2, 4.
    #[arg(long, value_delimiter = ',')]
    pub scaling_radii: Vec<f32>,
    /// Move the camera instead of holding it still: orbit (about its target), path (a
    /// straight walk forward and to the right) or scene (the view's own camera path); every
    /// frame is scored against its own reference. Writes motion.csv, motion.json, motion.md.
    #[arg(long)]
    pub motion: Option<String>,
    /// Score every frame since a reset instead of the last: N frames, no warm-up (replaces
    /// --frames and --warmup). Writes convergence.csv and convergence.png / .svg (SSIM against
    /// frames since the reset) beside the usual files.
    #[arg(long)]
    pub convergence: Option<u32>,
    /// Frames per second of a --motion run (frame i is at time i / fps).
    #[arg(long, default_value_t = aograph_bench::motion::DEFAULT_FPS)]
    pub fps: f32,
    /// Reference rays per pixel of a --motion run (one reference per measured frame).
    #[arg(long, default_value_t = aograph_bench::motion::DEFAULT_MOTION_RAYS)]
    pub motion_rays: u32,
}

/// The validated motion flags (`None` without --motion).
fn motion_settings(args: &BenchArgs) -> AppResult<Option<MotionSettings>> {
    let Some(kind) = args.motion.as_deref() else {
        return Ok(None);
    };
    if args.scaling {
        return Err(AppError::InvalidArgument {
            name: "--motion".into(),
            value: kind.into(),
            allowed: "no --motion with --scaling (scaling times a still camera)".into(),
        });
    }
    if !(args.fps.is_finite() && args.fps > 0.0) {
        return Err(AppError::InvalidArgument {
            name: "--fps".into(),
            value: args.fps.to_string(),
            allowed: "a finite number of frames per second greater than 0".into(),
        });
    }
    Ok(Some(MotionSettings {
        kind: MotionKind::parse(kind)?,
        fps: args.fps,
        rays: positive("--motion-rays", args.motion_rays)?,
    }))
}

/// How each run is made, shared by `bench` and `tune`.
#[derive(clap::Args, Clone, Debug)]
pub struct RunFlags {
    /// Output width in pixels.
    #[arg(long, default_value_t = 256)]
    pub width: u32,
    /// Output height in pixels.
    #[arg(long, default_value_t = 256)]
    pub height: u32,
    /// Measured frames per run.
    #[arg(long, default_value_t = 8)]
    pub frames: u32,
    /// Warm-up frames per run (rendered, not measured).
    #[arg(long, default_value_t = 2)]
    pub warmup: u32,
    /// Shared AO radius R: `auto` (default: each scene's size / 9) or world units.
    // A negative value reaches the range check (clap would read "-1" as a flag).
    #[arg(long, allow_hyphen_values = true)]
    pub radius: Option<String>,
    /// Reference rays per pixel.
    #[arg(long, default_value_t = 256)]
    pub rays: u32,
    /// Reference mode: binary or obscurance.
    #[arg(long, default_value = "binary")]
    pub mode: String,
    /// The normal that orients the reference's hemisphere: geometric or shading.
    #[arg(long, default_value = "geometric")]
    pub normals: String,
    /// Reference tracer: auto (hardware on a GPU with ray queries, compute on one without, the
    /// CPU on a software device), cpu, gpu (or compute) or hardware.
    #[arg(long, default_value = "auto")]
    pub tracer: String,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
}

impl RunFlags {
    /// Validated run settings with depth-edge band `edge_band`.
    pub(crate) fn settings(&self, edge_band: u32) -> AppResult<BenchSettings> {
        settings(
            self.width,
            self.height,
            self.frames,
            self.warmup,
            self.radius.as_deref(),
            self.rays,
            &self.mode,
            &self.normals,
            &self.tracer,
            edge_band,
        )
    }
}

fn positive(name: &str, v: u32) -> AppResult<u32> {
    if v == 0 {
        return Err(AppError::InvalidArgument {
            name: name.into(),
            value: "0".into(),
            allowed: "1 or more".into(),
        });
    }
    Ok(v)
}

fn check_radius(name: &str, r: f32) -> AppResult<f32> {
    Ok(aograph_ao_passes::Radius::new(name, r)?.get())
}

/// Validated run settings from the shared flags.
#[allow(clippy::too_many_arguments)]
fn settings(
    width: u32,
    height: u32,
    frames: u32,
    warmup: u32,
    radius: Option<&str>,
    rays: u32,
    mode: &str,
    normals: &str,
    tracer: &str,
    edge_band: u32,
) -> AppResult<BenchSettings> {
    let tracer =
        aograph_scene::ReferenceTracer::parse(tracer).map_err(|e| AppError::InvalidArgument {
            name: "--tracer".into(),
            value: tracer.into(),
            allowed: e,
        })?;
    let normals =
        aograph_scene::ReferenceNormals::parse(normals).map_err(|e| AppError::InvalidArgument {
            name: "--normals".into(),
            value: normals.into(),
            allowed: e,
        })?;
    let mode =
        aograph_app_config::config::parse_mode(mode).map_err(|e| AppError::InvalidArgument {
            name: "--mode".into(),
            value: mode.into(),
            allowed: e,
        })?;
    check_size("--width", width)?;
    check_size("--height", height)?;
    let radius = match radius {
        Some(r) => RadiusSetting::parse("--radius", r)?,
        None => RadiusSetting::Auto,
    };
    Ok(BenchSettings {
        width,
        height,
        frames: positive("--frames", frames)?,
        warmup,
        radius,
        rays: positive("--rays", rays)?,
        mode,
        normals,
        tracer,
        metrics: MetricOptions {
            edge_band,
            ..MetricOptions::default()
        },
        score_every_frame: false,
    })
}

/// Scenes from the flag, checked before any GPU work.
pub(crate) fn scenes(names: &[String]) -> AppResult<Vec<SceneSource>> {
    let mut out = Vec::new();
    for n in names.iter().map(|s| s.trim()).filter(|s| !s.is_empty()) {
        let s = SceneSource::parse(n);
        match &s {
            SceneSource::Procedural(p)
                if !aograph_scene::PROCEDURAL_SCENE_NAMES.contains(&p.as_str()) =>
            {
                let hint = aograph_ao_passes::nearest(
                    p,
                    aograph_scene::PROCEDURAL_SCENE_NAMES.iter().copied(),
                )
                .map(|h| format!("did you mean `{h}`? "))
                .unwrap_or_default();
                return Err(AppError::InvalidArgument {
                    name: "--scenes".into(),
                    value: p.clone(),
                    allowed: format!(
                        "{hint}procedural scenes {} or a .gltf/.glb file",
                        aograph_scene::PROCEDURAL_SCENE_NAMES.join(", ")
                    ),
                });
            }
            SceneSource::File(f) if !f.exists() => {
                return Err(AppError::io("find scene", f, "no such file"));
            }
            _ => out.push(s),
        }
    }
    if out.is_empty() {
        return Err(AppError::InvalidArgument {
            name: "--scenes".into(),
            value: String::new(),
            allowed: "one or more scenes".into(),
        });
    }
    Ok(out)
}

/// The techniques to run: `all`, a list, or (empty) the sweep's registered techniques (all
/// registered ones when there is no sweep or `default_all`).
pub(crate) fn techniques(
    registry: &TechniqueRegistry,
    flag: &[String],
    sweep: Option<&Sweep>,
    default_all: bool,
) -> AppResult<Vec<String>> {
    let flag: Vec<&str> = flag
        .iter()
        .map(|s| s.trim())
        .filter(|s| !s.is_empty())
        .collect();
    if flag.is_empty() {
        if let (Some(s), false) = (sweep, default_all) {
            let t = s.registered_techniques(registry)?;
            if t.is_empty() {
                return Err(AppError::Config {
                    path: s.source.clone(),
                    message: format!(
                        "the sweep names no registered technique (registered: {}); pass --techniques",
                        registry.names().join(", ")
                    ),
                });
            }
            return Ok(t);
        }
        if let Some(s) = sweep {
            s.registered_techniques(registry)?;
        }
        return Ok(registry.names());
    }
    if flag == ["all"] {
        return Ok(registry.names());
    }
    let mut out: Vec<String> = Vec::new();
    for t in flag {
        registry.get(t)?;
        if !out.iter().any(|o| o == t) {
            out.push(t.to_string());
        }
    }
    Ok(out)
}

/// "WIDTHxHEIGHT", each side within the output limits.
pub(crate) fn parse_size(flag: &str, text: &str) -> AppResult<aograph_graph::Extent> {
    let bad = || AppError::InvalidArgument {
        name: flag.into(),
        value: text.into(),
        allowed: "WIDTHxHEIGHT in pixels, e.g. 1280x720".into(),
    };
    let (w, h) = text.trim().split_once(['x', 'X']).ok_or_else(bad)?;
    let w: u32 = w.trim().parse().map_err(|_| bad())?;
    let h: u32 = h.trim().parse().map_err(|_| bad())?;
    check_size(flag, w)?;
    check_size(flag, h)?;
    Ok(aograph_graph::Extent::new(w, h))
}

fn radii(args: &BenchArgs, base: RadiusSetting) -> AppResult<scaling::ScalingRadii> {
    if args.scaling_radii.is_empty() {
        return Ok(match base {
            RadiusSetting::Units(r) => scaling::ScalingRadii::Units(
                scaling::DEFAULT_RADIUS_FACTORS
                    .iter()
                    .map(|f| f * r.get())
                    .collect(),
            ),
            RadiusSetting::Auto | RadiusSetting::AutoView => {
                scaling::ScalingRadii::Factors(scaling::DEFAULT_RADIUS_FACTORS.to_vec())
            }
        });
    }
    Ok(scaling::ScalingRadii::Units(
        args.scaling_radii
            .iter()
            .map(|r| check_radius("--scaling-radii", *r))
            .collect::<AppResult<_>>()?,
    ))
}

/// The views the flags pick.
pub(crate) fn view_choice(
    views: &[String],
    camera: Option<&str>,
    config: Option<&std::path::Path>,
    registry: &TechniqueRegistry,
) -> AppResult<ViewChoice> {
    let config_views = match config {
        Some(p) => aograph_app_config::config::AppConfig::load(p, registry)?.views,
        None => Vec::new(),
    };
    let names: Vec<String> = views
        .iter()
        .map(|s| s.trim().to_string())
        .filter(|s| !s.is_empty())
        .collect();
    Ok(ViewChoice {
        names: if names.is_empty() {
            vec!["default".into()]
        } else {
            names
        },
        camera: camera.map(CameraSpec::parse).transpose()?,
        config_views,
    })
}

pub fn bench(args: &BenchArgs) -> AppResult<()> {
    let registry = TechniqueRegistry::with_builtins();
    let mut settings = args.run.settings(args.edge_band)?;
    if let Some(n) = args.convergence {
        if args.scaling || args.motion.is_some() || !args.sizes.is_empty() {
            return Err(AppError::InvalidArgument {
                name: "--convergence".into(),
                value: n.to_string(),
                allowed:
                    "a still-camera bench at one size: not with --scaling, --motion or --sizes"
                        .into(),
            });
        }
        settings.frames = positive("--convergence", n)?;
        settings.warmup = 0;
        settings.score_every_frame = true;
    }
    let sweep = args.sweep.as_deref().map(Sweep::load).transpose()?;
    let techniques = techniques(&registry, &args.techniques, sweep.as_ref(), false)?;
    let sets = plan_param_sets(&registry, &techniques, sweep.as_ref())?;
    let plan = BenchPlan {
        scenes: scenes(&args.scenes)?,
        views: view_choice(
            &args.views,
            args.camera.as_deref(),
            args.config.as_deref(),
            &registry,
        )?,
        sets,
        settings,
        sizes: args
            .sizes
            .iter()
            .map(|s| parse_size("--sizes", s))
            .collect::<AppResult<_>>()?,
    };
    let sides: Vec<u32> = args
        .scaling_sizes
        .iter()
        .map(|s| check_size("--scaling-sizes", *s).map(|_| *s))
        .collect::<AppResult<_>>()?;
    let radii = radii(args, plan.settings.radius)?;
    let motion = motion_settings(args)?;
    let gpu = gpu()?;
    // The device's own peaks, for the roofline of every pass (a second or two).
    let peaks = if args.scaling || motion.is_some() {
        None
    } else {
        Some(aograph_bench::roofline::measure_peaks(&gpu)?)
    };
    let ctx = BenchContext {
        gpu,
        shaders: shader_library(),
        registry,
        peaks,
    };
    let started = std::time::Instant::now();
    let out = &args.out;
    if args.scaling {
        let r =
            aograph_bench::run_scaling(&ctx, &plan, &sides, &radii, Some(out), !args.run.quiet)?;
        println!(
            "timed {} points of {} parameter set(s) on {} in {:.1} s ({})",
            r.points.len(),
            plan.sets.len(),
            ctx.gpu.describe(),
            started.elapsed().as_secs_f64(),
            if ctx.gpu.is_software() {
                "software device: CPU times"
            } else {
                "GPU device"
            }
        );
        for f in [
            "scaling.csv",
            "scaling_points.csv",
            "scaling.json",
            "report.md",
        ] {
            println!("wrote {}", out.join(f).display());
        }
        return Ok(());
    }
    if let Some(m) = motion {
        let records = run_motion_bench(&ctx, &plan, &m, Some(out), !args.run.quiet)?;
        println!(
            "ran {} run(s) under motion `{}` ({} frame(s) each, {} references/view) on {} in {:.1} s",
            records.len(),
            m.kind.name(),
            plan.settings.frames,
            plan.settings.frames,
            ctx.gpu.describe(),
            started.elapsed().as_secs_f64(),
        );
        for f in [
            "motion.csv",
            "motion_frames.csv",
            "motion.json",
            "motion.md",
            "images/",
        ] {
            println!("wrote {}", out.join(f).display());
        }
        return Ok(());
    }
    let records = aograph_bench::run_bench(&ctx, &plan, Some(out), !args.run.quiet)?;
    println!(
        "ran {} run(s) ({} scene(s) x {} parameter set(s)) on {} in {:.1} s{}",
        records.len(),
        plan.scenes.len(),
        plan.sets.len(),
        ctx.gpu.describe(),
        started.elapsed().as_secs_f64(),
        if ctx.gpu.is_software() {
            " (software device: times are CPU times)"
        } else {
            ""
        }
    );
    for f in [
        "results.csv",
        "results.json",
        "report.md",
        "pareto.svg",
        "pareto.png",
        "images/",
    ] {
        println!("wrote {}", out.join(f).display());
    }
    Ok(())
}
