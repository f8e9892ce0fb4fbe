//! An application's frame made from aograph's own g-buffer, for the embedding tests: its
//! linear depth written into a hardware depth buffer of any format and convention (a
//! full-screen pass writing `frag_depth`, as the application's depth pre-pass would leave it),
//! and its view-space normals re-encoded in the application's encodings.

use glam::{Mat4, Vec2, Vec3};

/// The depth `proj` stores for linear depth `lin` (0 = sky: the far plane's value).
pub fn hardware_depth(proj: Mat4, lin: f32, reversed: bool) -> f32 {
    if lin <= 0.0 {
        return if reversed { 0.0 } else { 1.0 };
    }
    let (p22, p32) = (proj.z_axis.z, proj.w_axis.z);
    if proj.w_axis.w == 1.0 {
        p32 - p22 * lin
    } else {
        p32 / lin - p22
    }
}

const DEPTH_WRITER: &str = r#"
@group(0) @binding(0) var lin: texture_2d<f32>;
@group(0) @binding(1) var<uniform> rows: vec4<f32>; // P22, P32, orthographic, far value

@vertex
fn vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let uv = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(uv * 2.0 - 1.0, 0.0, 1.0);
}

@fragment
fn fs(@builtin(position) frag: vec4<f32>) -> @builtin(frag_depth) f32 {
    let l = textureLoad(lin, vec2<i32>(frag.xy), 0).r;
    if (l <= 0.0) { return rows.w; }
    if (rows.z > 0.5) { return clamp(rows.y - rows.x * l, 0.0, 1.0); }
    return clamp(rows.y / l - rows.x, 0.0, 1.0);
}
"#;

/// A texture of `format` holding `bytes` (tightly packed rows).
pub fn upload(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    format: wgpu::TextureFormat,
    (w, h): (u32, u32),
    bytes: &[u8],
) -> wgpu::Texture {
    let t = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("user input"),
        size: wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    let bpp = format.block_copy_size(None).expect("colour format");
    queue.write_texture(
        t.as_image_copy(),
        bytes,
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(w * bpp),
            rows_per_image: Some(h),
        },
        wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
    );
    t
}

/// A `format` depth buffer holding linear depth `lin` through `proj` (reversed: sky is 0).
pub fn depth_buffer(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    lin: &[f32],
    size: (u32, u32),
    proj: Mat4,
    reversed: bool,
    format: wgpu::TextureFormat,
) -> wgpu::Texture {
    let src = upload(
        device,
        queue,
        wgpu::TextureFormat::R32Float,
        size,
        bytemuck::cast_slice(lin),
    );
    let depth = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("user depth"),
        size: wgpu::Extent3d {
            width: size.0,
            height: size.1,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
        view_formats: &[],
    });
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("depth writer"),
        source: wgpu::ShaderSource::Wgsl(DEPTH_WRITER.into()),
    });
    let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("depth writer"),
        layout: None,
        vertex: wgpu::VertexState {
            module: &module,
            entry_point: Some("vs"),
            compilation_options: Default::default(),
            buffers: &[],
        },
        primitive: Default::default(),
        depth_stencil: Some(wgpu::DepthStencilState {
            format,
            depth_write_enabled: Some(true),
            depth_compare: Some(wgpu::CompareFunction::Always),
            stencil: Default::default(),
            bias: Default::default(),
        }),
        multisample: Default::default(),
        fragment: Some(wgpu::FragmentState {
            module: &module,
            entry_point: Some("fs"),
            compilation_options: Default::default(),
            targets: &[],
        }),
        multiview_mask: None,
        cache: None,
    });
    let ortho = proj.w_axis.w == 1.0;
    let rows = [
        proj.z_axis.z,
        proj.w_axis.z,
        ortho as u32 as f32,
        if reversed { 0.0 } else { 1.0 },
    ];
    let uniform = wgpu::util::DeviceExt::create_buffer_init(
        device,
        &wgpu::util::BufferInitDescriptor {
            label: Some("rows"),
            contents: bytemuck::cast_slice(&rows),
            usage: wgpu::BufferUsages::UNIFORM,
        },
    );
    let src_view = src.create_view(&Default::default());
    let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(&src_view),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: uniform.as_entire_binding(),
            },
        ],
    });
    let view = depth.create_view(&Default::default());
    let mut enc = device.create_command_encoder(&Default::default());
    {
        let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("depth writer"),
            color_attachments: &[],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(rows[3]),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            ..Default::default()
        });
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind, &[]);
        pass.draw(0..3, 0..1);
    }
    queue.submit([enc.finish()]);
    depth
}

/// Octahedral encoding of a unit vector, xy in [-1, 1] (Cigolle et al. 2014).
pub fn oct_encode(n: Vec3) -> Vec2 {
    let p = Vec2::new(n.x, n.y) / (n.x.abs() + n.y.abs() + n.z.abs());
    if n.z >= 0.0 {
        p
    } else {
        let s = Vec2::new(
            if p.x >= 0.0 { 1.0 } else { -1.0 },
            if p.y >= 0.0 { 1.0 } else { -1.0 },
        );
        (Vec2::ONE - Vec2::new(p.y.abs(), p.x.abs())) * s
    }
}

/// Rgb10a2Unorm bits of `v` in [0, 1]^3 (alpha 1).
pub fn pack_rgb10a2(v: Vec3) -> u32 {
    let q = |x: f32| ((x.clamp(0.0, 1.0) * 1023.0).round() as u32) & 1023;
    q(v.x) | (q(v.y) << 10) | (q(v.z) << 20) | (3 << 30)
}
