//! `pass_costs`: invocations, declared loads and the bytes each pass must touch, from the
//! declaration alone (GPU-free), checked against hand counts.

use aograph_graph::*;
use wgpu::TextureFormat::{R32Float, Rgba8Unorm, Rgba16Float};

const SHADERS: &[(&str, &str)] = &[
    (
        "half.wgsl",
        "@group(0) @binding(0) var src: texture_2d<f32>;\n\
         @group(0) @binding(1) var dst: texture_storage_2d<rgba16float, write>;\n\
         @compute @workgroup_size(8, 4)\n\
         fn main(@builtin(global_invocation_id) id: vec3<u32>) {\n\
             textureStore(dst, vec2<i32>(id.xy), vec4<f32>(textureLoad(src, vec2<i32>(id.xy) * 2, 0).r));\n\
         }\n",
    ),
    (
        "draw.wgsl",
        "@group(0) @binding(0) var src: texture_2d<f32>;\n\
         @vertex fn vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {\n\
             return vec4<f32>(f32(i & 1u), f32(i >> 1u), 0.0, 1.0);\n\
         }\n\
         @fragment fn fs(@builtin(position) p: vec4<f32>) -> @location(0) vec4<f32> {\n\
             return textureLoad(src, vec2<i32>(p.xy), 0);\n\
         }\n",
    ),
];

#[test]
fn costs_count_invocations_declared_loads_and_bytes_touched() {
    let lib = ShaderLibrary::inline_only();
    for (n, s) in SHADERS {
        lib.add_inline(n, s);
    }
    let mut b = GraphBuilder::new();
    let src = b.import_texture("src", TextureDesc::new(R32Float, SizeClass::FULL));
    let half = b.create_texture(
        "half",
        TextureDesc::new(Rgba16Float, SizeClass::half_pow(1)),
    );
    let mut p = b.compute_pass("downsample", "half.wgsl", "main");
    p.sample("src", src).loads_per_invocation(4.0);
    let half = p.write_storage("dst", half);
    p.dispatch_over(half);
    let out = b.create_texture("out", TextureDesc::new(Rgba8Unorm, SizeClass::FULL));
    let mut q = b.fullscreen_pass("draw", "draw.wgsl", "vs", "fs");
    q.sample("src", half);
    let out = q.color_attachment(out);
    b.export(out);
    let plan = compile(b.build(), &lib, CompileOptions::default()).unwrap();
    let size = Extent::new(64, 48);
    let costs = pass_costs(&plan, size);
    assert_eq!(costs.len(), 2);
    // 32x24 threads, each stating 4 loads; reads 64x48 x 4 B, writes 32x24 x 8 B.
    assert_eq!(costs[0].pass, "downsample");
    assert_eq!(costs[0].invocations, 32 * 24);
    assert_eq!(costs[0].loads(), Some(4.0 * 32.0 * 24.0));
    assert_eq!(costs[0].bytes_read, 64 * 48 * 4);
    assert_eq!(costs[0].bytes_written, 32 * 24 * 8);
    // One fragment per attachment pixel; no loads declared; a cleared attachment is not read.
    assert_eq!(costs[1].invocations, 64 * 48);
    assert_eq!(costs[1].loads(), None);
    assert_eq!(costs[1].bytes_read, 32 * 24 * 8);
    assert_eq!(costs[1].bytes_written, 64 * 48 * 4);
    assert_eq!(costs[1].bytes(), 32 * 24 * 8 + 64 * 48 * 4);
}
