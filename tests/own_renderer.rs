//! examples/own_renderer.rs's renderer (its own vertex buffers and reversed-Z Depth32Float
//! depth buffer, no aograph scene or g-buffer) with aograph's AO from that depth: sky is
//! unoccluded, the glTF's creases and the cage are dark, and the shaded image carries it.

#[path = "../examples/own_renderer/frame.rs"]
mod frame;

use aograph_embed::{AmbientOcclusion, AoInputs, DepthInput};
use aograph_graph::{read_texture, test_gpu};
use frame::{Mesh, OwnRenderer};

#[test]
fn the_applications_own_depth_gives_ao_that_its_shading_shows() {
    let Some(gpu) = test_gpu() else { return };
    let Some(path) = aograph_scene::test_scene(
        "the_applications_own_depth_gives_ao_that_its_shading_shows",
        "shadowscene_fire.gltf",
    ) else {
        return;
    };
    let mesh = Mesh::load(&path).unwrap();
    let (w, h) = (161, 90);
    let renderer = OwnRenderer::new(&gpu.device, &gpu.queue, &mesh, w, h);
    let config = format!("technique = \"gtao\"\nradius = {}", renderer.ao_radius());
    let mut ao =
        AmbientOcclusion::from_toml(&gpu.adapter, &gpu.device, &gpu.queue, &config).unwrap();
    let (view, proj) = renderer.camera(0.0);
    renderer.set_camera(view, proj);
    let frame = |ao: &mut AmbientOcclusion| {
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        renderer.depth_prepass(&mut encoder);
        let out = ao
            .encode(
                &mut encoder,
                &AoInputs::new(DepthInput::Hardware(&renderer.depth), proj, view),
            )
            .unwrap();
        renderer.shade(&mut encoder, &out.view);
        gpu.queue.submit([encoder.finish()]);
        let occlusion = read_texture(&gpu.device, &gpu.queue, &out.texture, 0)
            .unwrap()
            .bytes;
        let shaded = read_texture(&gpu.device, &gpu.queue, &renderer.color, 0)
            .unwrap()
            .bytes;
        (occlusion, shaded)
    };
    let (occlusion, shaded) = frame(&mut ao);
    let depth = read_texture(&gpu.device, &gpu.queue, &renderer.depth, 0)
        .unwrap()
        .to_f32()
        .unwrap();
    let sky: Vec<usize> = (0..depth.len()).filter(|&i| depth[i] == 0.0).collect();
    let geometry: Vec<usize> = (0..depth.len()).filter(|&i| depth[i] > 0.0).collect();
    println!("{} sky, {} geometry pixels", sky.len(), geometry.len());
    assert!(
        !sky.is_empty() && geometry.len() > depth.len() / 4,
        "the view frames the scene"
    );
    // Where the application drew nothing, nothing occludes: exactly 1 (255 in R8Unorm).
    assert!(
        sky.iter().all(|&i| occlusion[i] == 255),
        "sky must be unoccluded"
    );
    let dark = geometry.iter().filter(|&&i| occlusion[i] < 204).count();
    println!("{dark} of {} geometry pixels below 0.8", geometry.len());
    assert!(
        dark >= 20,
        "the cage and creases occlude ({dark} pixels below 0.8)"
    );

    // The shading multiplies AO into its ambient term: without occlusion the same pixels are
    // brighter.
    ao.set_config_toml(&format!(
        "technique = \"none\"\nradius = {}",
        renderer.ao_radius()
    ))
    .unwrap();
    let (unoccluded, lit) = frame(&mut ao);
    assert!(unoccluded.iter().all(|&a| a == 255));
    let darker = geometry
        .iter()
        .filter(|&&i| occlusion[i] < 204 && shaded[4 * i] < lit[4 * i])
        .count();
    assert_eq!(
        darker, dark,
        "every occluded pixel is darker in the application's image"
    );
    assert!(gpu.take_errors().is_empty());
}
