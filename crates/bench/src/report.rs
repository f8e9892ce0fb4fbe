//! The bench's files: results.csv (one row per finished run, appended as it finishes),
//! results.json (rewritten atomically after every run) and report.md (Markdown tables,
//! regenerated with the plots after every run), so an interrupted run keeps what it finished.

use std::fmt::Write as _;
use std::io::Write as _;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::images::write_atomic;
use crate::metrics::nonfinite::format as num;
use crate::plot::{by_scene, pareto_front, short_scene};
pub use crate::results_csv::{CSV_HEADER, csv_row};
use crate::run::RunRecord;
use crate::scaling::ScalingResults;
use aograph_app_config::error::{AppError, AppResult};

/// Results files written before the reference mode was recorded used binary mode.
fn binary() -> String {
    "binary".into()
}

/// Results files written before the reference normals were recorded used shading normals.
fn shading() -> String {
    "shading".into()
}

/// The device and settings every run of a bench shares.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BenchMeta {
    /// `GpuContext::describe()`: "name (backend, device type)".
    pub device: String,
    /// The wgpu backend as `Debug` prints it: `Vulkan`, `Metal`, `Dx12`, `Gl`.
    pub backend: String,
    /// A CPU device (lavapipe): its times are CPU times.
    pub software: bool,
    /// Whether the adapter has timestamp queries (else times are CPU wall time per pass).
    pub timestamps: bool,
    /// Output width in pixels (with `--sizes`, the first size; each row has its own).
    pub width: u32,
    /// Output height in pixels (with `--sizes`, the first size; each row has its own).
    pub height: u32,
    /// Measured frames per run.
    pub frames: u32,
    /// Warm-up frames per run, rendered and discarded before the measured ones.
    pub warmup: u32,
    /// The radius in scene units, or `None` for `auto` (per scene; each row has its own).
    pub radius: Option<f32>,
    /// Reference rays per pixel.
    pub rays: u32,
    /// "binary" or "obscurance".
    #[serde(default = "binary")]
    pub mode: String,
    /// The normal that orients the reference's hemisphere: "geometric" or "shading".
    #[serde(default = "shading")]
    pub normals: String,
    /// The SSIM settings in words (window, k1, k2, L), as report.md prints them.
    pub ssim: String,
    /// Half-width in pixels of the depth-edge band that edge MAE is taken over.
    pub edge_band: u32,
    /// Relative depth jump between neighbouring pixels that marks a depth edge (0.1 = 10%).
    pub edge_jump: f32,
    /// The device's peaks measured in the run (the roofline's ceilings).
    #[serde(default)]
    pub peaks: Option<crate::roofline::DevicePeaks>,
    /// The command that made the run, as typed (`aograph bench ...`), the output folder
    /// written `<out>` so no path of the machine is kept.
    #[serde(default)]
    pub command: String,
    /// The source's commit (`git rev-parse --short HEAD`, `+dirty` with uncommitted
    /// changes), when the run was made in a git checkout.
    #[serde(default)]
    pub commit: Option<String>,
    /// The day of the run, UTC, as YYYY-MM-DD.
    #[serde(default)]
    pub date: String,
}

