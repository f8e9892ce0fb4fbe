//! Full-resolution reference throughput (ignored by default: run it with
//! `cargo test -p aograph-scene --release --test reference_throughput -- --ignored --nocapture`).

use aograph_scene::reference::ProgressMode;
use aograph_scene::{
    ReferenceMode, ReferenceParams, TriangleBvh, primary_hits, procedural_scene, trace_reference,
};
use std::time::Instant;

#[test]
#[ignore = "takes tens of seconds; a measurement, not a check"]
fn columns_full_resolution_throughput() {
    let (size, rays) = (512, 256);
    let scene = procedural_scene("columns").unwrap();
    let start = Instant::now();
    let bvh = TriangleBvh::new(&scene.world_triangles(0.0));
    let build = start.elapsed().as_secs_f64();
    let surfaces = primary_hits(&scene, &scene.camera, size, size, 0.0);
    let params = ReferenceParams {
        radius: 1.0,
        rays_per_pixel: rays,
        mode: ReferenceMode::Binary,
        progress: ProgressMode::Auto,
    };
    let start = Instant::now();
    let image = trace_reference(&bvh, &surfaces, &params).unwrap();
    let seconds = start.elapsed().as_secs_f64();
    let traced = surfaces.valid_count() as f64 * f64::from(rays);
    eprintln!(
        "columns {size}x{size} x {rays} rays: BVH build {build:.3} s, {traced:.0} rays in \
         {seconds:.2} s = {:.2} Mrays/s on {} threads",
        traced / seconds / 1e6,
        rayon::current_num_threads()
    );
    let out = std::env::temp_dir().join("aograph-columns-reference-512.png");
    image.write_png(&out).unwrap();
    eprintln!("wrote {}", out.display());
    assert!(image.accessibility.iter().all(|a| (0.0..=1.0).contains(a)));
}
