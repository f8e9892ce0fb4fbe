//! Buffers in and out of the device for the ray tracer's own compute passes (the ray batch and
//! the GPU reference, which run outside a frame graph): storage and uniform buffers from Pod
//! slices, a readback that waits for the queue, and a compute pipeline from a library shader
//! with its includes expanded. GPU failures come back as [`TracingError::Gpu`], never a panic.

use crate::error::TracingError;
use aograph_graph::{GpuContext, ShaderLibrary};
use bytemuck::Pod;
use wgpu::util::DeviceExt;

/// A buffer holding `items` (at least one element's worth of zeros when empty: wgpu has no
/// zero-size bindings).
pub(crate) fn buffer_of<T: Pod>(
    gpu: &GpuContext,
    label: &str,
    items: &[T],
    usage: wgpu::BufferUsages,
) -> wgpu::Buffer {
    let bytes: &[u8] = bytemuck::cast_slice(items);
    let padding = vec![0u8; std::mem::size_of::<T>().max(16)];
    gpu.device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents: if bytes.is_empty() { &padding } else { bytes },
            usage,
        })
}

/// A compute pipeline for `entry` of library shader `file`.
pub(crate) fn compute_pipeline(
    gpu: &GpuContext,
    shaders: &ShaderLibrary,
    file: &str,
) -> Result<wgpu::ComputePipeline, TracingError> {
    let module = shaders.load(file).map_err(|e| TracingError::Gpu {
        what: "loading a ray tracing shader",
        message: e.to_string(),
    })?;
    let module = gpu
        .device
        .create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(file),
            source: wgpu::ShaderSource::Wgsl(module.source.as_str().into()),
        });
    let pipeline = gpu
        .device
        .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(file),
            layout: None,
            module: &module,
            entry_point: Some("main"),
            compilation_options: Default::default(),
            cache: None,
        });
    check_gpu_errors(gpu, "creating a ray tracing pipeline")?;
    Ok(pipeline)
}

/// A bind group of `pipeline`'s group 0 with `(binding, resource)` entries.
pub(crate) fn bind_group<'a>(
    gpu: &GpuContext,
    pipeline: &wgpu::ComputePipeline,
    entries: impl IntoIterator<Item = (u32, wgpu::BindingResource<'a>)>,
) -> wgpu::BindGroup {
    let entries: Vec<wgpu::BindGroupEntry> = entries
        .into_iter()
        .map(|(binding, resource)| wgpu::BindGroupEntry { binding, resource })
        .collect();
    gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &pipeline.get_bind_group_layout(0),
        entries: &entries,
    })
}

/// Submits one compute pass of `pipeline` with `group` over `groups` (x, y) workgroups.
pub(crate) fn submit_dispatch(
    gpu: &GpuContext,
    pipeline: &wgpu::ComputePipeline,
    group: &wgpu::BindGroup,
    groups: (u32, u32),
) {
    let mut enc = gpu
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
    {
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor::default());
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, group, &[]);
        pass.dispatch_workgroups(groups.0, groups.1, 1);
    }
    gpu.queue.submit([enc.finish()]);
}

/// Workgroups of 64 invocations covering `count`, as (x, y) within the 65535 limit per
/// dimension, and the invocations per row.
pub(crate) fn dispatch_grid(count: u32) -> (u32, u32, u32) {
    let groups = count.div_ceil(64).max(1);
    let x = groups.min(65535);
    let y = groups.div_ceil(x);
    (x, y, x * 64)
}

/// The device's largest storage binding (and buffer), in bytes.
pub(crate) fn storage_limit(gpu: &GpuContext) -> u64 {
    let l = gpu.device.limits();
    l.max_storage_buffer_binding_size.min(l.max_buffer_size)
}

/// Refuses a `size`-byte storage buffer over the device's limit, naming `what` it holds.
pub(crate) fn check_storage(
    gpu: &GpuContext,
    what: &'static str,
    size: u64,
) -> Result<(), TracingError> {
    let limit = storage_limit(gpu);
    if size > limit {
        return Err(TracingError::OverDeviceLimit { what, size, limit });
    }
    Ok(())
}

/// The device errors raised since the last check (wgpu reports them to the context's sink,
/// not to the call), as one [`TracingError::Gpu`].
pub(crate) fn check_gpu_errors(gpu: &GpuContext, what: &'static str) -> Result<(), TracingError> {
    let errors = gpu.take_errors();
    if errors.is_empty() {
        Ok(())
    } else {
        Err(TracingError::Gpu {
            what,
            message: errors.join("; "),
        })
    }
}

/// Copies `buffer` (`size` bytes) back to the CPU, waiting for the queue; a device error
/// raised by the work before it (an invalid dispatch, say) is an error, never zeros.
pub(crate) fn read_back(
    gpu: &GpuContext,
    buffer: &wgpu::Buffer,
    size: u64,
) -> Result<Vec<u8>, TracingError> {
    let gpu_error = |message: String| TracingError::Gpu {
        what: "reading ray tracing results back",
        message,
    };
    let staging = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("ray tracing readback"),
        size,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut enc = gpu
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
    enc.copy_buffer_to_buffer(buffer, 0, &staging, 0, size);
    gpu.queue.submit([enc.finish()]);
    let (tx, rx) = std::sync::mpsc::channel();
    staging.slice(..).map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    gpu.device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| gpu_error(e.to_string()))?;
    check_gpu_errors(gpu, "tracing rays")?;
    rx.recv()
        .map_err(|e| gpu_error(e.to_string()))?
        .map_err(|e| gpu_error(e.to_string()))?;
    let bytes = staging
        .slice(..)
        .get_mapped_range()
        .map_err(|e| gpu_error(e.to_string()))?
        .to_vec();
    staging.unmap();
    Ok(bytes)
}
