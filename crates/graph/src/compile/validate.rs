//! Compile's checks of a declaration before anything is ordered: names unique where they key
//! a resource, every read of something written (or readable before a write), and render-pass
//! attachments that agree in size, mips and kind.
//!
//! Invariant: a declaration these accept has no resource read before it is written, no two
//! imports or histories sharing a name, and attachments a render pass can use together.

use std::collections::HashMap;

use super::pass_uses;
use crate::declaration::*;
use crate::error::{GraphError, GraphResult};
use crate::resource::TextureAccess;

/// Imported resources are bound by name and histories are stored by name: two of either with
/// one name would silently share one resource.
pub(super) fn validate_names(decl: &GraphDecl) -> GraphResult<()> {
    let mut seen: HashMap<(&str, &str), ()> = HashMap::new();
    for res in &decl.resources {
        let (kind, name) = match &res.origin {
            ResourceOrigin::Imported => ("import", res.name.as_str()),
            ResourceOrigin::HistoryCurrent { history } => ("history", history.as_str()),
            _ => continue,
        };
        if seen.insert((kind, name), ()).is_some() {
            return Err(GraphError::DuplicateName {
                kind: kind.into(),
                name: name.into(),
            });
        }
    }
    Ok(())
}

pub(super) fn validate_reads(decl: &GraphDecl) -> GraphResult<()> {
    for pass in &decl.passes {
        for (r, read, _) in pass_uses(pass) {
            let Some(res) = decl.resources.get(r) else {
                return Err(GraphError::InvalidPass {
                    pass: pass.name.clone(),
                    message: format!("uses resource #{r}, which this graph does not have"),
                });
            };
            if let Some(v) = read {
                if v > res.latest_version() {
                    return Err(GraphError::InvalidPass {
                        pass: pass.name.clone(),
                        message: format!(
                            "reads `{}` version {v}, which was never produced",
                            res.name
                        ),
                    });
                }
                if v == 0 && !res.readable_before_write() {
                    return Err(GraphError::ReadOfUnwritten {
                        pass: pass.name.clone(),
                        resource: res.name.clone(),
                    });
                }
            }
        }
    }
    for res in &decl.resources {
        if let ResourceOrigin::HistoryPrevious { history } = &res.origin {
            let read = decl.passes.iter().any(|p| {
                pass_uses(p).any(|(r, rd, _)| rd.is_some() && decl.resources[r].name == res.name)
            });
            let written = decl.resources.iter().any(|c| {
                matches!(&c.origin, ResourceOrigin::HistoryCurrent { history: h } if h == history)
                    && c.latest_version() > 0
            });
            if read && !written {
                return Err(GraphError::HistoryNeverWritten {
                    resource: history.clone(),
                });
            }
        }
    }
    Ok(())
}

/// Attachments of one render pass must share a size, mip counts must be respected, depth
/// attachments must have depth formats and colour attachments must not.
pub(super) fn validate_attachments(decl: &GraphDecl) -> GraphResult<()> {
    for pass in &decl.passes {
        let mut first: Option<(String, crate::SizeClass)> = None;
        for u in &pass.textures {
            let res = &decl.resources[u.resource()];
            let Some(desc) = res.texture_desc() else {
                return Err(GraphError::InvalidPass {
                    pass: pass.name.clone(),
                    message: format!("`{}` is a buffer, used as a texture", res.name),
                });
            };
            if let Some(m) = u.mip.filter(|&m| m >= desc.mip_levels) {
                return Err(GraphError::InvalidPass {
                    pass: pass.name.clone(),
                    message: format!(
                        "mip {m} of `{}`, which has {} mip levels (allowed 0..{})",
                        res.name, desc.mip_levels, desc.mip_levels
                    ),
                });
            }
            let is_depth = desc.format.is_depth_stencil_format();
            match u.access {
                TextureAccess::DepthAttachment | TextureAccess::DepthRead if !is_depth => {
                    return Err(GraphError::FormatMismatch {
                        pass: pass.name.clone(),
                        resource: res.name.clone(),
                        expected: "a depth format".into(),
                        found: desc.format,
                    });
                }
                TextureAccess::ColorAttachment
                | TextureAccess::StorageRead
                | TextureAccess::StorageWrite
                | TextureAccess::StorageReadWrite
                    if is_depth =>
                {
                    return Err(GraphError::FormatMismatch {
                        pass: pass.name.clone(),
                        resource: res.name.clone(),
                        expected: "a colour format".into(),
                        found: desc.format,
                    });
                }
                _ => {}
            }
            if matches!(
                u.access,
                TextureAccess::ColorAttachment
                    | TextureAccess::DepthAttachment
                    | TextureAccess::DepthRead
            ) {
                match &first {
                    None => first = Some((res.name.clone(), desc.size)),
                    Some((name, size)) if *size != desc.size => {
                        return Err(GraphError::SizeMismatch {
                            pass: pass.name.clone(),
                            resource: res.name.clone(),
                            expected: format!("{size} (the size of `{name}`)"),
                            found: desc.size.to_string(),
                        });
                    }
                    _ => {}
                }
            }
        }
        if matches!(pass.kind, PassKind::Copy) {
            let src = pass
                .textures
                .iter()
                .find(|u| u.access == TextureAccess::CopySrc);
            let dst = pass
                .textures
                .iter()
                .find(|u| u.access == TextureAccess::CopyDst);
            if let (Some(s), Some(d)) = (src, dst) {
                let (rs, rd) = (&decl.resources[s.resource()], &decl.resources[d.resource()]);
                let (ds, dd) = (rs.texture_desc().copied(), rd.texture_desc().copied());
                if let (Some(ds), Some(dd)) = (ds, dd) {
                    if ds.size != dd.size {
                        return Err(GraphError::SizeMismatch {
                            pass: pass.name.clone(),
                            resource: rd.name.clone(),
                            expected: format!("{} (the size of `{}`)", ds.size, rs.name),
                            found: dd.size.to_string(),
                        });
                    }
                    if ds.format != dd.format {
                        return Err(GraphError::FormatMismatch {
                            pass: pass.name.clone(),
                            resource: rd.name.clone(),
                            expected: format!("{:?} (the format of `{}`)", ds.format, rs.name),
                            found: dd.format,
                        });
                    }
                }
            }
        }
    }
    Ok(())
}
