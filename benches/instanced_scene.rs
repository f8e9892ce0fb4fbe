//! What a scene of many instances costs the CPU paths: 1,900 copies of a 4,000-triangle mesh
//! (7.6 M triangles placed; `aograph_scene::procedural::instanced_field`, written as a .glb and
//! loaded back, as `aograph scene info` meets such a file), timed and with the peak heap each
//! step reaches (a counting allocator):
//! - `scene_info`: the whole `aograph scene info` report (load, views, radii) on the file;
//! - `reference/two_level` and `reference/flat`: the CPU reference of one view, 64 x 48 pixels,
//!   16 rays, against `SceneRays` (shared meshes in object space) and against a `TriangleBvh`
//!   over the flattened `world_triangles` (what every CPU path did before): build plus trace.
//!
//! The two references are the same image (`crates/scene/tests/scene_rays_match_flat.rs`
//! checks it ray for ray at small sizes); here only their cost differs.
//! `AOGRAPH_INSTANCES` and `AOGRAPH_INSTANCE_TRIANGLES` change the shape.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use aograph::commands::scene_info_text;
use aograph_app_config::SceneSource;
use aograph_scene::{
    CpuGBuffer, ReferenceNormals, ReferenceParams, SceneRays, TriangleBvh, load_scene,
    trace_reference,
};
use criterion::Criterion;

/// The system allocator, counting the bytes live and the most ever live.
struct PeakHeap {
    live: AtomicUsize,
    peak: AtomicUsize,
}

unsafe impl GlobalAlloc for PeakHeap {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        // SAFETY: forwarded unchanged to the system allocator.
        let p = unsafe { System.alloc(layout) };
        if !p.is_null() {
            let live = self.live.fetch_add(layout.size(), Ordering::Relaxed) + layout.size();
            self.peak.fetch_max(live, Ordering::Relaxed);
        }
        p
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: forwarded unchanged to the system allocator.
        unsafe { System.dealloc(ptr, layout) };
        self.live.fetch_sub(layout.size(), Ordering::Relaxed);
    }
}

#[global_allocator]
static HEAP: PeakHeap = PeakHeap {
    live: AtomicUsize::new(0),
    peak: AtomicUsize::new(0),
};

/// Runs `step` once, printing its time and the heap it added at its peak.
fn measure<T>(name: &str, step: impl FnOnce() -> T) -> T {
    let before = HEAP.live.load(Ordering::Relaxed);
    HEAP.peak.store(before, Ordering::Relaxed);
    let start = Instant::now();
    let out = step();
    let seconds = start.elapsed().as_secs_f64();
    let peak = HEAP.peak.load(Ordering::Relaxed) - before;
    println!(
        "instanced_scene {name}: {seconds:.3} s, peak heap {:.1} MB",
        peak as f64 / 1e6
    );
    out
}

fn number(variable: &str, default: usize) -> usize {
    std::env::var(variable)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

fn main() {
    let (instances, triangles) = (
        number("AOGRAPH_INSTANCES", 1_900),
        number("AOGRAPH_INSTANCE_TRIANGLES", 4_000),
    );
    let dir = std::env::temp_dir().join(format!("aograph-instanced-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temporary folder");
    let file = dir.join("field.glb");
    let field = aograph_scene::procedural::instanced_field(instances, triangles);
    aograph_scene::export_glb(&field, &file).expect("the field exports");
    drop(field);
    println!("instanced_scene: {instances} instances of a {triangles}-triangle mesh");
    let source = SceneSource::File(file.clone());

    // One measured run of each step, with its peak heap, before criterion's timing.
    measure("scene_info", || {
        scene_info_text(&source).expect("scene info")
    });
    let scene = load_scene(&file).expect("the field loads");
    let surfaces =
        CpuGBuffer::trace(&scene, &scene.camera, 64, 48, 0.0).surfaces(ReferenceNormals::Geometric);
    let params = ReferenceParams {
        radius: scene.bounds().diagonal() / 9.0,
        rays_per_pixel: 16,
        progress: aograph_scene::reference::ProgressMode::Never,
        ..Default::default()
    };
    let two_level = || {
        let rays = SceneRays::new(&scene, 0.0);
        trace_reference(&rays, &surfaces, &params).expect("traces")
    };
    let flat = || {
        let bvh = TriangleBvh::new(&scene.world_triangles(0.0));
        trace_reference(&bvh, &surfaces, &params).expect("traces")
    };
    let a = measure("reference/two_level", two_level);
    let b = measure("reference/flat", flat);
    assert_eq!(
        a.accessibility, b.accessibility,
        "the two references differ"
    );

    let mut c = Criterion::default().configure_from_args().sample_size(10);
    c.bench_function("instanced_scene/scene_info", |b| {
        b.iter(|| scene_info_text(&source).expect("scene info"))
    });
    c.bench_function("instanced_scene/reference/two_level", |b| b.iter(two_level));
    c.bench_function("instanced_scene/reference/flat", |b| b.iter(flat));
    c.final_summary();
    let _ = std::fs::remove_dir_all(&dir);
}
