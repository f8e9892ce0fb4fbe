//! aograph's AO in an application's own renderer: this program draws a glTF with its own
//! minimal pipeline (its own vertex buffers and reversed-Z Depth32Float depth buffer, no
//! aograph scene or g-buffer: examples/own_renderer/frame.rs), hands its depth to
//! `aograph_embed::AmbientOcclusion`, multiplies the AO into its ambient light, and writes a
//! PNG per technique. Headless; it switches technique once, mid-run.
//!
//! cargo run --release --example own_renderer -- [scene.gltf] [out-dir]
//!
//! The scene defaults to the Flight Helmet vendored in tests/scenes (found, as the tests find
//! their files, by `aograph_scene::test_scene`: only the path comes from aograph, the file is
//! loaded with the application's own code); the output folder to out/own_renderer.

#[path = "own_renderer/frame.rs"]
mod frame;

use std::path::PathBuf;
use std::time::Instant;

use aograph_embed::{AmbientOcclusion, AoInputs, DepthInput};
use frame::{Mesh, OwnRenderer};

const WIDTH: u32 = 320;
const HEIGHT: u32 = 180;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let scene = match args.next() {
        Some(scene) => PathBuf::from(scene),
        None => {
            aograph_scene::test_scene("the own_renderer example", "FlightHelmet/FlightHelmet.gltf")
                .ok_or("no scene given, and the default tests/scenes/FlightHelmet is missing")?
        }
    };
    let out = args
        .next()
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("out/own_renderer"));
    std::fs::create_dir_all(&out)?;

    // The application's own device: aograph gets the same adapter, device and queue.
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle());
    let adapter = pollster::block_on(instance.request_adapter(&Default::default()))?;
    let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
        label: Some("own renderer"),
        // R16Float storage for aograph's intermediates, where the adapter has it.
        required_features: adapter.features()
            & wgpu::Features::TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES,
        ..Default::default()
    }))?;
    println!("device: {}", adapter.get_info().name);

    let mesh = Mesh::load(&scene)?;
    let renderer = OwnRenderer::new(&device, &queue, &mesh, WIDTH, HEIGHT);
    let radius = renderer.ao_radius();
    let (view0, _) = renderer.camera(0.0);
    let eye = view0.inverse().w_axis;
    println!(
        "{}: {} triangles; camera at ({:.3}, {:.3}, {:.3}), looking at {:?}; R = {radius}",
        scene.display(),
        mesh.indices.len() / 3,
        eye.x,
        eye.y,
        eye.z,
        mesh.bounds().0
    );
    let settings = |technique: &str| format!("technique = \"{technique}\"\nradius = {radius}");
    let mut ao = AmbientOcclusion::from_toml(&adapter, &device, &queue, &settings("gtao"))?;

    for frame in 0..4 {
        if frame == 2 {
            // Mid-run: another technique, same renderer, same depth.
            ao.set_config_toml(&settings("mssao"))?;
        }
        let t = frame as f32 * 0.05;
        let (view, proj) = renderer.camera(t);
        renderer.set_camera(view, proj);
        let mut encoder = device.create_command_encoder(&Default::default());
        renderer.depth_prepass(&mut encoder);
        let started = Instant::now();
        let mut inputs = AoInputs::new(DepthInput::Hardware(&renderer.depth), proj, view);
        inputs.time = t;
        let occlusion = ao.encode(&mut encoder, &inputs)?;
        let encode_ms = started.elapsed().as_secs_f64() * 1e3;
        renderer.shade(&mut encoder, &occlusion.view);
        queue.submit([encoder.finish()]);
        let technique = &ao.config().technique;
        println!("frame {frame}: {technique}, AO recorded in {encode_ms:.2} ms of CPU");
        if frame % 2 == 1 {
            let shaded = read_rgba8(&device, &queue, &renderer.color)?;
            let path = out.join(format!("shaded_{technique}.png"));
            image::RgbaImage::from_raw(WIDTH, HEIGHT, shaded)
                .ok_or("image size")?
                .save(&path)?;
            let ao_pixels = read_rgba8(&device, &queue, &occlusion.texture)?;
            let ao_path = out.join(format!("ao_{technique}.png"));
            image::GrayImage::from_raw(WIDTH, HEIGHT, ao_pixels)
                .ok_or("image size")?
                .save(&ao_path)?;
            println!("wrote {} and {}", path.display(), ao_path.display());
        }
    }
    Ok(())
}

/// The texels of an 8-bit texture (RGBA8 or R8), row by row.
fn read_rgba8(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
) -> Result<Vec<u8>, Box<dyn std::error::Error>> {
    Ok(aograph_graph::read_texture(device, queue, texture, 0)?.bytes)
}
