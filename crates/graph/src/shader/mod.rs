//! WGSL shaders: sources from mounts, inline names and a development directory
//! ([`ShaderLibrary`], `library.rs`; [`ShaderMount`], `mount.rs`), `#include` expansion
//! (`include.rs`), storage-precision and include variants (`variant.rs`), and naga validation
//! and reflection of bindings, entry points and constants (`reflect.rs`).
//!
//! Invariant: every [`ShaderModuleInfo`] the library hands out was validated by naga, its
//! bindings were reflected from the naga module (never written by hand), and an error in it
//! names the file and line it comes from, through any includes.

mod include;
mod library;
mod mount;
mod reflect;
mod variant;

pub use library::{ShaderLibrary, ShaderRevision};
pub use mount::{IncludeVariant, ShaderMount, shader_variant};
pub use reflect::{
    ShaderBinding, ShaderBindingKind, ShaderEntry, ShaderModuleInfo, ShaderOverride, StructMember,
};
pub(crate) use reflect::{binding_type, grouped_entries};
pub use variant::storage_precision_variant;
