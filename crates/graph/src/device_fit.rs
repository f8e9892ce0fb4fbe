//! Whether a compiled plan fits a device: for each kept pass, the bindings its pipeline layout
//! puts in each shader stage, its bind groups, its compute workgroup (size and `var<workgroup>`
//! bytes), its colour targets, the storage formats it reads and writes, and ray queries, each
//! against the device's limits and features.
//!
//! Pure: a [`DeviceProfile`] is plain data, so a plan is checked against WebGPU's default
//! limits ([`DeviceProfile::webgpu_defaults`]) on any machine, with no browser and no GPU.
//!
//! Invariant: [`check_plan`] accepts a plan only when none of those counts exceeds the
//! profile; otherwise it names the first pass over, the limit by its wgpu name, the device's
//! value and what the pass needs. Colour targets are checked for every pass that renders,
//! custom ones (aograph's g-buffer raster) included; the rest needs the pass's shader. What is sized by the frame (dispatch counts, texture sizes)
//! is checked when the frame is bound (`bind.rs`).

use crate::compile::CompiledGraph;
use crate::declaration::PassKind;
use crate::error::{GraphError, GraphResult};
use crate::gpu::GpuContext;
use crate::shader::{ShaderBindingKind, ShaderModuleInfo};

/// The formats a WGSL storage texture can name (`texture_storage_2d<F, access>`).
const STORAGE_FORMATS: [wgpu::TextureFormat; 17] = {
    use wgpu::TextureFormat as T;
    [
        T::R32Float,
        T::Rg32Float,
        T::Rgba32Float,
        T::R16Float,
        T::Rg16Float,
        T::Rgba16Float,
        T::R32Uint,
        T::Rg32Uint,
        T::Rgba32Uint,
        T::R32Sint,
        T::Rgba8Unorm,
        T::Rgba8Snorm,
        T::R8Unorm,
        T::Rg8Unorm,
        T::Rgba16Unorm,
        T::R16Unorm,
        T::Rgb10a2Unorm,
    ]
};

/// What a device allows, as a plan is checked against it.
#[derive(Clone, Debug)]
pub struct DeviceProfile {
    /// Named in errors: "a WebGPU device with default limits", or the adapter's description.
    pub name: String,
    /// The device's limits (what it was created with, not what the adapter could give).
    pub limits: wgpu::Limits,
    /// The device's features.
    pub features: wgpu::Features,
    /// Per storage-capable format: the storage accesses allowed (`STORAGE_READ_ONLY`,
    /// `STORAGE_WRITE_ONLY`, `STORAGE_READ_WRITE` flags).
    storage: Vec<(wgpu::TextureFormat, wgpu::TextureFormatFeatureFlags)>,
}

impl DeviceProfile {
    /// A browser's device made with no features and no limits asked for: WebGPU's default
    /// limits, the storage formats core WebGPU guarantees, no ray queries.
    pub fn webgpu_defaults() -> Self {
        Self::from_parts(
            "a WebGPU device with default limits".into(),
            wgpu::Limits::defaults(),
            wgpu::Features::empty(),
            |format| {
                let mut f = format.guaranteed_format_features(wgpu::Features::empty());
                // Formats behind a feature (16-bit norm, say) are not core WebGPU at all.
                if !format.required_features().is_empty() {
                    f.allowed_usages = wgpu::TextureUsages::empty();
                }
                f
            },
        )
    }

    /// What `gpu`'s device allows: its limits and features, and each storage format's
    /// accesses as [`GpuContext::format_features`] reports them.
    pub fn of(gpu: &GpuContext) -> Self {
        Self::from_parts(
            gpu.describe(),
            gpu.device.limits(),
            gpu.features,
            |format| gpu.format_features(format),
        )
    }

    /// A profile from `limits`, `features` and each format's features (`format_features`).
    pub fn from_parts(
        name: String,
        limits: wgpu::Limits,
        features: wgpu::Features,
        format_features: impl Fn(wgpu::TextureFormat) -> wgpu::TextureFormatFeatures,
    ) -> Self {
        let storage = STORAGE_FORMATS
            .iter()
            .map(|&format| {
                let f = format_features(format);
                let flags = if f
                    .allowed_usages
                    .contains(wgpu::TextureUsages::STORAGE_BINDING)
                {
                    f.flags
                } else {
                    wgpu::TextureFormatFeatureFlags::empty()
                };
                (format, flags)
            })
            .collect();
        Self {
            name,
            limits,
            features,
            storage,
        }
    }

