//! How many pixels the radius R covers in one view: what a screen-space technique must reach
//! to see every occluder the reference counts. Measured with a coarse grid of CPU primary rays
//! (48 across, as many down as the aspect gives) through the BVH, so it needs no GPU and costs
//! a few thousand rays.
//!
//! Perspective: R_px(z) = R H / (2 tan(fov_y / 2) z) at linear depth z; orthographic:
//! R H / view height everywhere. `closest_px` is R_px at the least depth the grid sees,
//! `nearest_px` at the 2nd percentile of the view's depths (robust to a stray sliver of near
//! geometry: the figure reports quote), `median_px` at the median, `farthest_px` at the 98th
//! percentile. Invariant: `None` only when the view sees no geometry; otherwise the values are
//! finite, positive and ordered closest >= nearest >= median >= farthest.
//!
//! [`ProjectedRadius::reach_needed_px`] is what an automatic level count must reach: R at the
//! closest depth, but never more than the image's diagonal (no tap lands farther away). It is
//! `closest_px`, not `nearest_px`: on `columns` at 1280x720 the 2% of pixels nearer than the
//! 2nd percentile are a whole wall, and a pyramid sized to the percentile left that wall 0.02
//! to 0.15 brighter than its mirror image (docs/results/output-sizes.md, "At every output
//! size").

use crate::camera::{Camera, Projection};
use crate::model::Scene;
use crate::reference::CpuGBuffer;

/// R in full-resolution pixels across one view.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProjectedRadius {
    /// R in pixels at the least depth any grid ray hit: the largest on screen.
    pub closest_px: f32,
    /// R in pixels at the 2nd percentile of the hit depths (ignores a stray near sliver).
    pub nearest_px: f32,
    /// R in pixels at the median hit depth.
    pub median_px: f32,
    /// R in pixels at the 98th percentile of the hit depths: the smallest, bar outliers.
    pub farthest_px: f32,
    /// The image's diagonal in pixels.
    pub diagonal_px: f32,
}

impl ProjectedRadius {
    /// What a kernel must reach to sample all of R at every pixel of the view, in pixels:
    /// `closest_px`, capped at the image's diagonal.
    pub fn reach_needed_px(&self) -> f32 {
        self.closest_px.min(self.diagonal_px)
    }
}

/// Grid columns of the coarse primary-ray grid.
const GRID_WIDTH: u32 = 48;

/// R projected in `camera`'s view of `scene` at time 0 on a `width` x `height` image.
pub fn projected_radius(
    scene: &Scene,
    camera: &Camera,
    width: u32,
    height: u32,
    radius: f32,
) -> Option<ProjectedRadius> {
    let aspect = width.max(1) as f32 / height.max(1) as f32;
    let gw = GRID_WIDTH;
    let gh = ((gw as f32 / aspect).round() as u32).clamp(1, 4 * GRID_WIDTH);
    let grid = CpuGBuffer::trace(scene, camera, gw, gh, 0.0);
    let forward = camera.forward();
    let mut depths: Vec<f32> = grid
        .points
        .iter()
        .zip(&grid.valid)
        .filter(|(_, v)| **v)
        .map(|(p, _)| match camera.projection {
            Projection::Perspective { .. } => (*p - camera.position).dot(forward),
            Projection::Orthographic { .. } => 1.0,
        })
        .filter(|z| z.is_finite() && *z > 0.0)
        .collect();
    if depths.is_empty() {
        return None;
    }
    depths.sort_by(f32::total_cmp);
    let at = |q: f32| depths[((depths.len() - 1) as f32 * q).round() as usize];
    let px = |z: f32| -> f32 {
        let h = height.max(1) as f32;
        let v = match (camera.fov_y(), camera.projection) {
            (Some(fov), _) => radius * h / (2.0 * (0.5 * fov).tan() * z),
            (None, Projection::Orthographic { height: view, .. }) => radius * h / view.max(1e-30),
            (None, _) => radius * h,
        };
        v.min(f32::MAX)
    };
    Some(ProjectedRadius {
        closest_px: px(at(0.0)),
        nearest_px: px(at(0.02)),
        median_px: px(at(0.5)),
        farthest_px: px(at(0.98)),
        diagonal_px: (width as f32).hypot(height as f32),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::procedural_scene;
    use glam::Vec3;

    #[test]
    fn a_plane_seen_straight_down_projects_r_by_the_closed_form() {
        // Looking straight down at the 1000-unit floor from 4 units: every depth is 4.
        let mut scene = procedural_scene("plane").unwrap();
        scene.camera = Camera {
            up: Vec3::Z,
            ..Camera::perspective(Vec3::new(0.0, 4.0, 0.0), Vec3::ZERO, 1.0, 0.1, 100.0)
        };
        let p = projected_radius(&scene, &scene.camera, 256, 256, 0.5).unwrap();
        let want = 0.5 * 256.0 / (2.0 * 0.5f32.tan() * 4.0);
        for v in [p.closest_px, p.nearest_px, p.median_px, p.farthest_px] {
            assert!((v / want - 1.0).abs() < 1e-4, "{p:?} against {want}");
        }
    }

    #[test]
    fn a_nearer_camera_and_a_larger_image_need_more_pixels() {
        let scene = procedural_scene("corner").unwrap();
        let far = projected_radius(&scene, &scene.camera, 256, 256, 1.0).unwrap();
        let big = projected_radius(&scene, &scene.camera, 1280, 1280, 1.0).unwrap();
        assert!((big.median_px / far.median_px - 5.0).abs() < 1e-3);
        let mut near = scene.camera;
        near.position = near.target + (near.position - near.target) * 0.5;
        let near = projected_radius(&scene, &near, 256, 256, 1.0).unwrap();
        assert!(near.median_px > 1.5 * far.median_px, "{near:?} {far:?}");
        assert!(far.closest_px >= far.nearest_px);
        assert!(far.nearest_px >= far.median_px && far.median_px >= far.farthest_px);
    }

    #[test]
    fn the_reach_needed_is_r_at_the_closest_depth_but_never_past_the_diagonal() {
        // Straight down at the floor from 4 units: every depth is 4, so R = 0.5 needs
        // R H / (2 tan(0.5) * 4) = 16.5 px at H = 144; R = 1000 would need 32,900 px, but no
        // tap lands farther than the 256x144 image's diagonal, 293.7 px.
        let mut scene = procedural_scene("plane").unwrap();
        scene.camera = Camera {
            up: Vec3::Z,
            ..Camera::perspective(Vec3::new(0.0, 4.0, 0.0), Vec3::ZERO, 1.0, 0.1, 100.0)
        };
        let small = projected_radius(&scene, &scene.camera, 256, 144, 0.5).unwrap();
        let want = 0.5 * 144.0 / (2.0 * 0.5f32.tan() * 4.0);
        assert!(
            (small.reach_needed_px() / want - 1.0).abs() < 1e-4,
            "{small:?}"
        );
        let huge = projected_radius(&scene, &scene.camera, 256, 144, 1000.0).unwrap();
        assert_eq!(huge.reach_needed_px(), 256f32.hypot(144.0));
    }
}
