//! The shared AO radius R, in its two forms, each checked in one place: [`RadiusSetting`], what
//! a config or a flag states (`auto` or a number of world units), and [`Radius`], the number a
//! frame graph is built with (a prepared scene resolves the setting into it).
//!
//! Invariant: a [`Radius`] is finite and greater than 0; it can only be made by
//! [`Radius::new`], whose message is the one every front end prints.

use crate::error::{AoError, AoResult};

/// What R allows, as every message says it.
pub const RADIUS_ALLOWED: &str = "\"auto\" (a fraction of the scene's size; of what the view \
     sees for an interior view), \"auto-view\" (a fraction of what the view sees) or a finite \
     number greater than 0 (world units)";

/// A world-space radius: finite and greater than 0.
#[derive(Clone, Copy, Debug, PartialEq, PartialOrd)]
pub struct Radius(f32);

impl Radius {
    /// One world unit.
    pub const UNIT: Radius = Radius(1.0);
    /// `value` as a radius, or an error naming `name` (the key or flag) and what is allowed.
    pub fn new(name: &str, value: f32) -> AoResult<Self> {
        if value.is_finite() && value > 0.0 {
            Ok(Radius(value))
        } else {
            Err(AoError::InvalidRadius {
                name: name.into(),
                value: value.to_string(),
                allowed: RADIUS_ALLOWED.into(),
            })
        }
    }
    /// The radius in world units (finite, greater than 0).
    pub fn get(self) -> f32 {
        self.0
    }
}

/// How R is chosen.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub enum RadiusSetting {
    /// A fraction of the scene's size (`aograph_scene::suggested_radius`), the default; for an
    /// interior view (an eye enclosed by geometry) the view rule of [`RadiusSetting::AutoView`].
    #[default]
    Auto,
    /// A fraction of the median depth the view sees (`aograph_scene::view_radius`), whatever
    /// the view.
    AutoView,
    /// A number of world units.
    Units(Radius),
}

impl RadiusSetting {
    /// `"auto"` or a number, as text (a flag's value); `name` is the key or flag in messages.
    pub fn parse(name: &str, text: &str) -> AoResult<Self> {
        let text = text.trim();
        if text == "auto" {
            return Ok(RadiusSetting::Auto);
        }
        if text == "auto-view" {
            return Ok(RadiusSetting::AutoView);
        }
        match text.parse::<f32>() {
            Ok(r) => Radius::new(name, r).map(RadiusSetting::Units),
            Err(_) => Err(AoError::InvalidRadius {
                name: name.into(),
                value: text.into(),
                allowed: RADIUS_ALLOWED.into(),
            }),
        }
    }
    /// `"auto"` or a number, as a TOML value (`[ao] radius`).
    pub fn from_toml(name: &str, value: &toml::Value) -> AoResult<Self> {
        match value {
            toml::Value::String(s) => Self::parse(name, s),
            toml::Value::Float(f) => Radius::new(name, *f as f32).map(RadiusSetting::Units),
            toml::Value::Integer(i) => Radius::new(name, *i as f32).map(RadiusSetting::Units),
            other => Err(AoError::InvalidRadius {
                name: name.into(),
                value: other.to_string(),
                allowed: RADIUS_ALLOWED.into(),
            }),
        }
    }
    /// The number of world units, when the setting is one.
    pub fn units(self) -> Option<f32> {
        match self {
            RadiusSetting::Auto | RadiusSetting::AutoView => None,
            RadiusSetting::Units(r) => Some(r.get()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_radius_is_finite_and_positive_and_every_form_says_so_alike() {
        assert_eq!(Radius::new("r", 0.5).map(Radius::get), Ok(0.5));
        for bad in [0.0, -1.0, f32::NAN, f32::INFINITY] {
            let e = Radius::new("--radius", bad).unwrap_err().to_string();
            assert!(e.contains("--radius") && e.contains(RADIUS_ALLOWED), "{e}");
        }
        assert_eq!(RadiusSetting::parse("r", " auto "), Ok(RadiusSetting::Auto));
        assert_eq!(
            RadiusSetting::parse("r", "2").map(RadiusSetting::units),
            Ok(Some(2.0))
        );
        let from_text = RadiusSetting::parse("[ao] radius", "-1").unwrap_err();
        let from_toml =
            RadiusSetting::from_toml("[ao] radius", &toml::Value::Integer(-1)).unwrap_err();
        assert_eq!(from_text, from_toml);
        assert!(RadiusSetting::parse("r", "big").is_err());
        assert!(RadiusSetting::from_toml("r", &toml::Value::Boolean(true)).is_err());
        assert_eq!(
            RadiusSetting::from_toml("r", &toml::Value::String("auto".into())),
            Ok(RadiusSetting::Auto)
        );
    }
}
