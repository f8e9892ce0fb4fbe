//! Pipelines and bind group layouts built from reflected shaders, and the executor's cache of
//! them, shared by every plan.
//!
//! Layout entries come from the naga reflection of the shader plus what the pass binds (found
//! through its binding slots): the texture's format (whether a float texture is filterable on
//! this device) and the declared sampler (whether it filters); nothing is written by hand. All
//! bindings are visible to every stage the pass uses. A pipeline is identified by its
//! [`PipelineKey`]: the shader's expanded source (by hash), its entry points, the layout
//! entries, the values of its pipeline-overridable constants, and for full-screen passes the colour targets (format, blend) and depth state. Two
//! plans, or two passes of one plan, with equal keys share one pipeline.

use std::collections::HashMap;
use std::sync::Arc;

use crate::attachment::AttachmentOps;
use crate::binding_slots::{BindingSlot, BindingSource};
use crate::declaration::{GraphDecl, PassDecl, PassKind, PipelineConstant};
use crate::sampler::SamplerDesc;
use crate::shader::{ShaderModuleInfo, binding_type, grouped_entries};

/// A pass's pipeline and its layouts, one per bind group index in use.
pub(crate) enum PassPipeline {
    Compute {
        pipeline: wgpu::ComputePipeline,
        groups: Vec<(u32, wgpu::BindGroupLayout)>,
        workgroup: [u32; 3],
    },
    Render {
        pipeline: wgpu::RenderPipeline,
        groups: Vec<(u32, wgpu::BindGroupLayout)>,
    },
}

impl PassPipeline {
    pub fn groups(&self) -> &[(u32, wgpu::BindGroupLayout)] {
        match self {
            PassPipeline::Compute { groups, .. } | PassPipeline::Render { groups, .. } => groups,
        }
    }
}

/// What identifies a pipeline (see the module docs).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub(crate) struct PipelineKey {
    source: u64,
    stage: StageKey,
    groups: Vec<(u32, Vec<wgpu::BindGroupLayoutEntry>)>,
    constants: Vec<PipelineConstant>,
}

#[derive(Clone, Debug, PartialEq, Eq, Hash)]
enum StageKey {
    Compute {
        entry: String,
    },
    Render {
        vertex: String,
        fragment: String,
        targets: Vec<(wgpu::TextureFormat, Option<wgpu::BlendState>)>,
        depth: Option<DepthKey>,
    },
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
struct DepthKey {
    format: wgpu::TextureFormat,
    compare: wgpu::CompareFunction,
    write: bool,
}

/// The key of `pass`'s pipeline, `None` for passes without one (copies, custom passes);
/// `slots` are the pass's binding slots and `samplers` the plan's samplers they index.
pub(crate) fn pipeline_key(
    features: wgpu::Features,
    decl: &GraphDecl,
    pass: &PassDecl,
    info: &ShaderModuleInfo,
    slots: &[BindingSlot],
    samplers: &[SamplerDesc],
) -> Option<PipelineKey> {
    let visibility = match pass.kind {
        PassKind::Compute { .. } => wgpu::ShaderStages::COMPUTE,
        _ => wgpu::ShaderStages::VERTEX_FRAGMENT,
    };
    let groups = grouped_entries(
        visibility,
        info.bindings.iter().zip(slots).map(|(b, slot)| {
            let format = slot
                .source
                .texture_resource()
                .and_then(|r| decl.resources[r].texture_desc())
                .map(|d| d.format);
            let sampler = match slot.source {
                BindingSource::Sampler { sampler } => samplers.get(sampler).copied(),
                _ => None,
            };
            (
                b.group,
                b.binding,
                binding_type(&b.kind, format, sampler, features),
            )
        }),
    );
    let stage = match &pass.kind {
        PassKind::Compute { entry, .. } => StageKey::Compute {
            entry: entry.clone(),
        },
        PassKind::Fullscreen {
            vertex, fragment, ..
        } => {
            let mut targets = Vec::new();
            let mut depth = None;
            for u in &pass.textures {
                let Some(desc) = decl.resources[u.resource()].texture_desc() else {
                    continue;
                };
                match u.attachment {
                    Some(AttachmentOps::Color { blend, .. }) => targets.push((desc.format, blend)),
                    Some(AttachmentOps::Depth {
                        compare, read_only, ..
                    }) if depth.is_none() => {
                        depth = Some(DepthKey {
                            format: desc.format,
                            compare,
                            write: !read_only,
                        })
                    }
                    _ => {}
                }
            }
            StageKey::Render {
                vertex: vertex.clone(),
                fragment: fragment.clone(),
                targets,
                depth,
            }
        }
        _ => return None,
    };
    Some(PipelineKey {
        source: info.source_hash,
        stage,
        groups,
        constants: pass.constants.clone(),
    })
}

struct CachedPipeline {
    pipeline: Arc<PassPipeline>,
    last_use: u64,
}

/// The executor's pipelines by key, with their shader modules, bounded by
/// [`PipelineCache::CAPACITY`] (least recently used evicted first).
#[derive(Default)]
pub(crate) struct PipelineCache {
    pipelines: HashMap<PipelineKey, CachedPipeline>,
    modules: HashMap<u64, wgpu::ShaderModule>,
    uses: u64,
    created: u64,
}

impl PipelineCache {
    /// Pipelines kept: every pass of every technique and preset, with room.
    pub const CAPACITY: usize = 512;

