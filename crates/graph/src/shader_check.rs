//! Edge checks between a pass's declared uses and its shader's reflected bindings, and the
//! binding slots they resolve to (`binding_slots.rs`).
//!
//! Every shader binding must be supplied by a use of the right kind (a sampler by a
//! `PassBuilder::sampler` declaration), every named use and declared sampler must exist in
//! the shader, and storage texture formats must equal the resource's format: a mismatch is a
//! compile error naming the pass and the resource. Invariant: this is the one place where WGSL
//! names are matched to uses; what it matched is handed on as indices.

use std::sync::Arc;

use crate::binding_slots::{BindingSlot, BindingSource};
use crate::declaration::{GraphDecl, PassDecl, PassId, PassKind};
use crate::error::{GraphError, GraphResult};
use crate::resource::{BufferAccess, TextureAccess};
use crate::sampler::SamplerDesc;
use crate::shader::{ShaderBindingKind, ShaderLibrary, ShaderModuleInfo};
use crate::uniform_layout::uniform_layout_mismatch;

/// A checked pass's shader and the slot of each of its bindings (in the order of
/// `ShaderModuleInfo::bindings`).
pub(crate) struct CheckedShader {
    pub info: Arc<ShaderModuleInfo>,
    pub slots: Vec<BindingSlot>,
}

/// Checks pass `p` against its shader and resolves its bindings; `None` for passes without a
/// shader. Sampler descriptions are interned into `samplers` (the plan's distinct samplers),
/// which the slots index.
pub(crate) fn check_pass_shader(
    decl: &GraphDecl,
    p: PassId,
    shaders: &ShaderLibrary,
    samplers: &mut Vec<SamplerDesc>,
) -> GraphResult<Option<CheckedShader>> {
    let pass = &decl.passes[p.0];
    let invalid = |message: String| GraphError::InvalidPass {
        pass: pass.name.clone(),
        message,
    };
    let (shader, entries): (&str, Vec<(&str, naga::ShaderStage)>) = match &pass.kind {
        PassKind::Compute {
            shader,
            entry,
            dispatch,
        } => {
            if dispatch.is_none() {
                return Err(invalid("a compute pass needs a dispatch size (`dispatch_over`, `dispatch_size` or `dispatch_workgroups`)".into()));
            }
            (shader, vec![(entry.as_str(), naga::ShaderStage::Compute)])
        }
        PassKind::Fullscreen {
            shader,
            vertex,
            fragment,
        } => (
            shader,
            vec![
                (vertex.as_str(), naga::ShaderStage::Vertex),
                (fragment.as_str(), naga::ShaderStage::Fragment),
            ],
        ),
        PassKind::Copy | PassKind::Custom(_) => {
            if let Some(s) = pass.samplers.first() {
                return Err(GraphError::Sampler {
                    pass: pass.name.clone(),
                    binding: s.binding.clone(),
                    message: "declared with `PassBuilder::sampler`, but only compute and \
                              full-screen passes bind samplers (a custom pass makes its own); \
                              remove the declaration"
                        .into(),
                });
            }
            return Ok(None);
        }
    };
    let info = shaders.load(shader)?;
    for (name, stage) in entries {
        match info.entry(name) {
            Some(e) if e.stage == stage => {}
            _ => {
                let have: Vec<_> = info
                    .entries
                    .iter()
                    .map(|e| format!("{} ({:?})", e.name, e.stage))
                    .collect();
                return Err(invalid(format!(
                    "shader `{shader}` has no {stage:?} entry point `{name}`; it has: {}",
                    have.join(", ")
                )));
            }
        }
    }
    let mut slots = Vec::with_capacity(info.bindings.len());
    for b in &info.bindings {
        let source = check_binding_supplied(decl, pass, &info, &b.name, &b.kind, samplers)?;
        slots.push(BindingSlot {
            group: b.group,
            binding: b.binding,
            source,
        });
    }
    // Pipeline constants: each set one is declared; each declared one without a default is set.
    let declared: Vec<&str> = info.overrides.iter().map(|o| o.name.as_str()).collect();
    for c in &pass.constants {
        if !declared.contains(&c.name.as_str()) {
            return Err(invalid(format!(
                "pipeline constant `{}` is set, but shader `{shader}` declares no `override {}`; \
                 it declares: {}",
                c.name,
                c.name,
                if declared.is_empty() {
                    "none".to_string()
                } else {
                    declared.join(", ")
                }
            )));
        }
    }
    for o in info.overrides.iter().filter(|o| !o.has_default) {
        if !pass.constants.iter().any(|c| c.name == o.name) {
            return Err(invalid(format!(
                "shader `{shader}` declares `override {}` without a default: set it with \
                 `PassBuilder::constant`",
                o.name
            )));
        }
    }
    let named = pass
        .textures
        .iter()
        .filter_map(|u| u.binding.as_deref())
        .chain(pass.buffers.iter().filter_map(|u| u.binding.as_deref()))
        .chain(
            pass.uniforms
                .iter()
                .map(|u| decl.uniforms[u.0].binding.as_str()),
        );
    for name in named {
        if info.binding(name).is_none() {
            let have: Vec<_> = info.bindings.iter().map(|b| b.name.as_str()).collect();
            return Err(invalid(format!(
                "shader `{shader}` has no binding `{name}`; it has: {}",
                have.join(", ")
            )));
        }
    }
    for s in &pass.samplers {
        let is_sampler = |b: &&crate::shader::ShaderBinding| b.kind == ShaderBindingKind::Sampler;
        if info.binding(&s.binding).filter(is_sampler).is_none() {
            let have: Vec<_> = info
                .bindings
                .iter()
                .filter(is_sampler)
                .map(|b| b.name.as_str())
                .collect();
            return Err(GraphError::Sampler {
                pass: pass.name.clone(),
                binding: s.binding.clone(),
                message: format!(
                    "declared with `PassBuilder::sampler`, but shader `{shader}` has no sampler \
                     binding of that name (its samplers: {}); rename or remove the declaration",
                    if have.is_empty() {
                        "none".to_string()
                    } else {
                        have.join(", ")
                    }
                ),
            });
        }
    }
    Ok(Some(CheckedShader { info, slots }))
}

