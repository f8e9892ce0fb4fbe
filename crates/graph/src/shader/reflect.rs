//! Validation and reflection: a WGSL source is parsed and validated by naga, and its resource
//! bindings, entry points and pipeline-overridable constants are read from the naga module.
//! [`binding_type`] turns a reflected binding into the wgpu layout entry type it needs.
//!
//! Invariant: a [`ShaderModuleInfo`] is only made from a module naga validated, with every
//! `@group @binding` global of the module in `bindings` (in declaration order) or an error
//! naming the global the graph cannot bind; layouts are derived from it, never hand-written.

use super::include::{Segment, locate};
use crate::error::{GraphError, GraphResult};
use crate::sampler::SamplerDesc;

/// What a shader global binds to.
#[derive(Clone, Debug, PartialEq)]
pub enum ShaderBindingKind {
    /// `texture_2d<T>` (or `texture_depth_2d` when `depth`).
    SampledTexture {
        /// True for `texture_depth_2d`.
        depth: bool,
        /// The sample type `T` (float, sint or uint); float for depth textures.
        scalar: naga::ScalarKind,
    },
    /// `texture_storage_2d<format, access>`.
    StorageTexture {
        /// The texel format the WGSL type names; the bound texture must have it.
        format: wgpu::TextureFormat,
        /// Read-only, write-only or read-write, from the WGSL access mode.
        access: wgpu::StorageTextureAccess,
    },
    /// `sampler`: its filter and address mode are declared on the pass
    /// (`PassBuilder::sampler`), not read from the shader.
    Sampler,
    /// `var<uniform>` of `size` bytes.
    Uniform {
        /// Size of the uniform's type in bytes (the minimum binding size).
        size: u64,
    },
    /// `acceleration_structure` (WGSL's `enable wgpu_ray_query;`): a TLAS.
    AccelerationStructure,
    /// `var<storage>`.
    StorageBuffer {
        /// True for `var<storage, read>`.
        read_only: bool,
        /// Size of the global's type in bytes (for a runtime-sized array, of its fixed part).
        size: u64,
    },
}

/// One `@group(g) @binding(b)` global.
#[derive(Clone, Debug, PartialEq)]
pub struct ShaderBinding {
    /// The global's WGSL name: what a pass's uses name as their binding.
    pub name: String,
    /// Its `@group` index.
    pub group: u32,
    /// Its `@binding` index within the group.
    pub binding: u32,
    /// What it binds to.
    pub kind: ShaderBindingKind,
    /// For a `var<uniform>` of struct type, its members' names and byte offsets in order
    /// (what a typed uniform block is checked against: `PassBuilder::uniform_struct`); empty
    /// otherwise.
    pub members: Vec<StructMember>,
}

/// One member of a uniform struct as naga lays it out.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct StructMember {
    /// Its WGSL name.
    pub name: String,
    /// Its byte offset in the struct.
    pub offset: u32,
    /// Its size in bytes (a `vec3<f32>` is 12, though it is aligned to 16).
    pub size: u32,
}

/// One entry point.
#[derive(Clone, Debug, PartialEq)]
pub struct ShaderEntry {
    /// The entry point's function name.
    pub name: String,
    /// Vertex, fragment or compute.
    pub stage: naga::ShaderStage,
    /// `@workgroup_size` (x, y, z) of a compute entry point; zeros for other stages.
    pub workgroup_size: [u32; 3],
    /// Bytes of `var<workgroup>` the entry point uses, as WebGPU counts them against
    /// `maxComputeWorkgroupStorageSize`: each variable's size rounded up to 16.
    pub workgroup_storage: u32,
}

/// A validated, reflected WGSL module.
#[derive(Debug)]
pub struct ShaderModuleInfo {
    /// The name the module was loaded by: the file name, variant suffix included.
    pub name: String,
    /// The source after include expansion (what the GPU compiles).
    pub source: String,
    /// A hash of `source`: identifies the module in the executor's pipeline cache.
    pub source_hash: u64,
    /// Every `@group @binding` global, in declaration order.
    pub bindings: Vec<ShaderBinding>,
    /// Every entry point, in declaration order.
    pub entries: Vec<ShaderEntry>,
    /// The module's pipeline-overridable constants (`override` declarations), by name.
    pub overrides: Vec<ShaderOverride>,
}

/// One `override NAME: T [= default];` declaration of a module.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ShaderOverride {
    /// The constant's WGSL name, which `PassBuilder::constant` sets.
    pub name: String,
    /// Whether the declaration has a default: one without must be set by every pass.
    pub has_default: bool,
}

impl ShaderModuleInfo {
    /// The entry point named `name`, if the module has one.
    pub fn entry(&self, name: &str) -> Option<&ShaderEntry> {
        self.entries.iter().find(|e| e.name == name)
    }
    /// The `@group @binding` global named `name`, if the module has one.
    pub fn binding(&self, name: &str) -> Option<&ShaderBinding> {
        self.bindings.iter().find(|b| b.name == name)
    }
    /// Bind group layout entries reflected from the module, by group, for passes that build
    /// their own pipelines. `format_of` names the texture format bound to a global, which
    /// decides whether a float texture is declared filterable. Samplers are declared
    /// non-filtering; see [`Self::layout_entries_with_samplers`] for filtering ones.
    pub fn layout_entries(
        &self,
        visibility: wgpu::ShaderStages,
        features: wgpu::Features,
        format_of: impl Fn(&str) -> Option<wgpu::TextureFormat>,
    ) -> Vec<(u32, Vec<wgpu::BindGroupLayoutEntry>)> {
        self.layout_entries_with_samplers(visibility, features, format_of, |_| None)
    }
    /// [`Self::layout_entries`] where `sampler_of` gives the sampler a pass binds to a
    /// `sampler` global (a linear one needs a filtering layout entry).
    pub fn layout_entries_with_samplers(
        &self,
        visibility: wgpu::ShaderStages,
        features: wgpu::Features,
        format_of: impl Fn(&str) -> Option<wgpu::TextureFormat>,
        sampler_of: impl Fn(&str) -> Option<SamplerDesc>,
    ) -> Vec<(u32, Vec<wgpu::BindGroupLayoutEntry>)> {
        grouped_entries(
            visibility,
            self.bindings.iter().map(|b| {
                let ty = binding_type(&b.kind, format_of(&b.name), sampler_of(&b.name), features);
                (b.group, b.binding, ty)
            }),
        )
    }
}

