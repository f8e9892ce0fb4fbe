//! The one error type of aograph-ao-passes: unknown techniques, bad parameters and graph errors, each
//! with what is allowed.

use aograph_graph::GraphError;
use thiserror::Error;

/// Everything that can go wrong configuring or building an AO technique; every message says
/// what was given and what is allowed.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum AoError {
    /// An error of the render graph, passed through (e.g. compiling a technique's passes into
    /// a plan).
    #[error(transparent)]
    Graph(#[from] GraphError),

    #[error(
        "unknown technique `{name}`{}; known techniques: {}",
        aograph_graph::did_you_mean(name, known.iter().map(String::as_str)),
        known.join(", ")
    )]
    /// No technique is registered under the name asked for (`[ao] technique`, a lookup).
    UnknownTechnique {
        /// The name asked for.
        name: String,
        /// The registered names, sorted; the message suggests the nearest.
        known: Vec<String>,
    },

    #[error("invalid parameter `{name}` = {value} for technique `{technique}`: allowed {allowed}")]
    /// A parameter (or a building block's argument) outside what it allows.
    InvalidParameter {
        /// The technique's registry name, or the pass prefix a block was given (e.g.
        /// `mssao.temporal`) when a block rejected the argument.
        technique: String,
        /// The key in `[ao.<technique>]`, or the block argument's name.
        name: String,
        /// The rejected value, as written.
        value: String,
        /// What is allowed, as [`crate::ParamDesc::allowed`] prints it (`4 to 64`).
        allowed: String,
    },

    #[error("invalid {name} = {value}: allowed {allowed}")]
    /// A radius R that is neither `auto` nor a finite number greater than 0.
    InvalidRadius {
        /// The key or flag that gave it (`[ao] radius`, `--radius`).
        name: String,
        /// The rejected value, as written.
        value: String,
        /// What R allows: [`crate::RADIUS_ALLOWED`].
        allowed: String,
    },

    #[error("invalid parameters for technique `{technique}`: {rule}")]
    /// Values that each pass their own check but break a rule across parameters (tssao's
    /// `n_smooth` at most `n_max`), or a setting the technique cannot honour
    /// (`resolution = "half"` on one that reads a channel the half g-buffer lacks).
    ParameterRule {
        /// The technique's registry name.
        technique: String,
        /// The rule broken, as a sentence for the user.
        rule: String,
    },

    /// A malformed `[ao]` section or `[ao.<technique>]` table (an unknown key, with the nearest
    /// suggested; a value of the wrong type; a bad `intermediate_format`). Holds the message.
    #[error("invalid [ao] config: {0}")]
    Config(String),

    #[error(
        "technique `{technique}` needs g-buffer channel `{channel}`, which the g-buffer did not provide"
    )]
    /// A technique or block needs a g-buffer channel the g-buffer did not write.
    MissingChannel {
        /// The technique's registry name, or the block's pass prefix.
        technique: String,
        /// The channel's name ([`aograph_frame::GBufferChannel::name`], e.g. `normals`).
        channel: String,
    },
}

/// The result of every fallible operation of aograph-ao-passes.
pub type AoResult<T> = Result<T, AoError>;

/// Checks `lo <= value <= hi` for a technique parameter.
pub fn check_param<T: PartialOrd + std::fmt::Display>(
    technique: &str,
    name: &str,
    value: T,
    lo: T,
    hi: T,
) -> AoResult<()> {
    if value >= lo && value <= hi {
        Ok(())
    } else {
        Err(AoError::InvalidParameter {
            technique: technique.into(),
            name: name.into(),
            value: value.to_string(),
            allowed: format!("{lo} to {hi}"),
        })
    }
}

/// Checks `value` is one of `allowed`.
pub fn check_one_of<T: PartialEq + std::fmt::Display>(
    technique: &str,
    name: &str,
    value: T,
    allowed: &[T],
) -> AoResult<()> {
    if allowed.contains(&value) {
        Ok(())
    } else {
        let list: Vec<String> = allowed.iter().map(|a| a.to_string()).collect();
        Err(AoError::InvalidParameter {
            technique: technique.into(),
            name: name.into(),
            value: value.to_string(),
            allowed: format!("one of {}", list.join(", ")),
        })
    }
}

/// The candidate closest to `word` by edit distance (the one rule of `aograph_graph`).
pub use aograph_graph::nearest_name as nearest;

/// The message for an unknown `key` in `[section]`, suggesting the nearest of `allowed`:
/// "unknown key `x` in \[section\]; did you mean `y`? (allowed: ...)".
pub fn unknown_key(section: &str, key: &str, allowed: &[&str]) -> String {
    let hint = nearest(key, allowed.iter().copied())
        .map(|n| format!("; did you mean `{n}`?"))
        .unwrap_or_default();
    format!(
        "unknown key `{key}` in [{section}]{hint} (allowed: {})",
        allowed.join(", ")
    )
}
