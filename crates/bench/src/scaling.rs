//! `aograph bench --scaling`: how each technique's time grows with resolution and radius.
//!
//! Every parameter set is timed on a grid of square resolutions x world radii (4 x 4 by
//! default). The radius in pixels is the world radius projected at the frame's median
//! non-sky depth (`R * f / z`, f the focal length in pixels; `R * H / h` for orthographic
//! cameras). A least-squares fit of log time = c + a log(pixels) + b log(radius in pixels)
//! over the grid gives a, the exponent against pixels at a fixed radius in pixels, and b, the
//! exponent against the radius in pixels at a fixed pixel count. With one size (or one
//! radius) only the other exponent is fitted. No reference is traced: this is time only.
//!
//! The Pyramid HBAO paper's claim (docs/techniques/pyramid-hbao.md §2.6) is about quality held fixed:
//! HBAO must grow D and S with the radius (quadratic time), Pyramid HBAO one level per 3x
//! (near-linear). At fixed parameters, as here, a technique that marches a fixed number of
//! samples does the same work at any radius, and b shows what the memory system charges for
//! spreading those samples wider.

use std::fmt::Write as _;

use aograph_scene::{Camera, Projection};
use serde::{Deserialize, Serialize};

use crate::csv;
use crate::metrics::nonfinite::format as num;
use crate::stats::{Spread, fit_power_law};

/// Default sides in pixels of the square outputs a scaling run times.
pub const DEFAULT_SIDES: [u32; 4] = [128, 256, 512, 1024];
/// Default multipliers of each scene's automatic radius.
pub const DEFAULT_RADIUS_FACTORS: [f32; 4] = [0.5, 1.0, 2.0, 4.0];

/// The radii a scaling run times.
#[derive(Clone, Debug, PartialEq)]
pub enum ScalingRadii {
    /// World units, the same for every scene.
    Units(Vec<f32>),
    /// Multiples of each scene's automatic radius (`auto`: the scene rule, or the view rule
    /// for an interior view).
    Factors(Vec<f32>),
}

impl ScalingRadii {
    /// The radii for `scene`.
    pub fn for_scene(&self, scene: &aograph_scene::Scene) -> Vec<f32> {
        match self {
            ScalingRadii::Units(r) => r.clone(),
            ScalingRadii::Factors(f) => {
                let r = aograph_app_config::prepared_scene::resolve_radius(
                    scene,
                    aograph_ao_passes::RadiusSetting::Auto,
                )
                .0
                .get();
                f.iter().map(|k| k * r).collect()
            }
        }
    }
    /// How many radii each scene gets.
    pub fn len(&self) -> usize {
        match self {
            ScalingRadii::Units(r) | ScalingRadii::Factors(r) => r.len(),
        }
    }
    /// True when there are none.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// One timed configuration.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ScalingPoint {
    /// The scene's label: the procedural name or the glTF path as given.
    pub scene: String,
    /// The technique's registry name.
    pub technique: String,
    /// The parameter set's label (`ParamSet::label`).
    pub label: String,
    /// Side in pixels of the square output.
    pub side: u32,
    /// Pixels of the output, side x side: the fit's first regressor.
    pub pixels: u64,
    /// The world radius R in scene units.
    pub radius: f32,
    /// R in pixels at the frame's median non-sky depth ([`radius_in_pixels`]): the fit's second
    /// regressor; NaN when the frame shows no geometry.
    pub radius_px: f64,
    /// Where the times come from: `gpu-timestamps`, `cpu-wall` or `none`.
    pub timing_source: String,
    /// The technique's time (its passes, g-buffer excluded) over the measured frames, in ms.
    pub total_ms: Spread,
}

/// The fitted exponents of one parameter set on one scene.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ScalingFit {
    /// The scene's label.
    pub scene: String,
    /// The technique's registry name.
    pub technique: String,
    /// The parameter set's label (`ParamSet::label`).
    pub label: String,
    /// a in time ∝ pixels^a at a fixed radius in pixels (1 = linear); `None` when the pixel
    /// count did not vary or the fit failed.
    pub pixel_exponent: Option<f64>,
    /// b in time ∝ (radius in pixels)^b at a fixed pixel count; `None` when the radius in
    /// pixels did not vary or the fit failed.
    pub radius_exponent: Option<f64>,
    /// Coefficient of determination of the log-log fit; `None` without a fit.
    pub r2: Option<f64>,
    /// Points of the group (timed points of this scene, technique and parameter set).
    pub points: usize,
}

/// Every point and fit of a scaling study (scaling.json).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ScalingResults {
    /// The sides in pixels of the square outputs timed.
    pub sides: Vec<u32>,
    /// The world radii timed, in scene units (the first scene's when they are multiples of each
    /// scene's automatic radius).
    pub radii: Vec<f32>,
    /// Measured frames per point.
    pub frames: u32,
    /// Warm-up frames per point, rendered and discarded first.
    pub warmup: u32,
    /// Every timed point, in the order timed.
    pub points: Vec<ScalingPoint>,
    /// One fit per (scene, technique, parameter set), redone by [`ScalingResults::refit`].
    pub fits: Vec<ScalingFit>,
}

