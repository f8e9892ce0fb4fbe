//! The tables `aograph docs` writes between its markers: a technique's settings table from
//! its parameter descriptors, and the results tables made from committed bench output
//! (results.json, motion.json), each followed by the line naming the command, commit, date and
//! device it came from. Invariant: every number printed is read from those files; nothing here
//! measures or rounds differently from one table to the next (`num` formats them all).

use std::fmt::Write as _;

use aograph_ao_passes::TechniqueRegistry;
use aograph_bench::convergence::TABLE_FRAMES;
use aograph_bench::motion::MotionFile;
use aograph_bench::plot::short_scene;
use aograph_bench::report::{BenchMeta, ResultsFile};

use aograph_app_config::error::AppResult;

/// A table cell's text: pipes escaped, newlines as spaces.
fn cell(text: &str) -> String {
    text.replace('|', "\\|").replace('\n', " ")
}

/// The settings table of `technique`, one row per parameter.
pub fn parameter_table(registry: &TechniqueRegistry, technique: &str) -> AppResult<String> {
    let t = registry.get(technique)?;
    if t.parameters().is_empty() {
        return Ok(format!("`{technique}` has no settings.\n"));
    }
    let mut s = String::from("| name | allowed | default | meaning |\n|---|---|---|---|\n");
    for p in t.parameters() {
        let _ = writeln!(
            s,
            "| `{}` | {} | {} | {} |",
            p.name,
            cell(&p.allowed()),
            cell(&p.default_text()),
            cell(p.doc)
        );
    }
    Ok(s)
}

/// A number with `digits` decimals, `-` when not finite.
fn num(v: f64, digits: usize) -> String {
    if v.is_finite() {
        format!("{v:.digits$}")
    } else {
        "-".into()
    }
}

/// The line under a results table saying where its numbers come from.
pub(super) fn provenance(m: &BenchMeta, file: &str) -> String {
    format!(
        "\n*Written by `aograph docs` from [{file}]({file}): `{}`, commit {}, {}, on {}.*\n",
        m.command,
        m.commit.as_deref().unwrap_or("unknown"),
        m.date,
        m.device
    )
}

/// Per technique and parameter set: the mean AO time over the scene views, then MAE / SSIM
/// in each scene view.
pub(super) fn summary_table(results: &ResultsFile) -> String {
    let mut views: Vec<String> = Vec::new();
    let mut settings: Vec<(String, String)> = Vec::new();
    for r in &results.runs {
        let view = r.scene_view();
        if !views.contains(&view) {
            views.push(view);
        }
        let key = (r.technique.clone(), r.label.clone());
        if !settings.contains(&key) {
            settings.push(key);
        }
    }
    let mut s = String::from("| technique | parameters | mean AO ms |");
    for v in &views {
        let _ = write!(s, " MAE / SSIM {} |", short_scene(v));
    }
    s.push_str("\n|---|---|---:|");
    s.push_str(&"---:|".repeat(views.len()));
    s.push('\n');
    for (technique, label) in &settings {
        let mine: Vec<_> = (results.runs.iter())
            .filter(|r| &r.technique == technique && &r.label == label)
            .collect();
        let mean_ms = mine.iter().map(|r| r.times.total_ms.median).sum::<f64>() / mine.len() as f64;
        let _ = write!(
            s,
            "| `{technique}` | {} | {} |",
            cell(label),
            num(mean_ms, 2)
        );
        for v in &views {
            match mine.iter().find(|r| &r.scene_view() == v) {
                Some(r) => {
                    let _ = write!(
                        s,
                        " {} / {} |",
                        num(r.metrics.mae, 4),
                        num(r.metrics.ssim, 3)
                    );
                }
                None => s.push_str(" - |"),
            }
        }
        s.push('\n');
    }
    s
}

/// Every run: scene view (and output size, when the runs have several), technique,
/// parameters, AO and frame time, MAE, SSIM, edge MAE.
pub(super) fn runs_table(results: &ResultsFile) -> String {
    let first = results.runs.first().map(|r| (r.width, r.height));
    let sized = results
        .runs
        .iter()
        .any(|r| Some((r.width, r.height)) != first);
    let mut s = String::from(if sized {
        "| scene / view | size | technique | parameters | AO ms | frame ms | MAE | SSIM | edge MAE |\n\
         |---|---|---|---|---:|---:|---:|---:|---:|\n"
    } else {
        "| scene / view | technique | parameters | AO ms | frame ms | MAE | SSIM | edge MAE |\n\
         |---|---|---|---:|---:|---:|---:|---:|\n"
    });
    for r in &results.runs {
        let size = if sized {
            format!(" {}x{} |", r.width, r.height)
        } else {
            String::new()
        };
        let _ = writeln!(
            s,
            "| {} |{size} `{}` | {} | {} | {} | {} | {} | {} |",
            short_scene(&r.scene_view()),
            r.technique,
            cell(&r.label),
            num(r.times.total_ms.median, 2),
            num(r.times.frame_ms.median, 2),
            num(r.metrics.mae, 4),
            num(r.metrics.ssim, 4),
            r.metrics.edge_mae.map_or("-".into(), |e| num(e, 4))
        );
    }
    s
}

