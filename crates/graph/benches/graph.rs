//! Graph benchmarks:
//! - compile time for 10, 100 and 1,000 passes, uncached and on a cache hit (the declaration
//!   is built outside the timed region: compile consumes it);
//! - the CPU time to record and submit a cached plan of 50 compute passes, with the GPU wait
//!   outside the timed region (throughput in passes, so criterion prints the time per pass),
//!   with timing off and with GPU timestamps, next to the same frame recorded by hand with raw
//!   wgpu (what wgpu and the driver cost; the difference is the executor's own);
//! - the time to switch to a plan seen before (its state and pipelines cached), to a plan not
//!   seen whose pipelines are cached (a new structure over the same shaders), and to a plan not
//!   seen on a fresh executor (pipelines created: on lavapipe, LLVM compiling shaders).

use std::hint::black_box;
use std::sync::Arc;
use std::time::{Duration, Instant};

use aograph_graph::*;
use criterion::{BatchSize, BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};

#[path = "../tests/common/hand_frame.rs"]
mod hand_frame;
use hand_frame::HandFrame;

/// A layered graph of `n` no-op passes: each reads two earlier outputs and writes one texture;
/// every tenth output is exported, the rest feed later passes or get culled.
pub fn layered_graph(n: usize) -> GraphDecl {
    let mut b = GraphBuilder::new();
    let desc = TextureDesc::new(wgpu::TextureFormat::R32Float, SizeClass::FULL);
    let mut outs: Vec<TextureHandle> = Vec::with_capacity(n);
    for i in 0..n {
        let t = b.create_texture(&format!("t{i}"), desc);
        let mut p = b.custom_pass(&format!("p{i}"), NoopPass);
        if i > 0 {
            p.read_texture(TextureAccess::Sampled, outs[i - 1]);
        }
        if i > 7 {
            p.read_texture(TextureAccess::Sampled, outs[i / 2]);
        }
        outs.push(p.write_texture(TextureAccess::StorageWrite, t));
    }
    for (i, h) in outs.iter().enumerate() {
        if i % 10 == 9 || i + 1 == n {
            b.export(*h);
        }
    }
    b.build()
}

const CHAIN_SHADER: &str = r#"
@group(0) @binding(0) var src: texture_2d<f32>;
@group(0) @binding(1) var dst: texture_storage_2d<r32float, write>;
@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(src);
    if (id.x >= size.x || id.y >= size.y) { return; }
    textureStore(dst, vec2<i32>(id.xy), textureLoad(src, vec2<i32>(id.xy), 0) * 0.5 + 0.25);
}
"#;

const SEED_SHADER: &str = r#"
@group(0) @binding(0) var dst: texture_storage_2d<r32float, write>;
@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    textureStore(dst, vec2<i32>(id.xy), vec4<f32>(f32(id.x + id.y), 0.0, 0.0, 0.0));
}
"#;

fn chain_library() -> ShaderLibrary {
    let lib = ShaderLibrary::inline_only();
    lib.add_inline("chain.wgsl", CHAIN_SHADER);
    lib.add_inline("seed.wgsl", SEED_SHADER);
    lib
}

/// A chain of `n` compute passes over tiny textures; `tag` names the passes, so chains with
/// different tags are different structures over the same shaders (same pipelines).
pub fn compute_chain(n: usize, tag: &str) -> GraphDecl {
    let mut b = GraphBuilder::new();
    let desc = TextureDesc::new(wgpu::TextureFormat::R32Float, SizeClass::FULL);
    let t = b.create_texture("seed", desc);
    let mut p = b.compute_pass(&format!("{tag}seed"), "seed.wgsl", "main");
    let mut cur = p.write_storage("dst", t);
    p.dispatch_over(cur);
    for i in 1..n {
        let t = b.create_texture(&format!("t{i}"), desc);
        let mut p = b.compute_pass(&format!("{tag}p{i}"), "chain.wgsl", "main");
        p.sample("src", cur);
        cur = p.write_storage("dst", t);
        p.dispatch_over(cur);
    }
    b.export(cur);
    b.build()
}

