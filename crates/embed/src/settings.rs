//! The settings an application chooses, checked before any plan is built: `[ao]` TOML parsed,
//! the technique resolved and checked against the device (the radius a number, r16float
//! intermediates only where the device writes them), and which techniques an application's
//! frame can feed, for the errors that suggest them.
//!
//! Invariant: a settings key names technique, parameters, radius and precision exactly, so two
//! configs with one key build the same plan.

use std::sync::Arc;

use aograph_ao::{AoConfig, ConfiguredTechnique, GraphSettings, RadiusSetting, TechniqueRegistry};
use aograph_graph::GpuContext;

use crate::adapters::producible;
use crate::error::{EmbedError, EmbedResult};

/// The techniques of `registry` an application's frame can feed at their defaults: each
/// channel they read is one the input adapters make, and they trace no scene (the cost floor,
/// `none`, left out). Asked of the techniques, not listed by name, so a user's technique
/// registered with the embedding is offered too.
pub(crate) fn feedable_techniques(registry: &TechniqueRegistry) -> Vec<String> {
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
                && aograph_ao::contract::declared_inputs(configured.as_ref())
                    .is_ok_and(|d| d.trace_backend().is_none())
        })
        .collect()
}

/// Parses `[ao]` TOML text (the section's keys at the top level).
pub(crate) fn parse_config(text: &str, registry: &TechniqueRegistry) -> EmbedResult<AoConfig> {
    let table: toml::Table = text.parse().map_err(|e: toml::de::Error| {
        aograph_ao::AoError::Config(format!("not valid TOML: {}", e.message()))
    })?;
    Ok(AoConfig::from_table(&table, registry)?)
}

/// The configured technique, its radius and the settings key, checked against the device.
pub(crate) fn resolve(
    gpu: &GpuContext,
    registry: &TechniqueRegistry,
    config: &AoConfig,
) -> EmbedResult<(Arc<dyn ConfiguredTechnique>, f32, GraphSettings)> {
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
    let usage = wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::TEXTURE_BINDING;
    if config.intermediate_format == aograph_ao::IntermediateFormat::R16Float
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
    let technique = config.resolve(registry)?;
    Ok((technique, radius, config.graph_settings()))
}
