//! The passes of `mssao`, one function per pass kind, and the uniform block they share
//! (mirrored by `MssaoParams` in shaders/common/mssao.wgsl).

use aograph_frame::ReadsView;
use aograph_graph::{SizeClass, TextureDesc, TextureHandle};
use bytemuck::{Pod, Zeroable};

use super::MssaoParams;
use crate::technique::AoBuildContext;

/// Format of pyramid depth (the g-buffer's LinearDepth format): positions are rebuilt from it.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;
/// Format of pyramid normals (the g-buffer's NormalsOct format: octahedral, one u32).
pub const NORMAL_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Uint;

/// One level of the g-buffer pyramid: linear depth and octahedral normals, 8 bytes a texel.
#[derive(Clone, Copy, Debug)]
pub struct Level {
    pub depth: TextureHandle,
    pub normals: TextureHandle,
}

/// The constants every MSSAO pass reads (48 bytes, WGSL uniform layout).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct MssaoUniform {
    pub level: u32,
    pub bilateral_blur: u32,
    /// `Upsampling::code`.
    pub upsampling: u32,
    pub pad0: u32,
    /// d_max of Eq. 7 = the shared radius R.
    pub d_max: f32,
    pub r_max: f32,
    pub d_threshold: f32,
    pub normal_power: f32,
    pub depth_power: f32,
    pub pad1: [f32; 3],
}

aograph_graph::uniform_layout!(MssaoUniform {
    level,
    bilateral_blur,
    upsampling,
    pad0,
    d_max,
    r_max,
    d_threshold,
    normal_power,
    depth_power,
    pad1
});

impl MssaoUniform {
    pub fn new(p: &MssaoParams, radius: f32, level: u32) -> Self {
        Self {
            level,
            bilateral_blur: p.bilateral_blur as u32,
            upsampling: p.upsampling.code(),
            pad0: 0,
            d_max: radius,
            r_max: p.r_max,
            d_threshold: p.d_threshold,
            normal_power: p.normal_power,
            depth_power: p.depth_power,
            pad1: [0.0; 3],
        }
    }
}

fn common(
    p: &mut aograph_graph::PassBuilder<'_>,
    view: aograph_graph::BufferHandle,
    u: &MssaoUniform,
) {
    p.read_view(view);
    p.uniform_struct("params", u);
}

/// `mssao.downsample{l}`: level l of the g-buffer pyramid from level l - 1 (Table 2).
pub fn downsample(ctx: &mut AoBuildContext<'_>, l: u32, src: Level, u: &MssaoUniform) -> Level {
    let size = SizeClass::half_pow(l);
    let depth = ctx.builder.create_texture(
        &format!("mssao.depth{l}"),
        TextureDesc::new(DEPTH_FORMAT, size),
    );
    let normals = ctx.builder.create_texture(
        &format!("mssao.normals{l}"),
        TextureDesc::new(NORMAL_FORMAT, size),
    );
    let view = ctx.view;
    let mut p = ctx.builder.compute_pass(
        &format!("mssao.downsample{l}"),
        "ao/mssao/downsample.wgsl",
        "main",
    );
    common(&mut p, view, u);
    p.sample("src_depth", src.depth)
        .sample("src_normals", src.normals)
        .loads_per_invocation(8.0); // 2x2 depths and normals (Table 2)
    let depth = p.write_storage("dst_depth", depth);
    let normals = p.write_storage("dst_normals", normals);
    p.dispatch_over(depth);
    Level { depth, normals }
}

/// `mssao.ao{l}` for a level l >= 1: the tuple of Eq. 10. `far` is the blurred tuple of level
/// l + 1 with that level's g-buffer (None at the coarsest level).
pub fn ao_level(
    ctx: &mut AoBuildContext<'_>,
    l: u32,
    g: Level,
    far: Option<(TextureHandle, Level)>,
    u: &MssaoUniform,
) -> TextureHandle {
    // The per-level tuple (AO_max, sum, count) at the intermediate precision (module docs).
    let tuple = ctx.builder.create_texture(
        &format!("mssao.tuple{l}"),
        TextureDesc::new(ctx.intermediate_rgba_format(), SizeClass::half_pow(l)),
    );
    let shader = ctx.shader(if far.is_some() {
        "ao/mssao/ao_level.wgsl"
    } else {
        "ao/mssao/ao_coarsest.wgsl"
    });
    let view = ctx.view;
    let mut p = ctx
        .builder
        .compute_pass(&format!("mssao.ao{l}"), &shader, "main");
    common(&mut p, view, u);
    p.sample("depth", g.depth).sample("normals", g.normals);
    if let Some((coarse, cg)) = far {
        p.sample("coarse_ao", coarse)
            .sample("coarse_depth", cg.depth)
            .sample("coarse_normals", cg.normals);
    }
    let tuple = p.write_storage("ao", tuple);
    p.dispatch_over(tuple);
    tuple
}

/// `mssao.blur{l}`: the 3x3 low-pass filter of level l's tuple before upsampling (Table 4).
pub fn blur(
    ctx: &mut AoBuildContext<'_>,
    l: u32,
    tuple: TextureHandle,
    g: Level,
    u: &MssaoUniform,
) -> TextureHandle {
    let out = ctx.builder.create_texture(
        &format!("mssao.blurred{l}"),
        TextureDesc::new(ctx.intermediate_rgba_format(), SizeClass::half_pow(l)),
    );
    let view = ctx.view;
    let shader = ctx.shader("ao/mssao/blur.wgsl");
    let mut p = ctx
        .builder
        .compute_pass(&format!("mssao.blur{l}"), &shader, "main");
    common(&mut p, view, u);
    p.sample("depth", g.depth)
        .sample("normals", g.normals)
        .sample("src", tuple)
        // 3x3 tuples, and each workgroup's 10x10 tile of depths and normals (shaders/ao/mssao/
        // blur.wgsl) shared by its 64 threads (Table 4).
        .loads_per_invocation(9.0 + 2.0 * 100.0 / 64.0);
    let out = p.write_storage("dst", out);
    p.dispatch_over(out);
    out
}

/// `mssao.ao0`: the finest level, Eq. 11, the accessibility output. `far` as in [`ao_level`]
/// (None when n = 1).
pub fn ao_finest(
    ctx: &mut AoBuildContext<'_>,
    g: Level,
    far: Option<(TextureHandle, Level)>,
    u: &MssaoUniform,
) -> TextureHandle {
    let out = ctx.accessibility_texture("ao");
    let shader = if far.is_some() {
        "ao/mssao/ao_final.wgsl"
    } else {
        "ao/mssao/ao_single.wgsl"
    };
    let view = ctx.view;
    let mut p = ctx.builder.compute_pass("mssao.ao0", shader, "main");
    common(&mut p, view, u);
    p.sample("depth", g.depth).sample("normals", g.normals);
    if let Some((coarse, cg)) = far {
        p.sample("coarse_ao", coarse)
            .sample("coarse_depth", cg.depth)
            .sample("coarse_normals", cg.normals);
    }
    let out = p.write_storage("accessibility", out);
    p.dispatch_over(out);
    out
}
