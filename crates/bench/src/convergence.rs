//! `aograph bench --convergence N`: every frame since a reset scored against the reference,
//! so a temporal technique's first frames (after a camera cut or a disocclusion) are measured
//! as well as its converged image. Writes convergence.csv (one row per run and frame) and
//! convergence.png / .svg (SSIM against frames since the reset, one panel per scene view, one
//! line per technique and parameter set). Invariant: frame 1 is the first frame the renderer
//! drew, with no history (the bench renders no warm-up frames in this mode).

use std::path::Path;

use plotters::prelude::*;

use crate::csv;
use crate::images::{write_atomic, write_rgb_png};
use crate::plot::{FONTS, PALETTE, PANEL, grid_of, plot_err, register_font, short_scene};
use crate::run::{ConvergencePoint, RunRecord};
use aograph_app_config::error::AppResult;

/// A panel's width: the chart as wide as the Pareto plot's, and a legend strip wide enough
/// for a technique with its parameter label (about 45 characters).
const PANEL_WIDTH: u32 = 1000;
/// The legend strip's width.
const KEY_WIDTH: u32 = 360;
/// Panels a row.
const COLUMNS: usize = 3;

/// Rows, columns and the picture's size in pixels for `panels` panels.
fn grid(panels: usize) -> (usize, usize, (u32, u32)) {
    grid_of(panels, COLUMNS, (PANEL_WIDTH, PANEL.1))
}

/// The frames the docs' convergence table shows (those the run reached).
pub const TABLE_FRAMES: [u32; 8] = [1, 2, 3, 6, 10, 30, 64, 128];

/// convergence.csv: one row per run and frame.
pub fn convergence_csv(records: &[RunRecord]) -> String {
    let mut s = String::from("scene,view,technique,label,frame,mae,ssim,edge_mae\n");
    for r in records {
        for p in &r.convergence {
            s.push_str(&format!(
                "{},{},{},{},{},{:.6},{:.6},{}\n",
                csv::field(&r.scene),
                csv::field(&r.view),
                csv::field(&r.technique),
                csv::field(&r.label),
                p.frame,
                p.mae,
                p.ssim,
                p.edge_mae.map(|e| format!("{e:.6}")).unwrap_or_default()
            ));
        }
    }
    s
}

/// The curves of one panel: (technique, parameter label, points).
type Curves<'a> = Vec<(&'a str, &'a str, &'a [ConvergencePoint])>;