impl BenchMeta {
    /// The sentence that says what the milliseconds are.
    /// Where the runs' times come from: the sources the runs record (`timing_source`), else
    /// what the adapter offers.
    pub fn timing_note(&self, runs: &[RunRecord]) -> String {
        let used: std::collections::BTreeSet<&str> = runs
            .iter()
            .map(|r| r.times.timing_source.as_str())
            .collect();
        let timestamps = match (used.contains("gpu-timestamps"), used.contains("cpu-wall")) {
            (true, true) => None,
            (true, false) => Some(true),
            (false, true) => Some(false),
            (false, false) => Some(self.timestamps),
        };
        let what = match timestamps {
            None => {
                "GPU timestamp queries for some runs and CPU wall time for others (results.csv, `timing_source`)"
            }
            Some(true) => "GPU timestamp queries around each pass",
            Some(false) if self.timestamps => {
                "CPU wall time around each pass (results.csv: cpu-wall; the adapter's timestamp queries were not used)"
            }
            Some(false) => "CPU wall time around each pass (the adapter has no timestamp queries)",
        };
        if self.software {
            format!(
                "Times come from {what}, but this is a software device (Mesa's lavapipe or another CPU driver): they are CPU times, so only ratios within this run are meaningful."
            )
        } else {
            format!("Times come from {what} on {}.", self.device)
        }
    }
    /// The x-axis title of the Pareto plot.
    pub fn time_axis(&self) -> String {
        format!(
            "AO time, ms (median{})",
            if self.software {
                "; CPU time, software device"
            } else {
                ""
            }
        )
    }
}

/// results.json.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ResultsFile {
    /// The device and settings every run shares.
    pub meta: BenchMeta,
    /// One record per finished run, in the order they finished.
    pub runs: Vec<RunRecord>,
}

/// Writes results.csv and results.json as runs finish.
pub struct ResultsWriter {
    dir: PathBuf,
    /// Everything written so far: the meta and every appended run (what results.json holds).
    pub file: ResultsFile,
}

impl ResultsWriter {
    /// Starts fresh files in `dir` (a previous run's results there are replaced).
    pub fn create(dir: &Path, meta: BenchMeta) -> AppResult<Self> {
        let w = Self {
            dir: dir.into(),
            file: ResultsFile {
                meta,
                runs: Vec::new(),
            },
        };
        write_atomic(&w.csv_path(), format!("{CSV_HEADER}\n").as_bytes())?;
        w.write_json()?;
        Ok(w)
    }
    /// The path of results.csv in the output directory.
    pub fn csv_path(&self) -> PathBuf {
        self.dir.join("results.csv")
    }
    /// The path of results.json in the output directory.
    pub fn json_path(&self) -> PathBuf {
        self.dir.join("results.json")
    }
    fn write_json(&self) -> AppResult<()> {
        let text = serde_json::to_string_pretty(&self.file)
            .map_err(|e| AppError::io("serialise", self.json_path(), e))?;
        write_atomic(&self.json_path(), text.as_bytes())
    }
    /// Appends `r` to the CSV (flushed) and rewrites the JSON.
    pub fn append(&mut self, r: RunRecord) -> AppResult<()> {
        let path = self.csv_path();
        let mut f = std::fs::OpenOptions::new()
            .append(true)
            .open(&path)
            .map_err(|e| AppError::io("append to", &path, e))?;
        writeln!(f, "{}", csv_row(&r))
            .and_then(|_| f.sync_data())
            .map_err(|e| AppError::io("append to", &path, e))?;
        self.file.runs.push(r);
        self.write_json()
    }
}

/// Reads a results.json back.
pub fn read_results(path: &Path) -> AppResult<ResultsFile> {
    let text = std::fs::read_to_string(path).map_err(|e| AppError::io("read", path, e))?;
    serde_json::from_str(&text).map_err(|e| AppError::io("parse", path, e))
}

fn mib(bytes: u64) -> String {
    format!("{:.2}", bytes as f64 / (1024.0 * 1024.0))
}

fn settings_line(m: &BenchMeta) -> String {
    format!(
        "{}x{}, {} warm-up + {} measured frames of a still camera (scene time 0), AO radius R = {}, reference: {} rays/pixel, {} mode ({}), hemisphere around the {} normal ({}); every technique is scored against this one reference.",
        m.width,
        m.height,
        m.warmup,
        m.frames,
        m.radius.map_or_else(
            || format!(
                "auto (each scene's content diagonal / {}, or for an interior view its median \
                 depth / {}; per row below)",
                aograph_scene::radius::AUTO_RADIUS_DIVISOR,
                aograph_scene::view_radius::VIEW_RADIUS_DIVISOR
            ),
            |r| r.to_string()
        ),
        m.rays,
        m.mode,
        if m.mode == "obscurance" {
            "a hit at distance d occludes by 1 - (d/R)^2"
        } else {
            "a hit within R occludes fully"
        },
        m.normals,
        if m.normals == "shading" {
            "the interpolated vertex normal"
        } else {
            "the hit triangle's face normal, facing the camera"
        }
    )
}

