//! A study, what one `aograph bench` invocation runs: the scenes x views x parameter sets (x
//! sizes, radii) it plans ([`BenchPlan`]), run after run with the reference of each still
//! frame traced once (cached on disk), and the files written as runs finish (results.csv,
//! results.json, report.md, the Pareto plot, images); or the scaling of the same sets over
//! resolutions and radii ([`run_scaling`]).
//!
//! Invariant: every run of a study is scored against the one reference of its scene, view
//! and size, and its row is on disk before the next run starts.

use std::path::Path;

use aograph_ao_passes::Radius;
use aograph_graph::{Extent, GpuContext};
use indicatif::{ProgressBar, ProgressStyle};

use crate::report::BenchMeta;
use crate::run::{BenchContext, BenchSettings, RunRecord};
use crate::scaling::ScalingResults;
use crate::sweep::ParamSet;
use crate::{convergence, plot, report, run, run_images, run_provenance, scaling};

use crate::images::{prepare_output_dir, write_atomic};
use aograph_app_config::camera_spec::{CameraSpec, NamedView};
use aograph_app_config::config::{RadiusSetting, SceneSource};
use aograph_app_config::error::{AppError, AppResult};
use aograph_app_config::prepared_scene::PreparedScene;
use aograph_renderer::frame_graph::FrameOutputs;
use aograph_renderer::renderer::Renderer;
use aograph_scene::views::SceneView;

/// What to run.
#[derive(Clone, Debug)]
pub struct BenchPlan {
    /// The scenes to run, in order; each is loaded once and run in every view the plan picks.
    pub scenes: Vec<SceneSource>,
    /// Which views of each scene: one row per scene, view and parameter set.
    pub views: ViewChoice,
    /// The parameter sets run on every scene, view and size (see [`plan_param_sets`](crate::plan_param_sets)).
    pub sets: Vec<ParamSet>,
    /// Output size, frame counts, radius, reference and metric settings every run shares
    /// (with `sizes`, each size replaces the width and height).
    pub settings: BenchSettings,
    /// `--sizes`: every run at each of these output sizes, each against its own reference;
    /// empty: the settings' width and height only.
    pub sizes: Vec<Extent>,
}

impl BenchPlan {
    /// The settings of each output size the plan runs at.
    pub fn sized_settings(&self) -> Vec<BenchSettings> {
        if self.sizes.is_empty() {
            return vec![self.settings.clone()];
        }
        self.sizes
            .iter()
            .map(|e| BenchSettings {
                width: e.width,
                height: e.height,
                ..self.settings.clone()
            })
            .collect()
    }
}

/// The views `--views` (and `--camera`) pick.
#[derive(Clone, Debug, PartialEq)]
pub struct ViewChoice {
    /// View names (`default`, `outside`, `interior-1`, a glTF camera, a `[[views]]` name) or
    /// `all`.
    pub names: Vec<String>,
    /// `--camera`: one view, replacing `names`.
    pub camera: Option<CameraSpec>,
    /// `[[views]]` from `--config`.
    pub config_views: Vec<NamedView>,
}

impl Default for ViewChoice {
    fn default() -> Self {
        Self {
            names: vec!["default".into()],
            camera: None,
            config_views: Vec::new(),
        }
    }
}

impl ViewChoice {
    /// The views of `scene` this choice picks, in order, each once. A config view wins over
    /// a scene view of the same name, whether picked by name or by `all` (as in
    /// [`CameraSpec::resolve`]): `all` lists it in the scene view's place.
    pub fn views(&self, scene: &aograph_scene::Scene) -> AppResult<Vec<SceneView>> {
        if let Some(c) = &self.camera {
            return Ok(vec![c.resolve(scene, &self.config_views)?]);
        }
        let mut out: Vec<SceneView> = Vec::new();
        for name in &self.names {
            let picked = if name == "all" {
                let configured = |v: &NamedView| SceneView {
                    name: v.name.clone(),
                    camera: v.params.camera(scene),
                    motion: None,
                };
                let mut all: Vec<SceneView> = aograph_scene::views::scene_views(scene)
                    .into_iter()
                    .map(
                        |v| match self.config_views.iter().find(|c| c.name == v.name) {
                            Some(c) => configured(c),
                            None => v,
                        },
                    )
                    .collect();
                all.extend(self.config_views.iter().map(configured));
                all
            } else {
                vec![CameraSpec::Named(name.clone()).resolve(scene, &self.config_views)?]
            };
            for v in picked {
                if !out.iter().any(|o| o.name == v.name) {
                    out.push(v);
                }
            }
        }
        Ok(out)
    }
}

