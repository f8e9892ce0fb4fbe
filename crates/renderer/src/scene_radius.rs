//! The AO radius R of a scene: a number of scene units, or `auto` (the scene's content
//! diagonal / 9, `aograph_scene::suggested_radius`), with the words that say where it came
//! from. Every command and the renderer resolve R here, so they agree.

use aograph_ao_passes::{Radius, RadiusSetting};
use aograph_scene::Scene;

/// R and its derivation for `scene` seen from its camera under `setting`: `auto` is the scene
/// rule for an open view and the view rule for an interior view (`aograph_scene::view_radius`
/// states both), `auto-view` the view rule for any view.
pub fn resolve_radius(scene: &Scene, setting: RadiusSetting) -> (Radius, String) {
    let by_view = |what: &str| {
        let v = aograph_scene::view_radius(scene, &scene.camera);
        let r = Radius::new("the automatic R", v.radius).unwrap_or(Radius::UNIT);
        (r, format!("{what}: {}", v.derivation))
    };
    match setting {
        RadiusSetting::Units(r) => (r, format!("set to {} scene units", short(r.get()))),
        RadiusSetting::AutoView => by_view("auto-view"),
        RadiusSetting::Auto if aograph_scene::is_interior_view(scene, &scene.camera) => {
            by_view("auto")
        }
        RadiusSetting::Auto => {
            let s = aograph_scene::suggested_radius(scene);
            // The suggestion is a positive diagonal / 9, or 1 for a scene without size; only
            // an underflow to 0 could fail the check, and one unit is then as good as any.
            let r = Radius::new("the automatic R", s.radius).unwrap_or(Radius::UNIT);
            (r, format!("auto: {}", s.derivation))
        }
    }
}

/// A radius printed with four significant digits.
pub fn short(r: f32) -> String {
    if r == 0.0 || !r.is_finite() {
        return format!("{r}");
    }
    let digits = (3i64 - r.abs().log10().floor() as i64).clamp(0, 8) as usize;
    format!("{r:.digits$}")
}