/// Checks that `pass` supplies shader binding `name` of `kind` and says where from: the first
/// use naming it, a uniform block before a buffer.
fn check_binding_supplied(
    decl: &GraphDecl,
    pass: &PassDecl,
    info: &ShaderModuleInfo,
    name: &str,
    kind: &ShaderBindingKind,
    samplers: &mut Vec<SamplerDesc>,
) -> GraphResult<BindingSource> {
    let invalid = |message: String| GraphError::InvalidPass {
        pass: pass.name.clone(),
        message,
    };
    let tex = pass
        .textures
        .iter()
        .enumerate()
        .find(|(_, u)| u.binding.as_deref() == Some(name));
    let buf_index = pass
        .buffers
        .iter()
        .position(|u| u.binding.as_deref() == Some(name));
    let buf = buf_index.map(|i| &pass.buffers[i]);
    let uni_handle = pass
        .uniforms
        .iter()
        .copied()
        .find(|u| decl.uniforms[u.0].binding == name);
    let uni = uni_handle.map(|u| &decl.uniforms[u.0]);
    // What a buffer binding binds: a uniform block of that name, else the buffer use.
    let buffer_source = || match (uni_handle, buf_index) {
        (Some(h), _) => Ok(BindingSource::Uniform(h)),
        (None, Some(i)) => {
            let u = &pass.buffers[i];
            let h = u
                .read
                .or(u.written)
                .ok_or_else(|| invalid(format!("buffer use `{name}` names no buffer version")))?;
            Ok(BindingSource::Buffer {
                buffer_use: i,
                resource: h.id as usize,
            })
        }
        (None, None) => Err(invalid(format!("nothing supplies `{name}`"))),
    };
    let missing = || {
        invalid(format!(
            "shader `{}` binds `{name}` ({kind:?}) but the pass supplies nothing for it",
            info.name
        ))
    };
    match kind {
        ShaderBindingKind::Sampler => {
            let Some(s) = pass.samplers.iter().find(|s| s.binding == name) else {
                return Err(GraphError::Sampler {
                    pass: pass.name.clone(),
                    binding: name.into(),
                    message: format!(
                        "shader `{}` binds this sampler but the pass declares none; call \
                         `PassBuilder::sampler(\"{name}\", SamplerDesc {{ filter, address }})`, \
                         e.g. with `SamplerDesc::LINEAR_CLAMP`",
                        info.name
                    ),
                });
            };
            let sampler = match samplers.iter().position(|d| *d == s.desc) {
                Some(i) => i,
                None => {
                    samplers.push(s.desc);
                    samplers.len() - 1
                }
            };
            Ok(BindingSource::Sampler { sampler })
        }
        ShaderBindingKind::SampledTexture { .. } => match tex {
            Some((i, u)) if u.access == TextureAccess::Sampled => {
                Ok(BindingSource::SampledTexture {
                    texture_use: i,
                    resource: u.resource(),
                    mip: u.mip,
                })
            }
            Some((_, u)) => Err(invalid(format!(
                "`{name}` is a sampled texture in the shader but the pass declares {:?}",
                u.access
            ))),
            None => Err(missing()),
        },
        ShaderBindingKind::StorageTexture { format, access } => {
            let Some((i, u)) = tex else {
                return Err(missing());
            };
            let res = &decl.resources[u.resource()];
            let ok_access = match access {
                wgpu::StorageTextureAccess::WriteOnly => u.access == TextureAccess::StorageWrite,
                wgpu::StorageTextureAccess::ReadOnly => u.access == TextureAccess::StorageRead,
                _ => u.access == TextureAccess::StorageReadWrite,
            };
            if !ok_access {
                return Err(invalid(format!(
                    "`{name}` is a {access:?} storage texture in the shader but the pass declares {:?}",
                    u.access
                )));
            }
            match res.texture_desc() {
                Some(d) if d.format == *format => Ok(BindingSource::StorageTexture {
                    texture_use: i,
                    resource: u.resource(),
                    mip: u.mip.unwrap_or(0),
                }),
                Some(d) => Err(GraphError::FormatMismatch {
                    pass: pass.name.clone(),
                    resource: res.name.clone(),
                    expected: format!("{format:?} (shader `{}` binding `{name}`)", info.name),
                    found: d.format,
                }),
                None => Err(invalid(format!(
                    "`{name}` is a texture in the shader but `{}` is a buffer",
                    res.name
                ))),
            }
        }
        ShaderBindingKind::Uniform { size } => {
            if let Some(u) = uni {
                if (u.initial.len() as u64) < *size {
                    return Err(invalid(format!(
                        "uniform `{name}` has {} bytes but the shader's type needs {size}",
                        u.initial.len()
                    )));
                }
                if let Some(fields) = u.fields {
                    let members = info.binding(name).map_or(&[][..], |b| &b.members[..]);
                    if let Some(why) = uniform_layout_mismatch(fields, members) {
                        return Err(invalid(format!(
                            "uniform `{name}` does not match shader `{}`'s struct: {why}",
                            info.name
                        )));
                    }
                }
                return buffer_source();
            }
            match buf {
                Some(b) if b.access == BufferAccess::Uniform => buffer_source(),
                _ => Err(missing()),
            }
        }
        ShaderBindingKind::StorageBuffer { read_only, .. } => match buf {
            Some(b) if b.access == BufferAccess::AccelerationStructure => Err(invalid(format!(
                "`{name}` is a storage buffer in the shader but the pass binds an acceleration \
                 structure to it"
            ))),
            Some(b) if *read_only != b.access.writes() => buffer_source(),
            Some(b) => Err(invalid(format!(
                "`{name}` read_only={read_only} in the shader but the pass declares {:?}",
                b.access
            ))),
            None => Err(missing()),
        },
        ShaderBindingKind::AccelerationStructure => match (buf_index, buf) {
            (Some(i), Some(b)) if b.access == BufferAccess::AccelerationStructure => {
                Ok(BindingSource::AccelerationStructure {
                    resource: b.read.map_or(0, |h| h.id as usize),
                    buffer_use: i,
                })
            }
            (Some(_), Some(_)) => Err(invalid(format!(
                "`{name}` is an acceleration structure in the shader; bind one with \
                 `PassBuilder::read_acceleration_structure`"
            ))),
            _ => Err(missing()),
        },
    }
}
