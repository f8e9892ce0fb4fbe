//! The one error type of aograph-ao: unknown techniques, bad parameters and graph errors, each
//! with what is allowed.

use aograph_graph::GraphError;
use thiserror::Error;

#[derive(Debug, Error, Clone, PartialEq)]
pub enum AoError {
    #[error(transparent)]
    Graph(#[from] GraphError),

    #[error(
        "unknown technique `{name}`{}; known techniques: {}",
        aograph_graph::did_you_mean(name, known.iter().map(String::as_str)),
        known.join(", ")
    )]
    UnknownTechnique { name: String, known: Vec<String> },

    #[error("invalid parameter `{name}` = {value} for technique `{technique}`: allowed {allowed}")]
    InvalidParameter {
        technique: String,
        name: String,
        value: String,
        allowed: String,
    },

    #[error("invalid {name} = {value}: allowed {allowed}")]
    InvalidRadius {
        name: String,
        value: String,
        allowed: String,
    },

    #[error("invalid parameters for technique `{technique}`: {rule}")]
    ParameterRule { technique: String, rule: String },

    #[error("invalid [ao] config: {0}")]
    Config(String),

    #[error(
        "technique `{technique}` needs g-buffer channel `{channel}`, which the g-buffer did not provide"
    )]
    MissingChannel { technique: String, channel: String },
}

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