/// The device and settings block of the results.
pub fn bench_meta(gpu: &GpuContext, s: &BenchSettings) -> BenchMeta {
    let p = &s.metrics.ssim;
    let window = match p.shape {
        crate::metrics::SsimWindow::Uniform => "uniform".to_string(),
        crate::metrics::SsimWindow::Gaussian { sigma } => format!("Gaussian sigma {sigma}"),
    };
    BenchMeta {
        device: gpu.describe(),
        backend: format!("{:?}", gpu.info.backend),
        software: gpu.is_software(),
        timestamps: gpu.has_timestamps(),
        width: s.width,
        height: s.height,
        frames: s.frames,
        warmup: s.warmup,
        radius: match s.radius {
            RadiusSetting::Auto | RadiusSetting::AutoView => None,
            RadiusSetting::Units(r) => Some(r.get()),
        },
        rays: s.rays,
        mode: format!("{:?}", s.mode).to_lowercase(),
        normals: s.normals.name().into(),
        ssim: format!(
            "{0}x{0} {window} window, k1 = {1}, k2 = {2}, L = {3} (the Pyramid HBAO paper's settings; k1 as printed there)",
            p.window, p.k1, p.k2, p.dynamic_range
        ),
        edge_band: s.metrics.edge_band,
        edge_jump: s.metrics.edge_jump,
        peaks: None,
        command: run_provenance::command_line(std::env::args()),
        commit: run_provenance::commit(),
        date: run_provenance::today(),
    }
}

/// A bar over `len` frames on stderr (drawn only on a terminal), or a hidden one.
pub fn progress_bar(len: u64, show: bool) -> ProgressBar {
    if !show {
        return ProgressBar::hidden();
    }
    let pb = ProgressBar::new(len);
    if let Ok(style) = ProgressStyle::with_template(
        "{elapsed_precise} [{bar:20}] {pos}/{len} frames (eta {eta}) {wide_msg}",
    ) {
        pb.set_style(style.progress_chars("=> "));
    }
    pb
}

pub(crate) fn file_safe(s: &str) -> String {
    s.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '.' {
                c
            } else {
                '_'
            }
        })
        .collect()
}

fn read_scaling(dir: &Path) -> Option<ScalingResults> {
    let text = std::fs::read_to_string(dir.join("scaling.json")).ok()?;
    serde_json::from_str(&text).ok()
}

