//! Writes a .glb of many instances of one mesh (`aograph_scene::procedural::instanced_field`),
//! the shape of the EXT_mesh_gpu_instancing scenes the CPU paths are measured on:
//! `cargo run --release -p aograph-scene --example instanced_glb -- out.glb [instances] [triangles]`
//! (default 1,900 instances of a 4,000-triangle mesh). The file has one node per instance, all
//! naming one mesh; `gltfpack -mi` turns those nodes into one EXT_mesh_gpu_instancing node.

use std::process::ExitCode;

fn main() -> ExitCode {
    let mut args = std::env::args().skip(1);
    let Some(out) = args.next() else {
        eprintln!("usage: instanced_glb OUT.glb [INSTANCES] [TRIANGLES]");
        return ExitCode::FAILURE;
    };
    let mut number = |default: usize| args.next().and_then(|a| a.parse().ok()).unwrap_or(default);
    let (instances, triangles) = (number(1_900), number(4_000));
    let scene = aograph_scene::procedural::instanced_field(instances, triangles);
    match aograph_scene::export_glb(&scene, &out) {
        Ok(()) => {
            println!(
                "{out}: {} instances, {} triangles placed",
                scene.instances.len(),
                scene.triangle_count()
            );
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
