//! Edge checks between a pass's declared uses and its shader's reflected bindings.
//!
//! Every shader binding must be supplied by a use of the right kind (samplers are supplied by
//! the graph), every named use must exist in the shader, and storage texture formats must equal
//! the resource's format: a mismatch is a compile error naming the pass and the resource.

use std::sync::Arc;

use crate::declaration::{GraphDecl, PassDecl, PassId, PassKind};
use crate::error::{GraphError, GraphResult};
use crate::resource::{BufferAccess, TextureAccess};
use crate::shader::{ShaderBindingKind, ShaderLibrary, ShaderModuleInfo};

pub(crate) fn check_pass_shader(
    decl: &GraphDecl,
    p: PassId,
    shaders: &ShaderLibrary,
) -> GraphResult<Option<Arc<ShaderModuleInfo>>> {
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
        PassKind::Copy | PassKind::Custom(_) => return Ok(None),
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
    for b in &info.bindings {
        check_binding_supplied(decl, pass, &info, &b.name, &b.kind)?;
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
    Ok(Some(info))
}

fn check_binding_supplied(
    decl: &GraphDecl,
    pass: &PassDecl,
    info: &ShaderModuleInfo,
    name: &str,
    kind: &ShaderBindingKind,
) -> GraphResult<()> {
    let invalid = |message: String| GraphError::InvalidPass {
        pass: pass.name.clone(),
        message,
    };
    let tex = pass
        .textures
        .iter()
        .find(|u| u.binding.as_deref() == Some(name));
    let buf = pass
        .buffers
        .iter()
        .find(|u| u.binding.as_deref() == Some(name));
    let uni = pass
        .uniforms
        .iter()
        .map(|u| &decl.uniforms[u.0])
        .find(|u| u.binding == name);
    let missing = || {
        invalid(format!(
            "shader `{}` binds `{name}` ({kind:?}) but the pass supplies nothing for it",
            info.name
        ))
    };
    match kind {
        ShaderBindingKind::Sampler { .. } => Ok(()),
        ShaderBindingKind::SampledTexture { .. } => match tex {
            Some(u) if u.access == TextureAccess::Sampled => Ok(()),
            Some(u) => Err(invalid(format!(
                "`{name}` is a sampled texture in the shader but the pass declares {:?}",
                u.access
            ))),
            None => Err(missing()),
        },
        ShaderBindingKind::StorageTexture { format, access } => {
            let Some(u) = tex else { return Err(missing()) };
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
                Some(d) if d.format == *format => Ok(()),
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
                return Ok(());
            }
            match buf {
                Some(b) if b.access == BufferAccess::Uniform => Ok(()),
                _ => Err(missing()),
            }
        }
        ShaderBindingKind::StorageBuffer { read_only, .. } => match buf {
            Some(b) if *read_only != b.access.writes() => Ok(()),
            Some(b) => Err(invalid(format!(
                "`{name}` read_only={read_only} in the shader but the pass declares {:?}",
                b.access
            ))),
            None => Err(missing()),
        },
    }
}