/// Runs `plan`; with `out`, writes every file there as runs finish. Returns the records.
pub fn run_bench(
    ctx: &BenchContext,
    plan: &BenchPlan,
    out: Option<&Path>,
    progress: bool,
) -> AppResult<Vec<RunRecord>> {
    let sized = plan.sized_settings();
    let meta = BenchMeta {
        peaks: ctx.peaks,
        ..bench_meta(&ctx.gpu, &sized[0])
    };
    let colours = ctx.registry.names();
    let mut writer = match out {
        Some(dir) => {
            prepare_output_dir(dir)?;
            let images = dir.join("images");
            std::fs::create_dir_all(&images).map_err(|e| AppError::io("create", &images, e))?;
            Some((dir, report::ResultsWriter::create(dir, meta.clone())?))
        }
        None => None,
    };
    let per_run = (plan.settings.warmup + plan.settings.frames) as u64;
    let pb = progress_bar(
        plan.scenes.len() as u64 * plan.sets.len() as u64 * sized.len() as u64 * per_run,
        progress,
    );
    let mut records = Vec::new();
    for source in &plan.scenes {
        let scene = aograph_app_config::load_scene(source)?;
        let views = plan.views.views(&scene)?;
        pb.inc_length(
            ((views.len() as u64).saturating_sub(1))
                * plan.sets.len() as u64
                * sized.len() as u64
                * per_run,
        );
        for (view, s) in views.iter().flat_map(|v| sized.iter().map(move |s| (v, s))) {
            pb.set_message(format!(
                "tracing the reference of {} / {} ({} rays/pixel)",
                source.label(),
                view.name,
                s.rays
            ));
            let prepared = PreparedScene::new(&scene, view, s.radius);
            let reference = run::scene_reference(ctx, &source.label(), prepared, s)?;
            for set in &plan.sets {
                pb.set_message(format!(
                    "{}: {} {}",
                    reference.label,
                    set.technique,
                    set.label()
                ));
                let mut done = run::run_technique(ctx, &reference, set, s, &mut || pb.inc(1))?;
                if let Some((dir, w)) = writer.as_mut() {
                    let size = if plan.sizes.is_empty() {
                        String::new()
                    } else {
                        format!("_{}x{}", s.width, s.height)
                    };
                    let name = format!(
                        "images/{}_{}_{}{size}.png",
                        file_safe(&source.short_name()),
                        file_safe(&reference.view),
                        set.slug()
                    );
                    run_images::write_side_by_side(
                        &dir.join(&name),
                        &done.ao,
                        &reference.accessibility,
                        &reference.valid,
                        s.width,
                        s.height,
                    )?;
                    done.record.image = Some(name);
                    w.append(done.record.clone())?;
                    report::write_report(dir, &meta, &w.file.runs, read_scaling(dir).as_ref())?;
                    plot::write_pareto(
                        &dir.join("pareto.svg"),
                        &dir.join("pareto.png"),
                        &w.file.runs,
                        &colours,
                        &meta.time_axis(),
                    )?;
                    convergence::write_convergence(dir, &w.file.runs)?;
                }
                records.push(done.record);
            }
        }
    }
    pb.finish_and_clear();
    Ok(records)
}

