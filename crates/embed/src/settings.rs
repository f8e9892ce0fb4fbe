//! The settings an application chooses, checked before any plan is built: `[ao]` TOML parsed,
//! the technique resolved and checked against the device (the radius a number, r16float
//! intermediates only where the device writes them) and against the frame inputs the
//! application supplies, and which techniques an application's frame can feed, for the errors
//! that suggest them.
//!
//! Invariant: a settings key names technique, parameters, radius and precision exactly, so two
//! configs with one key build the same plan.

use std::any::TypeId;
use std::sync::Arc;

use aograph_ao_passes::{
    AoConfig, ConfiguredTechnique, GraphSettings, RadiusSetting, TechniqueRegistry,
};
use aograph_frame::{DeclaredInputs, InputBindings, SceneAcceleration, SceneBvh, ViewBlock};
use aograph_graph::GpuContext;

use crate::adapters::producible;
use crate::error::{EmbedError, EmbedResult};

/// The techniques of `registry` an application's frame can feed at their defaults: each
/// channel they read is one the input adapters make, and they read no frame input beyond the
/// View block (no scene to trace, no lighting; the cost floor,
/// `none`, left out). Asked of the techniques, not listed by name, so a user's technique
/// registered with the embedding is offered too.
pub fn feedable_techniques(registry: &TechniqueRegistry) -> Vec<String> {
    registry
        .names()
        .into_iter()
        .filter(|name| {
            let Ok(technique) = registry.get(name) else {
                return false;
            };
            let Ok(configured) = technique.clone().configure(&toml::Table::new()) else {
                return false;
            };
            !configured.is_baseline()
                && configured.channels().iter().all(producible)
                && aograph_ao_passes::contract::declared_inputs(configured.as_ref())
                    .is_ok_and(|d| d.iter().all(|(t, _)| t == TypeId::of::<ViewBlock>()))
        })
        .collect()
}

/// `[ao]` TOML text (the section's keys at the top level, as [`crate::AmbientOcclusion::from_toml`]
/// takes them) parsed and checked for aograph's built-in techniques without a device: the
/// technique and each parameter known and in range, the radius a number, and the technique fed
/// by depth, normals and motion alone. An application checks settings where its user types them
/// (a bevy component, a config file) and hands the frame's settings over later; what only the
/// device decides (r16float intermediates) is checked when they are applied.
pub fn check_settings_toml(text: &str) -> EmbedResult<AoConfig> {
    let registry = TechniqueRegistry::with_builtins();
    let config = parse_config(text, &registry)?;
    check_settings(&registry, &config, &ViewBlockOnly)?;
    Ok(config)
}

/// The frame inputs settings are checked against: what an [`crate::AmbientOcclusion`] has bound,
/// or, before there is one, the View block alone (every embedding supplies it).
pub(crate) trait SuppliedInputs {
    /// The name of the first input `declared` lists that is not supplied.
    fn missing(&self, declared: &DeclaredInputs) -> Option<&'static str>;
}

impl SuppliedInputs for InputBindings {
    fn missing(&self, declared: &DeclaredInputs) -> Option<&'static str> {
        InputBindings::missing(self, declared)
    }
}

/// The View block, which every embedding supplies, and nothing else.
struct ViewBlockOnly;

impl SuppliedInputs for ViewBlockOnly {
    fn missing(&self, declared: &DeclaredInputs) -> Option<&'static str> {
        declared
            .iter()
            .find(|(t, _)| *t != TypeId::of::<ViewBlock>())
            .map(|(_, name)| name)
    }
}

/// Parses `[ao]` TOML text (the section's keys at the top level).
pub(crate) fn parse_config(text: &str, registry: &TechniqueRegistry) -> EmbedResult<AoConfig> {
    let table: toml::Table = text.parse().map_err(|e: toml::de::Error| {
        aograph_ao_passes::AoError::Config(format!("not valid TOML: {}", e.message()))
    })?;
    Ok(AoConfig::from_table(&table, registry)?)
}

