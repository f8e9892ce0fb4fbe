//! The g-buffer's second depth layer (`GBufferChannel::SecondLayerDepth`; Mara, McGuire,
//! Nowrouzezahrai, Luebke 2016) and what `layers = 2` does with it:
//! - on a slab floating over a floor, seen straight down, the second layer is the slab's
//!   bottom where Δ is below the slab's thickness and the floor where it is above, and empty
//!   where only the floor is seen (closed forms: the planes' linear depths);
//! - the plan draws the second pass only when a technique asks for two layers, and the
//!   half-resolution path, which has no second layer, refuses `layers = 2` by name;
//! - vbao with two layers reads a pit's wall as thick as it really is: a pit standing over a
//!   ground gives the closed form 1 - 2β/π with a thickness T of 0.01 R, which one layer cannot.
//!
//! gtao's two-layer estimator is checked pixel by pixel against a CPU recomputation in
//! tests/gtao_golden.rs. Skips (saying so) only without an adapter and AOGRAPH_REQUIRE_GPU.

mod common;

use aograph_graph::Extent;
use aograph_scene::{Camera, Instance, Scene, primitives};
use glam::{Mat4, Vec2, Vec3};

/// Odd and not square, as users' frames are.
const SIZE: Extent = Extent {
    width: 61,
    height: 47,
};
/// The camera's height over the floor; it looks straight down.
const EYE: f32 = 5.0;
/// The slab: 2 x 2 wide, from y = 1.0 to 1.4 (0.4 thick).
const SLAB_BOTTOM: f32 = 1.0;
const SLAB_TOP: f32 = 1.4;

fn slab_over_floor() -> Scene {
    let mut b = aograph_scene::SceneBuilder::new();
    let material = b.material([0.8, 0.8, 0.8]);
    b.add(primitives::quad(20.0, 20.0, material), Mat4::IDENTITY);
    b.add(
        primitives::cuboid(Vec3::new(2.0, SLAB_TOP - SLAB_BOTTOM, 2.0), material),
        Mat4::from_translation(Vec3::Y * 0.5 * (SLAB_TOP + SLAB_BOTTOM)),
    );
    b.build(Camera::perspective(
        Vec3::Y * EYE,
        Vec3::ZERO,
        50f32.to_radians(),
        0.05,
        100.0,
    ))
}

/// Where pixel `(x, y)`'s centre ray crosses the plane at height `h` (x, z).
fn ray_at(camera: &Camera, x: u32, y: u32, h: f32) -> Vec2 {
    let ndc = Vec2::new(
        (x as f32 + 0.5) / SIZE.width as f32 * 2.0 - 1.0,
        1.0 - (y as f32 + 0.5) / SIZE.height as f32 * 2.0,
    );
    let ray = camera.primary_ray(ndc, SIZE.width as f32 / SIZE.height as f32);
    let p = ray.origin + ray.direction * ((h - ray.origin.y) / ray.direction.y);
    Vec2::new(p.x, p.z)
}

/// The second layer's linear depth per pixel, from gtao with two layers at radius R.
fn second_layer(radius: f32) -> Option<(Vec<f32>, Camera)> {
    let config = common::ao_config("gtao", radius, "layers = 2");
    let run = common::render_ao(slab_over_floor(), &config, SIZE, 1)?;
    let r = &run.renderer;
    let h = r
        .graph
        .gbuffer
        .second_layer_depth
        .expect("layers = 2 asks for it");
    let t = r.exec.read_texture(&r.plan, h).expect("reads back");
    Some((t.to_f32().expect("R32Float"), r.camera()))
}

