//! The `[ao]` config section: which technique, the shared radius, the intermediate format and
//! one `[ao.<technique>]` table of parameters per technique.
//!
//! Swapping techniques changes only `technique = "..."`; the other tables may stay. Unknown
//! keys are rejected with the nearest valid key suggested.

use std::collections::BTreeMap;
use std::sync::Arc;

use crate::error::{AoError, AoResult, unknown_key};
use crate::radius::RadiusSetting;
use crate::registry::TechniqueRegistry;
use crate::technique::ConfiguredTechnique;

/// Default technique when the config names none: MSSAO is on the speed/accuracy Pareto front of
/// every scene in the bench of docs/results/speed-and-accuracy.md (fastest non-trivial
/// technique, lower MAE than ssao, hbao and pyramid-hbao on `columns` and `corner`) and needs
/// no history.
pub const DEFAULT_TECHNIQUE: &str = "mssao";

/// Format of intermediate AO textures (raw AO before a blur, a blur's first axis, MSSAO's
/// tuples, SSDO's raw radiance; 4-channel intermediates use the 4-channel format of the same
/// precision). The accessibility output is R32Float either way.
///
/// The default is R16Float, the cheapest format that loses under 0.002 MAE for every technique:
/// on `columns` at 128x96 (tests/precision.rs) the MAE between a technique's r16float and
/// r32float outputs is at most 0.0005 (hbao, pyramid-hbao), and the MAE against the reference
/// changes by at most 0.00012. It needs r16float storage textures (not core WebGPU; the
/// renderer reports a device without them and asks for "r32float").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum IntermediateFormat {
    /// `"r32float"`: full precision; a storage format core WebGPU guarantees.
    R32Float,
    /// `"r16float"` (the default): half the bandwidth; needs r16float storage textures.
    #[default]
    R16Float,
}

impl IntermediateFormat {
    /// The wgpu format of single-channel intermediates (four-channel ones take the
    /// four-channel format of the same precision:
    /// [`crate::AoBuildContext::intermediate_rgba_format`]).
    pub fn wgpu(self) -> wgpu::TextureFormat {
        match self {
            Self::R32Float => wgpu::TextureFormat::R32Float,
            Self::R16Float => wgpu::TextureFormat::R16Float,
        }
    }
    /// Parses the config's spelling, `"r32float"` or `"r16float"`; anything else is an
    /// [`AoError::Config`] saying so.
    pub fn parse(s: &str) -> AoResult<Self> {
        match s {
            "r32float" => Ok(Self::R32Float),
            "r16float" => Ok(Self::R16Float),
            _ => Err(AoError::Config(format!(
                "intermediate_format = \"{s}\": allowed \"r32float\" or \"r16float\""
            ))),
        }
    }
}

/// The parsed `[ao]` section.
#[derive(Clone, Debug, PartialEq)]
pub struct AoConfig {
    /// Registry name of the technique that runs (`[ao] technique`; [`DEFAULT_TECHNIQUE`] when
    /// the config names none).
    pub technique: String,
    /// How the shared world-space radius R is chosen (`radius = "auto"` or a number).
    pub radius: RadiusSetting,
    /// Format of intermediate AO textures (`[ao] intermediate_format`).
    pub intermediate_format: IntermediateFormat,
    /// `[ao.<technique>]` tables.
    pub params: BTreeMap<String, toml::Table>,
}

impl Default for AoConfig {
    fn default() -> Self {
        Self {
            technique: DEFAULT_TECHNIQUE.into(),
            radius: RadiusSetting::Auto,
            intermediate_format: IntermediateFormat::default(),
            params: BTreeMap::new(),
        }
    }
}

/// What decides a technique's frame graph, compared by value: the technique, its own
/// parameter table, how R is chosen and the intermediate format. Plan caches (the renderer's,
/// the embedding's) key on it; other techniques' tables do not enter it.
#[derive(Clone, Debug, PartialEq)]
pub struct GraphSettings {
    technique: String,
    params: toml::Table,
    radius: RadiusSetting,
    intermediate_format: IntermediateFormat,
}

impl AoConfig {
    /// The settings that decide this config's graph ([`GraphSettings`]).
    pub fn graph_settings(&self) -> GraphSettings {
        GraphSettings {
            technique: self.technique.clone(),
            params: self.params_for(&self.technique),
            radius: self.radius,
            intermediate_format: self.intermediate_format,
        }
    }

    /// Parses an `[ao]` table and validates it against the registry (technique name, radius,
    /// and every technique table that is present).
    pub fn from_table(t: &toml::Table, registry: &TechniqueRegistry) -> AoResult<Self> {
        let mut c = Self::default();
        let names = registry.names();
        for (k, v) in t {
            match (k.as_str(), v) {
                ("technique", toml::Value::String(s)) => c.technique = s.clone(),
                ("technique", _) => {
                    return Err(AoError::Config(
                        "`technique` must be a string naming a technique".into(),
                    ));
                }
                ("radius", v) => c.radius = RadiusSetting::from_toml("[ao] radius", v)?,
                ("intermediate_format", toml::Value::String(s)) => {
                    c.intermediate_format = IntermediateFormat::parse(s)?
                }
                (name, toml::Value::Table(params)) if names.iter().any(|n| n == name) => {
                    c.params.insert(name.to_string(), params.clone());
                }
                (name, _) => {
                    let mut allowed = vec!["technique", "radius", "intermediate_format"];
                    allowed.extend(names.iter().map(String::as_str));
                    return Err(AoError::Config(unknown_key("ao", name, &allowed)));
                }
            }
        }
        c.validate(registry)?;
        Ok(c)
    }

    /// Checks the technique exists and every technique table parses (R is checked when it is
    /// made: [`RadiusSetting`]).
    pub fn validate(&self, registry: &TechniqueRegistry) -> AoResult<()> {
        registry.get(&self.technique)?;
        for (name, params) in &self.params {
            registry.get(name)?.check(params)?;
        }
        Ok(())
    }

    /// Parameters of `technique` (empty: all defaults).
    pub fn params_for(&self, technique: &str) -> toml::Table {
        self.params.get(technique).cloned().unwrap_or_default()
    }

    /// The chosen technique with its parameters parsed and validated, once: what a frame graph
    /// is built from.
    pub fn resolve(&self, registry: &TechniqueRegistry) -> AoResult<Arc<dyn ConfiguredTechnique>> {
        let empty = toml::Table::new();
        let params = self.params.get(&self.technique).unwrap_or(&empty);
        registry.get(&self.technique)?.clone().configure(params)
    }
}
