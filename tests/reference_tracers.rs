//! `[reference] tracer` as the app uses it (`frame_reference`): "cpu", "gpu" (the compute BVH)
//! and "hardware" (acceleration structures, ray queries) trace the same rays, so the GPU ones
//! agree with the CPU within 4 standard errors on 99 % of pixels (rays grazing an edge may
//! answer differently); "hardware" runs only where the device has ray queries (CI requires
//! them: AOGRAPH_REQUIRE_RAY_QUERY=1). Odd, non-square size.

mod common;

use aograph_graph::Extent;
use aograph_scene::{ReferenceTracer, procedural_scene};

#[test]
fn every_tracer_traces_the_cpus_reference_within_four_standard_errors() {
    // A cache of its own: the cache keys hash the tracers' shaders, not the Rust that builds
    // their scenes, and this test is about the tracers, not the cache (the only test in this
    // binary, so the variable is set before any thread reads it).
    let cache = std::env::temp_dir().join(format!("aograph-tracers-{}", std::process::id()));
    // SAFETY: set before this test binary's only test starts any other thread.
    unsafe { std::env::set_var("AOGRAPH_REFERENCE_CACHE", &cache) };
    let size = Extent::new(45, 29);
    let Some(run) = common::render_ao(
        procedural_scene("cornell-box").unwrap(),
        &common::ao_config("gtao", 0.5, ""),
        size,
        1,
    ) else {
        return;
    };
    let trace = |tracer| {
        let mut s = aograph_renderer::ReferenceSettings::new(0.5, 64);
        s.tracer = tracer;
        aograph_renderer::frame_reference(&run.renderer, &s, false).expect("reference traces")
    };
    let cpu = trace(ReferenceTracer::Cpu);
    let mut tracers = vec![ReferenceTracer::Gpu];
    if run.renderer.gpu.has_ray_queries() {
        tracers.push(ReferenceTracer::Hardware);
    } else {
        assert!(
            std::env::var("AOGRAPH_REQUIRE_RAY_QUERY").as_deref() != Ok("1"),
            "AOGRAPH_REQUIRE_RAY_QUERY=1 but the device has no ray queries"
        );
    }
    for tracer in tracers {
        let image = trace(tracer);
        let outside = (0..cpu.accessibility.len())
            .filter(|&i| {
                let d = (image.accessibility[i] - cpu.accessibility[i]).abs();
                let se = (image.std_error[i].powi(2) + cpu.std_error[i].powi(2)).sqrt();
                d > 4.0 * se + 1e-6
            })
            .count();
        let differing = (0..cpu.accessibility.len())
            .filter(|&i| image.accessibility[i] != cpu.accessibility[i])
            .count();
        println!(
            "{}: {outside} of {} pixels beyond 4 SE of the CPU's ({differing} not identical)",
            tracer.name(),
            cpu.accessibility.len()
        );
        assert!(
            outside * 100 <= cpu.accessibility.len(),
            "{}: {outside} pixels beyond 4 SE",
            tracer.name()
        );
    }
    let _ = std::fs::remove_dir_all(&cache);
}
