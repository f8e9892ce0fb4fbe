//! One typed description per technique parameter: what values it takes (a range, a choice, a
//! flag, or a word-or-number), what it means, and (once registered) its default. Everything
//! about a parameter that is not its Rust type comes from here: validation and its messages,
//! the `aograph techniques` listing, the viewer's controls and the contract test
//! (`crate::contract`).
//!
//! Invariant: a value passes [`ParamDesc::check`] exactly when it lies in what
//! [`ParamDesc::allowed`] prints, so the message a user reads and the rule applied are one.

use std::fmt::Write as _;

/// What values a parameter takes.
#[derive(Clone, Debug, PartialEq)]
pub enum ParamKind {
    /// A number in `[min, max]` (`(min, max]` with `above_min`); `integer` for whole numbers,
    /// `odd` for odd whole numbers.
    Range {
        /// Smallest value allowed (itself excluded with `above_min`).
        min: f64,
        /// Largest value allowed.
        max: f64,
        /// Whole numbers only: a TOML integer (`4.0` is refused).
        integer: bool,
        /// Odd whole numbers only (e.g. a filter width in taps).
        odd: bool,
        /// `min` itself is excluded: the range is `(min, max]`.
        above_min: bool,
    },
    /// One of these words.
    Choice(&'static [&'static str]),
    /// `true` or `false`.
    Bool,
    /// A word (e.g. `auto`) or a whole number in `[min, max]`.
    WordOrNumber {
        /// The one word accepted besides numbers (e.g. `auto`).
        word: &'static str,
        /// Smallest whole number allowed.
        min: f64,
        /// Largest whole number allowed.
        max: f64,
    },
}

/// One parameter of a technique.
#[derive(Clone, Debug, PartialEq)]
pub struct ParamDesc {
    /// The key in `[ao.<technique>]`.
    pub name: &'static str,
    /// What values it takes: what [`ParamDesc::check`] applies and [`ParamDesc::allowed`]
    /// prints.
    pub kind: ParamKind,
    /// One line of meaning.
    pub doc: &'static str,
    /// What leaving the key out means when the parameter has no default value of its own (an
    /// override such as "the preset's"); `None` for a parameter with a default.
    pub unset: Option<&'static str>,
    /// The default, filled from the technique's `Params::default()` when the technique lists
    /// its parameters (`DynAoTechnique::parameters`); `None` for an unset override.
    pub default: Option<toml::Value>,
}

