//! aograph's ambient-occlusion techniques and the building blocks they share, as render-graph
//! plugins. A technique reads g-buffer channels and writes accessibility (1 = unoccluded);
//! which one runs is chosen by name in the `[ao]` config.

pub mod blocks;
mod config;
pub mod contract;
mod error;
mod levels;
mod param;
mod radius;
mod registry;
mod resolution;
mod technique;
pub mod techniques;
mod temporal_option;

pub use config::{AoConfig, DEFAULT_TECHNIQUE, IntermediateFormat, nearest, unknown_key};
pub use error::{AoError, AoResult, check_one_of, check_param};
pub use levels::Levels;
pub use param::{ParamDesc, ParamKind};
pub use radius::{RADIUS_ALLOWED, Radius, RadiusSetting};
pub use registry::TechniqueRegistry;
pub use resolution::{HALF_DEPTH_OUTPUT, Resolution};
pub use technique::{
    ACCESSIBILITY_FORMAT, AoBuildContext, AoOutput, AoTechnique, ConfiguredTechnique,
    DeclaredInputs, DynAoTechnique, RadianceEnvironment, RadianceOutput,
};
pub use temporal_option::{
    DEFAULT_TEMPORAL_FRAMES, PER_FRAME_OUTPUT, TEMPORAL_NOISE, TemporalOption,
};