fn compile_bench(c: &mut Criterion) {
    let lib = ShaderLibrary::inline_only();
    let mut g = c.benchmark_group("compile");
    for n in [10usize, 100, 1000] {
        let decl = layered_graph(n);
        g.bench_with_input(BenchmarkId::new("uncached", n), &decl, |bench, d| {
            bench.iter_batched(
                || d.clone(),
                |d| compile(black_box(d), &lib, CompileOptions::default()).map(|p| p.order.len()),
                BatchSize::SmallInput,
            )
        });
        let mut compiler = GraphCompiler::new();
        g.bench_with_input(BenchmarkId::new("cached", n), &decl, |bench, d| {
            bench.iter_batched(
                || d.clone(),
                |d| {
                    compiler
                        .compile(black_box(d), &lib, CompileOptions::default())
                        .map(|p| p.order.len())
                },
                BatchSize::SmallInput,
            )
        });
    }
    g.finish();
}

/// Sums the time `frame` reports over `iters` iterations (each times only its own part).
fn timed_iters(iters: u64, mut frame: impl FnMut() -> Duration) -> Duration {
    (0..iters).map(|_| frame()).sum()
}

/// The time `f` takes.
fn time(f: impl FnOnce()) -> Duration {
    let t = Instant::now();
    f();
    t.elapsed()
}

fn execute_bench(c: &mut Criterion) {
    let Ok(gpu) = GpuContext::new() else {
        eprintln!("SKIPPED: execute benchmarks need a GPU adapter");
        return;
    };
    let gpu = Arc::new(gpu);
    let lib = chain_library();
    let size = Extent::new(8, 8);
    let chain = |n, tag: &str| {
        Arc::new(compile(compute_chain(n, tag), &lib, CompileOptions::default()).unwrap())
    };
    // The hand-written frame's graph: an imported source and 50 passes, each writing its own
    // texture (no reuse), as `HandFrame` records them.
    let hand_lib = ShaderLibrary::inline_only();
    hand_lib.add_inline("inc.wgsl", hand_frame::SHADER);
    let plan = {
        let mut b = GraphBuilder::new();
        let desc = TextureDesc::new(wgpu::TextureFormat::R32Float, SizeClass::FULL);
        let mut cur = b.import_texture("src", desc);
        for i in 0..50 {
            let t = b.create_texture(&format!("t{i}"), desc);
            let mut p = b.compute_pass(&format!("p{i}"), "inc.wgsl", "main");
            p.sample("src", cur);
            cur = p.write_storage("dst", t);
            p.dispatch_over(cur);
        }
        b.export(cur);
        Arc::new(compile(b.build(), &hand_lib, CompileOptions { reuse: false }).unwrap())
    };

    interleaved_overhead(&gpu, &plan);

    let mut g = c.benchmark_group("record and submit a cached plan of 50 passes (8x8)");
    g.throughput(Throughput::Elements(50));
    let mut modes = vec![("timing off", TimingMode::Off)];
    if gpu.has_timestamps() {
        modes.push(("gpu timestamps", TimingMode::GpuTimestamps));
    }
    for (name, mode) in modes {
        let timestamps = mode == TimingMode::GpuTimestamps;
        let mut hand = HandFrame::new(&gpu, 50, 8, timestamps);
        g.bench_function(format!("{name}, by hand with wgpu"), |bench| {
            bench.iter_custom(|iters| {
                timed_iters(iters, || {
                    let d = time(|| hand.frame(&gpu));
                    let _ = gpu.wait_idle();
                    d
                })
            })
        });
        let mut exec = Executor::new(gpu.clone());
        exec.set_timing(mode).unwrap();
        exec.import_texture(
            "src",
            hand_frame::texture(&gpu, 8, wgpu::TextureUsages::TEXTURE_BINDING),
        );
        exec.execute(&plan, size).unwrap();
        g.bench_function(name, |bench| {
            bench.iter_custom(|iters| {
                timed_iters(iters, || {
                    let d = time(|| {
                        exec.execute(&plan, size).unwrap();
                    });
                    let _ = gpu.wait_idle();
                    d
                })
            })
        });
    }
    g.finish();

    let mut g = c.benchmark_group("switch plans (20 passes each, 8x8)");
    let (a, b) = (chain(20, "a."), chain(20, "b."));
    let mut exec = Executor::new(gpu.clone());
    exec.set_timing(TimingMode::Off).unwrap();
    exec.execute(&a, size).unwrap();
    exec.execute(&b, size).unwrap();
    g.bench_function("same plan again", |bench| {
        bench.iter_custom(|iters| {
            timed_iters(iters, || {
                let d = time(|| {
                    exec.execute(&a, size).unwrap();
                });
                let _ = gpu.wait_idle();
                d
            })
        })
    });
    g.bench_function("to a plan seen before", |bench| {
        bench.iter_custom(|iters| {
            timed_iters(iters, || {
                exec.execute(&b, size).unwrap();
                let _ = gpu.wait_idle();
                let d = time(|| {
                    exec.execute(&a, size).unwrap();
                });
                let _ = gpu.wait_idle();
                d
            })
        })
    });
    let mut unseen = 0u64;
    g.bench_function("to a plan not seen, pipelines cached", |bench| {
        bench.iter_custom(|iters| {
            timed_iters(iters, || {
                unseen += 1;
                let fresh = chain(20, &format!("u{unseen}."));
                let d = time(|| {
                    exec.execute(&fresh, size).unwrap();
                });
                let _ = gpu.wait_idle();
                d
            })
        })
    });
    g.sample_size(10);
    g.bench_function("to a plan not seen, fresh executor", |bench| {
        bench.iter_custom(|iters| {
            timed_iters(iters, || {
                let mut fresh = Executor::new(gpu.clone());
                fresh.set_timing(TimingMode::Off).unwrap();
                let d = time(|| {
                    fresh.execute(&a, size).unwrap();
                });
                let _ = gpu.wait_idle();
                d
            })
        })
    });
    g.finish();
}

