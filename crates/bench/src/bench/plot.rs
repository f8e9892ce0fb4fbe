//! The speed/accuracy plot: one panel per scene, the technique's median time (log scale)
//! against its MAE, one colour per technique, and the Pareto front (the runs no other run
//! beats on both time and MAE) drawn as a staircase: for a time budget on the x axis, the
//! front's height is the best MAE that budget buys. Written as SVG (text drawn by the viewer)
//! and PNG (through [`super::bitmap_text::TextBitmap`]).

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::bitmap_text::TextBitmap;
use super::run::RunRecord;
use crate::error::{AppError, AppResult};
use crate::images::{write_atomic, write_rgb_png};

const PANEL: (u32, u32) = (800, 480);
/// Width of the legend strip at the right of each panel.
const LEGEND_WIDTH: u32 = 160;
/// Tableau 10: distinguishable, colour-blind aware.
const PALETTE: [RGBColor; 10] = [
    RGBColor(78, 121, 167),
    RGBColor(242, 142, 43),
    RGBColor(225, 87, 89),
    RGBColor(118, 183, 178),
    RGBColor(89, 161, 79),
    RGBColor(237, 201, 72),
    RGBColor(176, 122, 161),
    RGBColor(255, 157, 167),
    RGBColor(156, 117, 95),
    RGBColor(186, 176, 172),
];
/// Times are clamped to this (ms) so a 0 ms timestamp still sits on a log axis.
const MIN_MS: f64 = 1e-4;

/// Font sizes: the SVG's text is drawn by the viewer; the PNG's 8x8 bitmap glyphs need
/// larger nominal sizes to fit plotters' layout estimate (see `bitmap_text`).
#[derive(Clone, Copy)]
struct Fonts {
    caption: u32,
    label: u32,
}
const SVG_FONTS: Fonts = Fonts {
    caption: 20,
    label: 14,
};
const PNG_FONTS: Fonts = Fonts {
    caption: 36,
    label: 18,
};

/// The decade at or below `v` (and above, with `up`).
fn decade(v: f64, up: bool) -> f64 {
    let e = v.log10();
    10f64.powf(if up { e.ceil() } else { e.floor() })
}

/// One plotted point.
#[derive(Clone, Debug, PartialEq)]
pub struct Point {
    /// The technique's registry name (it picks the point's colour).
    pub technique: String,
    /// The parameter set's label.
    pub label: String,
    /// The technique's median time in ms, at least 1e-4 so it sits on the log axis.
    pub ms: f64,
    /// MAE against the reference over the non-sky pixels, 0..1.
    pub mae: f64,
}

/// Indices of the Pareto-optimal points, by increasing time: each has a lower MAE than every
/// point at least as fast.
pub fn pareto_front(points: &[Point]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..points.len())
        .filter(|&i| points[i].ms.is_finite() && points[i].mae.is_finite())
        .collect();
    order.sort_by(|&a, &b| {
        points[a]
            .ms
            .total_cmp(&points[b].ms)
            .then(points[a].mae.total_cmp(&points[b].mae))
    });
    let (mut best, mut front) = (f64::INFINITY, Vec::new());
    for i in order {
        if points[i].mae < best {
            best = points[i].mae;
            front.push(i);
        }
    }
    front
}

/// Points per scene, in first-seen order.
pub fn by_scene(records: &[RunRecord]) -> Vec<(String, Vec<Point>)> {
    let mut out: Vec<(String, Vec<Point>)> = Vec::new();
    for r in records {
        let p = Point {
            technique: r.technique.clone(),
            label: r.label.clone(),
            ms: r.times.total_ms.median.max(MIN_MS),
            mae: r.metrics.mae,
        };
        let key = r.scene_view();
        match out.iter_mut().find(|(s, _)| *s == key) {
            Some((_, v)) => v.push(p),
            None => out.push((key, vec![p])),
        }
    }
    out
}

fn colour(techniques: &[String], t: &str) -> RGBColor {
    PALETTE[techniques.iter().position(|x| x == t).unwrap_or(0) % PALETTE.len()]
}

