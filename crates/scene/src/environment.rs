//! The environment light: a procedural sky with a sun, whose colour varies with direction, for
//! SSDO's direct term (the paper's environment map, Fig. 3) and the CPU radiance reference.
//!
//! The sky is a few colours and one lobe, so the GPU (`sky_radiance` in
//! shaders/ao/ssdo/common.wgsl) and the CPU ([`SkyEnvironment::radiance`]) evaluate the same
//! function: zenith to horizon by sqrt(y) above the horizon, horizon to ground within a few
//! degrees below it, plus a sun lobe E_sun (k + 1) / (2 pi) max(0, w . s)^k, which puts E_sun
//! of irradiance on a surface facing the sun (the integral of the lobe is 2 pi / (k + 1)).
//! Invariant: radiance is finite and >= 0 in every direction, unit or not (zero -> horizon).

/// This file's code (the sky model): the radiance reference's cache hashes it into its keys.
pub const SKY_SOURCE: &str = include_str!("environment.rs");

use glam::{Vec2, Vec3};

use crate::model::Scene;
use crate::reference::{cosine_hemisphere, sobol_2d, tangent_frame};

/// Sharpness k of the sun lobe: a soft sun, half its peak radiance 23 degrees from its centre.
/// What SSDO's 8 samples a pixel (128 over the 4x4 blur) can resolve: at k = 64 (8.5 degrees)
/// both SSDO and a 256-ray reference see the lobe through a handful of directions, and the
/// comparison measures their noise more than their difference (PSNR 18.0 against 19.2 dB on
/// `cornell-box`).
pub const SUN_EXPONENT: f32 = 8.0;
/// Below the horizon the sky turns to ground over this much of y (about 14 degrees).
pub const GROUND_BLEND: f32 = 0.25;

/// A sky with a sun: linear RGB radiances, world space, +Y up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SkyEnvironment {
    /// Sky radiance straight up (+Y), blended towards `horizon` by sqrt(y).
    pub zenith: Vec3,
    /// Sky radiance at the horizon (y = 0).
    pub horizon: Vec3,
    /// Radiance from below, reached [`GROUND_BLEND`] of y under the horizon and kept below.
    pub ground: Vec3,
    /// Unit direction towards the sun.
    pub sun_direction: Vec3,
    /// Irradiance the sun lobe puts on a surface facing it (colour times intensity).
    pub sun_irradiance: Vec3,
    /// Sharpness k of the sun lobe max(0, w . s)^k ([`SUN_EXPONENT`] for the built-in sky).
    pub sun_exponent: f32,
}

impl SkyEnvironment {
    /// The built-in sky of `scene`: the sun where its directional light comes from, with that
    /// light's colour and intensity; a blue zenith, a warm pale horizon and a brown ground,
    /// scaled so the horizon's mean channel is twice the mean channel of the scene's ambient.
    pub fn for_scene(scene: &Scene) -> Self {
        let l = &scene.light;
        let ambient = Vec3::from(scene.ambient).max(Vec3::ZERO);
        let level = if ambient.is_finite() {
            2.0 * ambient.element_sum() / 3.0
        } else {
            0.0
        };
        let colour = |rgb: [f32; 3]| Vec3::from(rgb) * level;
        let sun = Vec3::from(l.color) * l.intensity;
        SkyEnvironment {
            zenith: colour([0.35, 0.55, 1.0]),
            horizon: colour([1.0, 0.95, 0.85]),
            ground: colour([0.45, 0.35, 0.25]),
            sun_direction: (-l.direction).try_normalize().unwrap_or(Vec3::Y),
            sun_irradiance: if sun.is_finite() {
                sun.max(Vec3::ZERO)
            } else {
                Vec3::ZERO
            },
            sun_exponent: SUN_EXPONENT,
        }
    }

