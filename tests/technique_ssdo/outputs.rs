//! What `ssdo` writes: the g-buffer channels only it asks for, a plane's known direct radiance
//! and no indirect light, valid outputs across scenes and parameters, the radiance PNGs.

use std::sync::Arc;

use crate::common::plane_at;
use aograph_ao_passes::TechniqueRegistry;
use aograph_frame::GBufferChannel;
use aograph_graph::Extent;
use aograph_renderer::FrameOutputs;
use aograph_renderer::build_frame_graph;
use aograph_scene::procedural_scene;

use super::*;

#[test]
fn only_ssdo_makes_the_gbuffer_write_colour_and_direct_light() {
    let registry = TechniqueRegistry::with_builtins();
    let names = registry.names();
    assert!(
        names.iter().any(|n| n == "ssdo"),
        "ssdo is registered: {names:?}"
    );
    let scene = Arc::new(procedural_scene("cornell-box").unwrap());
    for name in &names {
        let config = common::ao_config(name, RADIUS, "");
        let fg = build_frame_graph(
            &registry,
            scene.clone(),
            &config,
            FrameOutputs::default(),
            aograph_graph::Extent::new(64, 48),
        )
        .unwrap_or_else(|e| panic!("{name}: {e}"));
        for c in [GBufferChannel::Albedo, GBufferChannel::DirectLight] {
            let declared = fg
                .decl
                .resource_by_name(&format!("gbuffer.{}", c.name()))
                .is_some();
            let requested = fg.channels.contains(c) || fg.gbuffer.get(c).is_some();
            if name == "ssdo" {
                assert!(
                    declared && requested,
                    "ssdo needs the g-buffer's {}",
                    c.name()
                );
            } else {
                assert!(
                    !declared && !requested,
                    "{name} must not make the g-buffer write {}",
                    c.name()
                );
            }
        }
    }
}

#[test]
fn plane_is_unoccluded_from_straight_down_to_80_degrees() {
    for degrees in [0.0, 30.0, 60.0, 80.0] {
        let Some(run) = common::render_ao(
            plane_at(degrees),
            &common::ao_config("ssdo", RADIUS, ""),
            Extent::new(64, 64),
            1,
        ) else {
            return;
        };
        let what = format!("ssdo on plane at {degrees} degrees");
        assert_valid(&run, &what);
        assert!(
            run.depth.iter().any(|&d| d > 0.0),
            "{what}: the camera sees the plane"
        );
        let min = run.ao.iter().copied().fold(1.0f32, f32::min);
        assert!(min >= 0.98, "{what}: darkest pixel {min}");
    }
    // Orthographic at 60 degrees: eye rays are parallel, the visibility test follows them.
    let mut scene = plane_at(60.0);
    scene.camera.projection = aograph_scene::Projection::Orthographic {
        height: 8.0,
        near: 0.05,
        far: 2000.0,
    };
    let Some(run) = common::render_ao(
        scene,
        &common::ao_config("ssdo", RADIUS, ""),
        Extent::new(64, 64),
        1,
    ) else {
        return;
    };
    assert_valid(&run, "ssdo on plane, orthographic");
    let min = run.ao.iter().copied().fold(1.0f32, f32::min);
    assert!(min >= 0.98, "orthographic: darkest pixel {min}");
}

/// Rounds to the nearest f16 (the radiance outputs and the g-buffer's direct light are
/// Rgba16Float).
fn f16(x: f32) -> f32 {
    let e = x.abs().log2().floor();
    let step = 2f32.powf(e - 10.0);
    (x / step).round() * step
}