fn panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    scene: &str,
    points: &[Point],
    techniques: &[String],
    time_label: &str,
    fonts: Fonts,
) -> Result<(), String> {
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let ok: Vec<&Point> = points
        .iter()
        .filter(|p| p.ms.is_finite() && p.mae.is_finite())
        .collect();
    let (lo, hi) = ok.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), p| {
        (lo.min(p.ms), hi.max(p.ms))
    });
    let (lo, hi) = if ok.is_empty() {
        (0.01, 1.0)
    } else {
        (decade(lo / 1.2, false), decade(hi * 1.2, true))
    };
    let top = ok.iter().map(|p| p.mae).fold(0.0f64, f64::max).max(1e-3) * 1.15;
    let mut chart = ChartBuilder::on(area)
        .caption(
            format!("{scene}: time against error"),
            ("sans-serif", fonts.caption),
        )
        .margin(16)
        .margin_right(40)
        .x_label_area_size(48)
        .y_label_area_size(84)
        .build_cartesian_2d((lo..hi).log_scale(), 0.0..top)
        .map_err(e)?;
    let label = ("sans-serif", fonts.label);
    chart
        .configure_mesh()
        .x_desc(time_label)
        .y_desc("MAE vs reference")
        .x_labels(8)
        .y_labels(6)
        .label_style(label)
        .axis_desc_style(label)
        .draw()
        .map_err(e)?;
    let front = pareto_front(points);
    if !front.is_empty() {
        let mut stairs = Vec::new();
        for (k, &i) in front.iter().enumerate() {
            if k > 0 {
                stairs.push((points[i].ms, points[front[k - 1]].mae));
            }
            stairs.push((points[i].ms, points[i].mae));
        }
        stairs.push((hi, points[*front.last().unwrap_or(&0)].mae));
        chart
            .draw_series(LineSeries::new(stairs, BLACK.stroke_width(1)))
            .map_err(e)?;
    }
    for t in techniques {
        let c = colour(techniques, t);
        let mine: Vec<(f64, f64)> = ok
            .iter()
            .filter(|p| &p.technique == t)
            .map(|p| (p.ms, p.mae))
            .collect();
        if mine.is_empty() {
            continue;
        }
        chart
            .draw_series(
                mine.into_iter()
                    .map(|(x, y)| Circle::new((x, y), 4, c.filled())),
            )
            .map_err(e)?;
    }
    Ok(())
}

/// The legend, in its own strip right of the chart so it never hides a point: one entry per
/// technique present in the panel, then the front.
fn legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    points: &[Point],
    techniques: &[String],
    fonts: Fonts,
) -> Result<(), String> {
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let style = ("sans-serif", fonts.label).into_font().color(&BLACK);
    let line = fonts.label as i32 + 8;
    let mut y = 60;
    for t in techniques
        .iter()
        .filter(|t| points.iter().any(|p| &p.technique == *t))
    {
        area.draw(&Circle::new((10, y), 5, colour(techniques, t).filled()))
            .map_err(e)?;
        area.draw(&Text::new(
            t.clone(),
            (22, y - fonts.label as i32 / 2),
            style.clone(),
        ))
        .map_err(e)?;
        y += line;
    }
    area.draw(&PathElement::new(
        vec![(2, y), (18, y)],
        BLACK.stroke_width(1),
    ))
    .map_err(e)?;
    area.draw(&Text::new(
        "Pareto front",
        (22, y - fonts.label as i32 / 2),
        style,
    ))
    .map_err(e)?;
    Ok(())
}

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    scenes: &[(String, Vec<Point>)],
    techniques: &[String],
    time_label: &str,
    fonts: Fonts,
) -> Result<(), String> {
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let panels = root.split_evenly((1, scenes.len().max(1)));
    for (area, (scene, points)) in panels.iter().zip(scenes) {
        let (chart, key) = area.split_horizontally(PANEL.0 - LEGEND_WIDTH);
        panel(&chart, scene, points, techniques, time_label, fonts)?;
        legend(&key, points, techniques, fonts)?;
    }
    root.present().map_err(|e| e.to_string())
}

