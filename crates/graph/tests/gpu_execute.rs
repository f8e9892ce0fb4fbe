//! GPU tests of execution on a real wgpu device (lavapipe where there is no GPU): results read
//! back and compared with a CPU computation of the same arithmetic, history across frames,
//! resize and reset invalidation, reuse on/off equivalence, timings and pool stability.
//! Each test skips (saying so) only when no adapter exists and AOGRAPH_REQUIRE_GPU is unset.

use std::sync::Arc;

use aograph_graph::*;
use wgpu::TextureFormat::R32Float;

#[path = "common/test_passes.rs"]
mod test_passes;
use test_passes::{params, pattern, shaders};

/// CPU version of the three-pass graph below.
fn expected(w: u32, h: u32, scale: f32, offset: f32) -> Vec<f32> {
    let mut out = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let (xl, xr) = (x.saturating_sub(1), (x + 1).min(w - 1));
            let blurred = (pattern(xl, y) + 2.0 * pattern(x, y) + pattern(xr, y)) * 0.25;
            out.push(blurred * scale + offset);
        }
    }
    out
}

fn render_blur_scale(b: &mut GraphBuilder) -> (TextureHandle, UniformHandle) {
    let desc = TextureDesc::new(R32Float, SizeClass::FULL);
    let img = b.create_texture("pattern", desc);
    let img = b
        .fullscreen_pass("pattern", "pattern.wgsl", "vs", "fs")
        .color_attachment(img);
    let tmp = b.create_texture("blurred", desc);
    let mut blur = b.compute_pass("blur", "blur.wgsl", "main");
    blur.sample("src", img);
    let tmp = blur.write_storage("dst", tmp);
    blur.dispatch_over(tmp);
    let out = b.create_texture("result", desc);
    let mut scale = b.compute_pass("scale", "scale.wgsl", "main");
    scale.sample("src", tmp);
    let u = scale.uniform("params", &params(2.0, 1.0));
    let out = scale.write_storage("dst", out);
    scale.dispatch_over(out);
    b.export(out);
    (out, u)
}

#[test]
fn render_blur_and_compute_match_cpu_arithmetic() {
    let Some(gpu) = test_gpu() else { return };
    let mut b = GraphBuilder::new();
    let (out, uniform) = render_blur_scale(&mut b);
    let plan =
        Arc::new(compile(b.build(), &shaders(), CompileOptions::default()).expect("compiles"));
    let mut exec = Executor::new(gpu.clone());
    let size = Extent::new(64, 48);
    exec.execute(&plan, size).expect("first frame");
    let got = exec.read_texture(&plan, out).unwrap().to_f32().unwrap();
    assert_eq!(
        got,
        expected(64, 48, 2.0, 1.0),
        "values are multiples of 1/64, so GPU and CPU agree exactly"
    );

    // Per-frame uniform update, same plan.
    exec.write_uniform(&plan, uniform, &params(-1.0, 0.5))
        .unwrap();
    exec.execute(&plan, size).unwrap();
    let got = exec.read_texture(&plan, out).unwrap().to_f32().unwrap();
    assert_eq!(got, expected(64, 48, -1.0, 0.5));
    assert!(gpu.take_errors().is_empty());
}

#[test]
fn odd_output_sizes_are_covered_by_dispatch() {
    let Some(gpu) = test_gpu() else { return };
    let mut b = GraphBuilder::new();
    let (out, _) = render_blur_scale(&mut b);
    let plan = Arc::new(compile(b.build(), &shaders(), CompileOptions::default()).unwrap());
    let mut exec = Executor::new(gpu);
    for (w, h) in [(1, 1), (2, 3), (97, 61)] {
        exec.execute(&plan, Extent::new(w, h)).unwrap();
        let got = exec.read_texture(&plan, out).unwrap().to_f32().unwrap();
        assert_eq!(got, expected(w, h, 2.0, 1.0), "{w}x{h}");
    }
}

fn accumulate_graph() -> (Arc<CompiledGraph>, TextureHandle) {
    let mut b = GraphBuilder::new();
    let hist = b.history_texture("count", TextureDesc::new(R32Float, SizeClass::FULL));
    let mut p = b.compute_pass("accumulate", "accumulate.wgsl", "main");
    p.sample("previous", hist.previous);
    let cur = p.write_storage("current", hist.current);
    p.dispatch_over(cur);
    (
        Arc::new(compile(b.build(), &shaders(), CompileOptions::default()).unwrap()),
        cur,
    )
}