    /// Whether a storage texture of `format` can be bound with `access`.
    pub fn allows_storage(
        &self,
        format: wgpu::TextureFormat,
        access: wgpu::StorageTextureAccess,
    ) -> bool {
        use wgpu::TextureFormatFeatureFlags as F;
        let needed = match access {
            wgpu::StorageTextureAccess::ReadOnly => F::STORAGE_READ_ONLY,
            wgpu::StorageTextureAccess::WriteOnly => F::STORAGE_WRITE_ONLY,
            _ => F::STORAGE_READ_WRITE,
        };
        self.storage
            .iter()
            .any(|(f, flags)| *f == format && flags.contains(needed))
    }
}

/// Per shader stage, the bindings of one kind a pipeline layout holds.
#[derive(Default)]
struct StageCounts {
    sampled_textures: u32,
    samplers: u32,
    storage_textures: u32,
    storage_buffers: u32,
    uniform_buffers: u32,
}

impl StageCounts {
    fn of(info: &ShaderModuleInfo) -> Self {
        let mut c = Self::default();
        for b in &info.bindings {
            match b.kind {
                ShaderBindingKind::SampledTexture { .. } => c.sampled_textures += 1,
                ShaderBindingKind::Sampler => c.samplers += 1,
                ShaderBindingKind::StorageTexture { .. } => c.storage_textures += 1,
                ShaderBindingKind::StorageBuffer { .. } => c.storage_buffers += 1,
                ShaderBindingKind::Uniform { .. } => c.uniform_buffers += 1,
                ShaderBindingKind::AccelerationStructure => {}
            }
        }
        c
    }
}

/// Checks every kept pass of `plan` against `device` (see the module's invariant).
pub fn check_plan(plan: &CompiledGraph, device: &DeviceProfile) -> GraphResult<()> {
    for &p in &plan.order {
        let pass = &plan.decl.passes[p.0];
        let over = |what: &str, limit: &str, needs: u64, allows: u64| -> GraphResult<()> {
            if needs <= allows {
                return Ok(());
            }
            Err(GraphError::OverDeviceLimit {
                pass: pass.name.clone(),
                what: what.into(),
                limit: limit.into(),
                needs,
                allows,
                device: device.name.clone(),
            })
        };
        let l = &device.limits;
        // Colour targets, of any pass that renders (a custom pass's too: a g-buffer raster).
        let targets: Vec<wgpu::TextureFormat> = pass
            .textures
            .iter()
            .filter(|u| matches!(u.attachment, Some(crate::AttachmentOps::Color { .. })))
            .filter_map(|u| plan.decl.resources[u.resource()].texture_desc())
            .map(|d| d.format)
            .collect();
        over(
            "colour attachments",
            "max_color_attachments",
            targets.len() as u64,
            l.max_color_attachments.into(),
        )?;
        over(
            "bytes per sample across its colour attachments",
            "max_color_attachment_bytes_per_sample",
            color_bytes_per_sample(&targets).into(),
            l.max_color_attachment_bytes_per_sample.into(),
        )?;
        let Some(info) = plan.shaders[p.0].as_deref() else {
            continue;
        };
        check_shader(pass, info, device, &over)?;
    }
    Ok(())
}

/// WebGPU's count of a render pass's colour bytes per sample: each target's byte cost added
/// after rounding the running total up to that target's component alignment.
fn color_bytes_per_sample(targets: &[wgpu::TextureFormat]) -> u32 {
    targets.iter().fold(0, |total, f| {
        let align = f.target_component_alignment().unwrap_or(1).max(1);
        total.next_multiple_of(align) + f.target_pixel_byte_cost().unwrap_or(0)
    })
}

