//! Subgraph plugins: named builders that add passes to a graph and return output handles,
//! a registry by name, and the TOML config that picks plugins and carries their parameters.
//!
//! An unknown plugin name is an error listing the known ones; parameters are deserialised into
//! the plugin's own struct (with `deny_unknown_fields`) and then range-checked by the plugin.

use std::collections::BTreeMap;
use std::sync::Arc;

use serde::Deserialize;
use serde::de::DeserializeOwned;

use crate::builder::GraphBuilder;
use crate::error::{GraphError, GraphResult};
use crate::resource::TextureHandle;

/// One parameter of a plugin, for listings and error messages.
#[derive(Clone, Debug, PartialEq)]
pub struct ParamSpec {
    pub name: &'static str,
    pub default: String,
    pub allowed: String,
    pub doc: &'static str,
}

/// Named textures flowing into or out of a plugin.
#[derive(Clone, Debug, Default)]
pub struct PluginIo {
    pub textures: Vec<(String, TextureHandle)>,
}

impl PluginIo {
    pub fn get(&self, name: &str) -> Option<TextureHandle> {
        self.textures
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, h)| *h)
    }
    pub fn with(mut self, name: &str, h: TextureHandle) -> Self {
        self.textures.push((name.to_string(), h));
        self
    }
    /// The input `name`, or an error naming the plugin and what it needs.
    pub fn require(&self, plugin: &str, name: &str) -> GraphResult<TextureHandle> {
        self.get(name).ok_or_else(|| {
            GraphError::Config(format!(
                "plugin `{plugin}` needs an input texture named `{name}`; it was given: [{}]",
                self.textures
                    .iter()
                    .map(|(n, _)| n.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            ))
        })
    }
}

/// A subgraph that adds passes to a graph.
pub trait GraphPlugin: Send + Sync {
    fn name(&self) -> &str;
    fn description(&self) -> &str;
    fn parameters(&self) -> Vec<ParamSpec>;
    /// Adds the plugin's passes, reading `inputs`, with parameters from `params`.
    fn build(
        &self,
        builder: &mut GraphBuilder,
        inputs: &PluginIo,
        params: &toml::Table,
    ) -> GraphResult<PluginIo>;
}

/// Plugins by name.
#[derive(Default, Clone)]
pub struct PluginRegistry {
    plugins: BTreeMap<String, Arc<dyn GraphPlugin>>,
}

impl PluginRegistry {
    pub fn new() -> Self {
        Self::default()
    }
    /// Adds (or replaces) a plugin under its name.
    pub fn register(&mut self, plugin: impl GraphPlugin + 'static) {
        self.plugins
            .insert(plugin.name().to_string(), Arc::new(plugin));
    }
    pub fn names(&self) -> Vec<String> {
        self.plugins.keys().cloned().collect()
    }
    /// The plugin `name`, or [`GraphError::UnknownPlugin`] listing the known ones.
    pub fn get(&self, name: &str) -> GraphResult<&Arc<dyn GraphPlugin>> {
        self.plugins
            .get(name)
            .ok_or_else(|| GraphError::UnknownPlugin {
                name: name.to_string(),
                known: self.names(),
            })
    }
    pub fn iter(&self) -> impl Iterator<Item = &Arc<dyn GraphPlugin>> {
        self.plugins.values()
    }
}

/// Deserialises a plugin's parameter table into its struct; unknown keys and wrong types are
/// errors naming the plugin and what is allowed.
pub fn parse_params<T: DeserializeOwned>(plugin: &str, params: &toml::Table) -> GraphResult<T> {
    T::deserialize(toml::Value::Table(params.clone())).map_err(|e| {
        GraphError::Config(format!(
            "parameters of `{plugin}`: {}",
            e.to_string().trim()
        ))
    })
}

/// Checks `lo <= value <= hi`, else [`GraphError::InvalidParameter`].
pub fn check_range<T: PartialOrd + std::fmt::Display>(
    owner: &str,
    name: &str,
    value: T,
    lo: T,
    hi: T,
) -> GraphResult<()> {
    if value >= lo && value <= hi {
        Ok(())
    } else {
        Err(GraphError::InvalidParameter {
            owner: owner.into(),
            name: name.into(),
            value: value.to_string(),
            allowed: format!("{lo} to {hi}"),
        })
    }
}

/// `[output]` of a graph config.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct OutputConfig {
    pub width: u32,
    pub height: u32,
}

/// One `[[plugin]]` entry: a name and its parameter table.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct PluginConfig {
    pub name: String,
    #[serde(default)]
    pub params: toml::Table,
}

/// A graph described in TOML: an output size and a chain of plugins, each fed the previous
/// one's outputs; the last plugin's outputs are exported.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct GraphConfig {
    pub output: OutputConfig,
    #[serde(rename = "plugin")]
    pub plugins: Vec<PluginConfig>,
}

impl GraphConfig {
    pub fn from_toml(text: &str) -> GraphResult<Self> {
        let c: GraphConfig = toml::from_str(text)
            .map_err(|e| GraphError::Config(e.to_string().trim().to_string()))?;
        if c.output.width == 0 || c.output.height == 0 {
            return Err(GraphError::InvalidParameter {
                owner: "output".into(),
                name: "width/height".into(),
                value: format!("{}x{}", c.output.width, c.output.height),
                allowed: "at least 1 pixel a side".into(),
            });
        }
        if c.plugins.is_empty() {
            return Err(GraphError::Config(
                "the config lists no [[plugin]]; add at least one".into(),
            ));
        }
        Ok(c)
    }
    /// Builds the chain into a fresh builder.
    pub fn build(&self, registry: &PluginRegistry) -> GraphResult<(GraphBuilder, PluginIo)> {
        let mut b = GraphBuilder::new();
        let mut io = PluginIo::default();
        for pc in &self.plugins {
            io = registry.get(&pc.name)?.build(&mut b, &io, &pc.params)?;
        }
        for (_, h) in &io.textures {
            b.export(*h);
        }
        Ok((b, io))
    }
}
