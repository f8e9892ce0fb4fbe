//! Whether a technique reaches the radius R in a view: R projected to pixels
//! (`aograph_scene::projected_radius`) against how far the technique samples
//! (`DynAoTechnique::reach_pixels`). Screen-space techniques cap their kernels in pixels
//! (MSSAO's r_max per level, Pyramid HBAO's march, HBAO/SSAO's screen-radius cap), so near
//! geometry can need more than they reach; the plan summary (`aograph graph`) and the bench
//! report say so with the fraction of R reached instead of cutting R silently.

use aograph_ao_passes::{AoConfig, TechniqueRegistry};
use aograph_graph::Extent;
use aograph_scene::{ProjectedRadius, Scene, projected_radius};

use aograph_app_config::error::AppResult;
use aograph_app_config::prepared_scene::short;

/// R in pixels in a view and the technique's reach.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RadiusReach {
    /// R projected to pixels in the view: at its closest, nearest (2nd percentile), median and
    /// farthest hit depths, with the image diagonal.
    pub needed: ProjectedRadius,
    /// `None`: the technique samples R in view space, wherever it projects.
    pub reach_px: Option<f32>,
}

impl RadiusReach {
    /// The share of R reached at the view's nearest geometry (1 when it reaches all of it).
    pub fn nearest_fraction(&self) -> f32 {
        self.reach_px
            .map_or(1.0, |r| (r / self.needed.nearest_px).min(1.0))
    }

    /// The share of R reached at the view's median depth.
    pub fn median_fraction(&self) -> f32 {
        self.reach_px
            .map_or(1.0, |r| (r / self.needed.median_px).min(1.0))
    }

    /// One line for a report: what R needs here and whether the technique reaches it.
    pub fn line(&self, technique: &str) -> String {
        let needed = format!(
            "R projects to {} px at the nearest geometry, {} px at the median depth",
            short(self.needed.nearest_px),
            short(self.needed.median_px)
        );
        match self.reach_px {
            None => format!("{needed}; {technique} samples R in view space: reached everywhere"),
            Some(r) if self.nearest_fraction() >= 1.0 => {
                format!("{needed}; {technique} reaches {} px: all of R", short(r))
            }
            Some(r) => format!(
                "{needed}; {technique} reaches only {} px: {:.0}% of R at the nearest geometry, {:.0}% at the median depth",
                short(r),
                100.0 * self.nearest_fraction(),
                100.0 * self.median_fraction()
            ),
        }
    }
}

/// The reach of `ao`'s technique in `scene`'s view (its camera at t = 0) at `size`; `None`
/// when the view sees no geometry.
pub fn radius_reach(
    registry: &TechniqueRegistry,
    ao: &AoConfig,
    scene: &Scene,
    size: Extent,
) -> AppResult<Option<RadiusReach>> {
    let Some(needed) = projected_radius(
        scene,
        &scene.camera_at(0.0),
        size.width,
        size.height,
        aograph_app_config::prepared_scene::resolve_radius(scene, ao.radius)
            .0
            .get(),
    ) else {
        return Ok(None);
    };
    let reach_px = ao
        .resolve(registry)?
        .reach_pixels(size.height, Some(needed.reach_needed_px()));
    Ok(Some(RadiusReach { needed, reach_px }))
}