impl ParamDesc {
    fn new(name: &'static str, kind: ParamKind) -> Self {
        Self {
            name,
            kind,
            doc: "",
            unset: None,
            default: None,
        }
    }
    /// A whole number in `min..=max`.
    pub fn int(name: &'static str, min: u32, max: u32) -> Self {
        Self::new(
            name,
            ParamKind::Range {
                min: min as f64,
                max: max as f64,
                integer: true,
                odd: false,
                above_min: false,
            },
        )
    }
    /// An odd whole number in `min..=max`.
    pub fn odd(name: &'static str, min: u32, max: u32) -> Self {
        let mut d = Self::int(name, min, max);
        if let ParamKind::Range { odd, .. } = &mut d.kind {
            *odd = true;
        }
        d
    }
    /// A number in `[min, max]`.
    pub fn float(name: &'static str, min: f64, max: f64) -> Self {
        Self::new(
            name,
            ParamKind::Range {
                min,
                max,
                integer: false,
                odd: false,
                above_min: false,
            },
        )
    }
    /// A number in `(min, max]`.
    pub fn float_above(name: &'static str, min: f64, max: f64) -> Self {
        let mut d = Self::float(name, min, max);
        if let ParamKind::Range { above_min, .. } = &mut d.kind {
            *above_min = true;
        }
        d
    }
    /// One of `options` (serde names of an enum).
    pub fn choice(name: &'static str, options: &'static [&'static str]) -> Self {
        Self::new(name, ParamKind::Choice(options))
    }
    /// `true` or `false`.
    pub fn flag(name: &'static str) -> Self {
        Self::new(name, ParamKind::Bool)
    }
    /// `word` or a whole number in `min..=max`.
    pub fn word_or_int(name: &'static str, word: &'static str, min: u32, max: u32) -> Self {
        Self::new(
            name,
            ParamKind::WordOrNumber {
                word,
                min: min as f64,
                max: max as f64,
            },
        )
    }
    /// The one line of meaning.
    pub fn doc(mut self, doc: &'static str) -> Self {
        self.doc = doc;
        self
    }
    /// An override without a default of its own: leaving it out means `meaning`.
    pub fn unset(mut self, meaning: &'static str) -> Self {
        self.unset = Some(meaning);
        self
    }

    /// True for whole-number parameters (ranges of integers and word-or-number).
    pub fn is_integer(&self) -> bool {
        match self.kind {
            ParamKind::Range { integer, .. } => integer,
            ParamKind::WordOrNumber { .. } => true,
            _ => false,
        }
    }

    /// What the parameter allows, as error messages and the listing print it: "4 to 64",
    /// "odd, 1 to 31", "greater than 0, at most 1", "\"low\" or \"high\"", "true or false",
    /// "\"auto\" or 1 to 8".
    pub fn allowed(&self) -> String {
        match &self.kind {
            ParamKind::Range {
                min,
                max,
                odd,
                above_min,
                ..
            } => {
                if *above_min {
                    format!("greater than {min}, at most {max}")
                } else if *odd {
                    format!("odd, {min} to {max}")
                } else {
                    format!("{min} to {max}")
                }
            }
            ParamKind::Choice(options) => quoted_list(options),
            ParamKind::Bool => "true or false".into(),
            ParamKind::WordOrNumber { word, min, max } => format!("\"{word}\" or {min} to {max}"),
        }
    }

    /// The default as the listing prints it (`16`, `0.025`, `"high"`, `the preset's`).
    pub fn default_text(&self) -> String {
        match (&self.default, self.unset) {
            // Parameters are f32: print the f32, not its widened f64 (0.03, not 0.0299999...).
            (Some(toml::Value::Float(f)), _) => format!("{:?}", *f as f32),
            (Some(v), _) => v.to_string(),
            (None, Some(meaning)) => meaning.to_string(),
            (None, None) => String::new(),
        }
    }

    /// Checks `value` against the description; the error is [`ParamDesc::allowed`].
    pub fn check(&self, value: &toml::Value) -> Result<(), String> {
        let number = || {
            value
                .as_float()
                .or_else(|| value.as_integer().map(|i| i as f64))
        };
        let ok = match &self.kind {
            ParamKind::Range {
                min,
                max,
                integer,
                odd,
                above_min,
            } => match (number(), integer) {
                (Some(_), true) if value.as_integer().is_none() => false,
                (Some(v), _) => {
                    let low = if *above_min { v > *min } else { v >= *min };
                    let odd_ok = !odd || value.as_integer().is_some_and(|i| i % 2 == 1);
                    low && v <= *max && odd_ok
                }
                (None, _) => false,
            },
            ParamKind::Choice(options) => value.as_str().is_some_and(|s| options.contains(&s)),
            ParamKind::Bool => value.as_bool().is_some(),
            ParamKind::WordOrNumber { word, min, max } => match value {
                toml::Value::String(s) => s == word,
                toml::Value::Integer(i) => (*min..=*max).contains(&(*i as f64)),
                _ => false,
            },
        };
        match (&self.kind, value.as_str()) {
            _ if ok => Ok(()),
            (ParamKind::Choice(options), Some(word)) => Err(format!(
                "{}{}",
                self.allowed(),
                aograph_graph::did_you_mean(word, options.iter().copied())
            )),
            _ => Err(self.allowed()),
        }
    }
}

/// `"a", "b" or "c"`.
fn quoted_list(options: &[&str]) -> String {
    let mut s = String::new();
    for (i, o) in options.iter().enumerate() {
        if i > 0 {
            s.push_str(if i + 1 == options.len() { " or " } else { ", " });
        }
        let _ = write!(s, "\"{o}\"");
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(text: &str) -> toml::Value {
        format!("v = {text}").parse::<toml::Table>().unwrap()["v"].clone()
    }

    #[test]
    fn allowed_text_is_what_check_applies() {
        let samples = ParamDesc::int("samples", 4, 64);
        assert_eq!(samples.allowed(), "4 to 64");
        for ok in ["4", "64", "17"] {
            assert_eq!(samples.check(&v(ok)), Ok(()), "{ok}");
        }
        for bad in ["3", "65", "4.0", "\"8\"", "true"] {
            assert_eq!(samples.check(&v(bad)), Err("4 to 64".into()), "{bad}");
        }
        let width = ParamDesc::odd("filter_width", 1, 31);
        assert_eq!(width.allowed(), "odd, 1 to 31");
        assert!(width.check(&v("5")).is_ok() && width.check(&v("4")).is_err());
        let bias = ParamDesc::float("bias", 0.0, 0.5);
        assert_eq!(bias.allowed(), "0 to 0.5");
        assert!(bias.check(&v("0")).is_ok() && bias.check(&v("0.5")).is_ok());
        assert!(bias.check(&v("nan")).is_err() && bias.check(&v("0.5000001")).is_err());
        let eps = ParamDesc::float_above("epsilon", 0.0, 1.0);
        assert_eq!(eps.allowed(), "greater than 0, at most 1");
        assert!(eps.check(&v("0")).is_err() && eps.check(&v("1e-9")).is_ok());
        let preset = ParamDesc::choice("preset", &["low", "medium", "high"]);
        assert_eq!(preset.allowed(), "\"low\", \"medium\" or \"high\"");
        assert!(preset.check(&v("\"high\"")).is_ok() && preset.check(&v("\"epic\"")).is_err());
        assert_eq!(ParamDesc::flag("blur").allowed(), "true or false");
        let levels = ParamDesc::word_or_int("levels", "auto", 1, 8);
        assert_eq!(levels.allowed(), "\"auto\" or 1 to 8");
        assert!(levels.check(&v("\"auto\"")).is_ok() && levels.check(&v("8")).is_ok());
        assert!(levels.check(&v("9")).is_err() && levels.check(&v("\"all\"")).is_err());
    }

    #[test]
    fn defaults_print_as_f32_or_the_unset_meaning() {
        let mut d = ParamDesc::float("bias", 0.0, 0.5);
        d.default = Some(toml::Value::Float(0.025f32 as f64));
        assert_eq!(d.default_text(), "0.025");
        let slices = ParamDesc::int("slices", 1, 32).unset("the preset's");
        assert_eq!(slices.default_text(), "the preset's");
    }
}
