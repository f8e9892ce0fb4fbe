//! [`ShaderLibrary`]: loads WGSL files from a shader root (and inline sources registered by
//! name), expands their includes, applies a variant suffix, and caches the validated modules.
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
use super::reflect::{ShaderModuleInfo, parse_and_reflect};
use super::variant::{
    SCENE_TRACE, SCENE_TRACE_HARDWARE, half_precision_variants, halve_aliases, hoist_enables,
    parse_variant, ray_tracer_variant,
};
use crate::error::{GraphError, GraphResult};

/// Loads shaders from a root directory (and inline sources registered by name), caching the
/// validated modules.
pub struct ShaderLibrary {
    root: Option<PathBuf>,
    inline: Mutex<HashMap<String, String>>,
    cache: Mutex<HashMap<String, Arc<ShaderModuleInfo>>>,
    id: u64,
    generation: AtomicU64,
}

/// Which library, and which of its sources, a plan was compiled against: unique per library
/// made in the process, and new after every [`ShaderLibrary::add_inline`]. (Files under the
/// root are read once per module and cached like inline sources: a file edited on disk is
/// read by a new library.)
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ShaderRevision {
    library: u64,
    generation: u64,
}

/// Ids of the libraries made so far (an id is never reused, unlike an address).
static NEXT_LIBRARY_ID: AtomicU64 = AtomicU64::new(0);

impl ShaderLibrary {
    /// Shaders are read from files under `root`.
    pub fn new(root: impl Into<PathBuf>) -> Self {
        Self::with_root(Some(root.into()))
    }
    /// No files; inline sources only (GPU-free tests).
    pub fn inline_only() -> Self {
        Self::with_root(None)
    }
    fn with_root(root: Option<PathBuf>) -> Self {
        Self {
            root,
            inline: Mutex::default(),
            cache: Mutex::default(),
            id: NEXT_LIBRARY_ID.fetch_add(1, Ordering::Relaxed),
            generation: AtomicU64::new(0),
        }
    }
    /// This library and the generation of its sources (see [`ShaderRevision`]).
    pub fn revision(&self) -> ShaderRevision {
        ShaderRevision {
            library: self.id,
            generation: self.generation.load(Ordering::Acquire),
        }
    }
    /// The directory shader files are read from (`None` for an inline-only library).
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
        let Some(root) = &self.root else {
            return Err(GraphError::ShaderFile {
                file: name.into(),
                message: "no inline shader of that name and no shader directory".into(),
            });
        };
        let path = root.join(name);
        std::fs::read_to_string(&path).map_err(|e| GraphError::ShaderFile {
            file: path.display().to_string(),
            message: e.to_string(),
        })
    }

    /// Every `.wgsl` file under the root, relative paths, sorted.
    pub fn files(&self) -> Vec<String> {
        let mut out = Vec::new();
        if let Some(root) = &self.root {
            collect_wgsl(root, root, &mut out);
        }
        out.sort();
        out
    }

    /// The validated module `name` (a file name, optionally with a variant suffix: see
    /// `variant.rs`), from the cache or parsed now.
    pub fn load(&self, name: &str) -> GraphResult<Arc<ShaderModuleInfo>> {
        if let Some(m) = lock(&self.cache).get(name) {
            return Ok(m.clone());
        }
        let (file, variant) = parse_variant(name)?;
        let (source, segments) = if variant.hardware_rays {
            let (source, segments) = expand(file, &|n| {
                self.read(if n == SCENE_TRACE {
                    SCENE_TRACE_HARDWARE
                } else {
                    n
                })
            })?;
            let (_, plain) = expand(file, &|n| self.read(n))?;
            if !plain.iter().any(|s| s.file() == SCENE_TRACE) {
                return Err(GraphError::ShaderFile {
                    file: name.into(),
                    message: format!(
                        "variant `RayTracer=hardware`: the file does not include `{SCENE_TRACE}`, \
                         so it traces no rays to move to the hardware tracer"
                    ),
                });
            }
            (source, segments)
        } else {
            expand(file, &|n| self.read(n))?
        };
        let source = hoist_enables(halve_aliases(name, file, source, &variant.halved)?);
        let info = Arc::new(parse_and_reflect(name, source, &segments)?);
        lock(&self.cache).insert(name.to_string(), info.clone());
        Ok(info)
    }

    /// The variant names file `name` supports besides itself: `name?Alias=f16` for each alias
    /// it declares at a 32-bit float storage format (see `variant.rs`).
    pub fn variants(&self, name: &str) -> GraphResult<Vec<String>> {
        let (source, segments) = expand(name, &|n| self.read(n))?;
        let mut out = half_precision_variants(name, &source);
        if name != SCENE_TRACE && segments.iter().any(|s| s.file() == SCENE_TRACE) {
            // Each precision traced with ray queries too (rtao at f16 on the hardware path).
            let hardware: Vec<String> = std::iter::once(name.to_string())
                .chain(out.iter().cloned())
                .map(|v| ray_tracer_variant(&v, true))
                .collect();
            out.extend(hardware);
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