/// The executor's own share of recording and submitting, measured against the same frame
/// recorded by hand, frame for frame in alternation (so machine noise hits both alike):
/// medians of each and their difference per pass, printed.
fn interleaved_overhead(gpu: &Arc<GpuContext>, plan: &Arc<CompiledGraph>) {
    let frames = if std::env::args().any(|a| a == "--test") {
        4
    } else {
        400
    };
    let mut modes = vec![TimingMode::Off];
    if gpu.has_timestamps() {
        modes.push(TimingMode::GpuTimestamps);
    }
    for mode in modes {
        let mut hand = HandFrame::new(gpu, 50, 8, mode == TimingMode::GpuTimestamps);
        let mut exec = Executor::new(gpu.clone());
        exec.set_timing(mode).unwrap();
        exec.import_texture(
            "src",
            hand_frame::texture(gpu, 8, wgpu::TextureUsages::TEXTURE_BINDING),
        );
        let size = Extent::new(8, 8);
        let (mut by_hand, mut by_exec) = (Vec::new(), Vec::new());
        for i in 0..frames + 20 {
            let h = time(|| hand.frame(gpu));
            let _ = gpu.wait_idle();
            let e = time(|| {
                exec.execute(plan, size).unwrap();
            });
            let _ = gpu.wait_idle();
            if i >= 20 {
                by_hand.push(h);
                by_exec.push(e);
            }
        }
        let median = |v: &mut Vec<Duration>| {
            v.sort();
            v[v.len() / 2].as_secs_f64() * 1e6
        };
        let (h, e) = (median(&mut by_hand), median(&mut by_exec));
        eprintln!(
            "{mode:?}, 50 passes, median of {frames} alternating frames: by hand {h:.1} us, \
             executor {e:.1} us; the executor's own share {:.2} us per pass",
            (e - h) / 50.0
        );
    }
}

criterion_group!(benches, compile_bench, execute_bench);
criterion_main!(benches);
