//! report.md's table by output size (`aograph bench --sizes`): every technique's MAE, SSIM,
//! signed error on the image's left and right fifths and share of R reached at each size it
//! ran at, so a user sees what a technique gives at the sizes they ship and whether it loses
//! accuracy as the image grows (a reach capped in pixels) or treats the two sides alike.
//! Only written when the runs hold more than one size.

use std::collections::BTreeSet;
use std::fmt::Write as _;

use crate::run::RunRecord;

/// The section, or `None` when every run has the same size.
pub fn size_section(runs: &[RunRecord]) -> Option<String> {
    let sizes: BTreeSet<(u64, u32, u32)> = runs
        .iter()
        .map(|r| (r.width as u64 * r.height as u64, r.width, r.height))
        .collect();
    if sizes.len() < 2 {
        return None;
    }
    let mut rows: Vec<&RunRecord> = runs.iter().collect();
    rows.sort_by(|a, b| {
        (
            a.scene_view(),
            &a.technique,
            &a.label,
            a.width as u64 * a.height as u64,
        )
            .cmp(&(
                b.scene_view(),
                &b.technique,
                &b.label,
                b.width as u64 * b.height as u64,
            ))
    });
    let mut s = String::from(
        "\n## By output size\n\nEach size against a reference traced at that size. Signed \
         error is technique - reference (negative: too dark) over the left and right fifth of \
         the image; on a view that is its own mirror image the two agree for a technique \
         without a left/right bias. R reached: the technique's reach over R in pixels at the \
         view's nearest geometry.\n\n\
         | scene | technique | parameters | size | MAE | SSIM | signed error left | right | R reached |\n\
         |---|---|---|---|---:|---:|---:|---:|---:|\n",
    );
    let opt = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:+.4}"));
    for r in rows {
        let m = &r.metrics;
        let _ = writeln!(
            s,
            "| {} | {} | {} | {}x{} | {:.4} | {:.4} | {} | {} | {:.0}% |",
            r.scene_view(),
            r.technique,
            r.label,
            r.width,
            r.height,
            m.mae,
            m.ssim,
            opt(m.signed_error_left),
            opt(m.signed_error_right),
            100.0 * r.radius_reached()
        );
    }
    s.push('\n');
    Some(s)
}