/// The main table, the Pareto fronts and the per-pass table.
fn runs_section(s: &mut String, m: &BenchMeta, runs: &[RunRecord]) {
    let _ = writeln!(
        s,
        "## Speed and accuracy\n\nAO ms: the technique's passes (g-buffer excluded), median over the measured frames with [min, max]; frame ms adds the g-buffer. Errors are against the reference over non-sky pixels, on the last frame (temporal techniques have had every warm-up and measured frame to converge); signed = technique - reference (negative = too dark); edge MAE within {} px of a depth jump > {}%. Textures: the bytes of the technique's whole plan (g-buffer channels it reads included), with texture reuse as planned and with none.\n",
        m.edge_band,
        m.edge_jump * 100.0
    );
    let _ = writeln!(
        s,
        "| scene | view | technique | parameters | R | R reached | AO ms | [min, max] | frame ms | MAE | RMSE | PSNR dB | SSIM | signed | edge MAE | flicker | textures MiB (reuse / none) |"
    );
    let _ = writeln!(
        s,
        "|---|---|---|---|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---|"
    );
    for r in runs {
        let (t, x) = (&r.times, &r.metrics);
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} | {} | [{}, {}] | {} | {} | {} | {} | {} | {} | {} | {} | {} / {} |",
            short_scene(&r.scene),
            r.view,
            r.technique,
            r.label,
            aograph_app_config::prepared_scene::short(r.radius),
            reached(r),
            num(t.total_ms.median, 3),
            num(t.total_ms.min, 3),
            num(t.total_ms.max, 3),
            num(t.frame_ms.median, 3),
            num(x.mae, 4),
            num(x.rmse, 4),
            num(x.psnr, 2),
            num(x.ssim, 4),
            num(x.signed_error, 4),
            x.edge_mae.map(|v| num(v, 4)).unwrap_or_else(|| "-".into()),
            x.flicker.map(|v| num(v, 5)).unwrap_or_else(|| "-".into()),
            mib(r.texture_bytes),
            mib(r.texture_bytes_unshared)
        );
    }
    views_section(s, runs);
    let _ = writeln!(
        s,
        "\n## Pareto front\n\nRuns no other run beats on both AO time and MAE, fastest first (pareto.svg, pareto.png).\n"
    );
    for (scene, points) in by_scene(runs) {
        let front: Vec<String> = pareto_front(&points)
            .into_iter()
            .map(|i| {
                format!(
                    "{} {} ({} ms, MAE {})",
                    points[i].technique,
                    points[i].label,
                    num(points[i].ms, 3),
                    num(points[i].mae, 4)
                )
            })
            .collect();
        let _ = writeln!(s, "- {scene}: {}", front.join(" → "));
    }
    let _ = writeln!(
        s,
        "\n## Per-pass times (ms)\n\n| scene | view | technique | parameters | pass | median | q1 | q3 | min | max |\n|---|---|---|---|---|---:|---:|---:|---:|---:|"
    );
    for r in runs {
        for p in &r.times.passes {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
                short_scene(&r.scene),
                r.view,
                r.technique,
                r.label,
                p.name,
                num(p.ms.median, 4),
                num(p.ms.q1, 4),
                num(p.ms.q3, 4),
                num(p.ms.min, 4),
                num(p.ms.max, 4)
            );
        }
    }
    let _ = writeln!(
        s,
        "\n## Metrics\n\n- MAE, RMSE, PSNR (peak 1, `inf` for identical images), mean signed error: over non-sky pixels (linear depth > 0).\n- SSIM: {}; windows centred on non-sky pixels, using only non-sky pixels, clipped at the border.\n- Edge MAE: MAE over non-sky pixels within {} px (Chebyshev) of a depth edge (4-neighbours whose depth differs by more than {}% of the nearer, or a silhouette against the sky).\n- Flicker: mean absolute change of accessibility between consecutive measured frames (still camera), `-` for one frame.\n- images/: per run, the technique's AO | signed error (blue = too dark, red = too bright, white = 0, saturating at ±0.25; sky grey) | the reference.",
        m.ssim,
        m.edge_band,
        m.edge_jump * 100.0
    );
}

