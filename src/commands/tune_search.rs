//! `aograph tune --search`: XeGTAO's auto-tune for any technique (crates/bench/src/search.rs): a
//! narrowing grid search over the parameters configs/tune/search.toml names, minimising the
//! mean MAE against the reference over the training scenes, then scored on held-out scenes
//! the search never saw. Prints, per technique, the defaults' and the tuned setting's MAE and
//! SSIM on both sets, and the tuned parameters as a config section.
//!
//! The default split is fixed and documented, so reruns compare: training `columns`,
//! `cornell-box`, `stairs`, `thin-bars`; held out `sphere-on-plane`, `corner`, `room`,
//! `node-transforms`, `dynamic`. `--train` and `--held-out` take any scenes, glTF files
//! included.

use std::fmt::Write as _;

use aograph_ao_passes::TechniqueRegistry;

use super::bench::{scenes, view_choice};
use super::gpu;
use super::tune::TuneArgs;
use crate::shader_library;
use aograph_app_config::config::SceneSource;
use aograph_app_config::error::{AppError, AppResult};
use aograph_bench::images::write_atomic;
use aograph_bench::search::{SearchSpaces, search};
use aograph_bench::{BenchContext, BenchPlan, ParamSet, run_bench};

/// The built-in search spaces used when `--space` is not given.
pub const DEFAULT_SPACES: &str = include_str!("../../configs/tune/search.toml");
/// The default training and held-out scenes.
pub const DEFAULT_TRAIN: [&str; 4] = ["columns", "cornell-box", "stairs", "thin-bars"];
pub const DEFAULT_HELD_OUT: [&str; 5] = [
    "sphere-on-plane",
    "corner",
    "room",
    "node-transforms",
    "dynamic",
];

/// Mean MAE and SSIM of one setting over a set of scenes and views.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Score {
    pub mae: f64,
    pub ssim: f64,
}

/// A value rounded to 4 significant digits, as the tuned config prints it.
fn round4(v: f64) -> f64 {
    if v == 0.0 || !v.is_finite() {
        return v;
    }
    let m = 10f64.powi(3 - v.abs().log10().floor() as i32);
    (v * m).round() / m
}

fn set_of(technique: &str, names: &[String], point: &[f64]) -> ParamSet {
    let mut params = toml::Table::new();
    for (n, v) in names.iter().zip(point) {
        params.insert(n.clone(), toml::Value::Float(round4(*v)));
    }
    ParamSet {
        technique: technique.into(),
        params,
    }
}