/// On an unoccluded plane every sample is visible, so the paper's direct term has a known
/// value, L_dir = rho * mean over the samples of L_in (the constant ambient, sky_gradient 0)
/// plus rho * E_sun * max(0, n.l) (every light sample visible), and the indirect term is exactly
/// zero (no sender occludes). The expected value is rebuilt from the scene: albedo as the
/// g-buffer stores it (Rgba8Unorm), the direct light as it stores it (f16 of
/// colour * light * n.l). Intermediates in r32float; tolerance: the output is f16 (relative
/// 2^-11) after a blur that averages equal values, so 1e-3 relative.
#[test]
fn unoccluded_plane_has_the_known_direct_radiance_and_no_indirect_light() {
    for degrees in [0.0, 40.0, 70.0] {
        let scene = plane_at(degrees);
        let material = scene.materials[scene.meshes[scene.instances[0].mesh].material];
        let light = scene.light;
        let n_dot_l = glam::Vec3::Y.dot(-light.direction.normalize()).max(0.0);
        let expected: Vec<f32> = (0..3)
            .map(|c| {
                let rho = material.base_color[c];
                let rho8 = (rho * 255.0).round() / 255.0;
                let sun = f16(rho * light.color[c] * light.intensity * n_dot_l);
                rho8 * scene.ambient[c] + sun
            })
            .collect();
        let config = aograph_ao_passes::AoConfig {
            intermediate_format: aograph_ao_passes::IntermediateFormat::R32Float,
            ..common::ao_config("ssdo", RADIUS, "sky_gradient = 0.0")
        };
        let Some(run) = common::render_ao(scene, &config, Extent::new(48, 48), 1) else {
            return;
        };
        let direct = run
            .renderer
            .read_extra(aograph_ao_passes::techniques::ssdo::DIRECT_OUTPUT)
            .unwrap();
        let indirect = run
            .renderer
            .read_extra(aograph_ao_passes::techniques::ssdo::INDIRECT_OUTPUT)
            .unwrap();
        let (mut checked, mut worst) = (0, 0.0f32);
        for (i, d) in run.depth.iter().enumerate() {
            if *d <= 0.0 {
                continue;
            }
            checked += 1;
            for c in 0..3 {
                let got = direct[i * 4 + c];
                let rel = (got - expected[c]).abs() / expected[c];
                worst = worst.max(rel);
                assert!(
                    rel <= 1e-3,
                    "{degrees} degrees, pixel {i}, channel {c}: ssdo_direct {got}, expected {}",
                    expected[c]
                );
                assert_eq!(
                    indirect[i * 4 + c],
                    0.0,
                    "{degrees} degrees: indirect light at pixel {i}"
                );
            }
        }
        assert!(
            checked > 500,
            "{degrees} degrees: only {checked} plane pixels"
        );
        eprintln!(
            "plane at {degrees} degrees: ssdo_direct = {expected:?} within {worst:.1e} relative on {checked} pixels, indirect exactly 0"
        );
    }
}

#[test]
fn outputs_are_valid_across_scenes_and_parameters() {
    for (scene, params) in [
        ("cornell-box", ""),
        ("columns", "samples = 16"),
        ("stairs", "samples = 4\nsky_gradient = 1.0\nlight_lobe = 64"),
        ("thin-bars", "bounce = false\nfade_start = 1.0\nbias = 0.0"),
    ] {
        let Some(run) = common::render_ao(
            procedural_scene(scene).unwrap(),
            &common::ao_config("ssdo", RADIUS, params),
            Extent::new(64, 48),
            1,
        ) else {
            return;
        };
        assert_valid(
            &run,
            &format!("ssdo [{}] on {scene}", params.replace('\n', ", ")),
        );
    }
    // A radius far beyond the scene: every sample off screen or far, still valid.
    let Some(run) = common::render_ao(
        procedural_scene("sphere-on-plane").unwrap(),
        &common::ao_config("ssdo", 1.0e6, "distance_clamp = 10000"),
        Extent::new(64, 64),
        1,
    ) else {
        return;
    };
    assert_valid(&run, "ssdo with R = 1e6");
}

#[test]
fn render_writes_the_radiance_images() {
    if aograph_graph::test_gpu().is_none() {
        return;
    }
    let out = std::path::PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/target/test-output/ssdo-render"
    ));
    let _ = std::fs::remove_dir_all(&out);
    let common_args = aograph::commands::CommonArgs {
        scene: Some("cornell-box".into()),
        technique: Some("ssdo".into()),
        width: Some(64),
        height: Some(48),
        radius: Some("0.5".into()),
        ..Default::default()
    };
    aograph::commands::render(&aograph::commands::RenderArgs {
        common: common_args,
        out: out.clone(),
        frames: Some(1),
        every: false,
    })
    .expect("render runs");
    for f in [
        "ao.png",
        "shaded.png",
        "ssdo_direct.png",
        "ssdo_indirect.png",
        "timings.txt",
    ] {
        assert!(out.join(f).is_file(), "{f} written");
    }
}