/// "100%" when the technique reaches all of R in the view, else the share and the pixels.
fn reached(r: &RunRecord) -> String {
    let f = r.radius_reached();
    if f >= 1.0 {
        "100%".into()
    } else {
        format!(
            "**{:.0}%** ({} of {} px)",
            100.0 * f,
            r.reach_px.map(|v| num(f64::from(v), 1)).unwrap_or_default(),
            r.radius_px
                .map(|v| num(f64::from(v), 1))
                .unwrap_or_default()
        )
    }
}

/// One row per scene and view: R, what it projects to and how occluded the reference is.
fn views_section(s: &mut String, runs: &[RunRecord]) {
    let _ = writeln!(
        s,
        "\n## Scenes and views\n\nR in pixels at the view's nearest geometry (2nd percentile depth); the reference's mean accessibility over geometry pixels (1 means R reaches nothing in this view and the measurement says little). Techniques that cannot reach R are marked in the R reached column above.\n\nThe two ceilings re-trace the reference's own rays against less geometry: (a) the surfaces the g-buffer holds (a mesh through neighbouring pixels' points, broken where depth jumps by over 10 %), (b) the scene's triangles some pixel sees (2 x 2 samples a pixel). Reference against (b) is what no screen-space technique can see; (b) against (a) the thickness and connectivity of what it sees; (a) against a technique its estimator (a thickness heuristic can beat (a)).\n\n| scene | view | R | R px (nearest) | reference mean accessibility | ceiling (a) MAE / SSIM | (a) with a guard band | (a) with two layers | ceiling (b) MAE / SSIM |\n|---|---|---:|---:|---:|---:|---:|---:|---:|"
    );
    let mut seen: Vec<String> = Vec::new();
    for r in runs {
        let key = r.scene_view();
        if seen.contains(&key) {
            continue;
        }
        seen.push(key);
        let mean = r.reference_mean.map(f64::from);
        let ceiling = |mae: Option<f64>, ssim: Option<f64>| match (mae, ssim) {
            (Some(m), Some(s)) => format!("{} / {}", num(m, 4), num(s, 4)),
            _ => "-".into(),
        };
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {}{} | {} | {} | {} | {} |",
            short_scene(&r.scene),
            r.view,
            aograph_app_config::prepared_scene::short(r.radius),
            r.radius_px
                .map(|v| num(f64::from(v), 1))
                .unwrap_or_else(|| "-".into()),
            mean.map(|v| num(v, 4)).unwrap_or_else(|| "-".into()),
            if mean.is_some_and(|m| m > 0.97) {
                " (little occlusion)"
            } else {
                ""
            },
            ceiling(
                r.ceilings.map(|c| c.gbuffer_mae),
                r.ceilings.map(|c| c.gbuffer_ssim)
            ),
            ceiling(
                r.ceilings.map(|c| c.guard_mae),
                r.ceilings.map(|c| c.guard_ssim)
            ),
            ceiling(
                r.ceilings.map(|c| c.two_layer_mae),
                r.ceilings.map(|c| c.two_layer_ssim)
            ),
            ceiling(
                r.ceilings.map(|c| c.seen_mae),
                r.ceilings.map(|c| c.seen_ssim)
            ),
        );
    }
}

