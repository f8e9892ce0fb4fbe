//! How the caller provides an executor's imported resources: by name for every plan, or for
//! one plan by the handles its builder returned (what frame inputs use), and how per-plan
//! bindings are dropped. The binding itself happens each frame in `bind.rs`, from slots.
//!
//! Invariant: a per-plan binding names an imported resource of that plan of the right kind
//! (texture, buffer, acceleration structure), or is refused with an error naming it.

use super::Executor;
use crate::compile::CompiledGraph;
use crate::declaration::{ResourceKind, ResourceOrigin};
use crate::error::{GraphError, GraphResult};
use crate::resource::{AccelerationStructureHandle, BufferHandle, TextureHandle};

impl Executor {
    /// Provides the texture behind imported resource `name` (for every plan importing it).
    pub fn import_texture(&mut self, name: &str, texture: wgpu::Texture) {
        let serial = self.pool.next_serial();
        self.imports.set_texture(name, texture, serial);
    }
    /// Provides the buffer behind imported buffer `name` (for every plan importing it).
    pub fn import_buffer(&mut self, name: &str, buffer: wgpu::Buffer) {
        self.imports.set_buffer(name, buffer);
    }
    /// Provides the top-level acceleration structure behind imported resource `name` (for
    /// every plan importing it). The graph binds it as it is: whoever built it rebuilds it
    /// (same object) when the scene moves, before the frame executes.
    pub fn import_acceleration_structure(&mut self, name: &str, tlas: wgpu::Tlas) {
        self.imports.set_acceleration_structure(name, tlas);
    }
    /// Provides the texture behind `plan`'s import `handle`, for that plan only: two plans may
    /// bind different textures to imports of the same name. It takes precedence over a
    /// texture imported by name. An error when `handle` is no imported texture of `plan`.
    pub fn bind_import_texture(
        &mut self,
        plan: &CompiledGraph,
        handle: TextureHandle,
        texture: wgpu::Texture,
    ) -> GraphResult<()> {
        let r = imported_resource(plan, handle.id, true)?;
        let serial = self.pool.next_serial();
        self.imports
            .set_plan_texture(plan.key(), r, texture, serial);
        Ok(())
    }
    /// Provides the buffer behind `plan`'s import `handle`, for that plan only (see
    /// [`Executor::bind_import_texture`]).
    pub fn bind_import_buffer(
        &mut self,
        plan: &CompiledGraph,
        handle: BufferHandle,
        buffer: wgpu::Buffer,
    ) -> GraphResult<()> {
        let r = imported_resource(plan, handle.id, false)?;
        self.imports.set_plan_buffer(plan.key(), r, buffer);
        Ok(())
    }
    /// Provides the acceleration structure behind `plan`'s import `handle`, for that plan only
    /// (see [`Executor::bind_import_texture`]). The graph binds it as it is: whoever built it
    /// rebuilds it (same object) when the scene moves, before the frame executes.
    pub fn bind_import_acceleration_structure(
        &mut self,
        plan: &CompiledGraph,
        handle: AccelerationStructureHandle,
        tlas: wgpu::Tlas,
    ) -> GraphResult<()> {
        let r = handle.id;
        let is_import = plan.decl.resources.get(r as usize).is_some_and(|res| {
            matches!(res.origin, ResourceOrigin::Imported)
                && matches!(res.kind, ResourceKind::AccelerationStructure)
        });
        if !is_import {
            return Err(GraphError::MissingResource {
                resource: format!("#{r}"),
                message: "not an imported acceleration structure of this plan: bind only \
                          handles from `import_acceleration_structure`"
                    .into(),
            });
        }
        self.imports
            .set_plan_acceleration_structure(plan.key(), r, tlas);
        Ok(())
    }
    /// Drops every per-plan binding (`bind_import_*`), releasing what they held (a replaced
    /// scene's BVH, say): bind again before those plans' next frames. Imports by name stay.
    pub fn clear_plan_bindings(&mut self) {
        self.imports.clear_plan_bindings();
    }
}

/// Resource `id` of `plan` when it is an imported texture (`texture`) or buffer, else an error
/// naming what it is.
fn imported_resource(plan: &CompiledGraph, id: u32, texture: bool) -> GraphResult<u32> {
    let kind = if texture { "texture" } else { "buffer" };
    let res = plan
        .decl
        .resources
        .get(id as usize)
        .ok_or_else(|| GraphError::MissingResource {
            resource: format!("#{id}"),
            message: "no resource of this plan: pass a handle its builder returned".into(),
        })?;
    let kind_matches = if texture {
        res.texture_desc().is_some()
    } else {
        matches!(res.kind, ResourceKind::Buffer(_))
    };
    if !matches!(res.origin, ResourceOrigin::Imported) || !kind_matches {
        return Err(GraphError::MissingResource {
            resource: res.name.clone(),
            message: format!(
                "not an imported {kind} of this plan: bind only handles from `import_{kind}`"
            ),
        });
    }
    Ok(id)
}
