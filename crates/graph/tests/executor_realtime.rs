//! The executor in a real-time loop: `execute` returns while the frame's GPU work is still
//! running, timings arrive frames later tagged with the frame they measured, and when every
//! pending slot is still waiting a frame's timings are dropped instead of stalling (the
//! dropped-frame case of wgpu-profiler's tests, ported).
//!
//! The GPU work is made deliberately slow (a compute loop whose length comes from a uniform,
//! so the compiler cannot fold it): on lavapipe one frame takes about 70 ms, so "still pending
//! right after `execute` returned" holds by a wide margin.
//!
//! On lavapipe (Mesa 22.3) a submission waits inside `vkQueueSubmit` for the previous one to
//! finish: wgpu-hal chains submissions with a semaphore, and Mesa's queue resolves that wait
//! synchronously. So there at most one frame runs while the CPU records the next; the
//! executor itself never waits (the frame after an idle GPU shows it), and on a GPU driver
//! that queues submissions several frames overlap.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use aograph_graph::*;

const SLOW: &str = r#"
struct Params { iterations: u32, pad0: u32, pad1: u32, pad2: u32 }
@group(0) @binding(0) var dst: texture_storage_2d<r32float, write>;
@group(0) @binding(1) var<uniform> params: Params;
@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    var x = f32(id.x) * 0.001 + f32(id.y) * 0.002;
    for (var i = 0u; i < params.iterations; i++) {
        x = fract(x * 1.000173 + 0.318);
    }
    textureStore(dst, vec2<i32>(id.xy), vec4<f32>(x, 0.0, 0.0, 0.0));
}
"#;

/// One slow compute pass writing an exported 64x64 texture.
fn slow_plan(iterations: u32) -> (Arc<CompiledGraph>, TextureHandle) {
    let lib = ShaderLibrary::inline_only();
    lib.add_inline("slow.wgsl", SLOW);
    let mut b = GraphBuilder::new();
    let t = b.create_texture(
        "slow",
        TextureDesc::new(wgpu::TextureFormat::R32Float, SizeClass::FULL),
    );
    let mut p = b.compute_pass("slow", "slow.wgsl", "main");
    let bytes: Vec<u8> = [iterations, 0, 0, 0]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    p.uniform("params", &bytes);
    let out = p.write_storage("dst", t);
    p.dispatch_over(out);
    b.export(out);
    let plan = compile(b.build(), &lib, CompileOptions::default()).expect("compiles");
    (Arc::new(plan), out)
}

/// A device of the test's own: other tests share `test_gpu()`'s, and a thread blocked in a
/// waiting poll on a shared device holds wgpu's device lock, which would make this test's
/// `execute` wait for *their* work.
fn own_gpu() -> Option<Arc<GpuContext>> {
    test_gpu()?;
    Some(Arc::new(
        GpuContext::new().expect("a second device on the same adapter"),
    ))
}

/// A flag set when the GPU finishes everything submitted so far (its callback runs at the next
/// poll, so `false` only counts right after a poll that found the work unfinished).
fn done_flag(gpu: &GpuContext) -> Arc<AtomicBool> {
    let flag = Arc::new(AtomicBool::new(false));
    let f = flag.clone();
    gpu.queue
        .on_submitted_work_done(move || f.store(true, Ordering::Release));
    flag
}

#[test]
fn execute_returns_while_the_gpu_works_and_timings_arrive_later_tagged_with_their_frame() {
    let Some(gpu) = own_gpu() else { return };
    if !gpu.has_timestamps() {
        eprintln!("SKIPPED: the device has no timestamp queries");
        return;
    }
    let (plan, out) = slow_plan(300_000);
    let size = Extent::new(64, 64);
    let mut exec = Executor::new(gpu.clone());
    assert_eq!(exec.timing(), TimingMode::GpuTimestamps);
    // Warm up (pipeline creation, first allocation), then wait so the test starts idle.
    exec.execute(&plan, size).unwrap();
    let warm = exec.wait_timings().unwrap().total_ms();
    println!("warm-up frame: {warm:.1} ms on the device");

    let started = Instant::now();
    let f1 = exec.execute(&plan, size).unwrap();
    let returned_after = started.elapsed();
    let done = done_flag(&gpu);
    // A non-blocking poll right after `execute`: the frame's work is still running.
    assert_eq!(
        exec.latest_timings().unwrap().frame,
        Some(FrameId(0)),
        "frame 1's timings cannot have arrived while its work runs"
    );
    assert!(
        !done.load(Ordering::Acquire),
        "execute waited for the GPU (returned after {returned_after:?})"
    );
    assert_eq!(exec.pending_timings(), 1);

    // Keep calling the non-blocking API until the timings come in: they do, tagged.
    let deadline = Instant::now() + std::time::Duration::from_secs(120);
    let mut polls = 0;
    while exec.latest_timings().unwrap().frame != Some(f1) && Instant::now() < deadline {
        polls += 1;
        std::thread::sleep(std::time::Duration::from_millis(2));
    }
    let t = exec.latest_timings().unwrap().clone();
    assert_eq!(t.frame, Some(f1), "{t:?}");
    assert_eq!(t.source, Some(TimingSource::GpuTimestamps));
    assert_eq!(t.passes.len(), 1);
    assert!(t.passes[0].1 > 0.0, "{t:?}");
    assert!(
        polls > 0,
        "the timings were there at once: the frame did not run long"
    );
    assert!(done.load(Ordering::Acquire));
    println!(
        "execute returned after {returned_after:?}; the frame then ran {:.1} ms on the device \
         and its timings arrived after {polls} non-blocking polls",
        t.passes[0].1
    );

    // Frames in a row: each result that arrives carries the frame it measured, in order.
    let frames: Vec<FrameId> = (0..3).map(|_| exec.execute(&plan, size).unwrap()).collect();
    let last = exec.wait_timings().unwrap().frame;
    assert_eq!(last, frames.last().copied());
    // The output of the last frame reads back as usual.
    let v = exec.read_texture(&plan, out).unwrap().channel(0).unwrap();
    assert!(v.iter().all(|x| x.is_finite() && (0.0..1.0).contains(x)));
    assert_eq!(exec.dropped_timings(), 0);
    assert!(gpu.take_errors().is_empty());
}

