//! Summary statistics of timing samples (median, min/max, quartiles) and the least-squares
//! power-law fit used by the scaling study.

use serde::{Deserialize, Serialize};

/// Median and spread of a set of samples (milliseconds).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Spread {
    /// Median of the finite samples; NaN when there are none.
    pub median: f64,
    /// Smallest finite sample; NaN when there are none.
    pub min: f64,
    /// Largest finite sample; NaN when there are none.
    pub max: f64,
    /// First and third quartiles (linear interpolation between order statistics).
    pub q1: f64,
    /// Third quartile, interpolated the same way.
    pub q3: f64,
    /// Number of finite samples the statistics are over.
    pub samples: usize,
}

/// The q-quantile of sorted samples, interpolating linearly between neighbours.
fn quantile(sorted: &[f64], q: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    let pos = q * (sorted.len() - 1) as f64;
    let (lo, hi) = (pos.floor() as usize, pos.ceil() as usize);
    sorted[lo] + (sorted[hi] - sorted[lo]) * (pos - lo as f64)
}

impl Spread {
    /// Statistics of `samples` (non-finite samples are dropped); NaN everywhere when empty.
    pub fn of(samples: &[f64]) -> Self {
        let mut s: Vec<f64> = samples.iter().copied().filter(|v| v.is_finite()).collect();
        s.sort_by(f64::total_cmp);
        Self {
            median: quantile(&s, 0.5),
            min: s.first().copied().unwrap_or(f64::NAN),
            max: s.last().copied().unwrap_or(f64::NAN),
            q1: quantile(&s, 0.25),
            q3: quantile(&s, 0.75),
            samples: s.len(),
        }
    }
}

/// Median and spread of one pass's time.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PassTime {
    /// The pass's name in the render graph.
    pub name: String,
    /// Its time in milliseconds over the measured frames.
    pub ms: Spread,
}

/// A fit of log y = c + sum_k e_k log x_k.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PowerFit {
    /// One exponent per regressor, in the order given.
    pub exponents: Vec<f64>,
    /// Coefficient of determination of the log-log fit.
    pub r2: f64,
    /// Points used by the fit (those with positive, finite values everywhere).
    pub points: usize,
}

/// Least squares of log y on the logs of the regressors (each row of `xs` is one point's
/// regressors). Points with a non-positive or non-finite value are skipped. `None` when the
/// system is singular (a regressor that never varies) or has too few points.
pub fn fit_power_law(xs: &[Vec<f64>], y: &[f64]) -> Option<PowerFit> {
    let k = xs.first()?.len();
    let rows: Vec<(Vec<f64>, f64)> = xs
        .iter()
        .zip(y)
        .filter(|(x, v)| {
            x.len() == k
                && **v > 0.0
                && v.is_finite()
                && x.iter().all(|a| *a > 0.0 && a.is_finite())
        })
        .map(|(x, v)| {
            (
                std::iter::once(1.0)
                    .chain(x.iter().map(|a| a.ln()))
                    .collect(),
                v.ln(),
            )
        })
        .collect();
    let m = k + 1;
    if rows.len() <= m {
        return None;
    }
    // Normal equations A^T A b = A^T y, solved by Gaussian elimination with partial pivoting.
    let mut a = vec![vec![0.0f64; m + 1]; m];
    for (r, v) in &rows {
        for i in 0..m {
            for j in 0..m {
                a[i][j] += r[i] * r[j];
            }
            a[i][m] += r[i] * v;
        }
    }
    let scale = a
        .iter()
        .flat_map(|r| r[..m].iter())
        .fold(0.0f64, |s, v| s.max(v.abs()));
    for col in 0..m {
        let pivot = (col..m).max_by(|&p, &q| a[p][col].abs().total_cmp(&a[q][col].abs()))?;
        if a[pivot][col].abs() <= 1e-10 * scale {
            return None;
        }
        a.swap(col, pivot);
        let pivot_row = a[col].clone();
        for (row, r) in a.iter_mut().enumerate() {
            if row != col {
                let f = r[col] / pivot_row[col];
                for (v, p) in r.iter_mut().zip(&pivot_row).skip(col) {
                    *v -= f * p;
                }
            }
        }
    }
    let b: Vec<f64> = (0..m).map(|i| a[i][m] / a[i][i]).collect();
    let mean = rows.iter().map(|(_, v)| v).sum::<f64>() / rows.len() as f64;
    let (mut ss_res, mut ss_tot) = (0.0, 0.0);
    for (r, v) in &rows {
        let pred: f64 = r.iter().zip(&b).map(|(x, c)| x * c).sum();
        ss_res += (v - pred).powi(2);
        ss_tot += (v - mean).powi(2);
    }
    let r2 = if ss_tot > 0.0 {
        1.0 - ss_res / ss_tot
    } else {
        1.0
    };
    Some(PowerFit {
        exponents: b[1..].to_vec(),
        r2,
        points: rows.len(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spread_of_known_samples() {
        let s = Spread::of(&[5.0, 1.0, 3.0, 2.0, 4.0]);
        assert_eq!(
            (s.median, s.min, s.max, s.q1, s.q3, s.samples),
            (3.0, 1.0, 5.0, 2.0, 4.0, 5)
        );
        assert_eq!(Spread::of(&[1.0, 2.0]).median, 1.5);
        assert!(Spread::of(&[]).median.is_nan());
    }

    #[test]
    fn recovers_known_exponents() {
        // t = 0.5 * P^1.0 * r^2.0 on a 4x4 grid.
        let mut xs = Vec::new();
        let mut y = Vec::new();
        for p in [1e4, 4e4, 1.6e5, 6.4e5] {
            for r in [2.0, 4.0, 8.0, 16.0] {
                xs.push(vec![p, r]);
                y.push(0.5 * p * r * r);
            }
        }
        let f = fit_power_law(&xs, &y).unwrap();
        assert!(
            (f.exponents[0] - 1.0).abs() < 1e-9 && (f.exponents[1] - 2.0).abs() < 1e-9,
            "{f:?}"
        );
        assert!((f.r2 - 1.0).abs() < 1e-12);
        // A regressor that never varies cannot be fitted.
        let flat: Vec<Vec<f64>> = xs.iter().map(|x| vec![x[0], 3.0]).collect();
        assert!(fit_power_law(&flat, &y).is_none());
        let one: Vec<Vec<f64>> = xs.iter().map(|x| vec![x[0]]).collect();
        assert!(fit_power_law(&one, &y).is_some());
    }
}
