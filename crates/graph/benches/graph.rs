//! Graph benchmarks: compile time for 10, 100 and 1,000 passes (uncached and cached), and the
//! CPU cost per frame of executing a cached plan of 50 small compute passes on the device.

use std::hint::black_box;
use std::sync::Arc;

use aograph_graph::*;
use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};

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

/// A chain of `n` compute passes over tiny textures.
pub fn compute_chain(n: usize) -> (GraphDecl, ShaderLibrary) {
    let lib = ShaderLibrary::inline_only();
    lib.add_inline("chain.wgsl", CHAIN_SHADER);
    lib.add_inline("seed.wgsl", SEED_SHADER);
    let mut b = GraphBuilder::new();
    let desc = TextureDesc::new(wgpu::TextureFormat::R32Float, SizeClass::FULL);
    let t = b.create_texture("seed", desc);
    let mut p = b.compute_pass("seed", "seed.wgsl", "main");
    let mut cur = p.write_storage("dst", t);
    p.dispatch_over(cur);
    for i in 1..n {
        let t = b.create_texture(&format!("t{i}"), desc);
        let mut p = b.compute_pass(&format!("p{i}"), "chain.wgsl", "main");
        p.sample("src", cur);
        cur = p.write_storage("dst", t);
        p.dispatch_over(cur);
    }
    b.export(cur);
    (b.build(), lib)
}

fn compile_bench(c: &mut Criterion) {
    let lib = ShaderLibrary::inline_only();
    let mut g = c.benchmark_group("compile");
    for n in [10usize, 100, 1000] {
        let decl = layered_graph(n);
        g.bench_with_input(BenchmarkId::new("uncached", n), &decl, |bench, d| {
            bench.iter(|| {
                compile(black_box(d.clone()), &lib, CompileOptions::default())
                    .map(|p| p.order.len())
            })
        });
        let mut compiler = GraphCompiler::new();
        g.bench_with_input(BenchmarkId::new("cached", n), &decl, |bench, d| {
            bench.iter(|| {
                compiler
                    .compile(black_box(d.clone()), &lib, CompileOptions::default())
                    .map(|p| p.order.len())
            })
        });
    }
    g.finish();
}

fn execute_bench(c: &mut Criterion) {
    let Ok(gpu) = GpuContext::new() else {
        eprintln!("SKIPPED: execute benchmark needs a GPU adapter");
        return;
    };
    let gpu = Arc::new(gpu);
    let (decl, lib) = compute_chain(50);
    let plan = Arc::new(compile(decl, &lib, CompileOptions::default()).expect("chain compiles"));
    let mut exec = Executor::new(gpu.clone());
    let size = Extent::new(8, 8);
    exec.execute(&plan, size).expect("first frame");
    c.bench_function("execute cached plan of 50 compute passes (8x8)", |bench| {
        bench.iter(|| {
            exec.execute(&plan, size).expect("frame");
            let _ = gpu.wait_idle();
        })
    });
}

criterion_group!(benches, compile_bench, execute_bench);
criterion_main!(benches);
