//! [`ShaderLibrary`]: WGSL sources from mounts (sets of sources compiled into the crates that
//! own them, the application's included), inline sources registered by name, and, for hot edits
//! during development, a directory whose files shadow both; expands their includes, applies a
//! variant suffix, and caches the validated modules.
//!
//! A name is looked up in this order: inline sources, the directory (when one is set and holds
//! the file), the mounts. A name found nowhere is an error that lists the mounts, so a crate
//! whose shaders were not mounted is named.
//!
//! Invariant: the cache holds, per name (variant suffix included), the module as validated
//! from the current sources; registering an inline source drops every cached module (any of
//! them may include it or be its variant) and moves the library to a new [`ShaderRevision`],
//! which the compile cache keys its plans by.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};

use super::include::expand;
use super::mount::{IncludeVariant, ShaderMount};
use super::reflect::{ShaderModuleInfo, parse_and_reflect};
use super::variant::{half_precision_variants, halve_aliases, hoist_enables, parse_variant};
use crate::error::{GraphError, GraphResult};

/// WGSL sources from mounts, inline sources and an optional directory, caching the validated
/// modules.
pub struct ShaderLibrary {
    root: Option<PathBuf>,
    mounts: Mutex<Vec<ShaderMount>>,
    inline: Mutex<HashMap<String, String>>,
    cache: Mutex<HashMap<String, Arc<ShaderModuleInfo>>>,
    id: u64,
    generation: AtomicU64,
}

/// Which library, and which of its sources, a plan was compiled against: unique per library
/// made in the process, and new after every [`ShaderLibrary::add_inline`] and
/// [`ShaderLibrary::mount`]. (Files under a directory are read once per module and cached like
/// inline sources: a file edited on disk is read by a new library.)
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ShaderRevision {
    library: u64,
    generation: u64,
}

/// Ids of the libraries made so far (an id is never reused, unlike an address).
static NEXT_LIBRARY_ID: AtomicU64 = AtomicU64::new(0);

impl ShaderLibrary {
    /// Shaders are read from files under `root` only (a development directory, or tests).
    pub fn new(root: impl Into<PathBuf>) -> Self {
        Self::with_root(Some(root.into()), Vec::new())
    }
    /// No files; inline sources only (GPU-free tests).
    pub fn inline_only() -> Self {
        Self::with_root(None, Vec::new())
    }
    /// Shaders from `mounts` (see [`ShaderLibrary::mount`]). Two mounts giving one name is an
    /// error naming both.
    pub fn from_mounts(mounts: impl IntoIterator<Item = ShaderMount>) -> GraphResult<Self> {
        let lib = Self::with_root(None, Vec::new());
        for m in mounts {
            lib.mount(m)?;
        }
        Ok(lib)
    }
    /// This library with `dir`'s files shadowing the mounted ones of the same name: hot edits
    /// of a shader folder during development (aograph reads `AOGRAPH_SHADERS`). A name the
    /// directory lacks still comes from the mounts.
    pub fn with_directory_override(mut self, dir: impl Into<PathBuf>) -> Self {
        self.root = Some(dir.into());
        self
    }
    fn with_root(root: Option<PathBuf>, mounts: Vec<ShaderMount>) -> Self {
        Self {
            root,
            mounts: Mutex::new(mounts),
            inline: Mutex::default(),
            cache: Mutex::default(),
            id: NEXT_LIBRARY_ID.fetch_add(1, Ordering::Relaxed),
            generation: AtomicU64::new(0),
        }
    }
    /// Adds `mount`'s sources (an application's own shaders beside aograph's, say). Mounting
    /// again a mount of the same owner replaces it; a name another owner's mount already gives
    /// is an error naming both (use [`ShaderLibrary::add_inline`] to replace a file on purpose).
    /// Cached modules are dropped, as for an inline source.
    pub fn mount(&self, mount: ShaderMount) -> GraphResult<()> {
        let mut mounts = lock(&self.mounts);
        mounts.retain(|m| m.owner() != mount.owner());
        for name in mount.names() {
            if let Some(other) = mounts.iter().find(|m| m.source(name).is_some()) {
                return Err(GraphError::ShaderFile {
                    file: name.into(),
                    message: format!(
                        "mounted by both `{}` and `{}`; a mount may not replace another's file \
                         (rename it, or replace it on purpose with `ShaderLibrary::add_inline`)",
                        other.owner(),
                        mount.owner()
                    ),
                });
            }
        }
        mounts.push(mount);
        drop(mounts);
        lock(&self.cache).clear();
        self.generation.fetch_add(1, Ordering::AcqRel);
        Ok(())
    }
    /// The owners of the mounted sources, in mount order.
    pub fn mounts(&self) -> Vec<String> {
        lock(&self.mounts)
            .iter()
            .map(|m| m.owner().to_string())
            .collect()
    }
    fn include_variants(&self) -> Vec<IncludeVariant> {
        lock(&self.mounts)
            .iter()
            .flat_map(|m| m.include_variants().iter().copied())
            .collect()
    }
    /// This library and the generation of its sources (see [`ShaderRevision`]).
    pub fn revision(&self) -> ShaderRevision {
        ShaderRevision {
            library: self.id,
            generation: self.generation.load(Ordering::Acquire),
        }
    }
    /// The directory shader files are read from first (`None` without one).
    pub fn root(&self) -> Option<&Path> {
        self.root.as_deref()
    }
    /// Registers `source` under `name`; it shadows a file of the same name. Every cached
    /// module is dropped (one may include `name`, or be a variant of it) and plans compiled
    /// against the old sources are no longer compile-cache hits.
    pub fn add_inline(&self, name: &str, source: &str) {
        lock(&self.inline).insert(name.to_string(), source.to_string());
        lock(&self.cache).clear();
        self.generation.fetch_add(1, Ordering::AcqRel);
    }