    /// Radiance arriving from direction `w` (pointing away from the receiver).
    pub fn radiance(&self, w: Vec3) -> Vec3 {
        let w = w.try_normalize().unwrap_or(Vec3::X);
        let sky = if w.y >= 0.0 {
            self.horizon.lerp(self.zenith, w.y.sqrt())
        } else {
            self.horizon
                .lerp(self.ground, (-w.y / GROUND_BLEND).min(1.0))
        };
        let k = self.sun_exponent;
        let lobe =
            w.dot(self.sun_direction).max(0.0).powf(k) * (k + 1.0) / (2.0 * std::f32::consts::PI);
        sky + self.sun_irradiance * lobe
    }
}

/// The cosine-weighted mean radiance (1/pi) * integral of L(w) max(0, n . w) dw over every
/// normal n, tabulated: what a Lambertian surface of albedo 1 with normal n sends out when
/// nothing blocks its sky. A latitude-longitude grid of normals, each integrated with
/// [`SkyIrradiance::SAMPLES`] Sobol cosine samples, looked up bilinearly.
#[derive(Clone, Debug)]
pub struct SkyIrradiance {
    values: Vec<Vec3>,
}

impl SkyIrradiance {
    /// Rows (polar angle 0..pi, cell centres) and columns (azimuth, wrapping).
    pub const ROWS: usize = 32;
    /// Columns of the table: azimuth 0..2 pi about +Y (from +X towards +Z), wrapping.
    pub const COLUMNS: usize = 64;
    /// Sobol cosine-weighted directions integrated per table cell.
    pub const SAMPLES: u32 = 1024;

    /// Tabulates `sky`: [`Self::ROWS`] x [`Self::COLUMNS`] normals of [`Self::SAMPLES`] rays
    /// each (about two million radiance evaluations, so build it once per sky).
    pub fn new(sky: &SkyEnvironment) -> Self {
        let mut values = Vec::with_capacity(Self::ROWS * Self::COLUMNS);
        for row in 0..Self::ROWS {
            for column in 0..Self::COLUMNS {
                let n = Self::normal(row as f32 + 0.5, column as f32 + 0.5);
                let (t, b) = tangent_frame(n);
                let sum: Vec3 = (0..Self::SAMPLES)
                    .map(|i| {
                        let l = cosine_hemisphere(sobol_2d(i, [0x2545_f491, 0x9e37_79b9]));
                        sky.radiance(t * l.x + b * l.y + n * l.z)
                    })
                    .sum();
                values.push(sum / Self::SAMPLES as f32);
            }
        }
        SkyIrradiance { values }
    }

    fn normal(row: f32, column: f32) -> Vec3 {
        let theta = row / Self::ROWS as f32 * std::f32::consts::PI;
        let phi = column / Self::COLUMNS as f32 * std::f32::consts::TAU;
        Vec3::new(
            theta.sin() * phi.cos(),
            theta.cos(),
            theta.sin() * phi.sin(),
        )
    }

