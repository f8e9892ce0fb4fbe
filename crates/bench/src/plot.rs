//! The speed/accuracy plot: a grid of panels, first a summary over every scene and view (each
//! technique and parameter set at its mean time against its mean MAE), then one panel per
//! scene and view (its median time, log scale, against its MAE), one colour per technique,
//! and in each the Pareto front (the runs no other run beats on both time and MAE) drawn as a
//! staircase: for a time budget on the x axis, the front's height is the best MAE that budget
//! buys. Panels are titled with short scene names ([`short_scene`]), at most four
//! a row, so a bench over many scenes reads at 100 % zoom. Written as SVG (text drawn by the
//! viewer) and PNG (text drawn by plotters from the Ubuntu Light font that
//! `epaint_default_fonts` embeds, Ubuntu Font Licence 1.0).

use std::path::Path;
use std::sync::Once;

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::images::{write_atomic, write_rgb_png};
use crate::run::RunRecord;
use aograph_app_config::error::{AppError, AppResult};

pub(super) const PANEL: (u32, u32) = (800, 480);
/// Panels a row: four 800-pixel panels make a 3,200-pixel row, readable at 100 % zoom on a
/// large screen and scrollable on a small one.
const GRID_COLUMNS: usize = 4;
/// Width of the legend strip at the right of each panel.
const LEGEND_WIDTH: u32 = 160;
/// Tableau 10: distinguishable, colour-blind aware.
pub(super) const PALETTE: [RGBColor; 10] = [
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

/// Font sizes in pixels, the same for the SVG and the PNG.
#[derive(Clone, Copy)]
pub(super) struct Fonts {
    pub(super) caption: u32,
    pub(super) label: u32,
}
pub(super) const FONTS: Fonts = Fonts {
    caption: 22,
    label: 15,
};

/// Registers the PNG's font with plotters (once per process): Ubuntu Light under the family
/// name the charts ask for.
pub(super) fn register_font() -> Result<(), String> {
    static REGISTER: Once = Once::new();
    let mut result = Ok(());
    REGISTER.call_once(|| {
        result = plotters::style::register_font(
            "sans-serif",
            FontStyle::Normal,
            epaint_default_fonts::UBUNTU_LIGHT,
        )
        .map_err(|_| "the embedded Ubuntu Light font does not parse".to_string());
    });
    result
}

/// A scene's name as a title shows it: a file's stem (`Sponza` for
/// `/any/where/Sponza/glTF/Sponza.gltf`), a procedural scene's name as it is, and the view
/// after a slash (`Sponza / outside`).
pub fn short_scene(scene_view: &str) -> String {
    let (scene, view) = match scene_view.rsplit_once(" / ") {
        Some((scene, view)) => (scene, Some(view)),
        None => (scene_view, None),
    };
    let path = Path::new(scene);
    let stem = match path.extension() {
        Some(_) => path
            .file_stem()
            .map_or(scene.into(), |s| s.to_string_lossy()),
        None => scene.into(),
    };
    match view {
        Some(view) => format!("{stem} / {view}"),
        None => stem.into_owned(),
    }
}

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

/// One point per technique and parameter set: its mean time and mean MAE over every scene and
/// view it ran on, in first-seen order.
pub fn summary(records: &[RunRecord]) -> Vec<Point> {
    let mut sums: Vec<(Point, usize)> = Vec::new();
    for r in records {
        let (ms, mae) = (r.times.total_ms.median.max(MIN_MS), r.metrics.mae);
        match (sums.iter_mut()).find(|(p, _)| p.technique == r.technique && p.label == r.label) {
            Some((p, n)) => {
                p.ms += ms;
                p.mae += mae;
                *n += 1;
            }
            None => sums.push((
                Point {
                    technique: r.technique.clone(),
                    label: r.label.clone(),
                    ms,
                    mae,
                },
                1,
            )),
        }
    }
    (sums.into_iter())
        .map(|(p, n)| Point {
            ms: p.ms / n as f64,
            mae: p.mae / n as f64,
            ..p
        })
        .collect()
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
    title: &str,
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
        .caption(title, ("sans-serif", fonts.caption))
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

/// The panels: the summary, then every scene and view, with their titles.
fn panels(records: &[RunRecord]) -> Vec<(String, Vec<Point>)> {
    let scenes = by_scene(records);
    let mut out = vec![(
        format!(
            "all {} scene views: mean time against mean MAE",
            scenes.len()
        ),
        summary(records),
    )];
    out.extend(
        scenes
            .into_iter()
            .map(|(scene, points)| (short_scene(&scene), points)),
    );
    out
}

/// The plot's size in pixels for `panels` panels.
fn grid(panels: usize) -> (usize, usize, (u32, u32)) {
    grid_of(panels, GRID_COLUMNS, PANEL)
}

/// Rows, columns and the picture's size in pixels for `panels` panels of `panel` pixels, at
/// most `columns` a row.
pub(super) fn grid_of(
    panels: usize,
    columns: usize,
    panel: (u32, u32),
) -> (usize, usize, (u32, u32)) {
    let columns = panels.clamp(1, columns.max(1));
    let rows = panels.max(1).div_ceil(columns);
    let size = (panel.0 * columns as u32, panel.1 * rows as u32);
    (rows, columns, size)
}

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    panels: &[(String, Vec<Point>)],
    techniques: &[String],
    time_label: &str,
) -> Result<(), String> {
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let (rows, columns, _) = grid(panels.len());
    let areas = root.split_evenly((rows, columns));
    for (area, (title, points)) in areas.iter().zip(panels) {
        let (chart, key) = area.split_horizontally(PANEL.0 - LEGEND_WIDTH);
        panel(&chart, title, points, techniques, time_label, FONTS)?;
        legend(&key, points, techniques, FONTS)?;
    }
    root.present().map_err(|e| e.to_string())
}

pub(super) fn plot_err(path: &Path, m: String) -> AppError {
    AppError::Image {
        path: path.into(),
        message: format!("plot: {m}"),
    }
}

/// Writes `svg` and `png` for `records`; `techniques` fixes the colour order.
pub fn write_pareto(
    svg: &Path,
    png: &Path,
    records: &[RunRecord],
    techniques: &[String],
    time_label: &str,
) -> AppResult<()> {
    let panels = panels(records);
    let (_, _, size) = grid(panels.len());
    // Both backends lay text out with the registered font.
    register_font().map_err(|m| plot_err(png, m))?;
    let mut text = String::new();
    draw(
        SVGBackend::with_string(&mut text, size).into_drawing_area(),
        &panels,
        techniques,
        time_label,
    )
    .map_err(|m| plot_err(svg, m))?;
    write_atomic(svg, text.as_bytes())?;
    write_pareto_png(png, records, techniques, time_label)
}

/// Writes only the PNG of [`write_pareto`] (what the docs commit beside a results file).
pub fn write_pareto_png(
    png: &Path,
    records: &[RunRecord],
    techniques: &[String],
    time_label: &str,
) -> AppResult<()> {
    let panels = panels(records);
    let (_, _, size) = grid(panels.len());
    register_font().map_err(|m| plot_err(png, m))?;
    let mut rgb = vec![255u8; size.0 as usize * size.1 as usize * 3];
    draw(
        BitMapBackend::with_buffer(&mut rgb, size).into_drawing_area(),
        &panels,
        techniques,
        time_label,
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
        use crate::run::FrameTimes;
        use crate::stats::Spread;
        RunRecord {
            scene: scene.into(),
            view: "default".into(),
            technique: technique.into(),
            baseline: aograph_ao_passes::TechniqueRegistry::with_builtins()
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
            convergence: Vec::new(),
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
        if let Ok(keep) = std::env::var("AOGRAPH_KEEP_PLOT") {
            std::fs::copy(&png, keep).unwrap();
        }
        let img = image::open(&png).unwrap();
        // The summary and the two scenes: three panels in one row.
        assert_eq!((img.width(), img.height()), (3 * PANEL.0, PANEL.1));
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn a_bench_of_22_views_is_a_grid_of_short_titled_panels_after_the_summary() {
        // Nine scenes by absolute path, 22 scene views, three techniques: the held-out bench.
        let dir = std::env::temp_dir().join(format!("aograph-grid-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let techniques: Vec<String> = ["gtao", "hbao", "ssao"].map(String::from).to_vec();
        let mut runs = Vec::new();
        for v in 0..22 {
            let scene = format!("/home/ci/scenes/model{}/glTF/Model{}.gltf", v % 9, v % 9);
            for (k, t) in techniques.iter().enumerate() {
                let mut r = record(&scene, t, "defaults", 1.0 + k as f64, 0.1 - 0.01 * k as f64);
                r.view = format!("view{}", v / 9);
                runs.push(r);
            }
        }
        let (svg, png) = (dir.join("p.svg"), dir.join("p.png"));
        write_pareto(&svg, &png, &runs, &techniques, "AO time, ms").unwrap();
        // 23 panels (the summary first), four a row: six rows.
        let img = image::open(&png).unwrap();
        assert_eq!((img.width(), img.height()), (4 * PANEL.0, 6 * PANEL.1));
        let text = std::fs::read_to_string(&svg).unwrap();
        assert!(text.contains("all 22 scene views: mean time against mean MAE"));
        assert!(
            text.contains("Model4 / view1"),
            "titles are file stems and views"
        );
        assert!(!text.contains("/home/ci"), "no absolute path in a title");
        if let Ok(keep) = std::env::var("AOGRAPH_KEEP_GRID") {
            std::fs::copy(&png, keep).unwrap();
        }
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn short_scene_names_keep_the_stem_and_the_view() {
        assert_eq!(
            short_scene("/a/b/Sponza/glTF/Sponza.gltf / outside"),
            "Sponza / outside"
        );
        assert_eq!(short_scene("columns"), "columns");
        assert_eq!(short_scene("columns / camera"), "columns / camera");
        assert_eq!(short_scene("tests/scenes/teapot.gltf"), "teapot");
    }

    #[test]
    fn the_summary_is_each_settings_mean_over_the_views() {
        let runs = [
            record("a", "gtao", "defaults", 1.0, 0.1),
            record("b", "gtao", "defaults", 3.0, 0.3),
            record("a", "ssao", "defaults", 2.0, 0.2),
        ];
        let s = summary(&runs);
        assert_eq!(s.len(), 2);
        assert_eq!(
            (s[0].technique.as_str(), s[0].ms, s[0].mae),
            ("gtao", 2.0, 0.2)
        );
        assert_eq!(
            (s[1].technique.as_str(), s[1].ms, s[1].mae),
            ("ssao", 2.0, 0.2)
        );
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