/// Per scene view, the SSIM against the reference of the two ceilings (a) and (b) and their
/// variants, and of the best screen-space technique (baselines and ray tracers aside: `rtao`
/// traces the real geometry, so no ceiling binds it), then the mean row.
pub(super) fn ceilings_table(results: &ResultsFile) -> String {
    let mut s = String::from(
        "| scene / view | reference mean | (a) | (a) + guard band | (a) + two layers | (b) | best screen-space technique |\n\
         |---|---:|---:|---:|---:|---:|---|\n",
    );
    let mut sums = [0.0f64; 4];
    let mut rows = 0usize;
    let mut views: Vec<String> = Vec::new();
    for r in &results.runs {
        if !views.contains(&r.scene_view()) {
            views.push(r.scene_view());
        }
    }
    for view in &views {
        let runs: Vec<_> = results
            .runs
            .iter()
            .filter(|r| &r.scene_view() == view)
            .collect();
        let Some(c) = runs.iter().find_map(|r| r.ceilings) else {
            continue;
        };
        let best = (runs.iter())
            .filter(|r| !r.baseline && r.technique != "rtao" && r.metrics.ssim.is_finite())
            .max_by(|a, b| a.metrics.ssim.total_cmp(&b.metrics.ssim));
        let reference = runs.iter().find_map(|r| r.reference_mean);
        let ssims = [c.gbuffer_ssim, c.guard_ssim, c.two_layer_ssim, c.seen_ssim];
        for (sum, v) in sums.iter_mut().zip(ssims) {
            *sum += v;
        }
        rows += 1;
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} | {} |",
            short_scene(view),
            reference.map_or("-".into(), |m| num(f64::from(m), 3)),
            num(ssims[0], 3),
            num(ssims[1], 3),
            num(ssims[2], 3),
            num(ssims[3], 3),
            best.map_or("-".into(), |r| format!(
                "{} {}",
                r.technique,
                num(r.metrics.ssim, 3)
            ))
        );
    }
    if rows > 0 {
        let mean = sums.map(|v| num(v / rows as f64, 3));
        let _ = writeln!(
            s,
            "| **mean** | | **{}** | **{}** | **{}** | **{}** | |",
            mean[0], mean[1], mean[2], mean[3]
        );
    }
    s
}

/// Per technique and parameter set (its first scene and view): the peak texture memory of its
/// plan, with the graph's reuse and without it.
pub(super) fn textures_table(results: &ResultsFile) -> String {
    let mib = |b: u64| num(b as f64 / 1_048_576.0, 1);
    let mut s = String::from(
        "| technique | parameters | size | textures MiB | without reuse MiB |\n|---|---|---|---:|---:|\n",
    );
    let mut seen: Vec<(&str, &str)> = Vec::new();
    for r in &results.runs {
        let key = (r.technique.as_str(), r.label.as_str());
        if seen.contains(&key) {
            continue;
        }
        seen.push(key);
        let _ = writeln!(
            s,
            "| `{}` | {} | {}x{} | {} | {} |",
            r.technique,
            cell(&r.label),
            r.width,
            r.height,
            mib(r.texture_bytes),
            mib(r.texture_bytes_unshared)
        );
    }
    s
}

/// Per scene view, technique and parameter set: SSIM (and MAE) at chosen frames since the
/// reset, from a `bench --convergence N` run; with `scene`, only that scene view's rows (its
/// short name, as the table shows it).
pub(super) fn convergence_table(results: &ResultsFile, scene: Option<&str>) -> String {
    let last = (results.runs.iter())
        .flat_map(|r| r.convergence.iter().map(|p| p.frame))
        .max()
        .unwrap_or(0);
    let frames: Vec<u32> = TABLE_FRAMES
        .iter()
        .copied()
        .filter(|f| *f <= last)
        .collect();
    let mut s = String::from("| scene / view | technique | parameters |");
    for f in &frames {
        let _ = write!(s, " frame {f} SSIM / MAE |");
    }
    s.push_str("\n|---|---|---|");
    s.push_str(&"---:|".repeat(frames.len()));
    s.push('\n');
    let shown = |r: &&aograph_bench::run::RunRecord| {
        !r.convergence.is_empty() && scene.is_none_or(|s| short_scene(&r.scene_view()) == s)
    };
    for r in results.runs.iter().filter(shown) {
        let _ = write!(
            s,
            "| {} | `{}` | {} |",
            short_scene(&r.scene_view()),
            r.technique,
            cell(&r.label)
        );
        for f in &frames {
            match r.convergence.iter().find(|p| p.frame == *f) {
                Some(p) => {
                    let _ = write!(s, " {} / {} |", num(p.ssim, 3), num(p.mae, 4));
                }
                None => s.push_str(" - |"),
            }
        }
        s.push('\n');
    }
    s
}

/// Every run of a motion bench: scene view and motion, technique, parameters, AO and frame
/// time, mean and worst MAE, SSIM, MAE near moving surfaces and flicker.
pub(super) fn motion_table(motion: &MotionFile) -> String {
    let opt = |v: Option<f64>, digits: usize| v.map_or("-".into(), |v| num(v, digits));
    let mut s = String::from(
        "| scene / view | motion | technique | parameters | AO ms | frame ms | MAE | worst MAE | SSIM | MAE near moving | flicker |\n\
         |---|---|---|---|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for r in &motion.runs {
        let _ = writeln!(
            s,
            "| {} | {} | `{}` | {} | {} | {} | {} | {} | {} | {} | {} |",
            short_scene(&if r.view == "default" {
                r.scene.clone()
            } else {
                format!("{} / {}", r.scene, r.view)
            }),
            r.motion,
            r.technique,
            cell(&r.label),
            num(r.times.total_ms.median, 2),
            num(r.times.frame_ms.median, 2),
            num(r.mae_mean, 4),
            num(r.mae_worst, 4),
            num(r.ssim_mean, 3),
            opt(r.moving_mae_mean, 4),
            opt(r.flicker, 5)
        );
    }
    s
}
