//! The per-pixel reference estimator, parallel across image rows with rayon.
//!
//! Each valid pixel shoots `rays_per_pixel` cosine-weighted rays (see `sampling`) from its point,
//! offset along its normal by eps = [`offset_epsilon`] against self-hits, over t in [0, R].
//! Points on a concave crease (a floor point at the foot of a wall, which rasterised and CPU
//! primary hits produce along creases) keep the wall at a tiny positive distance on the rays
//! towards it; [`TriangleBvh`](super::TriangleBvh) finds such hits however close (see its module docs). The
//! estimate is the mean per-ray occlusion o_i (binary: 1 for a hit; obscurance: rho(d)) and
//! A = 1 - mean. The reported standard error is sqrt(s^2 / N) with s^2 the unbiased sample
//! variance of o_i: the i.i.d. formula, which over-estimates the true error of the stratified
//! (quasi-Monte Carlo) estimate, so it is a safe bound for tolerances.
//! Invariants: sky pixels, and pixels whose point or normal is not finite (or whose normal is
//! zero), are exactly 1 with error 0; output is finite, in [0, 1], and independent of thread
//! scheduling (each pixel's rays depend only on its index).

use super::bvh::RayQueries;
use super::output::ReferenceImage;
use super::progress::row_progress;
use super::sampling::{cosine_hemisphere, pixel_scramble, sobol_2d, tangent_frame};
use super::{ReferenceMode, ReferenceParams, SurfaceBuffer};
use crate::error::SceneError;
use glam::Vec3;
use rayon::prelude::*;

/// How far along its normal a ray origin is moved off the surface: 1e-4 R (occluders closer
/// than that are ignored, a negligible bias) plus 4e-6 times the point's largest coordinate
/// (about 30 float ulps there, covering g-buffer reconstruction error). This keeps rays clear of
/// their own surface at scene scales from 1e-3 to 1e4.
pub fn offset_epsilon(point: Vec3, radius: f32) -> f32 {
    1e-4 * radius + 4e-6 * point.abs().max_element()
}

/// Checks the buffer sizes and parameters before tracing.
pub fn check_inputs(surfaces: &SurfaceBuffer, params: &ReferenceParams) -> Result<(), SceneError> {
    if !(params.radius.is_finite() && params.radius > 0.0) {
        return Err(SceneError::InvalidParameter {
            name: "radius",
            value: params.radius.to_string(),
            allowed: "a finite number > 0 (world units)",
        });
    }
    if params.rays_per_pixel == 0 {
        return Err(SceneError::InvalidParameter {
            name: "rays_per_pixel",
            value: "0".into(),
            allowed: "at least 1",
        });
    }
    let expected = surfaces.pixel_count();
    for (what, actual) in [
        ("points", surfaces.points.len()),
        ("normals", surfaces.normals.len()),
        ("valid mask", surfaces.valid.len()),
    ] {
        if actual != expected {
            return Err(SceneError::InputSizeMismatch {
                what,
                width: surfaces.width,
                height: surfaces.height,
                expected,
                actual,
            });
        }
    }
    Ok(())
}

/// Accessibility and standard error of one pixel.
fn trace_pixel(
    bvh: &(impl RayQueries + ?Sized),
    pixel: u32,
    point: Vec3,
    normal: Vec3,
    params: &ReferenceParams,
) -> (f32, f32) {
    let Some(normal) = normal.try_normalize() else {
        return (1.0, 0.0);
    };
    if !point.is_finite() {
        return (1.0, 0.0);
    }
    let radius = params.radius;
    let origin = point + normal * offset_epsilon(point, radius);
    let (tangent, bitangent) = tangent_frame(normal);
    let scramble = pixel_scramble(pixel);
    let n = params.rays_per_pixel;
    let (mut sum, mut sum_squares) = (0.0f64, 0.0f64);
    for i in 0..n {
        let local = cosine_hemisphere(sobol_2d(i, scramble));
        let direction = tangent * local.x + bitangent * local.y + normal * local.z;
        let occlusion = match params.mode {
            ReferenceMode::Binary => {
                if bvh.any_hit(origin, direction, 0.0, radius) {
                    1.0
                } else {
                    0.0
                }
            }
            ReferenceMode::Obscurance => bvh
                .closest_hit(origin, direction, 0.0, radius)
                .map_or(0.0, |hit| 1.0 - (hit.distance / radius).powi(2).min(1.0)),
        };
        sum += f64::from(occlusion);
        sum_squares += f64::from(occlusion * occlusion);
    }
    let count = f64::from(n);
    let mean = sum / count;
    let variance = if n > 1 {
        ((sum_squares - count * mean * mean) / (count - 1.0)).max(0.0)
    } else {
        0.0
    };
    let accessibility = (1.0 - mean).clamp(0.0, 1.0) as f32;
    (accessibility, (variance / count).sqrt() as f32)
}