#[test]
fn the_second_layer_is_the_nearest_surface_at_least_delta_behind_the_first() {
    // Δ = 0.05 R: 0.05 (the slab's 0.4 is further) and 0.5 (it is nearer: the floor is next).
    for (radius, inner) in [(1.0, EYE - SLAB_BOTTOM), (10.0, EYE)] {
        let Some((layer, camera)) = second_layer(radius) else {
            return;
        };
        let (mut inside, mut outside) = (0, 0);
        for y in 0..SIZE.height {
            for x in 0..SIZE.width {
                let got = layer[(y * SIZE.width + x) as usize];
                // Well inside the slab's bottom (its sides are behind the top's rim) ...
                let bottom = ray_at(&camera, x, y, SLAB_BOTTOM);
                // ... and well outside its top (only the floor is seen, nothing behind it).
                let top = ray_at(&camera, x, y, SLAB_TOP);
                if bottom.abs().max_element() < 0.95 {
                    inside += 1;
                    // Linear depth is the interpolated view-space z of a plane facing the
                    // camera: exact but for f32 rounding.
                    assert!(
                        (got - inner).abs() < 1e-4,
                        "R = {radius}, ({x}, {y}): {got}, want {inner}"
                    );
                } else if top.abs().max_element() > 1.05 {
                    outside += 1;
                    assert_eq!(got, 0.0, "R = {radius}, ({x}, {y}): only the floor is seen");
                }
            }
        }
        assert!(inside > 100 && outside > 100, "{inside} / {outside} pixels");
    }
}

#[test]
fn the_second_pass_is_drawn_only_for_two_layers_and_half_resolution_refuses_them() {
    for technique in ["gtao", "vbao"] {
        for (params, drawn) in [("", false), ("layers = 1", false), ("layers = 2", true)] {
            let config = common::ao_config(technique, 1.0, params);
            let Some(r) = common::renderer(slab_over_floor(), &config, SIZE) else {
                return;
            };
            let names = r.plan.pass_names();
            assert_eq!(
                names.contains(&"gbuffer.second_layer"),
                drawn,
                "{technique} [{params}]: {names:?}"
            );
            assert_eq!(r.graph.gbuffer.second_layer_depth.is_some(), drawn);
        }
        let config = common::ao_config(technique, 1.0, "layers = 2\nresolution = \"half\"");
        let Some(gpu) = aograph_graph::test_gpu() else {
            return;
        };
        let e = aograph_renderer::Renderer::new(
            gpu,
            aograph::shader_library(),
            &aograph_ao_passes::TechniqueRegistry::with_builtins(),
            std::sync::Arc::new(slab_over_floor()),
            &config,
            aograph_renderer::FrameOutputs::default(),
            SIZE,
        )
        .err()
        .expect("refused");
        let message = e.to_string();
        assert!(
            message.contains("layers = 2") && message.contains("resolution = \"full\""),
            "{technique}: {message}"
        );
    }
}

/// `common::cone_pit` over a ground 2 units below it: seen from above, the ground is every
/// wall pixel's second layer, so the walls are solid down to below the pit's floor.
fn pit_over_ground(beta: f32) -> Scene {
    let mut scene = common::cone_pit(beta, 0.05, 1.6, 0.0);
    let material = scene.meshes[0].material;
    scene.meshes.push(primitives::quad(20.0, 20.0, material));
    scene.instances.push(Instance::fixed(
        scene.meshes.len() - 1,
        Mat4::from_translation(Vec3::NEG_Y * 2.0),
    ));
    scene
}

#[test]
fn vbao_with_two_layers_reads_a_pit_wall_as_thick_as_it_is() {
    let size = Extent::new(65, 65);
    // tests/technique_vbao.rs's pit: β on whole sectors, MIP 0 only, no denoiser; but a
    // thickness of 0.01 R, far too thin to cover the arc from a wall tap down to the tangent
    // plane. With two layers the back of each wall tap is the ground under it, below the
    // tangent plane, so the arc is covered as by a solid wall.
    let base = "denoise_passes = 0\ndepth_mip_offset = 6.0\nthickness = 0.01\nsteps = 4";
    for beta_deg in [22.5f32, 45.0] {
        let beta = beta_deg.to_radians();
        let want = 1.0 - 2.0 * beta / std::f32::consts::PI;
        let centre = |layers: u32| {
            let config = common::ao_config("vbao", 1.0, &format!("{base}\nlayers = {layers}"));
            let run = common::render_ao(pit_over_ground(beta), &config, size, 1)?;
            Some(common::centre_value(&run.ao, size))
        };
        let (Some(two), Some(one)) = (centre(2), centre(1)) else {
            return;
        };
        println!(
            "vbao pit beta = {beta_deg}: two layers {two:.5}, one {one:.5}, closed form {want:.5}"
        );
        // f32 rounding of the sums only, as in the one-layer pit test.
        assert!(
            (two - want).abs() <= 1e-4,
            "beta = {beta_deg}: two layers {two}, closed form {want}"
        );
        assert!(one > want + 0.05, "one layer with T = 0.01 R: {one}");
    }
}