/// MAE of `none` (accessibility 1) in `r`'s scene and view: that run's own when `none` ran,
/// else 1 - the reference's mean accessibility, which is the same number (the reference is
/// never above 1 and both average over the reference's geometry pixels). `None` for records
/// from before the reference mean was kept.
fn none_mae(r: &RunRecord, runs: &[RunRecord]) -> Option<f64> {
    runs.iter()
        .find(|o| o.baseline && o.scene_view() == r.scene_view())
        .map(|none| none.metrics.mae)
        .or_else(|| r.reference_mean.map(|m| 1.0 - f64::from(m)))
}

/// Per technique and parameter set over every scene and view: mean and worst.
fn aggregate_section(s: &mut String, runs: &[RunRecord]) {
    let mut keys: Vec<(String, String, bool)> = Vec::new();
    for r in runs {
        let k = (r.technique.clone(), r.label.clone(), r.baseline);
        if !keys.contains(&k) {
            keys.push(k);
        }
    }
    let views = {
        let mut v: Vec<String> = runs.iter().map(RunRecord::scene_view).collect();
        v.sort();
        v.dedup();
        v.len()
    };
    let _ = writeln!(
        s,
        "\n## Summary: over every scene and view\n\nPer technique and parameter set over the {views} scene/view pair(s) it ran on: mean and worst MAE and SSIM, mean AO time, and in how many pairs it beats `none` (accessibility 1) on MAE.\n\n| technique | parameters | pairs | mean MAE | worst MAE | mean SSIM | worst SSIM | mean AO ms | beats none |\n|---|---|---:|---:|---:|---:|---:|---:|---:|"
    );
    for (technique, label, baseline) in keys {
        let rows: Vec<&RunRecord> = runs
            .iter()
            .filter(|r| r.technique == technique && r.label == label)
            .collect();
        let n = rows.len() as f64;
        let mean = |f: &dyn Fn(&RunRecord) -> f64| rows.iter().map(|r| f(r)).sum::<f64>() / n;
        let worst_mae = rows.iter().map(|r| r.metrics.mae).fold(f64::NAN, f64::max);
        let worst_ssim = rows.iter().map(|r| r.metrics.ssim).fold(f64::NAN, f64::min);
        let baselines: Vec<(f64, f64)> = rows
            .iter()
            .filter_map(|r| none_mae(r, runs).map(|none| (r.metrics.mae, none)))
            .collect();
        let beats = baselines.iter().filter(|(mae, none)| mae < none).count();
        let _ = writeln!(
            s,
            "| {technique} | {label} | {} | {} | {} | {} | {} | {} | {} |",
            rows.len(),
            num(mean(&|r| r.metrics.mae), 4),
            num(worst_mae, 4),
            num(mean(&|r| r.metrics.ssim), 4),
            num(worst_ssim, 4),
            num(mean(&|r| r.times.total_ms.median), 3),
            if baseline || baselines.is_empty() {
                "-".to_string()
            } else {
                format!("{beats} of {}", baselines.len())
            }
        );
    }
}

/// The best run per scene and view: the lowest MAE among the techniques (baselines aside),
/// with its SSIM and time, scenes by their short names.
fn best_section(s: &mut String, runs: &[RunRecord]) {
    let _ = writeln!(
        s,
        "\n## Best per scene and view\n\nThe run with the lowest MAE in each scene and view (`none` and other baselines aside).\n\n| scene / view | technique | parameters | MAE | SSIM | AO ms |\n|---|---|---|---:|---:|---:|"
    );
    for (scene, _) in by_scene(runs) {
        let best = (runs.iter())
            .filter(|r| !r.baseline && r.scene_view() == scene && r.metrics.mae.is_finite())
            .min_by(|a, b| a.metrics.mae.total_cmp(&b.metrics.mae));
        if let Some(r) = best {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {} | {} |",
                short_scene(&scene),
                r.technique,
                r.label,
                num(r.metrics.mae, 4),
                num(r.metrics.ssim, 4),
                num(r.times.total_ms.median, 3)
            );
        }
    }
    s.push('\n');
}

