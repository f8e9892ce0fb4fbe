//! GPU tests of declared samplers: what a pass declares with `PassBuilder::sampler` is what
//! its shader samples with (filter and address mode), whatever the WGSL global is called, and
//! the executor makes one sampler per distinct description, not one per pass, plan or frame.
//! Skips (saying so) only when no adapter exists and AOGRAPH_REQUIRE_GPU is unset.

use std::sync::Arc;

use aograph_graph::wgpu::{AddressMode, FilterMode, TextureFormat};
use aograph_graph::*;

/// Samples a 2x1 texture holding 0 and 1 at u = 0.6 (between the texel centres) and at
/// u = 1.3 (outside, so the address mode decides), into texels 0 and 1 of `dst`.
const PROBE: &str = "@group(0) @binding(0) var src: texture_2d<f32>;
@group(0) @binding(1) var linear_probe: sampler;
@group(0) @binding(2) var dst: texture_storage_2d<r32float, write>;
@compute @workgroup_size(1)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    var u = 0.6;
    if (id.x == 1u) { u = 1.3; }
    let v = textureSampleLevel(src, linear_probe, vec2<f32>(u, 0.5), 0.0).r;
    textureStore(dst, vec2<i32>(id.xy), vec4<f32>(v, 0.0, 0.0, 0.0));
}
";

const NEAREST_REPEAT: SamplerDesc = SamplerDesc {
    filter: FilterMode::Nearest,
    address: AddressMode::Repeat,
};

fn shaders() -> ShaderLibrary {
    let lib = ShaderLibrary::inline_only();
    lib.add_inline("probe.wgsl", PROBE);
    lib
}

/// One probing pass per description, each into its own exported output.
fn plan(descs: &[SamplerDesc]) -> (Arc<CompiledGraph>, Vec<TextureHandle>) {
    let mut b = GraphBuilder::new();
    let size = SizeClass::fixed(2, 1);
    let src = b.import_texture(
        "two_texels",
        TextureDesc::new(TextureFormat::Rgba8Unorm, size),
    );
    let mut outs = Vec::new();
    for (i, desc) in descs.iter().enumerate() {
        let out = b.create_texture(
            &format!("out{i}"),
            TextureDesc::new(TextureFormat::R32Float, size),
        );
        let mut p = b.compute_pass(&format!("probe{i}"), "probe.wgsl", "main");
        p.sample("src", src).sampler("linear_probe", *desc);
        let out = p.write_storage("dst", out);
        p.dispatch_workgroups(2, 1, 1);
        b.export(out);
        outs.push(out);
    }
    let plan = compile(b.build(), &shaders(), CompileOptions::default()).expect("compiles");
    (Arc::new(plan), outs)
}

fn two_texels(gpu: &GpuContext) -> wgpu::Texture {
    let texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some("two texels"),
        size: wgpu::Extent3d {
            width: 2,
            height: 1,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: TextureFormat::Rgba8Unorm,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    gpu.queue.write_texture(
        texture.as_image_copy(),
        &[0, 0, 0, 255, 255, 0, 0, 255],
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(8),
            rows_per_image: Some(1),
        },
        wgpu::Extent3d {
            width: 2,
            height: 1,
            depth_or_array_layers: 1,
        },
    );
    texture
}

#[test]
fn declared_filter_and_address_are_what_the_shader_samples_with() {
    let Some(gpu) = test_gpu() else { return };
    let descs = [
        SamplerDesc::LINEAR_CLAMP,
        SamplerDesc::NEAREST_CLAMP,
        NEAREST_REPEAT,
    ];
    let (plan, outs) = plan(&descs);
    let mut exec = Executor::new(gpu.clone());
    exec.import_texture("two_texels", two_texels(&gpu));
    exec.execute(&plan, Extent::new(4, 4)).expect("frame");
    let read = |h| exec.read_texture(&plan, h).unwrap().to_f32().unwrap();
    let linear = read(outs[0]);
    assert!(
        (linear[0] - 0.7).abs() < 0.01 && linear[1] == 1.0,
        "linear clamp: {linear:?}"
    );
    // The global is called `linear_probe`: declared nearest, it does not filter.
    assert_eq!(read(outs[1]), vec![1.0, 1.0], "nearest clamp");
    assert_eq!(
        read(outs[2]),
        vec![1.0, 0.0],
        "nearest repeat wraps u = 1.3 to 0.3"
    );
    assert!(gpu.take_errors().is_empty());
}

#[test]
fn one_sampler_per_distinct_description_across_passes_plans_and_frames() {
    let Some(gpu) = test_gpu() else { return };
    let mut exec = Executor::new(gpu.clone());
    exec.import_texture("two_texels", two_texels(&gpu));
    assert_eq!(exec.sampler_count(), 0, "made when a plan needs them");
    let (a, _) = plan(&[
        SamplerDesc::LINEAR_CLAMP,
        NEAREST_REPEAT,
        SamplerDesc::LINEAR_CLAMP,
    ]);
    assert_eq!(a.samplers.len(), 2);
    for _ in 0..3 {
        exec.execute(&a, Extent::new(4, 4)).unwrap();
    }
    assert_eq!(exec.sampler_count(), 2);
    let (b, _) = plan(&[SamplerDesc::NEAREST_CLAMP, SamplerDesc::LINEAR_CLAMP]);
    for _ in 0..3 {
        exec.execute(&b, Extent::new(4, 4)).unwrap();
        exec.execute(&a, Extent::new(4, 4)).unwrap();
    }
    assert_eq!(exec.sampler_count(), 3, "only NEAREST_CLAMP is new");
    gpu.wait_idle().unwrap();
    assert!(gpu.take_errors().is_empty());
}
