//! The radiance reference SSDO is scored against (issue 19): from each g-buffer point,
//! cosine-weighted rays; a ray that escapes within R brings the environment's radiance, a ray
//! that hits geometry within R brings one diffuse bounce, the hit surface's albedo times its
//! own unoccluded environment light ([`SkyIrradiance`]). With pixel albedo rho:
//!
//!   direct   = rho * mean over rays of (escaped ? L_env(w) : 0)       (SSDO's L_dir, E1)
//!   indirect = rho * mean over rays of (hit ? rho_hit * E_cos(n_hit) : 0)   (L_ind, E2)
//!
//! where E_cos(n) is the cosine-weighted mean sky radiance around the hit's face normal,
//! turned towards the ray. As in the AO reference, only geometry within R occludes (the
//! paper's r_max): a ray that hits beyond R counts as escaped. The rays are the AO reference's
//! (same Sobol sequence, same per-pixel scramble, same origin offset), so a pixel's direct
//! term is its binary AO estimate weighted by the sky.
//! Invariants: deterministic; every value finite and >= 0; sky pixels get exactly 0.

use crate::error::TracingError;
use glam::Vec3;
use rayon::prelude::*;

use aograph_scene::environment::{SkyEnvironment, SkyIrradiance};
use aograph_scene::error::SceneError;
use aograph_scene::reference::RayQueries;
use aograph_scene::reference::offset_epsilon;
use aograph_scene::reference::{ReferenceParams, SurfaceBuffer};
use aograph_scene::reference::{cosine_hemisphere, pixel_scramble, sobol_2d, tangent_frame};

/// Linear radiance per pixel, split into its direct and one-bounce parts.
#[derive(Clone, Debug, PartialEq)]
pub struct RadianceImage {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Linear RGB radiance from the sky through unoccluded rays, times the pixel's albedo,
    /// row-major, top row first (0 on sky pixels).
    pub direct: Vec<Vec3>,
    /// Linear RGB radiance of one diffuse bounce off geometry within R, times the pixel's
    /// albedo, same layout (0 on sky pixels).
    pub indirect: Vec<Vec3>,
}

/// What the traced geometry looks like to a bounce: per triangle (the order of
/// `Scene::world_triangles`), its albedo.
pub struct BounceSurfaces<'a> {
    /// World-space triangles, as [`Scene::world_triangles`](aograph_scene::model::Scene::world_triangles)
    /// returns them at the traced time (the triangles the BVH was built from).
    pub triangles: &'a [[Vec3; 3]],
    /// Linear RGB albedo of each triangle, one per entry of `triangles`.
    pub albedo: &'a [Vec3],
}

/// Traces the radiance reference of `surfaces` (with per-pixel `albedo`) under `sky`.
///
/// Errors: a non-positive or non-finite radius, zero rays, or buffers whose lengths differ
/// from width * height (or, for the bounce surfaces, from each other).
pub fn trace_radiance(
    bvh: &(impl RayQueries + ?Sized),
    bounce: &BounceSurfaces<'_>,
    surfaces: &SurfaceBuffer,
    albedo: &[Vec3],
    sky: &SkyEnvironment,
    params: &ReferenceParams,
) -> Result<RadianceImage, TracingError> {
    aograph_scene::reference::check_inputs(surfaces, params)?;
    for (what, actual, expected) in [
        ("pixel albedo", albedo.len(), surfaces.pixel_count()),
        (
            "triangle albedo",
            bounce.albedo.len(),
            bounce.triangles.len(),
        ),
    ] {
        if actual != expected {
            return Err(SceneError::InputSizeMismatch {
                what,
                width: surfaces.width,
                height: surfaces.height,
                expected,
                actual,
            }
            .into());
        }
    }
    let table = SkyIrradiance::new(sky);
    let pixels: Vec<(Vec3, Vec3)> = (0..surfaces.pixel_count())
        .into_par_iter()
        .map(|i| {
            if !surfaces.valid[i] {
                return (Vec3::ZERO, Vec3::ZERO);
            }
            let (d, b) = trace_pixel(
                bvh,
                bounce,
                &table,
                sky,
                i as u32,
                surfaces.points[i],
                surfaces.normals[i],
                params,
            );
            let rho = albedo[i].max(Vec3::ZERO);
            let clean = |v: Vec3| if v.is_finite() { v } else { Vec3::ZERO };
            (clean(rho * d), clean(rho * b))
        })
        .collect();
    let (direct, indirect) = pixels.into_iter().unzip();
    Ok(RadianceImage {
        width: surfaces.width,
        height: surfaces.height,
        direct,
        indirect,
    })
}

/// Mean escaped sky radiance and mean bounce radiance over a pixel's rays.
#[allow(clippy::too_many_arguments)]
fn trace_pixel(
    bvh: &(impl RayQueries + ?Sized),
    bounce: &BounceSurfaces<'_>,
    table: &SkyIrradiance,
    sky: &SkyEnvironment,
    pixel: u32,
    point: Vec3,
    normal: Vec3,
    params: &ReferenceParams,
) -> (Vec3, Vec3) {
    let Some(normal) = normal.try_normalize() else {
        return (Vec3::ZERO, Vec3::ZERO);
    };
    if !point.is_finite() {
        return (Vec3::ZERO, Vec3::ZERO);
    }
    let radius = params.radius;
    let origin = point + normal * offset_epsilon(point, radius);
    let (tangent, bitangent) = tangent_frame(normal);
    let scramble = pixel_scramble(pixel);
    let (mut direct, mut indirect) = (Vec3::ZERO, Vec3::ZERO);
    for i in 0..params.rays_per_pixel {
        let local = cosine_hemisphere(sobol_2d(i, scramble));
        let w = tangent * local.x + bitangent * local.y + normal * local.z;
        match bvh.closest_hit(origin, w, 0.0, radius) {
            None => direct += sky.radiance(w),
            Some(hit) => {
                let [a, b, c] = bounce.triangles[hit.triangle];
                let face = (b - a).cross(c - a).try_normalize().unwrap_or(-w);
                let face = if face.dot(w) > 0.0 { -face } else { face };
                indirect += bounce.albedo[hit.triangle].max(Vec3::ZERO) * table.mean_radiance(face);
            }
        }
    }
    let n = params.rays_per_pixel as f32;
    (direct / n, indirect / n)
}

