//! The automatic AO radius (`[ao] radius = "auto"`, the default): a stated fraction of the
//! scene's size, so a scene in centimetres gets the same measurement as the same scene in
//! metres, and a 60-unit room is not measured with a radius that reaches nothing.
//!
//! Rule: R = D / 9, D the diagonal of the scene's content bounds (`Scene::content_bounds`:
//! everything but the backdrops that stand in for unbounded floors and walls). 1/9 is the
//! fraction that keeps the procedural scenes at the R they were built and measured with, 1
//! unit, on average: over the eight with content (D from 3.5 to 29.5) the geometric mean of
//! their automatic radii is 0.97 (from 0.38 for `cornell-box` to 3.3 for `columns`). A scene made
//! only of backdrops (`plane`, `wall`, `corner`: unbounded planes, which have no size) keeps
//! R = 1 unit. For real scenes it gives a 60 x 20 x 40 room R = 8.3 and a 3 x 2 x 2 building
//! 0.46. A smaller fraction (1/30) left the reference at a mean accessibility of 0.97 to 1 from
//! most views of the shared glTF scenes: a measurement of almost nothing
//! (docs/guide/scenes-and-views.md, "Your own scenes"). Invariant: the radius is finite and > 0
//! for every scene.

use crate::model::Scene;

/// R = content diagonal / AUTO_RADIUS_DIVISOR.
pub const AUTO_RADIUS_DIVISOR: f32 = 9.0;

/// The radius `auto` resolves to, and how it was derived (printed by `aograph scene info` and
/// wherever the radius is reported).
#[derive(Clone, Debug, PartialEq)]
pub struct SuggestedRadius {
    /// The AO radius R in world units: finite and > 0 (1 for a backdrop-only scene).
    pub radius: f32,
    /// One human-readable line saying how `radius` was computed (the diagonal and box size,
    /// or why it fell back to 1 unit).
    pub derivation: String,
}

/// The automatic radius of `scene` (see the module docs).
pub fn suggested_radius(scene: &Scene) -> SuggestedRadius {
    let content = scene.content_bounds();
    let d = content.diagonal();
    if content.is_empty() || !(d.is_finite() && d > 0.0) {
        return SuggestedRadius {
            radius: 1.0,
            derivation: "1 unit: the scene is only unbounded backdrop planes, which have no size"
                .into(),
        };
    }
    let radius = d / AUTO_RADIUS_DIVISOR;
    let size = content.size();
    SuggestedRadius {
        radius,
        derivation: format!(
            "the content's bounding-box diagonal {d:.4} ({:.4} x {:.4} x {:.4}{}) / {AUTO_RADIUS_DIVISOR}",
            size.x,
            size.y,
            size.z,
            if scene.instances.iter().any(|i| i.backdrop) {
                ", backdrops left out"
            } else {
                ""
            }
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{PROCEDURAL_SCENE_NAMES, procedural_scene};
    use glam::{Mat4, Vec3};

    #[test]
    fn procedural_scenes_keep_radius_one_on_average_and_backdrop_scenes_get_one_unit() {
        // Every procedural scene with content, however many there are: the divisor is tuned
        // so that a new scene does not move the average far from 1.
        let (with_content, backdrop_only): (Vec<&str>, Vec<&str>) = PROCEDURAL_SCENE_NAMES
            .iter()
            .partition(|n| !procedural_scene(n).unwrap().content_bounds().is_empty());
        assert_eq!(backdrop_only, ["plane", "wall", "corner"]);
        let log_sum: f32 = with_content
            .iter()
            .map(|n| suggested_radius(&procedural_scene(n).unwrap()).radius.ln())
            .sum();
        let geometric_mean = (log_sum / with_content.len() as f32).exp();
        assert!((geometric_mean - 1.0).abs() < 0.05, "{geometric_mean}");
        for name in backdrop_only {
            let r = suggested_radius(&procedural_scene(name).unwrap());
            assert_eq!(r.radius, 1.0, "{name}: {}", r.derivation);
        }
    }

    #[test]
    fn the_radius_scales_with_the_scene() {
        // The same scene in centimetres gets 100 times the radius.
        let metres = procedural_scene("stairs").unwrap();
        let mut centimetres = metres.clone();
        for instance in &mut centimetres.instances {
            instance.transform = Mat4::from_scale(Vec3::splat(100.0)) * instance.transform;
        }
        let (m, cm) = (suggested_radius(&metres), suggested_radius(&centimetres));
        assert!((cm.radius / m.radius - 100.0).abs() < 1e-2, "{m:?} {cm:?}");
        assert!(
            m.derivation.contains("backdrops left out"),
            "{}",
            m.derivation
        );
    }
}
