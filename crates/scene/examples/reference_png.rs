//! Renders the CPU reference AO of a procedural scene or a glTF file to a 16-bit PNG.
//!
//! Usage: cargo run -p aograph-scene --release --example reference_png -- \
//!            SCENE_OR_FILE OUT.png [WIDTH HEIGHT RAYS RADIUS [obscurance]]
//! Prints the time taken and the ray throughput.

use aograph_scene::reference::ProgressMode;
use aograph_scene::{
    ReferenceMode, ReferenceParams, Scene, TriangleBvh, load_scene, primary_hits, procedural_scene,
    trace_reference,
};
use std::time::Instant;

fn run() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [source, out, rest @ ..] = args.as_slice() else {
        return Err(
            "usage: reference_png SCENE_OR_FILE OUT.png [WIDTH HEIGHT RAYS RADIUS [obscurance]]"
                .into(),
        );
    };
    let number = |i: usize, default: &str| rest.get(i).map_or(default, String::as_str).to_owned();
    let (width, height): (u32, u32) = (number(0, "256").parse()?, number(1, "256").parse()?);
    let rays: u32 = number(2, "64").parse()?;
    let radius: f32 = number(3, "1").parse()?;
    let mode = match rest.get(4).map(String::as_str) {
        Some("obscurance") => ReferenceMode::Obscurance,
        _ => ReferenceMode::Binary,
    };
    let scene: Scene = if source.ends_with(".gltf") || source.ends_with(".glb") {
        load_scene(source)?
    } else {
        procedural_scene(source)?
    };
    let triangles = scene.world_triangles(0.0);
    let start = Instant::now();
    let bvh = TriangleBvh::new(&triangles);
    let built = start.elapsed();
    let surfaces = primary_hits(&scene, &scene.camera, width, height, 0.0);
    let start = Instant::now();
    let params = ReferenceParams {
        radius,
        rays_per_pixel: rays,
        mode,
        progress: ProgressMode::Auto,
    };
    let image = trace_reference(&bvh, &surfaces, &params)?;
    let traced = start.elapsed().as_secs_f64();
    let total_rays = surfaces.valid_count() as f64 * f64::from(rays);
    println!(
        "{source}: {} triangles, BVH {:.3} s, {width}x{height} x {rays} rays in {traced:.2} s: {:.2} Mrays/s",
        triangles.len(),
        built.as_secs_f64(),
        total_rays / traced / 1e6
    );
    image.write_png(out)?;
    Ok(())
}

fn main() {
    if let Err(e) = run() {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}