pub fn tune_search(args: &TuneArgs) -> AppResult<()> {
    let registry = TechniqueRegistry::with_builtins();
    let settings = args
        .run
        .settings(aograph_bench::metrics::DEFAULT_EDGE_BAND)?;
    let spaces = match &args.space {
        Some(p) => {
            let text = std::fs::read_to_string(p)
                .map_err(|e| AppError::io("read search space", p, e.to_string()))?;
            SearchSpaces::parse(&text, &p.display().to_string())?
        }
        None => SearchSpaces::parse(DEFAULT_SPACES, "configs/tune/search.toml (built in)")?,
    };
    let listed = |v: &[String], d: &[&str]| -> Vec<String> {
        if v.is_empty() {
            d.iter().map(|s| s.to_string()).collect()
        } else {
            v.to_vec()
        }
    };
    let train = scenes(&listed(&args.train, &DEFAULT_TRAIN))?;
    let held_out = scenes(&listed(&args.held_out, &DEFAULT_HELD_OUT))?;
    if let Some(s) = train.iter().find(|s| held_out.contains(s)) {
        return Err(AppError::InvalidArgument {
            name: "--held-out".into(),
            value: format!("{s:?}"),
            allowed: "scenes not in --train (a held-out score must be on unseen scenes)".into(),
        });
    }
    let techniques: Vec<String> =
        if args.techniques.is_empty() || args.techniques.iter().any(|t| t == "all") {
            spaces.techniques.keys().cloned().collect()
        } else {
            args.techniques.clone()
        };
    for t in &techniques {
        registry.get(t)?;
        if !spaces.techniques.contains_key(t) {
            return Err(AppError::InvalidArgument {
                name: "--techniques".into(),
                value: t.clone(),
                allowed: format!(
                    "techniques the search space names: {}",
                    spaces
                        .techniques
                        .keys()
                        .cloned()
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            });
        }
    }
    let views = view_choice(&args.views, None, None, &registry)?;
    let ctx = BenchContext {
        gpu: gpu()?,
        shaders: shader_library(),
        registry,
        peaks: None,
    };
    let evaluate = |scenes: &[SceneSource], sets: &[ParamSet]| -> AppResult<Vec<Score>> {
        let plan = BenchPlan {
            scenes: scenes.to_vec(),
            views: views.clone(),
            sets: sets.to_vec(),
            settings: settings.clone(),
            sizes: Vec::new(),
        };
        let records = run_bench(&ctx, &plan, None, false)?;
        Ok(sets
            .iter()
            .map(|set| {
                let label = set.label();
                let rows: Vec<_> = records
                    .iter()
                    .filter(|r| r.technique == set.technique && r.label == label)
                    .collect();
                let n = rows.len().max(1) as f64;
                Score {
                    mae: rows.iter().map(|r| r.metrics.mae).sum::<f64>() / n,
                    ssim: rows.iter().map(|r| r.metrics.ssim).sum::<f64>() / n,
                }
            })
            .collect())
    };
    let mut report = format!(
        "# aograph tune --search ({} x {}, {} frames, {} rays; {} steps per axis, {} passes)\n\n\
         training: {}\nheld out: {}\n\n\
         | technique | tuned | train MAE before | train MAE after | held-out MAE before | held-out MAE after | held-out SSIM before | held-out SSIM after |\n\
         |---|---|---:|---:|---:|---:|---:|---:|\n",
        settings.width,
        settings.height,
        settings.frames,
        settings.rays,
        args.steps,
        args.passes,
        names(&train),
        names(&held_out),
    );
    let mut configs = String::new();
    for t in &techniques {
        let axes = &spaces.techniques[t];
        let axis_names: Vec<String> = axes.iter().map(|a| a.name.clone()).collect();
        let technique = ctx.registry.get(t)?;
        let defaults = ParamSet::defaults(t);
        let before_train = evaluate(&train, std::slice::from_ref(&defaults))?[0];
        let before_held = evaluate(&held_out, std::slice::from_ref(&defaults))?[0];
        let found = search(axes, args.steps, args.passes, |points| {
            let sets: Vec<ParamSet> = points.iter().map(|p| set_of(t, &axis_names, p)).collect();
            for s in &sets {
                technique.check(&s.params)?;
            }
            let scores = evaluate(&train, &sets)?;
            Ok(scores.iter().map(|s| s.mae).collect())
        })?;
        let tuned = set_of(t, &axis_names, &found.best);
        let after_held = evaluate(&held_out, std::slice::from_ref(&tuned))?[0];
        let row = format!(
            "| `{t}` | {} | {:.4} | {:.4} | {:.4} | {:.4} | {:.3} | {:.3} |\n",
            tuned.label(),
            before_train.mae,
            found.score,
            before_held.mae,
            after_held.mae,
            before_held.ssim,
            after_held.ssim
        );
        eprint!("{t} ({} evaluations): {row}", found.evaluations);
        report.push_str(&row);
        let _ = writeln!(configs, "\n[ao.{t}]");
        for (k, v) in &tuned.params {
            let _ = writeln!(configs, "{k} = {v}");
        }
    }
    report.push_str("\nTuned parameters, as config sections:\n\n```toml");
    report.push_str(&configs);
    report.push_str("```\n");
    print!("{report}");
    if let Some(p) = &args.out {
        write_atomic(p, report.as_bytes())?;
        eprintln!("wrote {}", p.display());
    }
    Ok(())
}

fn names(scenes: &[SceneSource]) -> String {
    scenes
        .iter()
        .map(|s| match s {
            SceneSource::Procedural(n) => n.clone(),
            SceneSource::File(p) => p.display().to_string(),
        })
        .collect::<Vec<_>>()
        .join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn built_in_spaces_name_valid_parameters_of_registered_techniques() {
        let spaces = SearchSpaces::parse(DEFAULT_SPACES, "built in").unwrap();
        let registry = TechniqueRegistry::with_builtins();
        assert!(spaces.techniques.contains_key("gtao") && spaces.techniques.contains_key("vbao"));
        for (t, axes) in &spaces.techniques {
            let technique = registry.get(t).unwrap();
            for corner in [0.0, 1.0] {
                let point: Vec<f64> = axes.iter().map(|a| a.lo + corner * (a.hi - a.lo)).collect();
                let names: Vec<String> = axes.iter().map(|a| a.name.clone()).collect();
                let set = set_of(t, &names, &point);
                technique
                    .check(&set.params)
                    .unwrap_or_else(|e| panic!("{t} {:?}: {e}", set.params));
            }
        }
    }

    #[test]
    fn rounds_to_four_significant_digits_and_splits_are_disjoint() {
        assert_eq!(round4(1.234567), 1.235);
        assert_eq!(round4(0.0012345), 0.001235);
        assert_eq!(round4(0.0), 0.0);
        assert!(DEFAULT_TRAIN.iter().all(|t| !DEFAULT_HELD_OUT.contains(t)));
        for s in DEFAULT_TRAIN.iter().chain(&DEFAULT_HELD_OUT) {
            assert!(aograph_scene::PROCEDURAL_SCENE_NAMES.contains(s), "{s}");
        }
    }
}
