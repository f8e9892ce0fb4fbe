//! The kind of control a technique parameter gets, read from its `ParamSpec`: the allowed
//! range ("0.3 to 3", "1 to 32", "odd, 1 to 31", "greater than 0, at most 1"), the choices
//! ("\"low\", \"medium\" or \"high\""), "true or false", or "\"auto\" or 1 to 8". Whether a
//! number is an integer comes from its default, or, where the default depends on a preset,
//! from asking the technique which it accepts.
//!
//! Invariant: a control built from a kind can only produce values inside the allowed range
//! (sliders are bounded, odd counts step by two); the session still checks every value with the
//! technique before applying it, so a range this parser cannot read becomes a text field whose
//! value is rejected, with the technique's message, when it is not allowed.

use aograph_ao::ParamSpec;

/// What control a parameter gets.
#[derive(Clone, Debug, PartialEq)]
pub enum ParamKind {
    Bool,
    Choice(Vec<String>),
    Int {
        min: i64,
        max: i64,
        odd: bool,
    },
    Float {
        min: f64,
        max: f64,
    },
    /// A word (e.g. "auto") or an integer in range.
    WordOrInt {
        word: String,
        min: i64,
        max: i64,
    },
    /// Anything else: typed as text and checked by the technique.
    Text,
}

/// The quoted words of `s`.
fn quoted(s: &str) -> Vec<String> {
    s.split('"')
        .enumerate()
        .filter(|(i, _)| i % 2 == 1)
        .map(|(_, w)| w.to_string())
        .collect()
}

/// The first "A to B" of `s` with both numbers.
fn range(s: &str) -> Option<(f64, f64, bool)> {
    let words: Vec<&str> = s
        .split(|c: char| c.is_whitespace() || c == ',')
        .filter(|w| !w.is_empty())
        .collect();
    words.windows(3).find_map(|w| {
        let (a, b) = (w[0].parse::<f64>().ok()?, w[2].parse::<f64>().ok()?);
        (w[1] == "to").then_some((a, b, !w[0].contains('.') && !w[2].contains('.')))
    })
}

/// The kind of `spec`; `accepts_int` says whether the technique takes an integer value for it
/// (asked only when the default does not tell).
pub fn param_kind(spec: &ParamSpec, accepts_int: impl Fn() -> bool) -> ParamKind {
    let allowed = spec.allowed.trim();
    if allowed == "true or false" {
        return ParamKind::Bool;
    }
    let words = quoted(allowed);
    if let Some((a, b, ints)) = range(allowed) {
        if let [word] = words.as_slice() {
            if ints {
                return ParamKind::WordOrInt {
                    word: word.clone(),
                    min: a as i64,
                    max: b as i64,
                };
            }
            return ParamKind::Text;
        }
        let default_is_int = spec.default.parse::<i64>().is_ok();
        let default_is_float = !default_is_int && spec.default.parse::<f64>().is_ok();
        let int = ints && (default_is_int || (!default_is_float && accepts_int()));
        return if int {
            ParamKind::Int {
                min: a as i64,
                max: b as i64,
                odd: allowed.starts_with("odd"),
            }
        } else {
            ParamKind::Float { min: a, max: b }
        };
    }
    if !words.is_empty() {
        return ParamKind::Choice(words);
    }
    if let Some(rest) = allowed.strip_prefix("greater than 0, at most ") {
        if let Ok(max) = rest.trim().parse::<f64>() {
            // The smallest value a slider offers: well above 0, far below any useful value.
            return ParamKind::Float { min: 1e-4, max };
        }
    }
    ParamKind::Text
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(allowed: &str, default: &str) -> ParamSpec {
        ParamSpec {
            name: "p",
            default: default.into(),
            allowed: allowed.into(),
            doc: "",
        }
    }

    #[test]
    fn every_form_of_allowed_range_reads_as_its_control() {
        let no = || false;
        let yes = || true;
        assert_eq!(
            param_kind(&spec("true or false", "true"), no),
            ParamKind::Bool
        );
        assert_eq!(
            param_kind(&spec("0.3 to 3", "1.457"), no),
            ParamKind::Float { min: 0.3, max: 3.0 }
        );
        assert_eq!(
            param_kind(&spec("1 to 64", "8"), no),
            ParamKind::Int {
                min: 1,
                max: 64,
                odd: false
            }
        );
        assert_eq!(
            param_kind(&spec("odd, 1 to 31", "5"), no),
            ParamKind::Int {
                min: 1,
                max: 31,
                odd: true
            }
        );
        // An integer-looking range with a float default is a float.
        assert_eq!(
            param_kind(&spec("0 to 64", "8.0"), yes),
            ParamKind::Float {
                min: 0.0,
                max: 64.0
            }
        );
        // No default to tell: the technique is asked.
        assert_eq!(
            param_kind(&spec("0 to 60 (degrees)", "the preset's"), no),
            ParamKind::Float {
                min: 0.0,
                max: 60.0
            }
        );
        assert_eq!(
            param_kind(&spec("1 to 32", "the preset's"), yes),
            ParamKind::Int {
                min: 1,
                max: 32,
                odd: false
            }
        );
        assert_eq!(
            param_kind(
                &spec("\"low\", \"medium\", \"high\" or \"ultra\"", "\"high\""),
                no
            ),
            ParamKind::Choice(vec![
                "low".into(),
                "medium".into(),
                "high".into(),
                "ultra".into()
            ])
        );
        assert_eq!(
            param_kind(&spec("\"auto\" or 1 to 8", "\"auto\""), no),
            ParamKind::WordOrInt {
                word: "auto".into(),
                min: 1,
                max: 8
            }
        );
        assert_eq!(
            param_kind(&spec("greater than 0, at most 1", "0.03"), no),
            ParamKind::Float {
                min: 1e-4,
                max: 1.0
            }
        );
        assert_eq!(param_kind(&spec("0 to n_max", "32"), no), ParamKind::Text);
    }

    #[test]
    fn every_builtin_parameter_gets_a_control() {
        // Every parameter of every technique reads as a bounded control except the one whose
        // bound is another parameter (tssao's n_smooth, "0 to n_max"): a text field.
        let registry = aograph_ao::TechniqueRegistry::with_builtins();
        let mut text = Vec::new();
        for t in registry.iter() {
            for p in t.parameters() {
                let kind = param_kind(&p, || {
                    let mut table = toml::Table::new();
                    table.insert(p.name.into(), toml::Value::Integer(1));
                    t.check(&table).is_ok()
                });
                if kind == ParamKind::Text {
                    text.push(format!("{}.{}", t.name(), p.name));
                }
            }
        }
        assert_eq!(text, ["tssao.n_smooth"]);
    }
}
