//! WGSL shaders: loading from the shader root, `#include`, naga validation and reflection.
//!
//! A shader file may start with lines `#include "common/name.wgsl"`; includes (and theirs) are
//! expanded depth first, each file once, before the file's own text, and errors are mapped back to the file and line
//! they come from. Every module is validated by naga before use; bind group layouts are
//! reflected from the naga module, never written by hand.
//!
//! # Storage-precision variants
//!
//! A shader name may carry a variant suffix, `file.wgsl?Alias=f16`: for a file that declares a
//! storage texture type once, on a line of its own, as written at 32-bit float precision,
//!
//! ```text
//! alias Alias = texture_storage_2d<r32float, write>;
//! ```
//!
//! and uses `Alias` for the globals it writes, `?Alias=f16` rewrites the format on that line
//! only to the 16-bit float format with the same channels (r32float -> r16float, rg32float ->
//! rg16float, rgba32float -> rgba16float); `?Alias=f32` is the file as written. Several pairs
//! join with `&`. Nothing else in the file changes, line numbers included. Naming an alias the
//! file does not declare (at a 32-bit float format) is an error: the suffix would silently do
//! nothing. [`storage_precision_variant`] builds the name; [`ShaderLibrary::variants`] lists
//! the variants a file has (the naga test validates each). The graph gives the alias no
//! meaning: a crate above it chooses which alias follows which setting.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use crate::error::{GraphError, GraphResult};

/// What a shader global binds to.
#[derive(Clone, Debug, PartialEq)]
pub enum ShaderBindingKind {
    /// `texture_2d<T>` (or `texture_depth_2d` when `depth`).
    SampledTexture {
        depth: bool,
        scalar: naga::ScalarKind,
    },
    /// `texture_storage_2d<format, access>`.
    StorageTexture {
        format: wgpu::TextureFormat,
        access: wgpu::StorageTextureAccess,
    },
    /// `sampler`: names containing `linear` get a bilinear clamp sampler, others nearest clamp.
    Sampler { linear: bool },
    /// `var<uniform>` of `size` bytes.
    Uniform { size: u64 },
    /// `var<storage>`.
    StorageBuffer { read_only: bool, size: u64 },
}

/// One `@group(g) @binding(b)` global.
#[derive(Clone, Debug, PartialEq)]
pub struct ShaderBinding {
    pub name: String,
    pub group: u32,
    pub binding: u32,
    pub kind: ShaderBindingKind,
}

/// One entry point.
#[derive(Clone, Debug, PartialEq)]
pub struct ShaderEntry {
    pub name: String,
    pub stage: naga::ShaderStage,
    pub workgroup_size: [u32; 3],
}

/// A validated, reflected WGSL module.
#[derive(Debug)]
pub struct ShaderModuleInfo {
    pub name: String,
    /// The source after include expansion (what the GPU compiles).
    pub source: String,
    /// A hash of `source`: identifies the module in the executor's pipeline cache.
    pub source_hash: u64,
    pub bindings: Vec<ShaderBinding>,
    pub entries: Vec<ShaderEntry>,
    /// The module's pipeline-overridable constants (`override` declarations), by name.
    pub overrides: Vec<ShaderOverride>,
}

/// One `override NAME: T [= default];` declaration of a module.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ShaderOverride {
    pub name: String,
    /// Whether the declaration has a default: one without must be set by every pass.
    pub has_default: bool,
}

impl ShaderModuleInfo {
    pub fn entry(&self, name: &str) -> Option<&ShaderEntry> {
        self.entries.iter().find(|e| e.name == name)
    }
    pub fn binding(&self, name: &str) -> Option<&ShaderBinding> {
        self.bindings.iter().find(|b| b.name == name)
    }
    /// Bind group layout entries reflected from the module, by group, for passes that build
    /// their own pipelines. `format_of` names the texture format bound to a global, which
    /// decides whether a float texture is declared filterable.
    pub fn layout_entries(
        &self,
        visibility: wgpu::ShaderStages,
        features: wgpu::Features,
        format_of: impl Fn(&str) -> Option<wgpu::TextureFormat>,
    ) -> Vec<(u32, Vec<wgpu::BindGroupLayoutEntry>)> {
        let mut groups: std::collections::BTreeMap<u32, Vec<wgpu::BindGroupLayoutEntry>> =
            Default::default();
        for b in &self.bindings {
            let ty = crate::pipeline::binding_type(&b.kind, format_of(&b.name), features);
            groups
                .entry(b.group)
                .or_default()
                .push(wgpu::BindGroupLayoutEntry {
                    binding: b.binding,
                    visibility,
                    ty,
                    count: None,
                });
        }
        groups.into_iter().collect()
    }
}