/// The world radius `radius` in pixels at depth `depth` for an output `height` pixels tall.
pub fn radius_in_pixels(camera: &Camera, height: u32, radius: f32, depth: f64) -> f64 {
    match camera.projection {
        Projection::Perspective { fov_y, .. } => {
            radius as f64 * (height as f64 / 2.0) / (fov_y as f64 / 2.0).tan() / depth
        }
        Projection::Orthographic { height: h, .. } => radius as f64 * height as f64 / h as f64,
    }
}

/// The median of the positive depths (0 when there are none).
pub fn median_depth(depth: &[f32]) -> f64 {
    let mut d: Vec<f64> = depth
        .iter()
        .filter(|v| **v > 0.0 && v.is_finite())
        .map(|v| *v as f64)
        .collect();
    if d.is_empty() {
        return 0.0;
    }
    d.sort_by(f64::total_cmp);
    d[d.len() / 2]
}

impl ScalingResults {
    /// Refits every (scene, technique, parameters) group from the points.
    pub fn refit(&mut self) {
        let mut groups: Vec<(String, String, String)> = Vec::new();
        for p in &self.points {
            let key = (p.scene.clone(), p.technique.clone(), p.label.clone());
            if !groups.contains(&key) {
                groups.push(key);
            }
        }
        self.fits = groups
            .into_iter()
            .map(|(scene, technique, label)| {
                let pts: Vec<&ScalingPoint> = self
                    .points
                    .iter()
                    .filter(|p| p.scene == scene && p.technique == technique && p.label == label)
                    .collect();
                let varies = |f: &dyn Fn(&ScalingPoint) -> f64| {
                    pts.iter()
                        .any(|p| (f(p) - f(pts[0])).abs() > 1e-9 * f(pts[0]).abs().max(1.0))
                };
                let (use_pixels, use_radius) =
                    (varies(&|p| p.pixels as f64), varies(&|p| p.radius_px));
                let xs: Vec<Vec<f64>> = pts
                    .iter()
                    .map(|p| {
                        [(use_pixels, p.pixels as f64), (use_radius, p.radius_px)]
                            .into_iter()
                            .filter(|(u, _)| *u)
                            .map(|(_, v)| v)
                            .collect()
                    })
                    .collect();
                let y: Vec<f64> = pts.iter().map(|p| p.total_ms.median).collect();
                let fit = if use_pixels || use_radius {
                    fit_power_law(&xs, &y)
                } else {
                    None
                };
                let mut e = fit
                    .as_ref()
                    .map(|f| f.exponents.clone())
                    .unwrap_or_default()
                    .into_iter();
                let pixel_exponent = if use_pixels { e.next() } else { None };
                let radius_exponent = if use_radius { e.next() } else { None };
                ScalingFit {
                    scene,
                    technique,
                    label,
                    pixel_exponent,
                    radius_exponent,
                    r2: fit.as_ref().map(|f| f.r2),
                    points: pts.len(),
                }
            })
            .collect();
    }

    /// scaling.csv's header: one row per [`ScalingFit`].
    pub const FITS_HEADER: &'static str =
        "scene,technique,params,pixel_exponent,radius_exponent,r2,points";
    /// scaling_points.csv's header: one row per [`ScalingPoint`], times in ms.
    pub const POINTS_HEADER: &'static str = "scene,technique,params,side,pixels,radius,radius_px,timing_source,total_ms_median,total_ms_min,total_ms_max";

    /// scaling.csv: one row per fit.
    pub fn fits_csv(&self) -> String {
        let o = |v: Option<f64>| v.map(|v| num(v, 4)).unwrap_or_default();
        let mut s = format!("{}\n", Self::FITS_HEADER);
        for f in &self.fits {
            let _ = writeln!(
                s,
                "{},{},{},{},{},{},{}",
                csv::field(&f.scene),
                csv::field(&f.technique),
                csv::field(&f.label),
                o(f.pixel_exponent),
                o(f.radius_exponent),
                o(f.r2),
                f.points
            );
        }
        s
    }

    /// One scaling_points.csv row.
    pub fn point_row(p: &ScalingPoint) -> String {
        format!(
            "{},{},{},{},{},{},{},{},{},{},{}",
            csv::field(&p.scene),
            csv::field(&p.technique),
            csv::field(&p.label),
            p.side,
            p.pixels,
            p.radius,
            num(p.radius_px, 3),
            p.timing_source,
            num(p.total_ms.median, 5),
            num(p.total_ms.min, 5),
            num(p.total_ms.max, 5)
        )
    }

