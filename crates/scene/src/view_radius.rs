//! The AO radius from what a view sees (`[ao] radius = "auto-view"`, and `"auto"` for interior
//! views): inside a building the scene-wide rule (content diagonal / 9, `radius.rs`) gives an
//! R bigger than the rooms, which no user standing in one would pick.
//!
//! Rule: R = median linear depth of the geometry the view sees / [`VIEW_RADIUS_DIVISOR`], the
//! depths taken from a probe of [`PROBE_WIDTH`] x [`PROBE_HEIGHT`] primary rays at t = 0. The
//! divisor 8 is the smallest that keeps the view rule within 2x of the scene rule on every
//! outside view of the procedural and shared scenes (0.77x to 1.86x, tests/view_radius.rs): an
//! outside view stands 1.3 content diagonals from the centre, so its median depth is about one
//! diagonal. It was chosen on those outside views, not on the interiors it is for.
//!
//! A view is an interior view when its eye is enclosed (`views::is_enclosed_at`: geometry in
//! at least 90% of the directions around it, not inside a solid), as inside a room or a
//! building: then `"auto"` uses this rule too. A view among open content (the `columns`
//! scene's own camera) is not one, and keeps the scene rule.
//! Invariant: the radius is finite and > 0 (a view that sees nothing keeps the scene rule).

use crate::camera::Camera;
use crate::model::Scene;
use crate::radius::suggested_radius;
use crate::reference::primary_hits;
use crate::views::is_enclosed_at;

/// R = median view depth / VIEW_RADIUS_DIVISOR (see the module docs).
pub const VIEW_RADIUS_DIVISOR: f32 = 8.0;
/// Probe width in rays (16:9, as most outputs).
pub const PROBE_WIDTH: u32 = 64;
/// Probe height in rays.
pub const PROBE_HEIGHT: u32 = 36;

/// What a view sees, for its radius.
#[derive(Clone, Debug, PartialEq)]
pub struct ViewRadius {
    /// R by the view rule (the scene rule's when the view sees nothing).
    pub radius: f32,
    /// Median linear depth of the probe's geometry (0 when it sees none).
    pub median_depth: f32,
    /// Share of the probe's rays that hit geometry.
    pub geometry_fraction: f32,
    /// The eye is enclosed by geometry (an interior view).
    pub interior: bool,
    /// One line saying how `radius` was derived.
    pub derivation: String,
}

/// Whether `camera` stands in an interior: its eye inside the content's bounds (checked first,
/// for free) and enclosed by geometry.
pub fn is_interior_view(scene: &Scene, camera: &Camera) -> bool {
    let content = scene.content_bounds();
    !content.is_empty()
        && camera.position.cmpge(content.min).all()
        && camera.position.cmple(content.max).all()
        && is_enclosed_at(scene, camera.position)
}

/// The view rule's radius of `scene` seen from `camera` (see the module docs).
pub fn view_radius(scene: &Scene, camera: &Camera) -> ViewRadius {
    let hits = primary_hits(scene, camera, PROBE_WIDTH, PROBE_HEIGHT, 0.0);
    let forward = camera.forward();
    let mut depths: Vec<f32> = hits
        .points
        .iter()
        .zip(&hits.valid)
        .filter(|(_, v)| **v)
        .map(|(p, _)| (*p - camera.position).dot(forward))
        .filter(|z| z.is_finite() && *z > 0.0)
        .collect();
    let geometry_fraction = depths.len() as f32 / (PROBE_WIDTH * PROBE_HEIGHT) as f32;
    let interior = is_interior_view(scene, camera);
    if depths.is_empty() {
        let s = suggested_radius(scene);
        return ViewRadius {
            radius: s.radius,
            median_depth: 0.0,
            geometry_fraction,
            interior,
            derivation: format!("the view sees no geometry: {}", s.derivation),
        };
    }
    depths.sort_by(f32::total_cmp);
    let median_depth = depths[depths.len() / 2];
    let radius = median_depth / VIEW_RADIUS_DIVISOR;
    ViewRadius {
        radius,
        median_depth,
        geometry_fraction,
        interior,
        derivation: format!(
            "the view's median depth {median_depth:.4} / {VIEW_RADIUS_DIVISOR} ({:.0}% of a \
             {PROBE_WIDTH}x{PROBE_HEIGHT} probe sees geometry{})",
            100.0 * geometry_fraction,
            if interior { "; an interior view" } else { "" }
        ),
    }
}
