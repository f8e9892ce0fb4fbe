//! XeGTAO's auto-tune search (docs/techniques/gtao.md §10, `Vanilla.cpp`'s AutoTuneTool): a full grid
//! over a technique's named parameters, then narrowing passes around the best point. Pure:
//! the objective is a callback over a batch of points, so the search is tested without a GPU.
//!
//! Per pass every axis holds `steps` evenly spaced values over its current range, ends
//! included; the grid is their product. After a pass every range becomes
//! [lerp(lo, best - step, 0.6), lerp(hi, best + step, 0.6)] (XeGTAO's rule: each end moves 60%
//! of the way to one step beyond the best value), clamped to the axis's original bounds.
//! Invariant: every evaluated point lies within the original bounds; the result is the best
//! point ever evaluated (ties: the first).

use std::collections::BTreeMap;

use aograph_app_config::error::{AppError, AppResult};

/// XeGTAO's narrowing factor.
pub const SHRINK: f64 = 0.6;

/// One searched parameter and its bounds.
#[derive(Clone, Debug, PartialEq)]
pub struct Axis {
    /// The parameter's name, as the technique's parameter table takes it.
    pub name: String,
    /// Lower bound, included in the search.
    pub lo: f64,
    /// Upper bound (greater than `lo`), included in the search.
    pub hi: f64,
}

/// The searched parameters of each technique: configs/tune/search.toml's schema,
/// `[technique] parameter = [lo, hi]`.
#[derive(Clone, Debug, Default)]
pub struct SearchSpaces {
    /// Technique name to its searched parameters (at least one each).
    pub techniques: BTreeMap<String, Vec<Axis>>,
}

impl SearchSpaces {
    /// Parses `text` (`source` names it in errors).
    pub fn parse(text: &str, source: &str) -> AppResult<Self> {
        let bad = |message: String| AppError::Config {
            path: source.to_string(),
            message,
        };
        let table: toml::Table = text.parse().map_err(|e| bad(format!("{e}")))?;
        let mut out = SearchSpaces::default();
        for (technique, params) in table {
            let params = params
                .as_table()
                .ok_or_else(|| bad(format!("[{technique}] must be a table of parameters")))?;
            let mut axes = Vec::new();
            for (name, range) in params {
                let pair: Option<Vec<f64>> = range.as_array().and_then(|a| {
                    a.iter()
                        .map(|v| v.as_float().or(v.as_integer().map(|i| i as f64)))
                        .collect()
                });
                match pair.as_deref() {
                    Some([lo, hi]) if lo.is_finite() && hi.is_finite() && lo < hi => {
                        axes.push(Axis {
                            name: name.clone(),
                            lo: *lo,
                            hi: *hi,
                        })
                    }
                    _ => {
                        return Err(bad(format!(
                            "[{technique}] {name} = {range}: allowed [lo, hi], two finite numbers with lo < hi"
                        )));
                    }
                }
            }
            if axes.is_empty() {
                return Err(bad(format!("[{technique}] names no parameter")));
            }
            out.techniques.insert(technique, axes);
        }
        Ok(out)
    }
}

/// What a search found.
#[derive(Clone, Debug, PartialEq)]
pub struct SearchResult {
    /// The best point, one value per axis.
    pub best: Vec<f64>,
    /// The objective's score at `best` (lower is better; +inf when every point scored NaN).
    pub score: f64,
    /// Points evaluated over all passes.
    pub evaluations: usize,
}

/// `steps` values over [lo, hi], ends included (one value, the midpoint, when steps = 1).
pub fn axis_values(lo: f64, hi: f64, steps: usize) -> Vec<f64> {
    if steps <= 1 {
        return vec![0.5 * (lo + hi)];
    }
    (0..steps)
        .map(|i| lo + (hi - lo) * i as f64 / (steps - 1) as f64)
        .collect()
}

/// Every combination of the axes' values (the first axis varies slowest).
pub fn grid(ranges: &[(f64, f64)], steps: usize) -> Vec<Vec<f64>> {
    let mut points = vec![Vec::new()];
    for &(lo, hi) in ranges {
        let values = axis_values(lo, hi, steps);
        points = points
            .into_iter()
            .flat_map(|p| {
                values.iter().map(move |v| {
                    let mut q = p.clone();
                    q.push(*v);
                    q
                })
            })
            .collect();
    }
    points
}

/// The next pass's range of an axis whose current range is [lo, hi] and best value `best`,
/// clamped to the original [min, max].
pub fn narrow(lo: f64, hi: f64, best: f64, steps: usize, min: f64, max: f64) -> (f64, f64) {
    let step = if steps > 1 {
        (hi - lo) / (steps - 1) as f64
    } else {
        hi - lo
    };
    let lerp = |a: f64, b: f64| a + (b - a) * SHRINK;
    (
        lerp(lo, best - step).clamp(min, max),
        lerp(hi, best + step).clamp(min, max),
    )
}

