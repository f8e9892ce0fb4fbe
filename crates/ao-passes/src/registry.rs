//! The technique registry: every built-in technique by name, and room for the user's own.

use std::collections::BTreeMap;
use std::sync::Arc;

use crate::error::{AoError, AoResult};
use crate::technique::{AoTechnique, DynAoTechnique};
use crate::techniques;

/// Techniques by registry name.
#[derive(Clone, Default)]
pub struct TechniqueRegistry {
    techniques: BTreeMap<&'static str, Arc<dyn DynAoTechnique>>,
}

impl TechniqueRegistry {
    /// An empty registry.
    pub fn empty() -> Self {
        Self::default()
    }
    /// Every built-in technique.
    pub fn with_builtins() -> Self {
        let mut r = Self::empty();
        for t in techniques::builtins() {
            r.techniques.insert(t.name(), t);
        }
        r
    }
    /// Adds (or replaces) a technique under its name.
    pub fn register<T: AoTechnique>(&mut self, technique: T) {
        self.techniques.insert(T::NAME, Arc::new(technique));
    }
    /// The registered names, sorted: what `[ao] technique` accepts.
    pub fn names(&self) -> Vec<String> {
        self.techniques.keys().map(|s| s.to_string()).collect()
    }
    /// The technique `name`, or an error listing the known ones.
    pub fn get(&self, name: &str) -> AoResult<&Arc<dyn DynAoTechnique>> {
        self.techniques
            .get(name)
            .ok_or_else(|| AoError::UnknownTechnique {
                name: name.to_string(),
                known: self.names(),
            })
    }
    /// Every registered technique, in name order.
    pub fn iter(&self) -> impl Iterator<Item = &Arc<dyn DynAoTechnique>> {
        self.techniques.values()
    }
}