fn all_equal(exec: &Executor, plan: &CompiledGraph, h: TextureHandle, v: f32) -> bool {
    exec.read_texture(plan, h)
        .unwrap()
        .to_f32()
        .unwrap()
        .iter()
        .all(|&x| x == v)
}

#[test]
fn history_is_invalid_on_first_frame_then_reads_previous_values() {
    let Some(gpu) = test_gpu() else { return };
    let (plan, cur) = accumulate_graph();
    let mut exec = Executor::new(gpu);
    let size = Extent::new(32, 32);
    assert!(
        !exec.history_valid(&plan, "count", size),
        "first frame has no history"
    );
    exec.execute(&plan, size).unwrap();
    assert!(
        all_equal(&exec, &plan, cur, 1.0),
        "invalid previous reads as zero"
    );
    for frame in 2..=3 {
        assert!(exec.history_valid(&plan, "count", size));
        exec.execute(&plan, size).unwrap();
        assert!(
            all_equal(&exec, &plan, cur, frame as f32),
            "frame {frame} adds to the previous value"
        );
    }
}

#[test]
fn resize_and_reset_invalidate_history() {
    let Some(gpu) = test_gpu() else { return };
    let (plan, cur) = accumulate_graph();
    let mut exec = Executor::new(gpu);
    for _ in 0..3 {
        exec.execute(&plan, Extent::new(32, 32)).unwrap();
    }
    assert!(all_equal(&exec, &plan, cur, 3.0));
    let resized = Extent::new(40, 24);
    assert!(
        !exec.history_valid(&plan, "count", resized),
        "a resize invalidates"
    );
    exec.execute(&plan, resized).unwrap();
    assert!(all_equal(&exec, &plan, cur, 1.0));
    exec.execute(&plan, resized).unwrap();
    assert!(all_equal(&exec, &plan, cur, 2.0));
    exec.reset_history();
    assert!(
        !exec.history_valid(&plan, "count", resized),
        "a reset (camera cut) invalidates"
    );
    exec.execute(&plan, resized).unwrap();
    assert!(
        all_equal(&exec, &plan, cur, 1.0),
        "nothing from before the cut survives"
    );
}

/// A chain of blurs through same-descriptor intermediates: reuse folds them into two textures.
fn blur_chain(b: &mut GraphBuilder, n: usize) -> TextureHandle {
    let desc = TextureDesc::new(R32Float, SizeClass::FULL);
    let img = b.create_texture("pattern", desc);
    let mut cur = b
        .fullscreen_pass("pattern", "pattern.wgsl", "vs", "fs")
        .color_attachment(img);
    for i in 0..n {
        let t = b.create_texture(&format!("blur{i}"), desc);
        let mut p = b.compute_pass(&format!("blur{i}"), "blur.wgsl", "main");
        p.sample("src", cur);
        cur = p.write_storage("dst", t);
        p.dispatch_over(cur);
    }
    b.export(cur);
    cur
}

#[test]
fn reuse_on_and_off_give_identical_images() {
    let Some(gpu) = test_gpu() else { return };
    let mut images = Vec::new();
    let mut physical = Vec::new();
    for reuse in [true, false] {
        let mut b = GraphBuilder::new();
        let out = blur_chain(&mut b, 6);
        let plan = Arc::new(compile(b.build(), &shaders(), CompileOptions { reuse }).unwrap());
        physical.push(plan.physical.len());
        let mut exec = Executor::new(gpu.clone());
        exec.execute(&plan, Extent::new(50, 30)).unwrap();
        images.push(exec.read_texture(&plan, out).unwrap().bytes);
    }
    assert_eq!(images[0], images[1]);
    assert!(
        physical[0] < physical[1],
        "reuse {} textures, without {}",
        physical[0],
        physical[1]
    );
}