/// Writes report.md from whatever `runs` and `scaling` hold.
pub fn write_report(
    dir: &Path,
    meta: &BenchMeta,
    runs: &[RunRecord],
    scaling: Option<&ScalingResults>,
) -> AppResult<()> {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "# aograph bench\n\nDevice: **{}** (backend {}).\n\n{}\n",
        meta.device,
        meta.backend,
        meta.timing_note(runs)
    );
    if !meta.command.is_empty() {
        let _ = writeln!(
            s,
            "Run: `{}`, commit {}, {}.\n",
            meta.command,
            meta.commit.as_deref().unwrap_or("unknown"),
            meta.date
        );
    }
    if !runs.is_empty() {
        let _ = writeln!(s, "Settings: {}\n", settings_line(meta));
        // The summary first: per technique over everything, then the best per scene and
        // view; the full tables follow.
        aggregate_section(&mut s, runs);
        best_section(&mut s, runs);
        runs_section(&mut s, meta, runs);
        radiance_section(&mut s, runs);
        if let Some(t) = crate::size_table::size_section(runs) {
            s.push_str(&t);
        }
        if let Some(peaks) = &meta.peaks {
            s.push_str(&crate::roofline_table::roofline_section(peaks, runs));
        }
    }
    if let Some(sc) = scaling {
        s.push('\n');
        s.push_str(&sc.markdown());
    }
    write_atomic(&dir.join("report.md"), s.as_bytes())
}

/// SSDO's radiance against the radiance reference (runs with `environment = "sky"`).
fn radiance_section(s: &mut String, runs: &[RunRecord]) {
    let scored: Vec<&RunRecord> = runs.iter().filter(|r| r.radiance.is_some()).collect();
    if scored.is_empty() {
        return;
    }
    s.push_str(
        "\n## SSDO radiance against the radiance reference\n\nLinear radiance over the non-sky \
         pixels, all three channels; PSNR's peak is the reference's brightest channel.\n\n\
         | scene | parameters | direct RMSE | direct PSNR dB | direct + bounce RMSE | direct + bounce PSNR dB |\n\
         |---|---|---:|---:|---:|---:|\n",
    );
    for r in scored {
        if let Some(x) = r.radiance {
            let _ = writeln!(
                s,
                "| {} | {} | {:.4} | {:.2} | {:.4} | {:.2} |",
                short_scene(&r.scene_view()),
                r.label,
                x.direct_rmse,
                x.direct_psnr,
                x.full_rmse,
                x.full_psnr
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plot::tests::record;

    fn aggregate(runs: &[RunRecord]) -> String {
        let mut s = String::new();
        aggregate_section(&mut s, runs);
        s
    }

    #[test]
    fn beats_none_is_judged_from_the_reference_mean_when_none_did_not_run() {
        // Reference mean 0.9: `none` would score MAE 0.1 here.
        let mut better = record("columns", "hbao", "a", 10.0, 0.05);
        better.reference_mean = Some(0.9);
        let mut worse = record("corner", "hbao", "a", 10.0, 0.15);
        worse.reference_mean = Some(0.9);
        let s = aggregate(&[better, worse]);
        assert!(s.contains("| 1 of 2 |"), "{s}");
    }

    #[test]
    fn beats_none_prefers_the_run_of_none_and_is_blank_without_any_baseline() {
        let mut ours = record("columns", "hbao", "a", 10.0, 0.05);
        // The reference mean says `none` scores 0.1, but the run of `none` scored 0.04.
        ours.reference_mean = Some(0.9);
        let none = record("columns", "none", "defaults", 1.0, 0.04);
        let s = aggregate(&[ours.clone(), none]);
        assert!(s.contains("| 0 of 1 |"), "{s}");
        ours.reference_mean = None;
        let s = aggregate(&[ours]);
        assert!(s.trim_end().ends_with("| - |"), "{s}");
    }
}
