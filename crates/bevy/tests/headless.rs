//! aograph's AO inside a real bevy app on lavapipe, headless: what bevy's PBR pass reads at
//! binding 17 is aograph's AO of the camera's own prepass, bevy's SSAO passes do not run,
//! switching back to seen settings creates no pipeline, and no render error is recorded.

mod support;

use aograph_bevy::AographAo;
use bevy::prelude::*;
use support::Harness;

const GTAO: &str = "technique = \"gtao\"\nradius = 0.5";
const MSSAO: &str = "technique = \"mssao\"\nradius = 0.5";

/// 16:9 and not a multiple of 8 or 16 (bevy's and aograph's workgroup sizes).
const WIDTH: u32 = 200;
const HEIGHT: u32 = 113;

#[test]
fn bevy_reads_aographs_ao_and_switching_back_creates_no_pipeline() {
    let mut app = Harness::new(WIDTH, HEIGHT, AographAo::from_toml(GTAO).unwrap());
    app.run_until_technique("gtao", 4);
    let frame = app.probe_frame(GTAO);
    assert_eq!((frame.width, frame.height), (WIDTH, HEIGHT));

    // Binding 17 holds aograph's AO of this very prepass: a fresh aograph-embed on the same
    // depth, normals and matrices gives the same values, to bevy's R16Float (one unit in the
    // last place below 1 is 2^-11 = 4.9e-4; 1e-3 leaves room and is far below any AO
    // difference: bevy's own texture, left in place, differs by up to 1).
    let worst = worst_difference(&frame);
    assert!(
        worst <= 1e-3,
        "binding 17 differs from aograph's AO by up to {worst}"
    );
    let crease = assert_open_floor_and_crease(&mut app, &frame, Vec3::new(-4.0, 0.0, 3.0));
    // gtao at full resolution there reads 0.504 on lavapipe; R16Float and the packed normals
    // move it by under 1e-3, and 0.02 leaves room for another driver's rounding.
    assert!((crease - 0.504).abs() < 0.02, "crease AO {crease}");
    // bevy's own SSAO passes do not run for the camera: bevy's render diagnostics never see
    // their span.
    assert_eq!(app.span_gpu_ms("ssao", 2), None, "bevy's SSAO ran");

    // gtao -> mssao -> gtao: the way back creates no pipeline.
    app.set_ao(AographAo::from_toml(MSSAO).unwrap());
    app.run_until_technique("mssao", 30);
    let after_mssao = app.status().camera(app.camera).unwrap().pipelines_created;
    app.set_ao(AographAo::from_toml(GTAO).unwrap());
    app.run_until_technique("gtao", 2);
    app.update();
    let back = app.status().camera(app.camera).unwrap();
    assert_eq!(
        back.pipelines_created, after_mssao,
        "switching back to gtao created pipelines"
    );
    assert!(back.pipelines_created > 0);

    assert_eq!(app.status().errors(), vec![], "aograph recorded an error");
    assert_eq!(
        app.render_errors(),
        Vec::<String>::new(),
        "bevy recorded a render error"
    );
}

#[test]
fn bad_settings_are_an_err_where_the_user_sets_them() {
    let unknown = AographAo::from_toml("technique = \"gtoa\"\nradius = 0.5").unwrap_err();
    assert!(unknown.to_string().contains("gtoa"), "{unknown}");
    let negative = AographAo::from_toml("technique = \"gtao\"\nradius = -1.0").unwrap_err();
    assert!(negative.to_string().contains("radius"), "{negative}");
    let auto = AographAo::from_toml("technique = \"gtao\"\nradius = \"auto\"").unwrap_err();
    assert!(auto.to_string().contains("radius"), "{auto}");
    let traced = AographAo::from_toml("technique = \"rtao\"\nradius = 0.5").unwrap_err();
    assert!(traced.to_string().contains("rtao"), "{traced}");
    let parameter =
        AographAo::from_toml("technique = \"gtao\"\nradius = 0.5\n[gtao]\nslices = 0").unwrap_err();
    assert!(parameter.to_string().contains("slices"), "{parameter}");
}

/// AO at `open`, a floor point with no geometry within the radius, and beside the cube.
/// Returns the crease's AO.
fn assert_open_floor_and_crease(app: &mut Harness, frame: &support::AoFrame, open: Vec3) -> f32 {
    // On open floor nothing occludes: exactly 1 but for the 10-bit packed normals bevy's
    // prepass stores (a tilt of ~2e-3 rad).
    let (fx, fy) = app.pixel_of(open);
    let open = frame.at(&frame.bound, fx, fy);
    assert!(
        (open - 1.0).abs() < 0.02,
        "open floor AO {open} at ({fx}, {fy})"
    );
    // A floor point 5 cm from the cube's face sees the face fill a quarter of its hemisphere
    // within the radius: clearly occluded (0.504 with gtao at full resolution).
    let (cx, cy) = app.pixel_of(Vec3::new(0.0, 0.0, 1.05));
    let crease = frame.at(&frame.bound, cx, cy);
    assert!(
        crease < 0.8,
        "crease AO {crease} at ({cx}, {cy}) is not darker"
    );
    crease
}

/// Largest difference between what binding 17 holds and a fresh aograph-embed's AO of the
/// same frame.
fn worst_difference(frame: &support::AoFrame) -> f32 {
    frame
        .bound
        .iter()
        .zip(&frame.fresh)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0f32, f32::max)
}