#[test]
fn a_full_ring_drops_the_new_frames_timings_instead_of_waiting() {
    let Some(gpu) = own_gpu() else { return };
    if !gpu.has_timestamps() {
        eprintln!("SKIPPED: the device has no timestamp queries");
        return;
    }
    let (plan, _) = slow_plan(300_000);
    let size = Extent::new(64, 64);
    let mut exec = Executor::new(gpu.clone());
    exec.set_pending_timing_frames(1);
    exec.execute(&plan, size).unwrap();
    exec.wait_timings().unwrap();
    let dropped = exec.dropped_timings();

    // Two frames while the first is still running: the one pending slot is taken, so the
    // second frame is not timed (the executor does not wait for the slot).
    let a = exec.execute(&plan, size).unwrap();
    let b = exec.execute(&plan, size).unwrap();
    assert_eq!(exec.dropped_timings(), dropped + 1);

    // Waiting gives exactly the first frame's timings; nothing more arrives for the second.
    assert_eq!(exec.wait_timings().unwrap().frame, Some(a));
    gpu.wait_idle().unwrap();
    assert_eq!(exec.latest_timings().unwrap().frame, Some(a));
    assert_eq!(exec.pending_timings(), 0);
    // The ring is free again: the next frame is timed.
    let c = exec.execute(&plan, size).unwrap();
    assert_eq!(exec.wait_timings().unwrap().frame, Some(c));
    assert!(b < c);
}

#[test]
fn timing_off_records_no_queries_and_gpu_timestamps_is_refused_without_them() {
    let Some(gpu) = test_gpu() else { return };
    let (plan, _) = slow_plan(10);
    let mut exec = Executor::new(gpu.clone());
    exec.set_timing(TimingMode::Off).unwrap();
    for _ in 0..5 {
        exec.execute(&plan, Extent::new(16, 16)).unwrap();
    }
    assert_eq!(exec.wait_timings().unwrap().frame, None);
    assert_eq!(exec.pending_timings(), 0);
    assert_eq!(exec.timing_source(), None);
    if !gpu.has_timestamps() {
        let e = exec.set_timing(TimingMode::GpuTimestamps).unwrap_err();
        assert!(e.to_string().contains("CpuWall"), "{e}");
    }
}

/// As a browser's WebGPU device: timestamp queries, but none inside command encoders.
fn pass_timestamps_only_gpu() -> Option<Arc<GpuContext>> {
    let shared = test_gpu()?;
    if !shared
        .adapter
        .features()
        .contains(wgpu::Features::TIMESTAMP_QUERY)
    {
        return None;
    }
    let (device, queue) =
        pollster::block_on(shared.adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("pass timestamps only"),
            required_features: wgpu::Features::TIMESTAMP_QUERY,
            ..Default::default()
        }))
        .ok()?;
    Some(Arc::new(GpuContext::from_device(
        shared.adapter.clone(),
        device,
        queue,
    )))
}

#[test]
fn without_timestamps_inside_encoders_a_pass_writes_its_own_at_its_boundaries() {
    let Some(gpu) = pass_timestamps_only_gpu() else {
        eprintln!("SKIPPED: the adapter has no timestamp queries");
        return;
    };
    assert!(gpu.has_timestamps());
    assert!(
        !gpu.features
            .contains(wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS)
    );
    let (plan, _) = slow_plan(300_000);
    let mut exec = Executor::new(gpu.clone());
    assert_eq!(exec.timing(), TimingMode::GpuTimestamps);
    let frame = exec.execute(&plan, Extent::new(64, 64)).unwrap();
    let t = exec.wait_timings().unwrap().clone();
    assert_eq!(t.frame, Some(frame));
    assert_eq!(t.source, Some(TimingSource::GpuTimestamps));
    assert_eq!(t.passes.len(), 1);
    // 300,000 iterations over 64x64 texels take tens of milliseconds on lavapipe: a pass that
    // wrote no timestamps of its own would read 0 (or whatever the unwritten queries hold).
    assert!(t.passes[0].1 > 1.0, "{t:?}");
    assert!(gpu.take_errors().is_empty());
}

#[test]
fn a_frame_encoded_into_the_callers_encoder_is_timed_once_the_next_frame_begins() {
    let Some(gpu) = pass_timestamps_only_gpu() else {
        eprintln!("SKIPPED: the adapter has no timestamp queries");
        return;
    };
    let (plan, _) = slow_plan(300_000);
    let size = Extent::new(64, 64);
    let mut exec = Executor::new(gpu.clone());
    let encode = |exec: &mut Executor| {
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        let frame = exec.encode(&plan, size, &mut encoder).unwrap();
        gpu.queue.submit([encoder.finish()]);
        frame
    };
    let first = encode(&mut exec);
    // Nothing can be read before the caller's submit is known to have happened.
    assert_eq!(exec.wait_timings().unwrap().frame, None);
    let second = encode(&mut exec);
    let t = exec.wait_timings().unwrap().clone();
    assert_eq!(t.frame, Some(first));
    assert_eq!(t.source, Some(TimingSource::GpuTimestamps));
    assert!(t.passes[0].1 > 1.0, "{t:?}");
    assert!(second > first);
    assert!(gpu.take_errors().is_empty());
}