    /// The tabulated cosine-weighted mean radiance around unit normal `n`.
    pub fn mean_radiance(&self, n: Vec3) -> Vec3 {
        let n = n.try_normalize().unwrap_or(Vec3::Y);
        let theta = n.y.clamp(-1.0, 1.0).acos();
        let phi = n.z.atan2(n.x).rem_euclid(std::f32::consts::TAU);
        let at = Vec2::new(
            phi / std::f32::consts::TAU * Self::COLUMNS as f32 - 0.5,
            theta / std::f32::consts::PI * Self::ROWS as f32 - 0.5,
        );
        let (c0, r0) = (at.x.floor(), at.y.floor());
        let (fx, fy) = (at.x - c0, at.y - r0);
        let row = |r: f32| (r.max(0.0) as usize).min(Self::ROWS - 1);
        let column = |c: f32| (c as i64).rem_euclid(Self::COLUMNS as i64) as usize;
        let get = |r: f32, c: f32| self.values[row(r) * Self::COLUMNS + column(c)];
        let top = get(r0, c0).lerp(get(r0, c0 + 1.0), fx);
        let bottom = get(r0 + 1.0, c0).lerp(get(r0 + 1.0, c0 + 1.0), fx);
        top.lerp(bottom, fy)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sky() -> SkyEnvironment {
        SkyEnvironment::for_scene(&crate::procedural_scene("plane").unwrap())
    }

    #[test]
    fn the_sun_lobe_puts_its_irradiance_on_a_surface_facing_it() {
        // Only the lobe: integral of L cos over the hemisphere around the sun = E_sun.
        let s = SkyEnvironment {
            zenith: Vec3::ZERO,
            horizon: Vec3::ZERO,
            ground: Vec3::ZERO,
            ..sky()
        };
        let (t, b) = tangent_frame(s.sun_direction);
        let n = 1 << 16;
        let mean: Vec3 = (0..n)
            .map(|i| {
                let l = cosine_hemisphere(sobol_2d(i, [1, 2]));
                s.radiance(t * l.x + b * l.y + s.sun_direction * l.z)
            })
            .sum::<Vec3>()
            / n as f32;
        // integral of L cos = E (k + 1) / (2 pi) * 2 pi / (k + 2) = E (k + 1) / (k + 2): the
        // lobe's own cosine (0.9 at k = 8); the cosine-weighted mean of L is that over pi.
        let e = mean * std::f32::consts::PI;
        let ratio = e / s.sun_irradiance;
        let k = s.sun_exponent;
        let expected = (k + 1.0) / (k + 2.0);
        assert!(
            (ratio - Vec3::splat(expected)).abs().max_element() < 0.005,
            "{ratio} vs {expected}"
        );
    }

    #[test]
    fn a_constant_sky_has_its_own_radiance_as_every_mean() {
        let c = Vec3::new(0.2, 0.3, 0.4);
        let s = SkyEnvironment {
            zenith: c,
            horizon: c,
            ground: c,
            sun_irradiance: Vec3::ZERO,
            ..sky()
        };
        let table = SkyIrradiance::new(&s);
        for n in [Vec3::Y, Vec3::NEG_Y, Vec3::new(0.3, -0.2, 0.9)] {
            assert!((table.mean_radiance(n) - c).abs().max_element() < 1e-5);
        }
    }

    #[test]
    fn the_table_matches_direct_integration_and_faces_see_their_own_sky() {
        let s = sky();
        let table = SkyIrradiance::new(&s);
        for n in [
            Vec3::Y,
            Vec3::NEG_Y,
            Vec3::X,
            s.sun_direction,
            Vec3::new(-0.4, 0.2, 0.7).normalize(),
        ] {
            let (t, b) = tangent_frame(n);
            let m = 1 << 14;
            let direct: Vec3 = (0..m)
                .map(|i| {
                    let l = cosine_hemisphere(sobol_2d(i, [7, 11]));
                    s.radiance(t * l.x + b * l.y + n * l.z)
                })
                .sum::<Vec3>()
                / m as f32;
            let err = (table.mean_radiance(n) - direct).abs() / direct.max(Vec3::splat(1e-3));
            assert!(
                err.max_element() < 0.05,
                "{n}: {} vs {direct}",
                table.mean_radiance(n)
            );
        }
        // An upward face sees blue sky, a downward one brown ground.
        let (up, down) = (
            table.mean_radiance(Vec3::Y),
            table.mean_radiance(Vec3::NEG_Y),
        );
        assert!(up.z > up.x && down.x > down.z, "{up} {down}");
    }

    #[test]
    fn radiance_is_finite_and_non_negative_everywhere() {
        let s = sky();
        for w in [
            Vec3::ZERO,
            Vec3::NAN,
            Vec3::Y * 1e30,
            Vec3::new(0.0, -1e-30, 0.0),
        ] {
            let l = s.radiance(w);
            assert!(l.is_finite() && l.min_element() >= 0.0, "{w}: {l}");
        }
    }
}