/// Loads shaders from a root directory (and inline sources registered by name), caching the
/// validated modules.
pub struct ShaderLibrary {
    root: Option<PathBuf>,
    inline: Mutex<HashMap<String, String>>,
    cache: Mutex<HashMap<String, Arc<ShaderModuleInfo>>>,
}

/// A piece of the expanded source: lines `start..` come from `file` starting at its line 1.
struct Segment {
    start: u32,
    file: String,
}

impl ShaderLibrary {
    /// Shaders are read from files under `root`.
    pub fn new(root: impl Into<PathBuf>) -> Self {
        Self {
            root: Some(root.into()),
            inline: Mutex::default(),
            cache: Mutex::default(),
        }
    }
    /// No files; inline sources only (GPU-free tests).
    pub fn inline_only() -> Self {
        Self {
            root: None,
            inline: Mutex::default(),
            cache: Mutex::default(),
        }
    }
    pub fn root(&self) -> Option<&Path> {
        self.root.as_deref()
    }
    /// Registers `source` under `name`; it shadows a file of the same name.
    pub fn add_inline(&self, name: &str, source: &str) {
        lock(&self.inline).insert(name.to_string(), source.to_string());
        lock(&self.cache).remove(name);
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

    /// The validated module `name` (a file name, optionally with a variant suffix: see the
    /// module docs), from the cache or parsed now.
    pub fn load(&self, name: &str) -> GraphResult<Arc<ShaderModuleInfo>> {
        if let Some(m) = lock(&self.cache).get(name) {
            return Ok(m.clone());
        }
        let (file, halved) = parse_variant(name)?;
        let (mut source, segments) = self.expand(file)?;
        for alias in halved {
            source = half_storage(&source, alias).ok_or_else(|| GraphError::Shader {
                file: file.into(),
                line: 1,
                message: format!(
                    "variant `{name}`: the file has no line `alias {alias} = \
                     texture_storage_2d<r32float, write>;` (or rg32float, rgba32float) to rewrite"
                ),
            })?;
        }
        let info = Arc::new(parse_and_reflect(name, source, &segments)?);
        lock(&self.cache).insert(name.to_string(), info.clone());
        Ok(info)
    }

    /// The variant names file `name` supports besides itself: `name?Alias=f16` for each alias
    /// it declares at a 32-bit float storage format (see the module docs).
    pub fn variants(&self, name: &str) -> GraphResult<Vec<String>> {
        let (source, _) = self.expand(name)?;
        Ok(storage_aliases(&source)
            .into_iter()
            .filter(|alias| half_storage(&source, alias).is_some())
            .map(|alias| storage_precision_variant(name, alias, true))
            .collect())
    }

    fn expand(&self, name: &str) -> GraphResult<(String, Vec<Segment>)> {
        let mut out = Expansion {
            source: String::new(),
            segments: Vec::new(),
            line: 1,
            seen: Vec::new(),
        };
        self.append(name, &mut out)?;
        Ok((out.source, out.segments))
    }

    /// Appends `name` after its includes (depth first, each file once), keeping the file's own
    /// line numbers by blanking its `#include` lines.
    fn append(&self, name: &str, out: &mut Expansion) -> GraphResult<()> {
        if out.seen.iter().any(|s| s == name) {
            return Ok(());
        }
        out.seen.push(name.to_string());
        let text = self.read(name)?;
        let mut includes = Vec::new();
        let mut body_start = 0;
        for (i, line) in text.lines().enumerate() {
            let t = line.trim();
            if let Some(rest) = t.strip_prefix("#include") {
                let inc = rest.trim().trim_matches('"').to_string();
                if inc.is_empty() {
                    return Err(GraphError::Shader {
                        file: name.into(),
                        line: i as u32 + 1,
                        message: "`#include` needs a file name in quotes".into(),
                    });
                }
                includes.push(inc);
                body_start = i + 1;
            } else if !t.is_empty() && !t.starts_with("//") {
                break;
            }
        }
        for inc in &includes {
            self.append(inc, out)?;
        }
        out.segments.push(Segment {
            start: out.line,
            file: name.to_string(),
        });
        for (i, l) in text.lines().enumerate() {
            if i >= body_start {
                out.source.push_str(l);
            }
            out.source.push('\n');
            out.line += 1;
        }
        Ok(())
    }
}

/// The expanded source being built, with where each piece came from.
struct Expansion {
    source: String,
    segments: Vec<Segment>,
    line: u32,
    seen: Vec<String>,
}

/// The name of `file`'s variant whose storage alias `alias` is at 16-bit float precision
/// (`half`) or as written: `file?alias=f16` or `file` itself.
pub fn storage_precision_variant(file: &str, alias: &str, half: bool) -> String {
    if half {
        format!("{file}?{alias}=f16")
    } else {
        file.to_string()
    }
}

/// The file name and the aliases to halve, from `file?A=f16&B=f32`.
fn parse_variant(name: &str) -> GraphResult<(&str, Vec<&str>)> {
    let Some((file, suffix)) = name.split_once('?') else {
        return Ok((name, Vec::new()));
    };
    let mut halved = Vec::new();
    for pair in suffix.split('&') {
        match pair.split_once('=') {
            Some((alias, "f16")) if is_identifier(alias) => halved.push(alias),
            Some((alias, "f32")) if is_identifier(alias) => {}
            _ => {
                return Err(GraphError::ShaderFile {
                    file: name.into(),
                    message: format!(
                        "unknown shader variant `{pair}`; a variant is `Alias=f16` or \
                         `Alias=f32`, naming a storage alias the file declares (pairs joined \
                         with `&`)"
                    ),
                });
            }
        }
    }
    Ok((file, halved))
}

fn is_identifier(s: &str) -> bool {
    s.chars()
        .next()
        .is_some_and(|c| c.is_alphabetic() || c == '_')
        && s.chars().all(|c| c.is_alphanumeric() || c == '_')
}

/// The alias named on a line `alias NAME = texture_storage_2d<...>;`, if `line` is one.
fn storage_alias(line: &str) -> Option<&str> {
    let rest = line.trim_start().strip_prefix("alias")?;
    if !rest.starts_with(char::is_whitespace) {
        return None;
    }
    let (name, ty) = rest.split_once('=')?;
    ty.trim_start()
        .starts_with("texture_storage_2d<")
        .then_some(name.trim())
}

/// Every storage alias `source` declares.
fn storage_aliases(source: &str) -> Vec<&str> {
    let mut out: Vec<&str> = source.lines().filter_map(storage_alias).collect();
    out.dedup();
    out
}

/// `source` with the format of its `alias ALIAS = texture_storage_2d<F, A>;` line(s) halved
/// (r32float -> r16float etc.); `None` when no such line names a 32-bit float format. Other
/// lines are untouched.
fn half_storage(source: &str, alias: &str) -> Option<String> {
    let mut out = String::with_capacity(source.len());
    let mut found = false;
    for line in source.split_inclusive('\n') {
        match (
            storage_alias(line) == Some(alias),
            line.find("texture_storage_2d<"),
        ) {
            (true, Some(open)) => {
                let start = open + "texture_storage_2d<".len();
                let len = line[start..].find(',')?;
                let format = line[start..start + len].trim();
                let half = match format {
                    "r32float" => "r16float",
                    "rg32float" => "rg16float",
                    "rgba32float" => "rgba16float",
                    _ => return None,
                };
                out.push_str(&line[..start]);
                out.push_str(half);
                out.push_str(&line[start + len..]);
                found = true;
            }
            _ => out.push_str(line),
        }
    }
    found.then_some(out)
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

/// Maps a line of the expanded source to (file, line in that file).
fn locate(segments: &[Segment], line: u32) -> (String, u32) {
    let seg = segments
        .iter()
        .rev()
        .find(|s| s.start <= line)
        .unwrap_or(&segments[0]);
    (seg.file.clone(), line - seg.start + 1)
}

fn parse_and_reflect(
    name: &str,
    source: String,
    segments: &[Segment],
) -> GraphResult<ShaderModuleInfo> {
    let module = naga::front::wgsl::parse_str(&source).map_err(|e| {
        let line = e.location(&source).map(|l| l.line_number).unwrap_or(1);
        let (file, line) = locate(segments, line);
        GraphError::Shader {
            file,
            line,
            message: e.message().to_string(),
        }
    })?;
    let mut validator = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    );
    validator.validate(&module).map_err(|e| {
        let line = e.location(&source).map(|l| l.line_number).unwrap_or(1);
        let (file, line) = locate(segments, line);
        let mut message = e.as_inner().to_string();
        let mut src: Option<&dyn std::error::Error> = std::error::Error::source(e.as_inner());
        while let Some(s) = src {
            message.push_str(": ");
            message.push_str(&s.to_string());
            src = s.source();
        }
        GraphError::Shader {
            file,
            line,
            message,
        }
    })?;
    let bindings = reflect_bindings(name, &module)?;
    let entries = module
        .entry_points
        .iter()
        .map(|e| ShaderEntry {
            name: e.name.clone(),
            stage: e.stage,
            workgroup_size: e.workgroup_size,
        })
        .collect();
    let source_hash = {
        use std::hash::{Hash, Hasher};
        let mut h = std::collections::hash_map::DefaultHasher::new();
        source.hash(&mut h);
        h.finish()
    };
    let overrides = module
        .overrides
        .iter()
        .filter_map(|(_, o)| {
            Some(ShaderOverride {
                name: o.name.clone()?,
                has_default: o.init.is_some(),
            })
        })
        .collect();
    Ok(ShaderModuleInfo {
        name: name.to_string(),
        source,
        source_hash,
        bindings,
        entries,
        overrides,
    })
}

fn reflect_bindings(name: &str, module: &naga::Module) -> GraphResult<Vec<ShaderBinding>> {
    let mut out = Vec::new();
    for (_, var) in module.global_variables.iter() {
        let Some(rb) = &var.binding else { continue };
        let gname = var.name.clone().unwrap_or_default();
        let unsupported = |what: &str| GraphError::Shader {
            file: name.into(),
            line: 0,
            message: format!(
                "global `{gname}`: {what} is not supported by the graph's binding reflection"
            ),
        };
        let kind = match (&module.types[var.ty].inner, var.space) {
            (
                naga::TypeInner::Image {
                    dim: naga::ImageDimension::D2,
                    arrayed: false,
                    class,
                },
                _,
            ) => match class {
                naga::ImageClass::Sampled { kind, multi: false } => {
                    ShaderBindingKind::SampledTexture {
                        depth: false,
                        scalar: *kind,
                    }
                }
                naga::ImageClass::Depth { multi: false } => ShaderBindingKind::SampledTexture {
                    depth: true,
                    scalar: naga::ScalarKind::Float,
                },
                naga::ImageClass::Storage { format, access } => {
                    let format = storage_format(*format)
                        .ok_or_else(|| unsupported(&format!("storage format {format:?}")))?;
                    let load = access.contains(naga::StorageAccess::LOAD);
                    let store = access.contains(naga::StorageAccess::STORE);
                    let access = match (load, store) {
                        (true, true) => wgpu::StorageTextureAccess::ReadWrite,
                        (true, false) => wgpu::StorageTextureAccess::ReadOnly,
                        _ => wgpu::StorageTextureAccess::WriteOnly,
                    };
                    ShaderBindingKind::StorageTexture { format, access }
                }
                _ => return Err(unsupported("a multisampled or external texture")),
            },
            (naga::TypeInner::Image { .. }, _) => {
                return Err(unsupported("a texture other than a plain texture_2d"));
            }
            (naga::TypeInner::Sampler { comparison: false }, _) => ShaderBindingKind::Sampler {
                linear: gname.contains("linear"),
            },
            (naga::TypeInner::Sampler { comparison: true }, _) => {
                return Err(unsupported("a comparison sampler"));
            }
            (ty, naga::AddressSpace::Uniform) => ShaderBindingKind::Uniform {
                size: ty.size(module.to_ctx()) as u64,
            },
            (ty, naga::AddressSpace::Storage { access }) => ShaderBindingKind::StorageBuffer {
                read_only: !access.contains(naga::StorageAccess::STORE),
                size: ty.size(module.to_ctx()) as u64,
            },
            _ => return Err(unsupported("this kind of global")),
        };
        out.push(ShaderBinding {
            name: gname,
            group: rb.group,
            binding: rb.binding,
            kind,
        });
    }
    Ok(out)
}

/// The wgpu format of a WGSL storage format.
fn storage_format(f: naga::StorageFormat) -> Option<wgpu::TextureFormat> {
    use naga::StorageFormat as S;
    use wgpu::TextureFormat as T;
    Some(match f {
        S::R32Float => T::R32Float,
        S::Rg32Float => T::Rg32Float,
        S::Rgba32Float => T::Rgba32Float,
        S::R16Float => T::R16Float,
        S::Rg16Float => T::Rg16Float,
        S::Rgba16Float => T::Rgba16Float,
        S::R32Uint => T::R32Uint,
        S::Rg32Uint => T::Rg32Uint,
        S::Rgba32Uint => T::Rgba32Uint,
        S::R32Sint => T::R32Sint,
        S::Rgba8Unorm => T::Rgba8Unorm,
        S::Rgba8Snorm => T::Rgba8Snorm,
        S::R8Unorm => T::R8Unorm,
        S::Rg8Unorm => T::Rg8Unorm,
        S::Rgba16Unorm => T::Rgba16Unorm,
        S::R16Unorm => T::R16Unorm,
        S::Rgb10a2Unorm => T::Rgb10a2Unorm,
        _ => return None,
    })
}
