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

use crate::compile::{CompiledGraph, PlanKey};
use crate::custom::BoundTexture;
use crate::declaration::{ResourceDecl, ResourceOrigin};
use crate::error::{GraphError, GraphResult};
use crate::name_lookups::count_name_lookup;
use crate::resource::{Extent, TextureDesc};

/// What is bound to one import name for every plan.
#[derive(Default)]
struct NamedImport {
    texture: Option<BoundTexture>,
    buffer: Option<wgpu::Buffer>,
    acceleration_structure: Option<Arc<wgpu::Tlas>>,
}

/// Textures and buffers provided for imported resources: by name for every plan (each name
/// interned once into a slot), and by (plan, resource index) for one plan.
#[derive(Default)]
pub(crate) struct ImportTable {
    /// Index of each name ever imported by name: consulted when a name is imported and when a
    /// plan resolves its imports ([`ImportSlots`]), never on a frame that reuses them.
    slot_of_name: HashMap<String, usize>,
    named: Vec<NamedImport>,
    plan_textures: HashMap<(PlanKey, u32), BoundTexture>,
    plan_buffers: HashMap<(PlanKey, u32), wgpu::Buffer>,
    plan_acceleration_structures: HashMap<(PlanKey, u32), Arc<wgpu::Tlas>>,
}

/// A plan's imported resources resolved to the table's name slots: per resource, the slot of
/// its name (if anything was imported under it), valid while the table holds `names` names.
#[derive(Default)]
pub(crate) struct ImportSlots {
    slots: Vec<Option<usize>>,
    names: usize,
    resolved: bool,
}

impl ImportTable {
    fn slot(&mut self, name: &str) -> usize {
        count_name_lookup();
        if let Some(&s) = self.slot_of_name.get(name) {
            return s;
        }
        self.named.push(NamedImport::default());
        self.slot_of_name
            .insert(name.to_string(), self.named.len() - 1);
        self.named.len() - 1
    }
    pub fn set_texture(&mut self, name: &str, texture: wgpu::Texture, serial: u64) {
        let s = self.slot(name);
        self.named[s].texture = Some(BoundTexture::new(texture, serial));
    }
    pub fn set_buffer(&mut self, name: &str, buffer: wgpu::Buffer) {
        let s = self.slot(name);
        self.named[s].buffer = Some(buffer);
    }
    pub fn set_acceleration_structure(&mut self, name: &str, tlas: wgpu::Tlas) {
        let s = self.slot(name);
        self.named[s].acceleration_structure = Some(Arc::new(tlas));
    }
    /// Resolves `plan`'s imported resources to name slots, unless `slots` already holds them
    /// for the names the table has now (a name imported since makes it resolve again).
    pub fn resolve(&self, plan: &CompiledGraph, slots: &mut ImportSlots) {
        if slots.resolved && slots.names == self.named.len() {
            return;
        }
        slots.slots.clear();
        slots.slots.extend(plan.decl.resources.iter().map(|r| {
            if !matches!(r.origin, ResourceOrigin::Imported) {
                return None;
            }
            count_name_lookup();
            self.slot_of_name.get(&r.name).copied()
        }));
        slots.names = self.named.len();
        slots.resolved = true;
    }
    fn named(&self, slots: &ImportSlots, resource: u32) -> Option<&NamedImport> {
        let s = (*slots.slots.get(resource as usize)?)?;
        self.named.get(s)
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
    /// Forgets every per-plan binding.
    pub fn clear_plan_bindings(&mut self) {
        self.plan_textures.clear();
        self.plan_buffers.clear();
        self.plan_acceleration_structures.clear();
    }
    /// `tlas` behind resource `resource` of the plan `plan` only.
    pub fn set_plan_acceleration_structure(
        &mut self,
        plan: PlanKey,
        resource: u32,
        tlas: wgpu::Tlas,
    ) {
        self.plan_acceleration_structures
            .insert((plan, resource), Arc::new(tlas));
    }
    /// `buffer` behind resource `resource` of the plan `plan` only.
    pub fn set_plan_buffer(&mut self, plan: PlanKey, resource: u32, buffer: wgpu::Buffer) {
        self.plan_buffers.insert((plan, resource), buffer);
    }
    /// The texture for `res`, checked against its descriptor at `extent` and the `usage` the
    /// plan needs.
    #[allow(clippy::too_many_arguments)]
    pub fn texture(
        &self,
        plan: PlanKey,
        slots: &ImportSlots,
        resource: u32,
        res: &ResourceDecl,
        desc: &TextureDesc,
        extent: Extent,
        usage: wgpu::TextureUsages,
    ) -> GraphResult<&BoundTexture> {
        let t = self
            .plan_textures
            .get(&(plan, resource))
            .or_else(|| self.named(slots, resource)?.texture.as_ref())
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
        slots: &ImportSlots,
        resource: u32,
        res: &ResourceDecl,
    ) -> GraphResult<&wgpu::Buffer> {
        self.plan_buffers
            .get(&(plan, resource))
            .or_else(|| self.named(slots, resource)?.buffer.as_ref())
            .ok_or_else(|| GraphError::MissingResource {
                resource: res.name.clone(),
                message: "imported buffer not provided; call Executor::bind_import_buffer (this \
                          plan) or Executor::import_buffer (every plan)"
                    .into(),
            })
    }
    /// The acceleration structure for imported resource `res`.
    pub fn acceleration_structure(
        &self,
        plan: PlanKey,
        slots: &ImportSlots,
        resource: u32,
        res: &ResourceDecl,
    ) -> GraphResult<&Arc<wgpu::Tlas>> {
        (self.plan_acceleration_structures.get(&(plan, resource)))
            .or_else(|| self.named(slots, resource)?.acceleration_structure.as_ref())
            .ok_or_else(|| GraphError::MissingResource {
                resource: res.name.clone(),
                message: "imported acceleration structure not provided; call \
                          Executor::bind_import_acceleration_structure (this plan) or \
                          Executor::import_acceleration_structure (every plan)"
                    .into(),
            })
    }
}
