//! Heap allocations per frame in steady state, counted with a counting global allocator, and
//! the executor's own share of them: a frame of a cached plan of 50 compute passes is
//! compared with the same frame recorded by hand with raw wgpu (same pipeline, same textures,
//! same bind groups, same commands). What wgpu 30 allocates to record and submit is in both;
//! the difference is the executor's.
//!
//! Measured (lavapipe allocates through malloc, not the Rust allocator, so it is not counted):
//! 645 allocations per frame with timing off and 914 with GPU timestamps, all of them wgpu's:
//! the executor's own share is 0.00 in both (wgpu's own count wobbles by a few allocations per
//! 200 frames as its internal vectors grow). The bound, half an allocation per frame, fails
//! for an executor that allocates once per frame, let alone once per pass.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};

use aograph_graph::*;

#[path = "common/hand_frame.rs"]
mod hand_frame;
use hand_frame::{HandFrame, SHADER};

struct Counting;
static ALLOCS: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, l: Layout) -> *mut u8 {
        ALLOCS.fetch_add(1, Ordering::Relaxed);
        unsafe { System.alloc(l) }
    }
    unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
        unsafe { System.dealloc(p, l) }
    }
    unsafe fn realloc(&self, p: *mut u8, l: Layout, n: usize) -> *mut u8 {
        ALLOCS.fetch_add(1, Ordering::Relaxed);
        unsafe { System.realloc(p, l, n) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

const PASSES: usize = 50;
const SIDE: u32 = 8;
const FRAMES: usize = 200;

/// Allocations per frame over `FRAMES` frames of `frame`, after 20 warm-up frames.
fn per_frame(gpu: &GpuContext, mut frame: impl FnMut()) -> f64 {
    for _ in 0..20 {
        frame();
    }
    gpu.wait_idle().unwrap();
    let before = ALLOCS.load(Ordering::Relaxed);
    for _ in 0..FRAMES {
        frame();
    }
    let after = ALLOCS.load(Ordering::Relaxed);
    gpu.wait_idle().unwrap();
    (after - before) as f64 / FRAMES as f64
}

/// The graph: an imported source, then `PASSES` passes each reading the previous output;
/// without reuse, so every pass writes its own texture as the hand-written frame does.
fn chain_plan(lib: &ShaderLibrary) -> (Arc<CompiledGraph>, TextureHandle) {
    let mut b = GraphBuilder::new();
    let desc = TextureDesc::new(wgpu::TextureFormat::R32Float, SizeClass::FULL);
    let mut cur = b.import_texture("src", desc);
    for i in 0..PASSES {
        let t = b.create_texture(&format!("t{i}"), desc);
        let mut p = b.compute_pass(&format!("p{i}"), "inc.wgsl", "main");
        p.sample("src", cur);
        cur = p.write_storage("dst", t);
        p.dispatch_over(cur);
    }
    b.export(cur);
    let plan = compile(b.build(), lib, CompileOptions { reuse: false }).unwrap();
    (Arc::new(plan), cur)
}

#[test]
fn the_executor_itself_allocates_nothing_per_frame() {
    // Debug builds of wgpu-core capture a backtrace whenever they take a resource lock, when
    // backtraces are enabled (RUST_BACKTRACE=1): its frame vector grows with the caller's stack
    // depth, which differs between the two frames compared. `Backtrace::capture` reads
    // RUST_LIB_BACKTRACE first and caches it at the first capture, which has not happened yet.
    // SAFETY: the only test of this binary, before any other thread reads the environment.
    unsafe { std::env::set_var("RUST_LIB_BACKTRACE", "0") };
    let Some(gpu) = test_gpu() else { return };
    let lib = ShaderLibrary::inline_only();
    lib.add_inline("inc.wgsl", SHADER);
    let (plan, _) = chain_plan(&lib);
    let size = Extent::new(SIDE, SIDE);
    let mut modes = vec![(TimingMode::Off, false)];
    if gpu.has_timestamps() {
        modes.push((TimingMode::GpuTimestamps, true));
    }
    for (mode, timestamps) in modes {
        let mut exec = Executor::new(gpu.clone());
        exec.set_timing(mode).unwrap();
        let src = hand_frame::texture(
            &gpu,
            SIDE,
            wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        );
        exec.import_texture("src", src);
        let graph = per_frame(&gpu, || {
            exec.execute(&plan, size).unwrap();
        });
        let mut hand = HandFrame::new(&gpu, PASSES, SIDE, timestamps);
        let baseline = per_frame(&gpu, || hand.frame(&gpu));
        let own = graph - baseline;
        println!(
            "{mode:?}: {graph:.2} allocations per frame ({PASSES} compute passes), \
             {baseline:.2} for the same frame recorded by hand with wgpu: the executor's own \
             share {own:.2}"
        );
        assert!(
            own < 0.5,
            "{mode:?}: the executor allocates {own:.2} times per frame of its own"
        );
        assert!(
            baseline > PASSES as f64,
            "the baseline must record the frame ({baseline:.2} allocations)"
        );
        // Timings keep arriving while nothing is allocated for them.
        if timestamps {
            assert!(exec.wait_timings().unwrap().frame.is_some());
        }
    }
}
