//! aograph's ambient-occlusion techniques and the building blocks they share, as render-graph
//! plugins. A technique reads g-buffer channels and writes accessibility (1 = unoccluded);
//! which one runs is chosen by name in the `[ao]` config.

pub mod blocks;
mod config;
mod error;
mod registry;
mod technique;
pub mod techniques;

pub use config::{nearest, unknown_key, AoConfig, IntermediateFormat, DEFAULT_TECHNIQUE};
pub use error::{check_one_of, check_param, AoError, AoResult};
pub use registry::TechniqueRegistry;
pub use technique::{spec, AoBuildContext, AoOutput, AoTechnique, DynAoTechnique, ACCESSIBILITY_FORMAT};