#[test]
fn timings_name_every_pass_from_both_sources() {
    let Some(gpu) = test_gpu() else { return };
    let mut b = GraphBuilder::new();
    blur_chain(&mut b, 3);
    let plan = Arc::new(compile(b.build(), &shaders(), CompileOptions::default()).unwrap());
    let mut exec = Executor::new(gpu.clone());
    let mut modes = vec![TimingMode::CpuWall];
    if gpu.has_timestamps() {
        modes.insert(0, TimingMode::GpuTimestamps);
    }
    for mode in modes {
        exec.set_timing(mode).unwrap();
        let frame = exec.execute(&plan, Extent::new(64, 64)).unwrap();
        let t = exec.wait_timings().unwrap().clone();
        assert_eq!(
            t.frame,
            Some(frame),
            "{mode:?}: the table is tagged with its frame"
        );
        assert_eq!(
            t.passes.iter().map(|(n, _)| n.as_str()).collect::<Vec<_>>(),
            ["pattern", "blur0", "blur1", "blur2"]
        );
        assert!(t.passes.iter().all(|(_, ms)| ms.is_finite() && *ms >= 0.0));
        let expected = match mode {
            TimingMode::CpuWall => TimingSource::CpuWall,
            _ => TimingSource::GpuTimestamps,
        };
        assert_eq!(t.source, Some(expected));
        assert!(t.table().contains("blur2") && t.table().contains("total"));
    }
    // Timing off: frames run, no new table arrives.
    exec.set_timing(TimingMode::Off).unwrap();
    let before = exec.wait_timings().unwrap().frame;
    exec.execute(&plan, Extent::new(64, 64)).unwrap();
    assert_eq!(exec.wait_timings().unwrap().frame, before);
}

/// Free textures wait `TexturePool::IDLE_FRAMES` (8) frames for a taker, so plans that take
/// turns keep theirs; after a resize the old size's textures are dropped once that many frames
/// passed, so the pool never holds more than both sizes' sets and returns to one set.
#[test]
fn pool_does_not_grow_across_resizes() {
    let Some(gpu) = test_gpu() else { return };
    let mut b = GraphBuilder::new();
    blur_chain(&mut b, 4);
    let plan = Arc::new(compile(b.build(), &shaders(), CompileOptions::default()).unwrap());
    let mut exec = Executor::new(gpu);
    exec.execute(&plan, Extent::new(16, 16)).unwrap();
    let steady = exec.pool_texture_count();
    for i in 0..60u32 {
        let size = if (i / 12) % 2 == 0 {
            Extent::new(16, 16)
        } else {
            Extent::new(24, 8)
        };
        exec.execute(&plan, size).unwrap();
        assert!(
            exec.pool_texture_count() <= steady * 2,
            "frame {i}: pool holds {}",
            exec.pool_texture_count()
        );
        if i % 12 >= 9 {
            assert_eq!(exec.pool_texture_count(), steady, "frame {i}: steady state");
        }
    }
}

#[test]
fn zero_size_output_is_an_error_not_a_panic() {
    let Some(gpu) = test_gpu() else { return };
    let mut b = GraphBuilder::new();
    blur_chain(&mut b, 1);
    let plan = Arc::new(compile(b.build(), &shaders(), CompileOptions::default()).unwrap());
    let mut exec = Executor::new(gpu);
    let err = exec.execute(&plan, Extent::new(0, 8)).unwrap_err();
    assert!(err.to_string().contains("output size"), "{err}");
}

#[test]
fn missing_import_is_reported_by_name() {
    let Some(gpu) = test_gpu() else { return };
    let mut b = GraphBuilder::new();
    let src = b.import_texture("gbuffer.depth", TextureDesc::new(R32Float, SizeClass::FULL));
    let out = b.create_texture("out", TextureDesc::new(R32Float, SizeClass::FULL));
    let mut p = b.compute_pass("blur", "blur.wgsl", "main");
    p.sample("src", src);
    let out = p.write_storage("dst", out);
    p.dispatch_over(out);
    b.export(out);
    let plan = Arc::new(compile(b.build(), &shaders(), CompileOptions::default()).unwrap());
    let mut exec = Executor::new(gpu.clone());
    let err = exec.execute(&plan, Extent::new(8, 8)).unwrap_err();
    assert!(err.to_string().contains("gbuffer.depth"), "{err}");
    // With the import provided, the blur of a constant image is that constant.
    let tex = gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: None,
        size: wgpu::Extent3d {
            width: 8,
            height: 8,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: R32Float,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    let data: Vec<u8> = (0..64).flat_map(|_| 0.75f32.to_le_bytes()).collect();
    gpu.queue.write_texture(
        tex.as_image_copy(),
        &data,
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(32),
            rows_per_image: None,
        },
        tex.size(),
    );
    exec.import_texture("gbuffer.depth", tex);
    exec.execute(&plan, Extent::new(8, 8)).unwrap();
    assert!(
        exec.read_texture(&plan, out)
            .unwrap()
            .to_f32()
            .unwrap()
            .iter()
            .all(|&v| v == 0.75)
    );
}