    /// The report.md section.
    pub fn markdown(&self) -> String {
        let o = |v: Option<f64>, d| v.map(|v| num(v, d)).unwrap_or_else(|| "-".into());
        let mut s = String::new();
        let sides: Vec<String> = self.sides.iter().map(|x| x.to_string()).collect();
        let radii: Vec<String> = self.radii.iter().map(|x| x.to_string()).collect();
        let _ = writeln!(
            s,
            "## Scaling\n\nAO time (median of {} frames after {} warm-up) at sides {} px and radii {} (world units), fitted as time ∝ pixels^a · (radius in pixels)^b by least squares on log-log (radius in pixels at the frame's median depth). 1 means linear, 2 quadratic. Parameters are held fixed: the paper's quadratic-versus-near-linear claim is for quality held fixed (HBAO growing D and S with R, Pyramid HBAO adding levels), so at fixed parameters b measures the cost of spreading the same samples wider.\n",
            self.frames,
            self.warmup,
            sides.join(", "),
            radii.join(", ")
        );
        let _ = writeln!(
            s,
            "| scene | technique | parameters | a (pixels) | b (radius px) | R² | points |\n|---|---|---|---:|---:|---:|---:|"
        );
        for f in &self.fits {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {} | {} | {} |",
                f.scene,
                f.technique,
                f.label,
                o(f.pixel_exponent, 3),
                o(f.radius_exponent, 3),
                o(f.r2, 3),
                f.points
            );
        }
        let _ = writeln!(
            s,
            "\n| scene | technique | parameters | side | radius | radius px | AO ms (median) | [min, max] |\n|---|---|---|---:|---:|---:|---:|---|"
        );
        for p in &self.points {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {} | {} | {} | [{}, {}] |",
                p.scene,
                p.technique,
                p.label,
                p.side,
                p.radius,
                num(p.radius_px, 1),
                num(p.total_ms.median, 4),
                num(p.total_ms.min, 4),
                num(p.total_ms.max, 4)
            );
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(side: u32, radius: f32, ms: f64) -> ScalingPoint {
        ScalingPoint {
            scene: "s".into(),
            technique: "t".into(),
            label: "defaults".into(),
            side,
            pixels: side as u64 * side as u64,
            radius,
            radius_px: radius as f64 * side as f64 / 10.0,
            timing_source: "cpu-wall".into(),
            total_ms: Spread::of(&[ms]),
        }
    }

    #[test]
    fn recovers_the_exponents_of_a_synthetic_technique() {
        // time = pixels * radius_px^2 * 1e-6
        let mut r = ScalingResults::default();
        for side in [64, 128, 256] {
            for radius in [1.0f32, 2.0, 4.0] {
                let rp = radius as f64 * side as f64 / 10.0;
                r.points
                    .push(point(side, radius, (side * side) as f64 * rp * rp * 1e-6));
            }
        }
        r.refit();
        let f = &r.fits[0];
        assert!(
            (f.pixel_exponent.unwrap() - 1.0).abs() < 1e-6
                && (f.radius_exponent.unwrap() - 2.0).abs() < 1e-6,
            "{f:?}"
        );
        assert!(
            r.fits_csv().lines().count() == 2
                && r.markdown()
                    .contains("| s | t | defaults | 1.000 | 2.000 |")
        );
    }

    #[test]
    fn one_size_fits_only_the_radius() {
        let mut r = ScalingResults::default();
        for radius in [1.0f32, 2.0, 4.0] {
            r.points.push(point(64, radius, radius as f64));
        }
        r.refit();
        assert_eq!(r.fits[0].pixel_exponent, None);
        assert!((r.fits[0].radius_exponent.unwrap() - 1.0).abs() < 1e-9);
    }

    #[test]
    fn radius_in_pixels_of_a_perspective_camera() {
        let c = Camera::perspective(
            glam::Vec3::ZERO,
            glam::Vec3::NEG_Z,
            std::f32::consts::FRAC_PI_2,
            0.1,
            100.0,
        );
        // fov 90 degrees: f = H / 2; R = 1 at depth 2 on 200 px is 50 px.
        assert!((radius_in_pixels(&c, 200, 1.0, 2.0) - 50.0).abs() < 1e-4);
        assert_eq!(median_depth(&[0.0, 3.0, 1.0, 2.0]), 2.0);
    }

    #[test]
    fn scaling_rows_quote_a_scene_with_commas_and_keep_every_column() {
        let mut r = ScalingResults::default();
        for side in [64, 128] {
            let mut p = point(side, 1.0, side as f64);
            p.scene = "scenes/hall, east.gltf".into();
            p.label = "a \"b\"".into();
            r.points.push(p);
        }
        r.refit();
        let row = csv::split_row(&ScalingResults::point_row(&r.points[0]));
        assert_eq!(row.len(), ScalingResults::POINTS_HEADER.split(',').count());
        assert_eq!(row[..3], ["scenes/hall, east.gltf", "t", "a \"b\""]);
        let fits = r.fits_csv();
        let fit = csv::split_row(fits.lines().nth(1).expect("one fit"));
        assert_eq!(fit.len(), ScalingResults::FITS_HEADER.split(',').count());
        assert_eq!(fit[..3], ["scenes/hall, east.gltf", "t", "a \"b\""]);
    }
}
