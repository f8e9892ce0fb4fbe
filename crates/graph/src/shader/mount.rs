//! [`ShaderMount`]: a named set of WGSL sources that one crate (or the application) brings to a
//! [`ShaderLibrary`](super::ShaderLibrary), and the include variants it defines.
//!
//! A mount's file names are the names shaders load and `#include` each other by (paths such as
//! `"ao/gtao/ao.wgsl"`), so a technique in one mount includes a block of another
//! (`#include "common/view.wgsl"`) as long as both are mounted. The graph knows no file of
//! aograph's: aograph's crates each make the mount of the folder they own, from the tables
//! their shader crate embeds at build time.
//!
//! Invariant: a mount never reads a file; its sources are the strings it was given.

use std::borrow::Cow;

/// A set of WGSL sources under the names shaders load them by, and who brings them.
#[derive(Clone, Debug)]
pub struct ShaderMount {
    owner: Cow<'static, str>,
    files: Vec<(Cow<'static, str>, Cow<'static, str>)>,
    include_variants: Vec<IncludeVariant>,
}

/// A variant that swaps one included file for another: `file.wgsl?KEY=SWAPPED` is `file.wgsl`
/// with `include` replaced by `replacement` wherever it is included; `?KEY=WRITTEN` is the
/// file as written. Asking for it of a file that does not include `include` is an error (the
/// suffix would do nothing). The crate that owns both files defines it (aograph's ray tracer:
/// `RayTracer=hardware` swaps the compute-BVH trace for the ray-query one).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct IncludeVariant {
    /// The variant key, as written after `?`.
    pub key: &'static str,
    /// The value meaning "as written" (`compute`).
    pub written: &'static str,
    /// The value that swaps the include (`hardware`).
    pub swapped: &'static str,
    /// The included file the variant replaces.
    pub include: &'static str,
    /// The file included in its place.
    pub replacement: &'static str,
}

impl IncludeVariant {
    /// The name of `file`'s variant with the include swapped (`swap`) or as written (`file`).
    pub fn of(&self, file: &str, swap: bool) -> String {
        if swap {
            shader_variant(file, self.key, self.swapped)
        } else {
            file.to_string()
        }
    }
}

/// `file` with one more `key=value` pair: `file?key=value`, or `file?...&key=value` when
/// `file` is a variant already (so variants compose).
pub fn shader_variant(file: &str, key: &str, value: &str) -> String {
    let sep = if file.contains('?') { '&' } else { '?' };
    format!("{file}{sep}{key}={value}")
}

impl ShaderMount {
    /// An empty mount brought by `owner` (a crate or application name, used in errors).
    pub fn new(owner: impl Into<Cow<'static, str>>) -> Self {
        Self {
            owner: owner.into(),
            files: Vec::new(),
            include_variants: Vec::new(),
        }
    }

    /// Adds embedded `(name, source)` pairs, such as a table `aograph-shaders` generates or
    /// the application's own `include_str!`s.
    pub fn with_files(mut self, files: &'static [(&'static str, &'static str)]) -> Self {
        self.files.extend(
            files
                .iter()
                .map(|(name, source)| (Cow::Borrowed(*name), Cow::Borrowed(*source))),
        );
        self
    }

    /// Adds one source under `name` (text made at run time, say).
    pub fn with_file(
        mut self,
        name: impl Into<Cow<'static, str>>,
        source: impl Into<Cow<'static, str>>,
    ) -> Self {
        self.files.push((name.into(), source.into()));
        self
    }

    /// Adds an include variant this mount defines.
    pub fn with_include_variant(mut self, variant: IncludeVariant) -> Self {
        self.include_variants.push(variant);
        self
    }

    /// Who brings this mount.
    pub fn owner(&self) -> &str {
        &self.owner
    }

    /// The names of its files, in the order added.
    pub fn names(&self) -> impl Iterator<Item = &str> {
        self.files.iter().map(|(n, _)| n.as_ref())
    }

    /// The source of `name`, if this mount has it.
    pub fn source(&self, name: &str) -> Option<&str> {
        self.files
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, s)| s.as_ref())
    }

    /// The include variants this mount defines.
    pub fn include_variants(&self) -> &[IncludeVariant] {
        &self.include_variants
    }

    /// The folders its files sit in (first path component), for messages: `common/, ao/`.
    pub(super) fn folders(&self) -> String {
        let mut folders: Vec<&str> = self
            .names()
            .map(|n| n.split_once('/').map_or("", |(f, _)| f))
            .collect();
        folders.sort_unstable();
        folders.dedup();
        if folders.is_empty() {
            return "no files".into();
        }
        folders
            .iter()
            .map(|f| {
                if f.is_empty() {
                    "./".to_string()
                } else {
                    format!("{f}/")
                }
            })
            .collect::<Vec<_>>()
            .join(", ")
    }
}