    fn read(&self, name: &str) -> GraphResult<String> {
        if let Some(s) = lock(&self.inline).get(name) {
            return Ok(s.clone());
        }
        if let Some(root) = &self.root {
            let path = root.join(name);
            match std::fs::read_to_string(&path) {
                Ok(s) => return Ok(s),
                Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
                    return Err(GraphError::ShaderFile {
                        file: path.display().to_string(),
                        message: e.to_string(),
                    });
                }
                Err(_) => {}
            }
        }
        let mounts = lock(&self.mounts);
        if let Some(s) = mounts.iter().find_map(|m| m.source(name)) {
            return Ok(s.to_string());
        }
        let mut places: Vec<String> = mounts
            .iter()
            .map(|m| format!("`{}` ({})", m.owner(), m.folders()))
            .collect();
        if let Some(root) = &self.root {
            places.insert(0, format!("the directory {}", root.display()));
        }
        let message = if places.is_empty() {
            "no inline shader of that name, and no shaders mounted or directory set".to_string()
        } else {
            format!(
                "in none of {}; mount the shaders of the crate that owns it \
                 (`ShaderLibrary::mount`) or register it with `add_inline`",
                places.join(", ")
            )
        };
        Err(GraphError::ShaderFile {
            file: name.into(),
            message,
        })
    }

    /// Every mounted name and `.wgsl` file under the directory (relative paths), sorted, each
    /// once.
    pub fn files(&self) -> Vec<String> {
        let mut out: Vec<String> = lock(&self.mounts)
            .iter()
            .flat_map(|m| m.names().map(str::to_string).collect::<Vec<_>>())
            .collect();
        if let Some(root) = &self.root {
            collect_wgsl(root, root, &mut out);
        }
        out.sort();
        out.dedup();
        out
    }

    /// The validated module `name` (a file name, optionally with a variant suffix: see
    /// `variant.rs`), from the cache or parsed now.
    pub fn load(&self, name: &str) -> GraphResult<Arc<ShaderModuleInfo>> {
        if let Some(m) = lock(&self.cache).get(name) {
            return Ok(m.clone());
        }
        let (file, variant) = parse_variant(name, &self.include_variants())?;
        let (source, segments) = if variant.swaps.is_empty() {
            expand(file, &|n| self.read(n))?
        } else {
            let swaps = &variant.swaps;
            let (source, segments) = expand(file, &|n| {
                self.read(
                    swaps
                        .iter()
                        .find(|v| v.include == n)
                        .map_or(n, |v| v.replacement),
                )
            })?;
            let (_, plain) = expand(file, &|n| self.read(n))?;
            if let Some(v) = swaps
                .iter()
                .find(|v| !plain.iter().any(|s| s.file() == v.include))
            {
                return Err(GraphError::ShaderFile {
                    file: name.into(),
                    message: format!(
                        "variant `{}={}`: the file does not include `{}`, the file this \
                         variant replaces with `{}`, so the suffix would change nothing",
                        v.key, v.swapped, v.include, v.replacement
                    ),
                });
            }
            (source, segments)
        };
        let source = hoist_enables(halve_aliases(name, file, source, &variant.halved)?);
        let info = Arc::new(parse_and_reflect(name, source, &segments)?);
        lock(&self.cache).insert(name.to_string(), info.clone());
        Ok(info)
    }

    /// The variant names file `name` supports besides itself: `name?Alias=f16` for each alias
    /// it declares at a 32-bit float storage format, and each of those with every mounted
    /// include variant whose include it has (see `variant.rs`).
    pub fn variants(&self, name: &str) -> GraphResult<Vec<String>> {
        let (source, segments) = expand(name, &|n| self.read(n))?;
        let mut out = half_precision_variants(name, &source);
        for v in self.include_variants() {
            if name != v.include && segments.iter().any(|s| s.file() == v.include) {
                // Each precision with the include swapped too (rtao at f16 on ray queries).
                let swapped: Vec<String> = std::iter::once(name.to_string())
                    .chain(out.iter().cloned())
                    .map(|f| v.of(&f, true))
                    .collect();
                out.extend(swapped);
            }
        }
        Ok(out)
    }
}

fn lock<T>(m: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|p| p.into_inner())
}

fn collect_wgsl(root: &Path, dir: &Path, out: &mut Vec<String>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let p = e.path();
        if p.is_dir() {
            collect_wgsl(root, &p, out);
        } else if p.extension().is_some_and(|x| x == "wgsl") {
            if let Ok(rel) = p.strip_prefix(root) {
                out.push(rel.to_string_lossy().replace('\\', "/"));
            }
        }
    }
}
