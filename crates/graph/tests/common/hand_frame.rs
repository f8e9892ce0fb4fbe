//! A frame of a chain of compute passes recorded by hand with raw wgpu, with the same calls
//! the executor makes (one pipeline, a bind group per pass, one labelled compute pass per graph
//! pass; with timestamps, the executor's read-back ring as plain wgpu calls). Shared by the
//! allocation test (the executor's own share of allocations) and the graph benchmarks (the
//! executor's own share of recording time).

#![allow(dead_code)]

use std::sync::Arc;
use std::sync::atomic::{AtomicU32, Ordering};

use aograph_graph::GpuContext;

/// Each pass adds one to what the previous one wrote.
pub const SHADER: &str = r#"
@group(0) @binding(0) var src: texture_2d<f32>;
@group(0) @binding(1) var dst: texture_storage_2d<r32float, write>;
@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(src);
    if (id.x >= size.x || id.y >= size.y) { return; }
    textureStore(dst, vec2<i32>(id.xy), textureLoad(src, vec2<i32>(id.xy), 0) + 1.0);
}
"#;

/// An R32Float texture `side` pixels square.
pub fn texture(gpu: &GpuContext, side: u32, usage: wgpu::TextureUsages) -> wgpu::Texture {
    gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some("t"),
        size: wgpu::Extent3d {
            width: side,
            height: side,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::R32Float,
        usage,
        view_formats: &[],
    })
}

/// The frame by hand: one pipeline, `passes` bind groups over `passes + 1` textures,
/// one labelled compute pass per graph pass. With `timestamps`, the read-back ring the
/// executor uses, as plain wgpu calls: two timestamps per pass, a resolve, a copy, a map
/// whose callback sets an atomic, a non-blocking poll, and unmapping finished slots.
pub struct HandFrame {
    passes: usize,
    side: u32,
    pipeline: wgpu::ComputePipeline,
    groups: Vec<wgpu::BindGroup>,
    names: Vec<String>,
    ring: Vec<(wgpu::QuerySet, wgpu::Buffer, wgpu::Buffer, Arc<AtomicU32>)>,
    next: usize,
}

impl HandFrame {
    pub fn new(gpu: &GpuContext, passes: usize, side: u32, timestamps: bool) -> Self {
        let module = gpu
            .device
            .create_shader_module(wgpu::ShaderModuleDescriptor {
                label: None,
                source: wgpu::ShaderSource::Wgsl(SHADER.into()),
            });
        let pipeline = gpu
            .device
            .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: None,
                layout: None,
                module: &module,
                entry_point: Some("main"),
                compilation_options: Default::default(),
                cache: None,
            });
        let usage = wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::STORAGE_BINDING;
        let textures: Vec<_> = (0..=passes).map(|_| texture(gpu, side, usage)).collect();
        let views: Vec<_> = textures
            .iter()
            .map(|t| t.create_view(&Default::default()))
            .collect();
        let layout = pipeline.get_bind_group_layout(0);
        let groups = (0..passes)
            .map(|i| {
                gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: None,
                    layout: &layout,
                    entries: &[
                        wgpu::BindGroupEntry {
                            binding: 0,
                            resource: wgpu::BindingResource::TextureView(&views[i]),
                        },
                        wgpu::BindGroupEntry {
                            binding: 1,
                            resource: wgpu::BindingResource::TextureView(&views[i + 1]),
                        },
                    ],
                })
            })
            .collect();
        let ring = if timestamps {
            (0..3)
                .map(|_| {
                    let n = 2 * passes as u32;
                    let set = gpu.device.create_query_set(&wgpu::QuerySetDescriptor {
                        label: None,
                        ty: wgpu::QueryType::Timestamp,
                        count: n,
                    });
                    let buffer = |usage| {
                        gpu.device.create_buffer(&wgpu::BufferDescriptor {
                            label: Some("timestamp readback"),
                            size: n as u64 * 8,
                            usage,
                            mapped_at_creation: false,
                        })
                    };
                    (
                        set,
                        buffer(wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC),
                        buffer(wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST),
                        Arc::new(AtomicU32::new(0)),
                    )
                })
                .collect()
        } else {
            Vec::new()
        };
        Self {
            pipeline,
            groups,
            passes,
            side,
            names: (0..passes).map(|i| format!("p{i}")).collect(),
            ring,
            next: 0,
        }
    }

    pub fn frame(&mut self, gpu: &GpuContext) {
        // Harvest finished slots (state 2), as the executor's ring does.
        if !self.ring.is_empty() {
            let _ = gpu.device.poll(wgpu::PollType::Poll);
            for (_, _, readback, state) in &self.ring {
                if state.load(Ordering::Acquire) == 2 {
                    let n = 2 * self.passes as u64 * 8;
                    {
                        let view = readback.slice(..n).get_mapped_range().unwrap();
                        std::hint::black_box(view.first());
                    }
                    readback.unmap();
                    state.store(0, Ordering::Release);
                }
            }
        }
        let slot = self
            .ring
            .get(self.next)
            .filter(|s| s.3.load(Ordering::Acquire) == 0);
        let mut encoder = gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("aograph frame"),
            });
        for (i, group) in self.groups.iter().enumerate() {
            if let Some((set, ..)) = slot {
                encoder.write_timestamp(set, 2 * i as u32);
            }
            {
                let mut cp = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some(&self.names[i]),
                    timestamp_writes: None,
                });
                cp.set_pipeline(&self.pipeline);
                cp.set_bind_group(0, group, &[]);
                let groups = self.side.div_ceil(8);
                cp.dispatch_workgroups(groups, groups, 1);
            }
            if let Some((set, ..)) = slot {
                encoder.write_timestamp(set, 2 * i as u32 + 1);
            }
        }
        let n = 2 * self.passes as u32;
        if let Some((set, resolve, readback, _)) = slot {
            encoder.resolve_query_set(set, 0..n, resolve, 0);
            encoder.copy_buffer_to_buffer(resolve, 0, readback, 0, n as u64 * 8);
        }
        gpu.queue.submit([encoder.finish()]);
        if let Some((_, _, readback, state)) = slot {
            state.store(1, Ordering::Release);
            let flag = state.clone();
            readback
                .slice(..n as u64 * 8)
                .map_async(wgpu::MapMode::Read, move |r| {
                    flag.store(if r.is_ok() { 2 } else { 3 }, Ordering::Release);
                });
            self.next = (self.next + 1) % self.ring.len();
        }
    }
}