/// Runs the search: `passes` passes of a `steps`-per-axis grid; `objective` scores a batch of
/// points (lower is better, one score per point, NaN counts as worst).
pub fn search(
    axes: &[Axis],
    steps: usize,
    passes: usize,
    mut objective: impl FnMut(&[Vec<f64>]) -> AppResult<Vec<f64>>,
) -> AppResult<SearchResult> {
    let mut ranges: Vec<(f64, f64)> = axes.iter().map(|a| (a.lo, a.hi)).collect();
    let mut best: Option<(Vec<f64>, f64)> = None;
    let mut evaluations = 0;
    for _ in 0..passes.max(1) {
        let points = grid(&ranges, steps.max(1));
        let scores = objective(&points)?;
        evaluations += points.len();
        for (p, s) in points.iter().zip(&scores) {
            let s = if s.is_nan() { f64::INFINITY } else { *s };
            if best.as_ref().is_none_or(|(_, b)| s < *b) {
                best = Some((p.clone(), s));
            }
        }
        let (b, _) = best.as_ref().expect("a pass evaluates at least one point");
        ranges = ranges
            .iter()
            .zip(axes)
            .zip(b)
            .map(|((&(lo, hi), a), &v)| narrow(lo, hi, v, steps, a.lo, a.hi))
            .collect();
    }
    let (best, score) = best.expect("at least one pass");
    Ok(SearchResult {
        best,
        score,
        evaluations,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn axes() -> Vec<Axis> {
        vec![
            Axis {
                name: "a".into(),
                lo: 0.0,
                hi: 4.0,
            },
            Axis {
                name: "b".into(),
                lo: -1.0,
                hi: 1.0,
            },
        ]
    }

    #[test]
    fn grid_is_the_product_of_evenly_spaced_axes_with_ends() {
        assert_eq!(axis_values(0.0, 4.0, 5), [0.0, 1.0, 2.0, 3.0, 4.0]);
        assert_eq!(axis_values(2.0, 4.0, 1), [3.0]);
        let g = grid(&[(0.0, 1.0), (10.0, 20.0)], 2);
        assert_eq!(g, [[0.0, 10.0], [0.0, 20.0], [1.0, 10.0], [1.0, 20.0]]);
    }

    #[test]
    fn narrowing_moves_each_end_60_percent_towards_one_step_past_the_best() {
        // Range [0, 4], 5 steps (step 1), best 3: lo -> 0 + 0.6 (2 - 0) = 1.2,
        // hi -> 4 + 0.6 (4 - 4) = 4.
        let (lo, hi) = narrow(0.0, 4.0, 3.0, 5, 0.0, 4.0);
        assert!(
            (lo - 1.2).abs() < 1e-12 && (hi - 4.0).abs() < 1e-12,
            "{lo} {hi}"
        );
        // Clamped to the original bounds: best at the lower end.
        let (lo, hi) = narrow(0.0, 4.0, 0.0, 5, 0.0, 4.0);
        // hi -> 4 + 0.6 (1 - 4) = 2.2; lo -> 0 + 0.6 (-1 - 0) = -0.6, clamped to 0.
        assert!(lo == 0.0 && (hi - 2.2).abs() < 1e-12, "{lo} {hi}");
    }

    #[test]
    fn finds_the_minimum_of_a_quadratic_between_grid_points() {
        // Minimum at (2.345, -0.321), off every first-pass grid point.
        let f = |p: &[f64]| (p[0] - 2.345).powi(2) + 4.0 * (p[1] + 0.321).powi(2);
        let r = search(&axes(), 5, 6, |pts| Ok(pts.iter().map(|p| f(p)).collect())).unwrap();
        // Each pass keeps about 0.7 of a range (0.4 of it plus 0.6 of two steps), so after 6
        // passes the step is 0.7^5 / 4 of the span: 0.17 on a, 0.08 on b; the best point
        // lies within half a step of the minimum.
        assert!((r.best[0] - 2.345).abs() < 0.09, "{r:?}");
        assert!((r.best[1] + 0.321).abs() < 0.045, "{r:?}");
        assert_eq!(r.evaluations, 6 * 25);
        // One pass is only the grid: the best grid point (2, -0.5), a worse score.
        let one = search(&axes(), 5, 1, |pts| Ok(pts.iter().map(|p| f(p)).collect())).unwrap();
        assert_eq!(one.best, [2.0, -0.5]);
        assert!(
            r.score < one.score / 4.0,
            "{} against {}",
            r.score,
            one.score
        );
    }

    #[test]
    fn never_leaves_the_bounds_and_treats_nan_as_worst() {
        let mut seen = Vec::new();
        let r = search(&axes(), 3, 4, |pts| {
            seen.extend(pts.iter().cloned());
            // Minimum beyond the upper corner; NaN at the lower corner.
            Ok(pts
                .iter()
                .map(|p| {
                    if p[0] == 0.0 && p[1] == -1.0 {
                        f64::NAN
                    } else {
                        -(p[0] + p[1])
                    }
                })
                .collect())
        })
        .unwrap();
        assert!(
            seen.iter()
                .all(|p| (0.0..=4.0).contains(&p[0]) && (-1.0..=1.0).contains(&p[1]))
        );
        assert_eq!(r.best, [4.0, 1.0]);
    }

    #[test]
    fn spaces_parse_and_name_bad_ranges() {
        let s = SearchSpaces::parse(
            "[gtao]\nradius_multiplier = [0.9, 2.0]\nfalloff_range = [0, 1]",
            "t",
        )
        .unwrap();
        assert_eq!(s.techniques["gtao"].len(), 2);
        for bad in ["[gtao]\nx = [2, 1]", "[gtao]\nx = 3", "[gtao]", "gtao = 1"] {
            let e = SearchSpaces::parse(bad, "t").unwrap_err().to_string();
            assert!(e.starts_with("t:") || e.contains("t:"), "{bad}: {e}");
        }
    }
}