    /// The pipeline for `key`, created on a miss from `info`'s module.
    pub fn get(
        &mut self,
        device: &wgpu::Device,
        key: &PipelineKey,
        info: &ShaderModuleInfo,
        label: &str,
    ) -> Arc<PassPipeline> {
        self.uses += 1;
        if let Some(c) = self.pipelines.get_mut(key) {
            c.last_use = self.uses;
            return c.pipeline.clone();
        }
        if self.pipelines.len() >= Self::CAPACITY {
            let oldest = self
                .pipelines
                .iter()
                .min_by_key(|(_, c)| c.last_use)
                .map(|(k, _)| k.clone());
            if let Some(k) = oldest {
                self.pipelines.remove(&k);
            }
        }
        let module = self
            .modules
            .entry(info.source_hash)
            .or_insert_with(|| {
                device.create_shader_module(wgpu::ShaderModuleDescriptor {
                    label: Some(&info.name),
                    source: wgpu::ShaderSource::Wgsl(info.source.as_str().into()),
                })
            })
            .clone();
        let pipeline = Arc::new(create_pipeline(device, key, &module, info, label));
        self.created += 1;
        self.pipelines.insert(
            key.clone(),
            CachedPipeline {
                pipeline: pipeline.clone(),
                last_use: self.uses,
            },
        );
        pipeline
    }
    /// Pipelines created since the executor was made.
    pub fn created(&self) -> u64 {
        self.created
    }
    /// Pipelines held now.
    pub fn len(&self) -> usize {
        self.pipelines.len()
    }
}

fn create_pipeline(
    device: &wgpu::Device,
    key: &PipelineKey,
    module: &wgpu::ShaderModule,
    info: &ShaderModuleInfo,
    label: &str,
) -> PassPipeline {
    let max_group = key.groups.iter().map(|(g, _)| *g).max();
    let groups: Vec<(u32, wgpu::BindGroupLayout)> = key
        .groups
        .iter()
        .map(|(g, entries)| {
            (
                *g,
                device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                    label: Some(label),
                    entries,
                }),
            )
        })
        .collect();
    // Groups may have gaps; fill them with empty layouts.
    let empty = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("empty"),
        entries: &[],
    });
    let all: Vec<Option<&wgpu::BindGroupLayout>> = (0..max_group.map_or(0, |m| m + 1))
        .map(|g| {
            Some(
                groups
                    .iter()
                    .find(|(i, _)| *i == g)
                    .map(|(_, l)| l)
                    .unwrap_or(&empty),
            )
        })
        .collect();
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(label),
        bind_group_layouts: &all,
        immediate_size: 0,
    });
    // The pass's `override` values, compiled into the pipeline by the driver.
    let constants: Vec<(&str, f64)> = key
        .constants
        .iter()
        .map(|c| (c.name.as_str(), c.value))
        .collect();
    let options = wgpu::PipelineCompilationOptions {
        constants: &constants,
        ..Default::default()
    };
    match &key.stage {
        StageKey::Compute { entry } => {
            let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(label),
                layout: Some(&layout),
                module,
                entry_point: Some(entry),
                compilation_options: options.clone(),
                cache: None,
            });
            PassPipeline::Compute {
                pipeline,
                groups,
                workgroup: info
                    .entry(entry)
                    .map(|e| e.workgroup_size)
                    .unwrap_or([1, 1, 1]),
            }
        }
        StageKey::Render {
            vertex,
            fragment,
            targets,
            depth,
        } => {
            let targets: Vec<Option<wgpu::ColorTargetState>> = targets
                .iter()
                .map(|(format, blend)| {
                    Some(wgpu::ColorTargetState {
                        format: *format,
                        blend: *blend,
                        write_mask: wgpu::ColorWrites::ALL,
                    })
                })
                .collect();
            let depth_stencil = depth.map(|d| wgpu::DepthStencilState {
                format: d.format,
                depth_write_enabled: Some(d.write),
                depth_compare: Some(d.compare),
                stencil: Default::default(),
                bias: Default::default(),
            });
            let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(label),
                layout: Some(&layout),
                vertex: wgpu::VertexState {
                    module,
                    entry_point: Some(vertex),
                    compilation_options: options.clone(),
                    buffers: &[],
                },
                primitive: wgpu::PrimitiveState::default(),
                depth_stencil,
                multisample: wgpu::MultisampleState::default(),
                fragment: Some(wgpu::FragmentState {
                    module,
                    entry_point: Some(fragment),
                    compilation_options: options.clone(),
                    targets: &targets,
                }),
                multiview_mask: None,
                cache: None,
            });
            PassPipeline::Render { pipeline, groups }
        }
    }
}
