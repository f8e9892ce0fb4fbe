//! Imported resources: textures and buffers the caller provides by name, checked against what
//! the plan declares before anything is recorded.
//!
//! Invariant: an imported texture bound to a frame has the declared format and size, and every
//! usage the plan needs of it (a target created without `RENDER_ATTACHMENT`, say, is an error
//! naming the missing flag, not a validation error at submit). Names are unique per plan
//! (compile rejects duplicates), so one name binds one texture.

use std::collections::HashMap;

use crate::custom::BoundTexture;
use crate::declaration::ResourceDecl;
use crate::error::{GraphError, GraphResult};
use crate::resource::{Extent, TextureDesc};

/// Textures and buffers provided for imported resources, by name.
#[derive(Default)]
pub(crate) struct ImportTable {
    textures: HashMap<String, BoundTexture>,
    buffers: HashMap<String, wgpu::Buffer>,
}

impl ImportTable {
    pub fn set_texture(&mut self, name: &str, texture: wgpu::Texture, serial: u64) {
        self.textures
            .insert(name.to_string(), BoundTexture::new(texture, serial));
    }
    pub fn set_buffer(&mut self, name: &str, buffer: wgpu::Buffer) {
        self.buffers.insert(name.to_string(), buffer);
    }
    /// The texture for `res`, checked against its descriptor at `extent` and the `usage` the
    /// plan needs.
    pub fn texture(
        &self,
        res: &ResourceDecl,
        desc: &TextureDesc,
        extent: Extent,
        usage: wgpu::TextureUsages,
    ) -> GraphResult<&BoundTexture> {
        let t = self
            .textures
            .get(&res.name)
            .ok_or_else(|| GraphError::MissingResource {
                resource: res.name.clone(),
                message: "imported texture not provided; call Executor::import_texture".into(),
            })?;
        if t.texture.format() != desc.format {
            return Err(GraphError::FormatMismatch {
                pass: "import".into(),
                resource: res.name.clone(),
                expected: format!("{:?}", desc.format),
                found: t.texture.format(),
            });
        }
        if t.extent != extent {
            return Err(GraphError::SizeMismatch {
                pass: "import".into(),
                resource: res.name.clone(),
                expected: extent.to_string(),
                found: t.extent.to_string(),
            });
        }
        let has = t.texture.usage();
        if !has.contains(usage) {
            return Err(GraphError::ImportUsage {
                resource: res.name.clone(),
                missing: format!("{:?}", usage - has),
                has: format!("{has:?}"),
            });
        }
        Ok(t)
    }
    /// The buffer for imported buffer `res`.
    pub fn buffer(&self, res: &ResourceDecl) -> GraphResult<&wgpu::Buffer> {
        self.buffers
            .get(&res.name)
            .ok_or_else(|| GraphError::MissingResource {
                resource: res.name.clone(),
                message: "imported buffer not provided; call Executor::import_buffer".into(),
            })
    }
}