/// Traces the reference for every pixel of `surfaces` against `bvh`.
///
/// Errors: a non-positive or non-finite radius, zero rays, or buffers whose lengths differ
/// from width * height.
pub fn trace_reference(
    bvh: &(impl RayQueries + ?Sized),
    surfaces: &SurfaceBuffer,
    params: &ReferenceParams,
) -> Result<ReferenceImage, SceneError> {
    trace_reference_rows(bvh, surfaces, params, 0..surfaces.height)
}

/// Traces rows `rows` of `surfaces` only (a band of a progressive trace); each pixel's rays are
/// the ones [`trace_reference`] gives it (they depend on its index in the whole image), so
/// bands traced one by one make exactly the whole image. The result is `rows.len()` rows tall.
pub fn trace_reference_rows(
    bvh: &(impl RayQueries + ?Sized),
    surfaces: &SurfaceBuffer,
    params: &ReferenceParams,
    rows: std::ops::Range<u32>,
) -> Result<ReferenceImage, SceneError> {
    check_inputs(surfaces, params)?;
    let rows = rows.start.min(surfaces.height)..rows.end.min(surfaces.height);
    let width = surfaces.width as usize;
    let progress = row_progress(params.progress, u64::from(rows.end - rows.start));
    let traced: Vec<Vec<(f32, f32)>> = (rows.start as usize..rows.end as usize)
        .into_par_iter()
        .map(|y| {
            let row = (0..width)
                .map(|x| {
                    let i = y * width + x;
                    if surfaces.valid[i] {
                        trace_pixel(
                            bvh,
                            i as u32,
                            surfaces.points[i],
                            surfaces.normals[i],
                            params,
                        )
                    } else {
                        (1.0, 0.0)
                    }
                })
                .collect();
            progress.inc(1);
            row
        })
        .collect();
    progress.finish_and_clear();
    let (accessibility, std_error) = traced.into_iter().flatten().unzip();
    Ok(ReferenceImage {
        width: surfaces.width,
        height: rows.end - rows.start,
        accessibility,
        std_error,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reference::TriangleBvh;

    #[test]
    fn bands_of_rows_traced_one_by_one_make_exactly_the_whole_image() {
        // A floor under a tilted ceiling: every pixel sees another amount of occlusion.
        let tri =
            |a: [f32; 3], b: [f32; 3], c: [f32; 3]| [Vec3::from(a), Vec3::from(b), Vec3::from(c)];
        let bvh = TriangleBvh::new(&[
            tri([-5.0, 0.2, -5.0], [5.0, 1.5, -5.0], [-5.0, 0.2, 5.0]),
            tri([5.0, 1.5, -5.0], [5.0, 1.5, 5.0], [-5.0, 0.2, 5.0]),
        ]);
        let (w, h) = (7u32, 5u32);
        let n = (w * h) as usize;
        let surfaces = SurfaceBuffer {
            width: w,
            height: h,
            points: (0..n)
                .map(|i| {
                    Vec3::new(
                        (i as u32 % w) as f32 - 3.0,
                        0.0,
                        (i as u32 / w) as f32 - 2.0,
                    )
                })
                .collect(),
            normals: vec![Vec3::Y; n],
            valid: (0..n).map(|i| i != 3).collect(),
        };
        let params = ReferenceParams {
            radius: 2.0,
            rays_per_pixel: 16,
            progress: super::super::ProgressMode::Never,
            ..Default::default()
        };
        let whole = trace_reference(&bvh, &surfaces, &params).unwrap();
        let mut bands = Vec::new();
        for y in (0..h).step_by(2) {
            let band = trace_reference_rows(&bvh, &surfaces, &params, y..(y + 2).min(h)).unwrap();
            assert_eq!(band.height, (y + 2).min(h) - y);
            bands.extend(band.accessibility);
        }
        assert_eq!(bands, whole.accessibility);
        assert!(whole.accessibility.iter().any(|&a| a < 1.0) && whole.accessibility[3] == 1.0);
        // Rows past the end are clipped, not an error.
        assert_eq!(
            trace_reference_rows(&bvh, &surfaces, &params, 4..9)
                .unwrap()
                .height,
            1
        );
    }

    #[test]
    fn bad_parameters_and_sizes_are_errors() {
        let bvh = TriangleBvh::new(&[]);
        let surfaces = SurfaceBuffer::one_pixel(Vec3::ZERO, Vec3::Y);
        let zero_radius = ReferenceParams {
            radius: 0.0,
            ..Default::default()
        };
        let message = trace_reference(&bvh, &surfaces, &zero_radius)
            .unwrap_err()
            .to_string();
        assert!(message.contains("radius"), "{message}");
        let mut short = surfaces.clone();
        short.normals.clear();
        let message = trace_reference(&bvh, &short, &ReferenceParams::default())
            .unwrap_err()
            .to_string();
        assert!(
            message.contains("normals") && message.contains("1x1"),
            "{message}"
        );
    }

    #[test]
    fn pixel_under_a_close_ceiling_is_fully_occluded() {
        let big = 100.0;
        let ceiling = [
            [
                Vec3::new(-big, 0.1, -big),
                Vec3::new(big, 0.1, -big),
                Vec3::new(big, 0.1, big),
            ],
            [
                Vec3::new(-big, 0.1, -big),
                Vec3::new(big, 0.1, big),
                Vec3::new(-big, 0.1, big),
            ],
        ];
        let bvh = TriangleBvh::new(&ceiling);
        let surfaces = SurfaceBuffer::one_pixel(Vec3::ZERO, Vec3::Y);
        // With cos^2(theta) uniform under cosine weighting, a ray escapes (d = 0.1 / cos > R)
        // with probability 0.01.
        let binary = trace_reference(&bvh, &surfaces, &ReferenceParams::default()).unwrap();
        let a = binary.accessibility[0];
        assert!((a - 0.01).abs() < 0.005, "{a}");
        // Obscurance: A = E[min(1, (d/R)^2)] = 0.01 + 0.01 ln(100) = 0.056.
        let params = ReferenceParams {
            mode: ReferenceMode::Obscurance,
            ..Default::default()
        };
        let obscurance = trace_reference(&bvh, &surfaces, &params).unwrap();
        let a = obscurance.accessibility[0];
        assert!((a - 0.056).abs() < 0.005, "{a}");
    }

    #[test]
    fn point_on_a_concave_crease_is_half_occluded_by_the_wall() {
        // Floor y = 0 and wall x = 0 (both large); the point lies 1e-7 from the wall.
        let big = 50.0;
        let floor_and_wall = [
            [
                Vec3::new(-big, 0.0, -big),
                Vec3::new(big, 0.0, big),
                Vec3::new(big, 0.0, -big),
            ],
            [
                Vec3::new(-big, 0.0, -big),
                Vec3::new(-big, 0.0, big),
                Vec3::new(big, 0.0, big),
            ],
            [
                Vec3::new(0.0, 0.0, -big),
                Vec3::new(0.0, big, -big),
                Vec3::new(0.0, big, big),
            ],
            [
                Vec3::new(0.0, 0.0, -big),
                Vec3::new(0.0, big, big),
                Vec3::new(0.0, 0.0, big),
            ],
        ];
        let bvh = TriangleBvh::new(&floor_and_wall);
        let surfaces = SurfaceBuffer::one_pixel(Vec3::new(-1e-7, 0.0, 0.3), Vec3::Y);
        let image = trace_reference(&bvh, &surfaces, &ReferenceParams::default()).unwrap();
        let a = image.accessibility[0];
        assert!((a - 0.5).abs() < 0.02, "{a}");
    }

    #[test]
    fn non_finite_inputs_count_as_sky() {
        let bvh = TriangleBvh::new(&[]);
        let surfaces = SurfaceBuffer::one_pixel(Vec3::new(f32::NAN, 0.0, 0.0), Vec3::Y);
        let image = trace_reference(&bvh, &surfaces, &ReferenceParams::default()).unwrap();
        assert_eq!(image.accessibility, vec![1.0]);
        let surfaces = SurfaceBuffer::one_pixel(Vec3::ZERO, Vec3::ZERO);
        let image = trace_reference(&bvh, &surfaces, &ReferenceParams::default()).unwrap();
        assert_eq!(image.accessibility, vec![1.0]);
    }
}
