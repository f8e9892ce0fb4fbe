//! report.md's roofline section: the device's peaks measured in the run, then per technique
//! and parameter set (its first scene and view) every pass with its rates and its share of
//! each peak ([`super::roofline`] measures them).

use std::fmt::Write as _;

use super::roofline::{DevicePeaks, PEAK_SIDE};
use super::run::RunRecord;

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
