//! `levels = "auto"` or a number: how many pyramid levels a multi-resolution technique
//! builds. With `auto`, a technique takes as many levels as the radius R needs in this view and
//! no more ("model only what a scene requires"): R projected to full-resolution pixels at the
//! view's closest geometry, at most the image's diagonal (`AoBuildContext::radius_pixels`),
//! decides it, and a near camera or a larger image gets more levels. Where the projection is unknown (a graph built without a view),
//! `auto` falls back to the technique's paper default.

use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// A level count or `auto`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Levels {
    /// As many as R needs in the view (see the module docs). The default.
    #[default]
    Auto,
    /// Exactly this many levels, the full-resolution one included (the technique checks its
    /// own range).
    Fixed(u32),
}

impl Levels {
    /// The count: `Fixed(n)` is n; `Auto` is the fewest levels in `1..=max` whose reach
    /// (`reach(levels)`, full-resolution pixels) covers `radius_pixels`, `max` when none does,
    /// and `fallback` when `radius_pixels` is unknown.
    pub fn resolve(
        self,
        radius_pixels: Option<f32>,
        max: u32,
        fallback: u32,
        reach: impl Fn(u32) -> f32,
    ) -> u32 {
        match (self, radius_pixels) {
            (Levels::Fixed(n), _) => n,
            (Levels::Auto, None) => fallback,
            (Levels::Auto, Some(px)) => (1..=max).find(|&n| reach(n) >= px).unwrap_or(max),
        }
    }
}

impl Serialize for Levels {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            Levels::Auto => s.serialize_str("auto"),
            Levels::Fixed(n) => s.serialize_u32(*n),
        }
    }
}

impl<'de> Deserialize<'de> for Levels {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl serde::de::Visitor<'_> for V {
            type Value = Levels;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("\"auto\" or a whole number of levels")
            }
            fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<Levels, E> {
                if v == "auto" {
                    Ok(Levels::Auto)
                } else {
                    Err(E::custom(format!(
                        "levels = \"{v}\": allowed \"auto\" or a whole number"
                    )))
                }
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<Levels, E> {
                u32::try_from(v)
                    .map(Levels::Fixed)
                    .map_err(|_| E::custom(format!("levels = {v}: must be positive")))
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<Levels, E> {
                u32::try_from(v)
                    .map(Levels::Fixed)
                    .map_err(|_| E::custom(format!("levels = {v} is too large")))
            }
        }
        d.deserialize_any(V)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn auto_takes_the_fewest_levels_that_reach_the_radius() {
        let reach = |n: u32| 5.0 * 2f32.powi(n as i32 - 1); // MSSAO: r_max 2^(n-1)
        assert_eq!(Levels::Auto.resolve(Some(40.0), 8, 4, reach), 4);
        assert_eq!(Levels::Auto.resolve(Some(41.0), 8, 4, reach), 5);
        assert_eq!(Levels::Auto.resolve(Some(3.0), 8, 4, reach), 1);
        assert_eq!(Levels::Auto.resolve(Some(1e6), 8, 4, reach), 8);
        assert_eq!(Levels::Auto.resolve(None, 8, 4, reach), 4);
        assert_eq!(Levels::Fixed(2).resolve(Some(1e6), 8, 4, reach), 2);
    }

    #[test]
    fn auto_and_numbers_parse_and_other_strings_are_errors() {
        #[derive(Deserialize, Serialize)]
        struct P {
            levels: Levels,
        }
        let p: P = toml::from_str("levels = \"auto\"").unwrap();
        assert_eq!(p.levels, Levels::Auto);
        let p: P = toml::from_str("levels = 3").unwrap();
        assert_eq!(p.levels, Levels::Fixed(3));
        let e = toml::from_str::<P>("levels = \"many\"")
            .err()
            .unwrap()
            .to_string();
        assert!(e.contains("allowed \"auto\""), "{e}");
        let e = toml::from_str::<P>("levels = -1")
            .err()
            .unwrap()
            .to_string();
        assert!(e.contains("positive"), "{e}");
        assert_eq!(
            toml::to_string(&P {
                levels: Levels::Auto
            })
            .unwrap()
            .trim(),
            "levels = \"auto\""
        );
    }
}