/// Layout entries by bind group (ascending), each group's in the order given: `entries` are
/// (group, binding, type).
pub(crate) fn grouped_entries(
    visibility: wgpu::ShaderStages,
    entries: impl IntoIterator<Item = (u32, u32, wgpu::BindingType)>,
) -> Vec<(u32, Vec<wgpu::BindGroupLayoutEntry>)> {
    let mut groups: std::collections::BTreeMap<u32, Vec<wgpu::BindGroupLayoutEntry>> =
        Default::default();
    for (group, binding, ty) in entries {
        groups
            .entry(group)
            .or_default()
            .push(wgpu::BindGroupLayoutEntry {
                binding,
                visibility,
                ty,
                count: None,
            });
    }
    groups.into_iter().collect()
}

/// The layout entry type of a binding of `kind`: `format` is the texture bound to it (whether
/// a float texture is filterable on this device), `sampler` the sampler bound to it (a linear
/// one filters; none counts as non-filtering).
pub(crate) fn binding_type(
    kind: &ShaderBindingKind,
    format: Option<wgpu::TextureFormat>,
    sampler: Option<SamplerDesc>,
    features: wgpu::Features,
) -> wgpu::BindingType {
    match kind {
        ShaderBindingKind::SampledTexture { depth, scalar } => {
            let sample_type = match (depth, scalar) {
                (true, _) => wgpu::TextureSampleType::Depth,
                (false, naga::ScalarKind::Uint) => wgpu::TextureSampleType::Uint,
                (false, naga::ScalarKind::Sint) => wgpu::TextureSampleType::Sint,
                (false, _) => {
                    let filterable = format.is_some_and(|f| {
                        !f.is_depth_stencil_format()
                            && f.sample_type(None, Some(features))
                                == Some(wgpu::TextureSampleType::Float { filterable: true })
                    });
                    wgpu::TextureSampleType::Float { filterable }
                }
            };
            wgpu::BindingType::Texture {
                sample_type,
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            }
        }
        ShaderBindingKind::StorageTexture { format, access } => wgpu::BindingType::StorageTexture {
            access: *access,
            format: *format,
            view_dimension: wgpu::TextureViewDimension::D2,
        },
        ShaderBindingKind::Sampler => wgpu::BindingType::Sampler(
            sampler.map_or(wgpu::SamplerBindingType::NonFiltering, |s| s.binding_type()),
        ),
        ShaderBindingKind::Uniform { size } => wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: wgpu::BufferSize::new(*size),
        },
        ShaderBindingKind::StorageBuffer { read_only, .. } => wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage {
                read_only: *read_only,
            },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        ShaderBindingKind::AccelerationStructure => wgpu::BindingType::AccelerationStructure {
            vertex_return: false,
        },
    }
}

/// Parses and validates `source` (the expansion of `name`, pieces from `segments`) and
/// reflects it; errors name the file and line of the piece they are in.
pub(super) fn parse_and_reflect(
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
    let validated = validator.validate(&module).map_err(|e| {
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
        .enumerate()
        .map(|(i, e)| ShaderEntry {
            name: e.name.clone(),
            stage: e.stage,
            workgroup_size: e.workgroup_size,
            workgroup_storage: workgroup_storage(&module, validated.get_entry_point(i)),
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

/// The workgroup memory an entry point uses: the `var<workgroup>` globals it (or a function it
/// calls) touches, each rounded up to 16 bytes (WebGPU's rule).
fn workgroup_storage(module: &naga::Module, entry: &naga::valid::FunctionInfo) -> u32 {
    module
        .global_variables
        .iter()
        .filter(|(h, v)| v.space == naga::AddressSpace::WorkGroup && !entry[*h].is_empty())
        .map(|(_, v)| {
            module.types[v.ty]
                .inner
                .size(module.to_ctx())
                .next_multiple_of(16)
        })
        .sum()
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
            (naga::TypeInner::Sampler { comparison: false }, _) => ShaderBindingKind::Sampler,
            (
                naga::TypeInner::AccelerationStructure {
                    vertex_return: false,
                },
                _,
            ) => ShaderBindingKind::AccelerationStructure,
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
        let members = match (&module.types[var.ty].inner, var.space) {
            (naga::TypeInner::Struct { members, .. }, naga::AddressSpace::Uniform) => members
                .iter()
                .map(|m| StructMember {
                    name: m.name.clone().unwrap_or_default(),
                    offset: m.offset,
                    size: module.types[m.ty].inner.size(module.to_ctx()),
                })
                .collect(),
            _ => Vec::new(),
        };
        out.push(ShaderBinding {
            name: gname,
            group: rb.group,
            binding: rb.binding,
            kind,
            members,
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