/// Writes `svg` and `png` for `records`; `techniques` fixes the colour order.
pub fn write_pareto(
    svg: &Path,
    png: &Path,
    records: &[RunRecord],
    techniques: &[String],
    time_label: &str,
) -> AppResult<()> {
    let scenes = by_scene(records);
    let size = (PANEL.0 * scenes.len().max(1) as u32, PANEL.1);
    let plot_err = |path: &Path, m: String| AppError::Image {
        path: path.into(),
        message: format!("plot: {m}"),
    };
    let mut text = String::new();
    draw(
        SVGBackend::with_string(&mut text, size).into_drawing_area(),
        &scenes,
        techniques,
        time_label,
        SVG_FONTS,
    )
    .map_err(|m| plot_err(svg, m))?;
    write_atomic(svg, text.as_bytes())?;
    let mut rgb = vec![255u8; size.0 as usize * size.1 as usize * 3];
    draw(
        TextBitmap::new(&mut rgb, size).into_drawing_area(),
        &scenes,
        techniques,
        time_label,
        PNG_FONTS,
    )
    .map_err(|m| plot_err(png, m))?;
    write_rgb_png(png, size.0, size.1, &rgb)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    fn p(ms: f64, mae: f64) -> Point {
        Point {
            technique: "t".into(),
            label: String::new(),
            ms,
            mae,
        }
    }

    /// A run record with only what the plot reads filled in.
    pub(crate) fn record(
        scene: &str,
        technique: &str,
        label: &str,
        ms: f64,
        mae: f64,
    ) -> RunRecord {
        use crate::bench::run::FrameTimes;
        use crate::bench::stats::Spread;
        RunRecord {
            scene: scene.into(),
            view: "default".into(),
            technique: technique.into(),
            baseline: aograph_ao::TechniqueRegistry::with_builtins()
                .get(technique)
                .is_ok_and(|t| t.is_baseline()),
            label: label.into(),
            params: Default::default(),
            width: 64,
            height: 64,
            radius: 1.0,
            radius_px: None,
            reach_px: None,
            reference_mean: None,
            rays: 16,
            frames: 1,
            warmup: 0,
            times: FrameTimes {
                timing_source: "cpu-wall".into(),
                total_ms: Spread::of(&[ms]),
                frame_ms: Spread::of(&[ms]),
                passes: Vec::new(),
            },
            texture_bytes: 0,
            texture_bytes_unshared: 0,
            roofline: Vec::new(),
            radiance: None,
            ceilings: None,
            metrics: crate::metrics::Metrics {
                pixels: 1,
                mae,
                rmse: mae,
                psnr: 1.0,
                ssim: 1.0,
                signed_error: 0.0,
                signed_error_left: None,
                signed_error_right: None,
                edge_mae: None,
                edge_pixels: 0,
                flicker: None,
            },
            image: None,
        }
    }

    #[test]
    fn writes_an_svg_and_a_png_with_several_techniques_and_scenes() {
        let dir = std::env::temp_dir().join(format!("aograph-plot-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let techniques: Vec<String> = ["hbao", "none", "pyramid-hbao", "ssao"]
            .map(String::from)
            .to_vec();
        let mut runs = Vec::new();
        for scene in ["columns", "sphere-on-plane"] {
            runs.push(record(scene, "none", "defaults", 0.05, 0.2));
            for (i, ms) in [0.6, 2.3, 9.5, 37.2].iter().enumerate() {
                runs.push(record(
                    scene,
                    "hbao",
                    &format!("directions={}", 8 << i),
                    *ms,
                    0.12 - 0.012 * i as f64,
                ));
            }
            for l in 1..=5 {
                runs.push(record(
                    scene,
                    "pyramid-hbao",
                    &format!("levels={l}"),
                    0.44 + 0.2 * l as f64,
                    0.12 - 0.01 * l.min(4) as f64,
                ));
            }
            runs.push(record(scene, "ssao", "defaults", 1.0, 0.15));
        }
        let (svg, png) = (dir.join("p.svg"), dir.join("p.png"));
        write_pareto(&svg, &png, &runs, &techniques, "AO time, ms").unwrap();
        assert!(std::fs::read_to_string(&svg).unwrap().starts_with("<svg"));
        let img = image::open(&png).unwrap();
        assert_eq!((img.width(), img.height()), (2 * PANEL.0, PANEL.1));
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn the_front_keeps_only_unbeaten_points() {
        let pts = [
            p(1.0, 0.3),
            p(2.0, 0.2),
            p(3.0, 0.25),
            p(0.5, 0.5),
            p(4.0, 0.1),
            p(2.0, 0.2),
            p(5.0, f64::NAN),
        ];
        assert_eq!(pareto_front(&pts), vec![3, 0, 1, 4]);
        assert!(pareto_front(&[]).is_empty());
    }
}