/// Two executors on two threads share one device, as two renderers in one application (or
/// two tests) do: a thread's poll may run the other's timestamp map callback after that
/// thread's own poll returned. The readback buffer must never be mapped when a frame copies
/// into it ("Buffer with 'timestamp readback' label is still mapped" at submit, before).
#[test]
fn executors_on_two_threads_keep_their_timestamp_readback_unmapped() {
    let Some(gpu) = test_gpu() else { return };
    let _ = gpu.take_errors();
    let threads: Vec<_> = (0..2)
        .map(|t| {
            let gpu = gpu.clone();
            std::thread::spawn(move || {
                let mut b = GraphBuilder::new();
                blur_chain(&mut b, 2);
                let plan =
                    Arc::new(compile(b.build(), &shaders(), CompileOptions::default()).unwrap());
                let mut exec = Executor::new(gpu.clone());
                let scope = gpu.device.push_error_scope(wgpu::ErrorFilter::Validation);
                for frame in 0..150u32 {
                    exec.execute(&plan, Extent::new(16 + t, 16)).unwrap();
                    if frame % 7 == 0 {
                        exec.latest_timings().unwrap();
                    }
                    if frame % 31 == 0 {
                        exec.wait_timings().unwrap();
                    }
                }
                pollster::block_on(scope.pop()).map(|e| e.to_string())
            })
        })
        .collect();
    for t in threads {
        let error = t.join().expect("thread runs");
        assert!(error.is_none(), "{error:?}");
    }
    assert!(gpu.take_errors().is_empty());
}

#[test]
fn supports_reports_format_usages() {
    let Some(gpu) = test_gpu() else { return };
    let storage = wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::TEXTURE_BINDING;
    assert!(gpu.supports(R32Float, storage));
    assert!(gpu.supports(
        wgpu::TextureFormat::Depth32Float,
        wgpu::TextureUsages::RENDER_ATTACHMENT
    ));
    assert!(!gpu.supports(wgpu::TextureFormat::Depth32Float, storage));
    println!(
        "{}: r16float storage {}",
        gpu.describe(),
        gpu.supports(wgpu::TextureFormat::R16Float, storage)
    );
}

/// Copies `value[0]` of an imported storage buffer into every texel.
const FILL_FROM_BUFFER: &str = "
@group(0) @binding(0) var<storage, read> value: array<f32>;
@group(0) @binding(1) var dst: texture_storage_2d<r32float, write>;
@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(dst);
    if (id.x >= size.x || id.y >= size.y) { return; }
    textureStore(dst, vec2<i32>(id.xy), vec4<f32>(value[0], 0.0, 0.0, 0.0));
}
";

#[test]
fn an_imported_buffer_replaced_between_frames_is_bound_the_next_frame() {
    // The bind group cache must key on the buffer too: the renderer replaces the scene BVH's
    // buffers under the same import names when the scene changes.
    let Some(gpu) = test_gpu() else { return };
    let lib = shaders();
    lib.add_inline("fill_from_buffer.wgsl", FILL_FROM_BUFFER);
    let mut b = GraphBuilder::new();
    let input = b.import_buffer("value", BufferDesc { size: 4 });
    let out = b.create_texture("out", TextureDesc::new(R32Float, SizeClass::FULL));
    let mut p = b.compute_pass("fill", "fill_from_buffer.wgsl", "main");
    p.read_buffer("value", BufferAccess::StorageRead, input);
    let out = p.write_storage("dst", out);
    p.dispatch_over(out);
    b.export(out);
    let plan = Arc::new(compile(b.build(), &lib, CompileOptions::default()).unwrap());
    let mut exec = Executor::with_shaders(gpu.clone(), Arc::new(lib));
    let buffer = |v: f32| {
        use wgpu::util::DeviceExt;
        gpu.device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: None,
                contents: &v.to_le_bytes(),
                usage: wgpu::BufferUsages::STORAGE,
            })
    };
    let size = Extent::new(9, 5);
    for v in [1.5f32, 2.5, 2.5, -4.0] {
        exec.import_buffer("value", buffer(v));
        exec.execute(&plan, size).unwrap();
        assert!(
            all_equal(&exec, &plan, out, v),
            "frame with buffer holding {v}"
        );
    }
}