#[test]
fn an_orthographic_camera_in_a_viewport_gets_half_resolution_ao_of_its_rectangle() {
    use bevy::camera::{ScalingMode, Viewport};
    let half = "technique = \"gtao\"\nradius = 0.5\n[gtao]\nresolution = \"half\"";
    let mut app = Harness::with_camera(
        WIDTH,
        HEIGHT,
        AographAo::from_toml(half).unwrap(),
        |camera| {
            camera.insert((
                Projection::Orthographic(OrthographicProjection {
                    scaling_mode: ScalingMode::FixedVertical {
                        viewport_height: 7.0,
                    },
                    ..OrthographicProjection::default_3d()
                }),
                Camera {
                    viewport: Some(Viewport {
                        physical_position: UVec2::new(37, 9),
                        physical_size: UVec2::new(141, 95),
                        ..default()
                    }),
                    ..default()
                },
            ));
        },
    );
    app.run_until_technique("gtao", 4);
    let frame = app.probe_frame(half);
    // bevy's PBR pass reads AO at frag_coord - viewport.xy: the texture is the viewport's size.
    assert_eq!((frame.width, frame.height), (141, 95));
    let worst = worst_difference(&frame);
    assert!(
        worst <= 1e-3,
        "binding 17 differs from aograph's AO by up to {worst}"
    );
    assert_open_floor_and_crease(&mut app, &frame, Vec3::new(-3.0, 0.0, 3.0));
    assert_eq!(app.status().errors(), vec![]);
    assert_eq!(app.render_errors(), Vec::<String>::new());
}

#[test]
fn every_technique_the_embedding_offers_runs_in_bevy() {
    let mut app = Harness::new(WIDTH, HEIGHT, AographAo::from_toml(GTAO).unwrap());
    app.run_until_technique("gtao", 4);
    // The techniques aograph_embed::feedable_techniques lists, and gtao temporal at half
    // resolution. A temporal technique's AO depends on its history, which a fresh instance
    // lacks: only the others are compared with a fresh aograph-embed.
    let offered =
        aograph_embed::feedable_techniques(&aograph_ao_passes::TechniqueRegistry::with_builtins());
    // A technique added to the embedding is added here, with whether it is temporal.
    assert_eq!(
        offered,
        [
            "gtao",
            "hbao",
            "mssao",
            "pyramid-hbao",
            "ssao",
            "tssao",
            "vbao"
        ]
    );
    let temporal = ["tssao"];
    let cases = offered
        .iter()
        .map(|t| (t.as_str(), "", !temporal.contains(&t.as_str())))
        .chain([(
            "gtao",
            "[gtao]\nresolution = \"half\"\ntemporal = true",
            false,
        )]);
    for (technique, table, compare) in cases {
        let toml = format!("technique = \"{technique}\"\nradius = 0.5\n{table}");
        app.set_ao(AographAo::from_toml(&toml).unwrap());
        app.run_until_technique(technique, 60);
        app.update();
        let frame = app.probe_frame(&toml);
        if compare {
            let worst = worst_difference(&frame);
            assert!(
                worst <= 1e-3,
                "{technique}: binding 17 differs by up to {worst}"
            );
        }
        let (cx, cy) = app.pixel_of(Vec3::new(0.0, 0.0, 1.05));
        let (fx, fy) = app.pixel_of(Vec3::new(-4.0, 0.0, 3.0));
        let (crease, open) = (
            frame.at(&frame.bound, cx, cy),
            frame.at(&frame.bound, fx, fy),
        );
        assert!(
            crease < open,
            "{technique}: crease {crease} not darker than open floor {open}"
        );
        assert_eq!(app.status().errors(), vec![], "{technique}");
    }
    assert_eq!(app.render_errors(), Vec::<String>::new());
}

#[test]
fn msaa_on_is_an_error_in_aographs_status_not_a_panic() {
    let mut app = Harness::with_camera(
        WIDTH,
        HEIGHT,
        AographAo::from_toml(GTAO).unwrap(),
        |camera| {
            camera.insert(Msaa::Sample4);
        },
    );
    for _ in 0..3 {
        app.update();
    }
    let errors = app.status().errors();
    assert_eq!(errors.len(), 1, "{errors:?}");
    assert!(errors[0].1.contains("Msaa::Sample4"), "{}", errors[0].1);
    // bevy itself refuses its SSAO resources on a multisampled camera (a validation error in
    // its own bind group, as without aograph): that is bevy's, and no aograph frame ran.
    assert_eq!(app.status().camera(app.camera).unwrap().frames, 0);
}

#[test]
fn removing_aograph_gives_the_camera_back_to_bevys_ssao() {
    let mut app = Harness::new(WIDTH, HEIGHT, AographAo::from_toml(GTAO).unwrap());
    app.run_until_technique("gtao", 4);
    assert_eq!(
        app.span_gpu_ms("ssao", 2),
        None,
        "bevy's SSAO ran beside aograph's"
    );
    // Without AographAo the camera keeps bevy's ScreenSpaceAmbientOcclusion (it was required):
    // bevy's own SSAO runs again, and aograph forgets the camera.
    let camera = app.camera;
    app.world().entity_mut(camera).remove::<AographAo>();
    let ssao = app.span_gpu_ms("ssao", 3);
    assert!(
        ssao.is_some_and(|ms| !ms.is_empty()),
        "bevy's SSAO did not run"
    );
    assert_eq!(app.status().camera(camera), None);
    assert_eq!(app.status().errors(), vec![]);
    assert_eq!(app.render_errors(), Vec::<String>::new());
}
