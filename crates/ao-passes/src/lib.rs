//! aograph's ambient-occlusion techniques and the building blocks they share, as render-graph
//! plugins. A technique reads g-buffer channels and writes accessibility (1 = unoccluded);
//! which one runs is chosen by name in the `[ao]` config.
//!
//! # Example
//!
//! Choosing and configuring a technique needs no GPU: the `[ao]` table is parsed and checked
//! against the registry once, and the configured technique says which g-buffer channels it
//! reads before any graph is built.
//!
//! ```
//! use aograph_ao_passes::{AoConfig, TechniqueRegistry};
//!
//! let registry = TechniqueRegistry::with_builtins();
//! let config: toml::Table = toml::from_str(
//!     r#"
//!     [ao]
//!     technique = "gtao"
//!     radius = 0.5            # world units, or "auto"
//!
//!     [ao.gtao]
//!     preset = "medium"       # 2 slices x 2 steps per side
//!     denoise_passes = 2
//!     "#,
//! )?;
//! let ao = AoConfig::from_table(config["ao"].as_table().unwrap(), &registry)?;
//! assert_eq!(ao.radius.units(), Some(0.5));
//!
//! let gtao = ao.resolve(&registry)?;
//! println!("{} reads {:?}", gtao.name(), gtao.channels());
//! let names: Vec<&str> = gtao.channels().iter().map(|c| c.name()).collect();
//! assert_eq!(names, ["linear_depth", "normals"]);
//! assert_eq!(gtao.params_table()["denoise_passes"].as_integer(), Some(2));
//!
//! // A misspelt key is refused with the nearest valid one suggested.
//! let typo: toml::Table = toml::from_str("technique = \"gtao\"\ngtao = { denoise_pases = 2 }")?;
//! let err = AoConfig::from_table(&typo, &registry).unwrap_err();
//! assert!(err.to_string().contains("did you mean `denoise_passes`?"), "{err}");
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

#![warn(missing_docs)]

pub mod blocks;
mod config;
pub mod contract;
mod error;
mod levels;
mod param;
mod radius;
mod registry;
mod resolution;
mod shader_mount;
mod spatial_options;
mod technique;
pub mod techniques;
mod temporal_option;
mod tracer;

pub use config::{AoConfig, DEFAULT_TECHNIQUE, GraphSettings, IntermediateFormat};
pub use error::{AoError, AoResult, check_one_of, check_param, nearest, unknown_key};
pub use levels::Levels;
pub use param::{ParamDesc, ParamKind};
pub use radius::{RADIUS_ALLOWED, Radius, RadiusSetting};
pub use registry::TechniqueRegistry;
pub use resolution::{HALF_DEPTH_OUTPUT, Resolution};
pub use shader_mount::{shader_library, shader_mount};
pub use spatial_options::SpatialOptions;
pub use technique::{
    ACCESSIBILITY_FORMAT, AoBuildContext, AoOutput, AoTechnique, ConfiguredTechnique,
    DynAoTechnique, ExtraOutput, RadianceEnvironment, RadianceOutput,
};
pub use temporal_option::{
    DEFAULT_TEMPORAL_FRAMES, PER_FRAME_OUTPUT, TEMPORAL_NOISE, TemporalOption,
};
pub use tracer::{RayTracer, TraceBackend, TracingSupport};