fn panels(records: &[RunRecord]) -> Vec<(String, Curves<'_>)> {
    let mut out: Vec<(String, Curves<'_>)> = Vec::new();
    for r in records.iter().filter(|r| !r.convergence.is_empty()) {
        let title = short_scene(&r.scene_view());
        let curve = (r.technique.as_str(), r.label.as_str(), &r.convergence[..]);
        match out.iter_mut().find(|(t, _)| *t == title) {
            Some((_, curves)) => curves.push(curve),
            None => out.push((title, vec![curve])),
        }
    }
    out
}

fn curve_name(technique: &str, label: &str) -> String {
    if label == "defaults" {
        technique.to_string()
    } else {
        format!("{technique} {label}")
    }
}

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    panels: &[(String, Curves<'_>)],
    names: &[String],
) -> Result<(), String> {
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let (rows, columns, _) = grid(panels.len());
    let colour = |n: &str| PALETTE[names.iter().position(|x| x == n).unwrap_or(0) % PALETTE.len()];
    for (area, (title, curves)) in root.split_evenly((rows, columns)).iter().zip(panels) {
        let (chart_area, key) = area.split_horizontally(PANEL_WIDTH - KEY_WIDTH);
        let last = (curves.iter())
            .flat_map(|(_, _, p)| p.iter().map(|p| p.frame))
            .max()
            .unwrap_or(1)
            .max(2);
        let low = (curves.iter())
            .flat_map(|(_, _, p)| p.iter().map(|p| p.ssim))
            .filter(|v| v.is_finite())
            .fold(1.0f64, f64::min);
        let bottom = ((low - 0.05) * 10.0).floor() / 10.0;
        let mut chart = ChartBuilder::on(&chart_area)
            .caption(title, ("sans-serif", FONTS.caption))
            .margin(16)
            .margin_right(40)
            .x_label_area_size(48)
            .y_label_area_size(84)
            .build_cartesian_2d((1.0..f64::from(last)).log_scale(), bottom.max(0.0)..1.0)
            .map_err(e)?;
        let label = ("sans-serif", FONTS.label);
        chart
            .configure_mesh()
            .x_desc("frames since reset")
            .y_desc("SSIM vs reference")
            .x_labels(8)
            .y_labels(6)
            .label_style(label)
            .axis_desc_style(label)
            .draw()
            .map_err(e)?;
        let style = ("sans-serif", FONTS.label).into_font().color(&BLACK);
        for (k, (technique, label, points)) in curves.iter().enumerate() {
            let name = curve_name(technique, label);
            let c = colour(&name);
            let line = points
                .iter()
                .filter(|p| p.ssim.is_finite())
                .map(|p| (f64::from(p.frame), p.ssim));
            chart
                .draw_series(LineSeries::new(line, c.stroke_width(2)))
                .map_err(e)?;
            let y = 60 + k as i32 * (FONTS.label as i32 + 8);
            key.draw(&PathElement::new(vec![(2, y), (18, y)], c.stroke_width(3)))
                .map_err(e)?;
            key.draw(&Text::new(
                name,
                (22, y - FONTS.label as i32 / 2),
                style.clone(),
            ))
            .map_err(e)?;
        }
    }
    root.present().map_err(|e| e.to_string())
}

/// Writes convergence.csv, .svg and .png into `dir` for the runs that were scored per frame;
/// nothing when none was.
pub fn write_convergence(dir: &Path, records: &[RunRecord]) -> AppResult<()> {
    if panels(records).is_empty() {
        return Ok(());
    }
    write_atomic(
        &dir.join("convergence.csv"),
        convergence_csv(records).as_bytes(),
    )?;
    let svg = dir.join("convergence.svg");
    let mut text = String::new();
    draw_with(records, &svg, |panels, names, size| {
        draw(
            SVGBackend::with_string(&mut text, size).into_drawing_area(),
            panels,
            names,
        )
    })?;
    write_atomic(&svg, text.as_bytes())?;
    write_convergence_png(&dir.join("convergence.png"), records)
}

/// Writes only the PNG of [`write_convergence`] (what the docs commit beside a results file).
pub fn write_convergence_png(png: &Path, records: &[RunRecord]) -> AppResult<()> {
    let mut size = (0, 0);
    let mut rgb = Vec::new();
    draw_with(records, png, |panels, names, s| {
        size = s;
        rgb = vec![255u8; s.0 as usize * s.1 as usize * 3];
        draw(
            BitMapBackend::with_buffer(&mut rgb, s).into_drawing_area(),
            panels,
            names,
        )
    })?;
    write_rgb_png(png, size.0, size.1, &rgb)
}

/// Lays out the panels and the curve names of `records` and calls `draw` with them and the
/// picture's size; errors name `path`.
fn draw_with(
    records: &[RunRecord],
    path: &Path,
    draw: impl FnOnce(&[(String, Curves<'_>)], &[String], (u32, u32)) -> Result<(), String>,
) -> AppResult<()> {
    let panels = panels(records);
    let mut names: Vec<String> = Vec::new();
    for (_, curves) in &panels {
        for (t, l, _) in curves {
            let n = curve_name(t, l);
            if !names.contains(&n) {
                names.push(n);
            }
        }
    }
    let (_, _, size) = grid(panels.len());
    let err = |m: String| plot_err(path, m);
    // Both backends lay text out with the registered font.
    register_font().map_err(err)?;
    draw(&panels, &names, size).map_err(err)
}