/// The configured technique, its radius and the settings key, checked against the device and
/// against the frame inputs `inputs` supplies (a technique reading one the application cannot
/// give is refused here, naming it, not at its first frame).
pub(crate) fn resolve(
    gpu: &GpuContext,
    registry: &TechniqueRegistry,
    config: &AoConfig,
    inputs: &InputBindings,
) -> EmbedResult<(Arc<dyn ConfiguredTechnique>, f32, GraphSettings)> {
    let (technique, radius) = check_settings(registry, config, inputs)?;
    let usage = wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::TEXTURE_BINDING;
    if config.intermediate_format == aograph_ao_passes::IntermediateFormat::R16Float
        && !gpu.supports(wgpu::TextureFormat::R16Float, usage)
    {
        return Err(EmbedError::InvalidSetting {
            name: "intermediate_format".into(),
            value: "\"r16float\"".into(),
            allowed: format!(
                "\"r32float\" on this device ({}): it cannot write r16float storage textures \
                 (enable TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES on the device if the adapter \
                 has it)",
                gpu.describe()
            ),
        });
    }
    Ok((technique, radius, config.graph_settings()))
}

/// The configured technique and its radius, checked without a device: the technique and its
/// parameters resolved, the radius a number, every channel one the adapters make, every frame
/// input one `inputs` supplies.
pub(crate) fn check_settings(
    registry: &TechniqueRegistry,
    config: &AoConfig,
    inputs: &dyn SuppliedInputs,
) -> EmbedResult<(Arc<dyn ConfiguredTechnique>, f32)> {
    config.validate(registry)?;
    let radius = match config.radius {
        RadiusSetting::Units(r) => r.get(),
        setting @ (RadiusSetting::Auto | RadiusSetting::AutoView) => {
            return Err(EmbedError::InvalidSetting {
                name: "radius".into(),
                value: if setting == RadiusSetting::Auto {
                    "\"auto\"".into()
                } else {
                    "\"auto-view\"".into()
                },
                allowed: "a positive number in the view matrix's units (the automatic radii \
                          size R from aograph's own scene, which an application's frame does \
                          not have)"
                    .into(),
            });
        }
    };
    let technique = config.resolve(registry)?;
    if let Some(c) = technique.channels().iter().find(|c| !producible(*c)) {
        return Err(EmbedError::UnsupportedTechnique {
            technique: technique.name().into(),
            what: format!("the g-buffer channel `{}`", c.name()),
            fix: match technique.dropping_channel(c) {
                Some(setting) => format!("set {setting}"),
                None => format!(
                    "choose a technique that reads depth, normals and motion only ({})",
                    feedable_techniques(registry).join(", ")
                ),
            },
        });
    }
    let declared = aograph_ao_passes::contract::declared_inputs(technique.as_ref())?;
    check_inputs(registry, technique.name(), &declared, inputs)?;
    Ok((technique, radius))
}

/// Refuses `technique` when it declared a frame input `inputs` does not supply, naming it.
pub(crate) fn check_inputs(
    registry: &TechniqueRegistry,
    technique: &str,
    declared: &DeclaredInputs,
    inputs: &dyn SuppliedInputs,
) -> EmbedResult<()> {
    let Some(input) = inputs.missing(declared) else {
        return Ok(());
    };
    let feedable = feedable_techniques(registry).join(", ");
    let tracing = declared.contains::<SceneBvh>() || declared.contains::<SceneAcceleration>();
    Err(EmbedError::UnsupportedTechnique {
        technique: technique.into(),
        what: if tracing {
            "the scene's triangles (it traces rays through a BVH or acceleration structures)".into()
        } else {
            format!("the frame input {input}")
        },
        fix: if tracing {
            format!("choose a screen-space technique ({feedable})")
        } else {
            format!(
                "supply it with AmbientOcclusion::bind_input before choosing the technique, or \
                 choose one that reads only the depth, normals and motion given ({feedable})"
            )
        },
    })
}