#[cfg(test)]
mod tests {
    use super::*;
    use aograph_scene::reference::TriangleBvh;

    fn params(radius: f32, rays: u32) -> ReferenceParams {
        ReferenceParams {
            radius,
            rays_per_pixel: rays,
            progress: aograph_scene::reference::ProgressMode::Never,
            ..Default::default()
        }
    }

    fn constant_sky(c: Vec3) -> SkyEnvironment {
        SkyEnvironment {
            zenith: c,
            horizon: c,
            ground: c,
            sun_direction: Vec3::Y,
            sun_irradiance: Vec3::ZERO,
            sun_exponent: 64.0,
        }
    }

    #[test]
    fn an_open_point_under_a_constant_sky_receives_albedo_times_the_sky() {
        let bvh = TriangleBvh::new(&[]);
        let tris: Vec<[Vec3; 3]> = Vec::new();
        let bounce = BounceSurfaces {
            triangles: &tris,
            albedo: &[],
        };
        let c = Vec3::new(0.2, 0.4, 0.8);
        let rho = Vec3::new(0.5, 0.25, 1.0);
        let img = trace_radiance(
            &bvh,
            &bounce,
            &SurfaceBuffer::one_pixel(Vec3::ZERO, Vec3::Y),
            &[rho],
            &constant_sky(c),
            &params(1.0, 64),
        )
        .unwrap();
        assert!((img.direct[0] - rho * c).abs().max_element() < 1e-6);
        assert_eq!(img.indirect[0], Vec3::ZERO);
    }

    #[test]
    fn a_point_under_a_low_ceiling_gets_the_ceilings_bounce_of_the_ground_below_it() {
        // A huge grey ceiling (albedo 0.5) 0.1 above the point, under a blue sky over red
        // ground: every ray hits the ceiling within R = 1; its face normal points down, so it
        // sends out 0.5 times the mean radiance of the lower hemisphere: red ground, but for
        // the blue horizon's blend just below the horizon (y in [-0.25, 0]).
        let big = 1e3;
        let tris = vec![
            [
                Vec3::new(-big, 0.1, -big),
                Vec3::new(big, 0.1, -big),
                Vec3::new(-big, 0.1, big),
            ],
            [
                Vec3::new(big, 0.1, -big),
                Vec3::new(big, 0.1, big),
                Vec3::new(-big, 0.1, big),
            ],
        ];
        let albedo = vec![Vec3::splat(0.5); 2];
        let bvh = TriangleBvh::new(&tris);
        let bounce = BounceSurfaces {
            triangles: &tris,
            albedo: &albedo,
        };
        let sky = SkyEnvironment {
            zenith: Vec3::Z,
            horizon: Vec3::Z,
            ground: Vec3::X,
            ..constant_sky(Vec3::ZERO)
        };
        let img = trace_radiance(
            &bvh,
            &bounce,
            &SurfaceBuffer::one_pixel(Vec3::ZERO, Vec3::Y),
            &[Vec3::ONE],
            &sky,
            &params(1.0, 256),
        )
        .unwrap();
        let down = SkyIrradiance::new(&sky).mean_radiance(Vec3::NEG_Y);
        assert!(down.x > 0.85 && down.z < 0.15 && down.y == 0.0, "{down}");
        // Rays at grazing angles pass R before reaching the ceiling (t = 0.1 / cos): the share
        // of cosine-weighted rays with cos < 0.1 is 0.1^2 = 1%; they see the blue sky.
        let expected = 0.99 * 0.5 * down;
        assert!(
            (img.indirect[0] - expected).abs().max_element() < 0.01,
            "{}",
            img.indirect[0]
        );
        assert!(
            (img.direct[0] - 0.01 * Vec3::Z).abs().max_element() < 0.01,
            "{}",
            img.direct[0]
        );
    }

    #[test]
    fn sky_pixels_are_zero_and_sizes_are_checked() {
        let bvh = TriangleBvh::new(&[]);
        let bounce = BounceSurfaces {
            triangles: &[],
            albedo: &[],
        };
        let mut s = SurfaceBuffer::one_pixel(Vec3::ZERO, Vec3::Y);
        s.valid[0] = false;
        let sky = constant_sky(Vec3::ONE);
        let img = trace_radiance(&bvh, &bounce, &s, &[Vec3::ONE], &sky, &params(1.0, 8)).unwrap();
        assert_eq!((img.direct[0], img.indirect[0]), (Vec3::ZERO, Vec3::ZERO));
        let e = trace_radiance(&bvh, &bounce, &s, &[], &sky, &params(1.0, 8)).unwrap_err();
        assert!(e.to_string().contains("pixel albedo"), "{e}");
    }
}
