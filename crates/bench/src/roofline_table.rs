//! report.md's roofline section: the device's peaks measured in the run, then per technique
//! and parameter set (its first scene and view) every pass with its rates and its share of
//! each peak ([`crate::roofline`] measures them).

use std::fmt::Write as _;

use crate::roofline::{DevicePeaks, PEAK_SIDE};
use crate::run::RunRecord;

/// The report's roofline section: the peaks, then per technique and parameter set (its first
/// scene and view) every pass with its rates and fractions.
pub fn roofline_section(peaks: &DevicePeaks, runs: &[RunRecord]) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "## Roofline

The device's peaks, measured in this run: **{:.3} G texel loads/s** (a \
         load-bound kernel, 49 loads a thread over a {PEAK_SIDE}x{PEAK_SIDE} R32Float texture) \
         and **{:.2} GB/s** (a {PEAK_SIDE}x{PEAK_SIDE} Rgba32Float copy, bytes read plus \
         written). Per pass: its median time, the texel loads its technique declares per \
         invocation for its parameters, the bytes it must touch (each texture it reads or \
         writes once), and the achieved share of each peak; the larger share is how close the \
         pass runs to the limit that binds it.\n",
        peaks.loads_per_s / 1e9,
        peaks.bytes_per_s / 1e9
    );
    let mut seen: Vec<(String, String)> = Vec::new();
    for r in runs {
        let key = (r.technique.clone(), r.label.clone());
        if r.roofline.is_empty() || seen.contains(&key) {
            continue;
        }
        seen.push(key);
        let _ = writeln!(
            s,
            "### {} ({}), {} / {} at {}x{}\n\n| pass | ms | invocations | loads/inv | G loads/s | % load peak | MiB | GB/s | % byte peak |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|",
            r.technique, r.label, r.scene, r.view, r.width, r.height
        );
        for p in &r.roofline {
            let _ = writeln!(
                s,
                "| {} | {:.3} | {} | {} | {} | {} | {:.2} | {:.2} | {:.1}% |",
                p.pass,
                p.ms,
                p.invocations,
                p.loads_per_invocation
                    .map(|l| format!("{l}"))
                    .unwrap_or_default(),
                p.loads_per_s
                    .map(|l| format!("{:.3}", l / 1e9))
                    .unwrap_or_default(),
                p.load_fraction
                    .map(|f| format!("{:.1}%", f * 100.0))
                    .unwrap_or_default(),
                p.bytes as f64 / 1048576.0,
                p.bytes_per_s / 1e9,
                p.byte_fraction * 100.0
            );
        }
        s.push('\n');
    }
    s
}

/// Passes faster than this are left out of [`roofline_by_technique`]: per-pass overhead
/// (about 0.1 ms on lavapipe) dominates them, so their share of a peak says nothing.
const SHORT_PASS_MS: f64 = 0.2;

/// The compact form the docs' roofline page shows: the peaks, then one row per technique and
/// parameter set (its first scene and view) listing each pass of its own (the g-buffer and
/// passes under 0.2 ms left out) as "name ms share", where the share is of the load peak (L)
/// when the pass declares its loads and of the byte peak (B) otherwise.
pub fn roofline_by_technique(peaks: Option<&DevicePeaks>, runs: &[RunRecord]) -> String {
    let mut s = String::new();
    if let Some(p) = peaks {
        let _ = writeln!(
            s,
            "Peaks measured in this run: {:.3} G texel loads/s, {:.2} GB/s.\n",
            p.loads_per_s / 1e9,
            p.bytes_per_s / 1e9
        );
    }
    s.push_str("| technique | parameters | pass: ms, share of peak |\n|---|---|---|\n");
    let mut seen: Vec<(&str, &str)> = Vec::new();
    for r in runs {
        let key = (r.technique.as_str(), r.label.as_str());
        if r.roofline.is_empty() || seen.contains(&key) {
            continue;
        }
        seen.push(key);
        let passes: Vec<String> = (r.roofline.iter())
            .filter(|p| p.pass != "gbuffer" && p.ms >= SHORT_PASS_MS)
            .map(|p| {
                let name = p.pass.split_once('.').map_or(p.pass.as_str(), |(_, n)| n);
                let share = match p.load_fraction {
                    Some(f) => format!("{:.1}% L", f * 100.0),
                    None => format!("{:.1}% B", p.byte_fraction * 100.0),
                };
                format!("{name} {} ms {share}", significant(p.ms))
            })
            .collect();
        let _ = writeln!(
            s,
            "| `{}` | {} | {} |",
            r.technique,
            r.label.replace('|', "\\|"),
            if passes.is_empty() {
                "-".to_string()
            } else {
                passes.join("; ")
            }
        );
    }
    s
}

/// `ms` to three significant figures (36.2, 4.36, 0.435).
fn significant(ms: f64) -> String {
    if ms >= 100.0 {
        format!("{ms:.0}")
    } else if ms >= 10.0 {
        format!("{ms:.1}")
    } else if ms >= 1.0 {
        format!("{ms:.2}")
    } else {
        format!("{ms:.3}")
    }
}

#[cfg(test)]
mod tests {
    use super::significant;

    #[test]
    fn times_keep_three_significant_figures() {
        assert_eq!(significant(135.2), "135");
        assert_eq!(significant(36.24), "36.2");
        assert_eq!(significant(4.364), "4.36");
        assert_eq!(significant(0.4351), "0.435");
    }
}