/// The checks of one pass that its shader decides: bindings per stage, groups, formats, ray
/// queries and, for a compute pass, its workgroup.
fn check_shader(
    pass: &crate::declaration::PassDecl,
    info: &ShaderModuleInfo,
    device: &DeviceProfile,
    over: &dyn Fn(&str, &str, u64, u64) -> GraphResult<()>,
) -> GraphResult<()> {
    let l = &device.limits;
    let stage = match &pass.kind {
        PassKind::Compute { .. } => "compute stage",
        _ => "vertex and fragment stages (each)",
    };
    let c = StageCounts::of(info);
    for (count, kind, limit, allows) in [
        (
            c.storage_textures,
            "storage textures",
            "max_storage_textures_per_shader_stage",
            l.max_storage_textures_per_shader_stage,
        ),
        (
            c.storage_buffers,
            "storage buffers",
            "max_storage_buffers_per_shader_stage",
            l.max_storage_buffers_per_shader_stage,
        ),
        (
            c.sampled_textures,
            "sampled textures",
            "max_sampled_textures_per_shader_stage",
            l.max_sampled_textures_per_shader_stage,
        ),
        (
            c.samplers,
            "samplers",
            "max_samplers_per_shader_stage",
            l.max_samplers_per_shader_stage,
        ),
        (
            c.uniform_buffers,
            "uniform buffers",
            "max_uniform_buffers_per_shader_stage",
            l.max_uniform_buffers_per_shader_stage,
        ),
    ] {
        over(
            &format!("{kind} in its {stage}"),
            limit,
            count.into(),
            allows.into(),
        )?;
    }
    let groups = info.bindings.iter().map(|b| b.group + 1).max().unwrap_or(0);
    over(
        "bind groups",
        "max_bind_groups",
        groups.into(),
        l.max_bind_groups.into(),
    )?;
    for b in &info.bindings {
        over(
            &format!(
                "binding slots in group {} (`{}` is @binding({}))",
                b.group, b.name, b.binding
            ),
            "max_bindings_per_bind_group",
            u64::from(b.binding) + 1,
            l.max_bindings_per_bind_group.into(),
        )?;
        match b.kind {
            ShaderBindingKind::Uniform { size } => over(
                &format!("bytes in the uniform block `{}`", b.name),
                "max_uniform_buffer_binding_size",
                size,
                l.max_uniform_buffer_binding_size,
            )?,
            ShaderBindingKind::StorageTexture { format, access }
                if !device.allows_storage(format, access) =>
            {
                return Err(GraphError::DeviceLacks {
                    pass: pass.name.clone(),
                    what: format!(
                        "{format:?} storage textures with {access:?} access (`{}`)",
                        b.name
                    ),
                    device: device.name.clone(),
                });
            }
            ShaderBindingKind::AccelerationStructure
                if !device
                    .features
                    .contains(wgpu::Features::EXPERIMENTAL_RAY_QUERY) =>
            {
                return Err(GraphError::DeviceLacks {
                    pass: pass.name.clone(),
                    what: format!(
                        "ray queries (`{}` is an acceleration structure; wgpu's \
                         EXPERIMENTAL_RAY_QUERY)",
                        b.name
                    ),
                    device: device.name.clone(),
                });
            }
            _ => {}
        }
    }
    if let PassKind::Compute { entry, .. } = &pass.kind
        && let Some(e) = info.entry(entry)
    {
        let [x, y, z] = e.workgroup_size;
        for (size, axis, allows) in [
            (x, "x", l.max_compute_workgroup_size_x),
            (y, "y", l.max_compute_workgroup_size_y),
            (z, "z", l.max_compute_workgroup_size_z),
        ] {
            over(
                &format!("invocations along {axis} in a workgroup"),
                &format!("max_compute_workgroup_size_{axis}"),
                size.into(),
                allows.into(),
            )?;
        }
        over(
            "invocations per workgroup",
            "max_compute_invocations_per_workgroup",
            u64::from(x) * u64::from(y) * u64::from(z),
            l.max_compute_invocations_per_workgroup.into(),
        )?;
        over(
            "bytes of workgroup storage",
            "max_compute_workgroup_storage_size",
            e.workgroup_storage.into(),
            l.max_compute_workgroup_storage_size.into(),
        )?;
    }
    Ok(())
}
