//! The built-in techniques, one file each; registering one is one line here.

pub mod none;

use crate::registry::TechniqueRegistry;

pub(crate) fn register_builtins(r: &mut TechniqueRegistry) {
    r.register(none::NoAo);
}
