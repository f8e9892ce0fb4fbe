//! Pipelines and bind group layouts built from reflected shaders.
//!
//! Layout entries come from the naga reflection of the shader plus the bound resource's format
//! (whether a float texture is filterable on this device); nothing is written by hand. All
//! bindings are visible to every stage the pass uses.

use std::collections::BTreeMap;

use crate::declaration::{GraphDecl, PassDecl, PassKind};
use crate::shader::{ShaderBindingKind, ShaderModuleInfo};

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

pub(crate) fn binding_type(
    kind: &ShaderBindingKind,
    format: Option<wgpu::TextureFormat>,
    features: wgpu::Features,
) -> wgpu::BindingType {
    match kind {
        ShaderBindingKind::SampledTexture { depth, scalar } => {
            let sample_type = match (depth, scalar) {
                (true, _) => wgpu::TextureSampleType::Depth,
                (false, naga::ScalarKind::Uint) => wgpu::TextureSampleType::Uint,
                (false, naga::ScalarKind::Sint) => wgpu::TextureSampleType::Sint,
                (false, _) => {
                    let filterable = format.is_some_and(|f| {
                        !f.is_depth_stencil_format()
                            && f.sample_type(None, Some(features))
                                == Some(wgpu::TextureSampleType::Float { filterable: true })
                    });
                    wgpu::TextureSampleType::Float { filterable }
                }
            };
            wgpu::BindingType::Texture {
                sample_type,
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            }
        }
        ShaderBindingKind::StorageTexture { format, access } => wgpu::BindingType::StorageTexture {
            access: *access,
            format: *format,
            view_dimension: wgpu::TextureViewDimension::D2,
        },
        ShaderBindingKind::Sampler { linear } => wgpu::BindingType::Sampler(if *linear {
            wgpu::SamplerBindingType::Filtering
        } else {
            wgpu::SamplerBindingType::NonFiltering
        }),
        ShaderBindingKind::Uniform { size } => wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: wgpu::BufferSize::new(*size),
        },
        ShaderBindingKind::StorageBuffer { read_only, .. } => wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage {
                read_only: *read_only,
            },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
    }
}

/// The format of the texture a pass binds to shader global `name`, if any.
pub(crate) fn bound_format(
    decl: &GraphDecl,
    pass: &PassDecl,
    name: &str,
) -> Option<wgpu::TextureFormat> {
    pass.textures
        .iter()
        .find(|u| u.binding.as_deref() == Some(name))
        .and_then(|u| decl.resources[u.resource()].texture_desc())
        .map(|d| d.format)
}

pub(crate) fn create_pipeline(
    device: &wgpu::Device,
    features: wgpu::Features,
    decl: &GraphDecl,
    pass: &PassDecl,
    info: &ShaderModuleInfo,
) -> Option<PassPipeline> {
    let visibility = match pass.kind {
        PassKind::Compute { .. } => wgpu::ShaderStages::COMPUTE,
        _ => wgpu::ShaderStages::VERTEX_FRAGMENT,
    };
    let mut by_group: BTreeMap<u32, Vec<wgpu::BindGroupLayoutEntry>> = BTreeMap::new();
    for b in &info.bindings {
        let ty = binding_type(&b.kind, bound_format(decl, pass, &b.name), features);
        by_group
            .entry(b.group)
            .or_default()
            .push(wgpu::BindGroupLayoutEntry {
                binding: b.binding,
                visibility,
                ty,
                count: None,
            });
    }
    let max_group = by_group.keys().max().copied();
    let groups: Vec<(u32, wgpu::BindGroupLayout)> = by_group
        .iter()
        .map(|(g, entries)| {
            (
                *g,
                device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                    label: Some(&pass.name),
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
        label: Some(&pass.name),
        bind_group_layouts: &all,
        immediate_size: 0,
    });
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(&info.name),
        source: wgpu::ShaderSource::Wgsl(info.source.as_str().into()),
    });
    match &pass.kind {
        PassKind::Compute { entry, .. } => {
            let workgroup = info
                .entry(entry)
                .map(|e| e.workgroup_size)
                .unwrap_or([1, 1, 1]);
            let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(&pass.name),
                layout: Some(&layout),
                module: &module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                cache: None,
            });
            Some(PassPipeline::Compute {
                pipeline,
                groups,
                workgroup,
            })
        }
        PassKind::Fullscreen {
            vertex, fragment, ..
        } => {
            let targets: Vec<Option<wgpu::ColorTargetState>> = pass
                .textures
                .iter()
                .filter(|u| u.access == crate::TextureAccess::ColorAttachment)
                .filter_map(|u| decl.resources[u.resource()].texture_desc())
                .map(|d| {
                    Some(wgpu::ColorTargetState {
                        format: d.format,
                        blend: None,
                        write_mask: wgpu::ColorWrites::ALL,
                    })
                })
                .collect();
            let depth_stencil = pass
                .textures
                .iter()
                .find(|u| {
                    matches!(
                        u.access,
                        crate::TextureAccess::DepthAttachment | crate::TextureAccess::DepthRead
                    )
                })
                .and_then(|u| decl.resources[u.resource()].texture_desc())
                .map(|d| wgpu::DepthStencilState {
                    format: d.format,
                    depth_write_enabled: Some(true),
                    depth_compare: Some(wgpu::CompareFunction::LessEqual),
                    stencil: Default::default(),
                    bias: Default::default(),
                });
            let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(&pass.name),
                layout: Some(&layout),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some(vertex),
                    compilation_options: Default::default(),
                    buffers: &[],
                },
                primitive: wgpu::PrimitiveState::default(),
                depth_stencil,
                multisample: wgpu::MultisampleState::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some(fragment),
                    compilation_options: Default::default(),
                    targets: &targets,
                }),
                multiview_mask: None,
                cache: None,
            });
            Some(PassPipeline::Render { pipeline, groups })
        }
        _ => None,
    }
}