/// Times every set of `plan` at each side in `sides` (square) and each radius in `radii`;
/// `plan.settings`' size and radius are not used. With `out`, writes scaling.csv (fits),
/// scaling_points.csv (appended per point), scaling.json and report.md as it goes.
pub fn run_scaling(
    ctx: &BenchContext,
    plan: &BenchPlan,
    sides: &[u32],
    radii: &scaling::ScalingRadii,
    out: Option<&Path>,
    progress: bool,
) -> AppResult<ScalingResults> {
    let s = &plan.settings;
    let mut results = ScalingResults {
        sides: sides.to_vec(),
        radii: Vec::new(),
        frames: s.frames,
        warmup: s.warmup,
        ..Default::default()
    };
    // report.md also shows a bench's results already in `out` (with that bench's settings).
    let (meta, runs) = match out {
        Some(dir) => {
            prepare_output_dir(dir)?;
            write_atomic(
                &dir.join("scaling_points.csv"),
                format!("{}\n", ScalingResults::POINTS_HEADER).as_bytes(),
            )?;
            report::read_results(&dir.join("results.json"))
                .map(|r| (r.meta, r.runs))
                .unwrap_or_else(|_| (bench_meta(&ctx.gpu, s), Vec::new()))
        }
        None => (bench_meta(&ctx.gpu, s), Vec::new()),
    };
    let per_point = (s.warmup + s.frames) as u64;
    let pb = progress_bar(
        plan.scenes.len() as u64
            * plan.sets.len() as u64
            * sides.len() as u64
            * radii.len() as u64
            * per_point,
        progress,
    );
    let smallest = sides.iter().copied().min().unwrap_or(64);
    for source in &plan.scenes {
        let scene = std::sync::Arc::new(aograph_app_config::load_scene(source)?);
        let radii = radii.for_scene(&scene);
        if results.radii.is_empty() {
            results.radii = radii.clone();
        }
        let mut probe = Renderer::gbuffer_only(
            ctx.gpu.clone(),
            ctx.shaders.clone(),
            scene.clone(),
            FrameOutputs {
                linear_depth: true,
                ..Default::default()
            },
            Extent::new(smallest, smallest),
        )?;
        probe.render(0.0)?;
        let depth = scaling::median_depth(&probe.read_linear_depth()?);
        let camera = probe.camera();
        for set in &plan.sets {
            for &side in sides {
                for &radius in &radii {
                    pb.set_message(format!(
                        "{}: {} {} at {side}x{side}, R = {radius}",
                        source.label(),
                        set.technique,
                        set.label()
                    ));
                    let mut r = Renderer::new(
                        ctx.gpu.clone(),
                        ctx.shaders.clone(),
                        &ctx.registry,
                        scene.clone(),
                        &run::ao_config(set, Radius::new("--scaling-radii", radius)?),
                        FrameOutputs::default(),
                        Extent::new(side, side),
                    )?;
                    let t = run::time_frames(
                        &mut r,
                        s.warmup,
                        s.frames,
                        &mut || pb.inc(1),
                        &mut |_| Ok(()),
                    )?;
                    let radius_px = if depth > 0.0 {
                        scaling::radius_in_pixels(&camera, side, radius, depth)
                    } else {
                        f64::NAN
                    };
                    let point = scaling::ScalingPoint {
                        scene: source.label(),
                        technique: set.technique.clone(),
                        label: set.label(),
                        side,
                        pixels: side as u64 * side as u64,
                        radius,
                        radius_px,
                        timing_source: t.timing_source,
                        total_ms: t.total_ms,
                    };
                    results.points.push(point.clone());
                    results.refit();
                    if let Some(dir) = out {
                        use std::io::Write as _;
                        let path = dir.join("scaling_points.csv");
                        let mut f = std::fs::OpenOptions::new()
                            .append(true)
                            .open(&path)
                            .map_err(|e| AppError::io("append to", &path, e))?;
                        writeln!(f, "{}", ScalingResults::point_row(&point))
                            .map_err(|e| AppError::io("append to", &path, e))?;
                        write_atomic(&dir.join("scaling.csv"), results.fits_csv().as_bytes())?;
                        let json = serde_json::to_string_pretty(&results)
                            .map_err(|e| AppError::io("serialise", dir.join("scaling.json"), e))?;
                        write_atomic(&dir.join("scaling.json"), json.as_bytes())?;
                        report::write_report(dir, &meta, &runs, Some(&results))?;
                    }
                }
            }
        }
    }
    pb.finish_and_clear();
    Ok(results)
}

#[cfg(test)]
mod tests {
    use super::*;
    use aograph_app_config::camera_spec::CameraParams;
    use glam::Vec3;

    #[test]
    fn all_views_list_a_config_view_in_place_of_the_scene_view_it_names() {
        let scene = aograph_scene::procedural_scene("columns").expect("built-in scene");
        let config_view = |name: &str, text: &str| NamedView {
            name: name.into(),
            params: CameraParams::parse_inline(text).expect("camera"),
        };
        let choice = ViewChoice {
            names: vec!["all".into()],
            camera: None,
            config_views: vec![
                config_view("outside", "pos=0,1,2 target=0,1,0"),
                config_view("aisle", "pos=3,1,0 target=0,1,0"),
            ],
        };
        let all = choice.views(&scene).expect("views");
        let names: Vec<&str> = all.iter().map(|v| v.name.as_str()).collect();
        let mut expected: Vec<String> = aograph_scene::views::scene_views(&scene)
            .into_iter()
            .map(|v| v.name)
            .collect();
        expected.push("aisle".into());
        assert_eq!(names, expected);
        // The one named `outside` is the config's, as `--views outside` picks it.
        let outside = all.iter().find(|v| v.name == "outside").expect("outside");
        assert_eq!(outside.camera.position, Vec3::new(0.0, 1.0, 2.0));
        let by_name = ViewChoice {
            names: vec!["outside".into()],
            ..choice.clone()
        };
        assert_eq!(
            by_name.views(&scene).expect("views")[0].camera,
            outside.camera
        );
    }
}
