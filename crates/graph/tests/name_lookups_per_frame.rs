//! A frame that reuses a plan looks nothing up by name: imports by name resolve to slots when
//! the plan is first bound (and again only after a new name is imported), histories resolve at
//! compile. Counted with the graph's own counter of name lookups
//! (`aograph_graph::name_lookup_count`), on a plan with an imported buffer, an imported
//! texture and a history, each frame checked against its known answer.

use std::sync::Arc;

use aograph_graph::*;
use wgpu::TextureFormat::R32Float;

#[path = "common/test_passes.rs"]
mod test_passes;
use test_passes::shaders;

/// dst = value[0] + src (an imported buffer and an imported texture).
const ADD_IMPORTS: &str = "
@group(0) @binding(0) var<storage, read> value: array<f32>;
@group(0) @binding(1) var src: texture_2d<f32>;
@group(0) @binding(2) var dst: texture_storage_2d<r32float, write>;
@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(dst);
    if (id.x >= size.x || id.y >= size.y) { return; }
    let s = textureLoad(src, vec2<i32>(id.xy), 0).r;
    textureStore(dst, vec2<i32>(id.xy), vec4<f32>(value[0] + s, 0.0, 0.0, 0.0));
}
";

#[test]
fn frames_of_a_bound_plan_look_up_no_name() {
    let Some(gpu) = test_gpu() else { return };
    let lib = shaders();
    lib.add_inline("add_imports.wgsl", ADD_IMPORTS);
    let desc = TextureDesc::new(R32Float, SizeClass::FULL);
    let mut b = GraphBuilder::new();
    let value = b.import_buffer("value", BufferDesc { size: 4 });
    let src = b.import_texture("src", desc);
    let sum = b.create_texture("sum", desc);
    let mut p = b.compute_pass("add", "add_imports.wgsl", "main");
    p.read_buffer("value", BufferAccess::StorageRead, value);
    p.sample("src", src);
    let sum = p.write_storage("dst", sum);
    p.dispatch_over(sum);
    let hist = b.history_texture("count", desc);
    let mut p = b.compute_pass("accumulate", "accumulate.wgsl", "main");
    p.sample("previous", hist.previous);
    let count = p.write_storage("current", hist.current);
    p.dispatch_over(count);
    b.export(sum);
    b.export(count);
    let plan = Arc::new(compile(b.build(), &lib, CompileOptions::default()).unwrap());

    let mut exec = Executor::with_shaders(gpu.clone(), Arc::new(lib));
    let size = Extent::new(7, 5); // odd, non-square
    let (w, h) = (size.width, size.height);
    use wgpu::util::DeviceExt;
    let buffer = gpu
        .device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: None,
            contents: &1.5f32.to_le_bytes(),
            usage: wgpu::BufferUsages::STORAGE,
        });
    let texels: Vec<u8> = (0..w * h).flat_map(|i| (i as f32).to_le_bytes()).collect();
    let texture = gpu.device.create_texture_with_data(
        &gpu.queue,
        &wgpu::TextureDescriptor {
            label: None,
            size: wgpu::Extent3d {
                width: w,
                height: h,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: R32Float,
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        &texels,
    );
    exec.import_buffer("value", buffer);
    exec.import_texture("src", texture);

    let frame = |exec: &mut Executor| {
        let valid = exec.all_history_valid(&plan, size);
        exec.execute(&plan, size).unwrap();
        valid
    };
    // The first frame resolves the plan's import names (two imports).
    let before_first = name_lookup_count();
    assert!(!frame(&mut exec), "no history on the first frame");
    assert_eq!(name_lookup_count() - before_first, 2);
    let before = name_lookup_count();
    for _ in 0..20 {
        assert!(
            frame(&mut exec),
            "the history is valid from the second frame"
        );
    }
    assert_eq!(
        name_lookup_count() - before,
        0,
        "20 frames of a bound plan looked names up"
    );
    // Known answers: 21 frames counted; value + the texel index.
    let count = exec.read_texture(&plan, count).unwrap().to_f32().unwrap();
    assert!(count.iter().all(|&c| c == 21.0), "{count:?}");
    let sum = exec.read_texture(&plan, sum).unwrap().to_f32().unwrap();
    let want: Vec<f32> = (0..w * h).map(|i| 1.5 + i as f32).collect();
    assert_eq!(sum, want);

    // A name imported since makes the plan resolve its imports again, once.
    exec.import_buffer(
        "unused",
        gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: None,
            size: 4,
            usage: wgpu::BufferUsages::STORAGE,
            mapped_at_creation: false,
        }),
    );
    let before = name_lookup_count();
    frame(&mut exec);
    frame(&mut exec);
    assert_eq!(
        name_lookup_count() - before,
        2,
        "one resolution of two imports"
    );
}
