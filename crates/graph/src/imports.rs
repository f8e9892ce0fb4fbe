//! Imported resources: textures and buffers the caller provides, checked against what the plan
//! declares before anything is recorded. Two ways to provide one: for one plan by the handle its
//! builder returned (`Executor::bind_import_texture`), so two plans may bind different textures
//! to imports of the same name; or by name for every plan (`Executor::import_texture`). A
//! plan's own binding wins.
//!
//! Invariant: an imported texture bound to a frame has the declared format and size, and every
//! usage the plan needs of it (a target created without `RENDER_ATTACHMENT`, say, is an error
//! naming the missing flag, not a validation error at submit). Names are unique per plan
//! (compile rejects duplicates), so one name binds one texture within a plan.

use std::collections::HashMap;
use std::sync::Arc;

use crate::compile::PlanKey;
use crate::custom::BoundTexture;
use crate::declaration::ResourceDecl;
use crate::error::{GraphError, GraphResult};
use crate::resource::{Extent, TextureDesc};

/// Textures and buffers provided for imported resources: by name for every plan, and by
/// (plan, resource index) for one plan.
#[derive(Default)]
pub(crate) struct ImportTable {
    textures: HashMap<String, BoundTexture>,
    buffers: HashMap<String, wgpu::Buffer>,
    plan_textures: HashMap<(PlanKey, u32), BoundTexture>,
    plan_buffers: HashMap<(PlanKey, u32), wgpu::Buffer>,
    acceleration_structures: HashMap<String, Arc<wgpu::Tlas>>,
}

impl ImportTable {
    pub fn set_texture(&mut self, name: &str, texture: wgpu::Texture, serial: u64) {
        self.textures
            .insert(name.to_string(), BoundTexture::new(texture, serial));
    }
    pub fn set_buffer(&mut self, name: &str, buffer: wgpu::Buffer) {
        self.buffers.insert(name.to_string(), buffer);
    }
    pub fn set_acceleration_structure(&mut self, name: &str, tlas: wgpu::Tlas) {
        self.acceleration_structures
            .insert(name.to_string(), Arc::new(tlas));
    }
    /// `texture` behind resource `resource` of the plan `plan` only.
    pub fn set_plan_texture(
        &mut self,
        plan: PlanKey,
        resource: u32,
        texture: wgpu::Texture,
        serial: u64,
    ) {
        self.plan_textures
            .insert((plan, resource), BoundTexture::new(texture, serial));
    }
    /// `buffer` behind resource `resource` of the plan `plan` only.
    pub fn set_plan_buffer(&mut self, plan: PlanKey, resource: u32, buffer: wgpu::Buffer) {
        self.plan_buffers.insert((plan, resource), buffer);
    }
    /// The texture for `res`, checked against its descriptor at `extent` and the `usage` the
    /// plan needs.
    pub fn texture(
        &self,
        plan: PlanKey,
        resource: u32,
        res: &ResourceDecl,
        desc: &TextureDesc,
        extent: Extent,
        usage: wgpu::TextureUsages,
    ) -> GraphResult<&BoundTexture> {
        let t = self
            .plan_textures
            .get(&(plan, resource))
            .or_else(|| self.textures.get(&res.name))
            .ok_or_else(|| GraphError::MissingResource {
                resource: res.name.clone(),
                message: "imported texture not provided; call Executor::bind_import_texture \
                          (this plan) or Executor::import_texture (every plan)"
                    .into(),
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
    /// The buffer for imported buffer `res`, resource `resource` of plan `plan`.
    pub fn buffer(
        &self,
        plan: PlanKey,
        resource: u32,
        res: &ResourceDecl,
    ) -> GraphResult<&wgpu::Buffer> {
        self.plan_buffers
            .get(&(plan, resource))
            .or_else(|| self.buffers.get(&res.name))
            .ok_or_else(|| GraphError::MissingResource {
                resource: res.name.clone(),
                message: "imported buffer not provided; call Executor::bind_import_buffer (this \
                          plan) or Executor::import_buffer (every plan)"
                    .into(),
            })
    }
    /// The acceleration structure for imported resource `res`.
    pub fn acceleration_structure(&self, res: &ResourceDecl) -> GraphResult<&Arc<wgpu::Tlas>> {
        self.acceleration_structures
            .get(&res.name)
            .ok_or_else(|| GraphError::MissingResource {
                resource: res.name.clone(),
                message: "imported acceleration structure not provided; call \
                          Executor::import_acceleration_structure"
                    .into(),
            })
    }
}
