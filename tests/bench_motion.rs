//! `aograph bench --motion`: per-frame references, the per-frame scores and the flicker of a
//! moving camera, and TSSAO's neighbourhood test (Eq. 8) measured near moving objects.
//! GPU tests: they skip only when there is no adapter and AOGRAPH_REQUIRE_GPU is unset.

use aograph::shader_library;
use aograph_ao_passes::TechniqueRegistry;
use aograph_app_config::config::RadiusSetting;
use aograph_app_config::prepared_scene::PreparedScene;
use aograph_bench::metrics::MetricOptions;
use aograph_bench::motion::{MotionKind, MotionSettings, motion_frames, run_motion_technique};
use aograph_bench::run::scene_reference;
use aograph_bench::{BenchContext, BenchSettings, ParamSet};
use aograph_scene::views::SceneView;
use aograph_scene::{ReferenceMode, ReferenceNormals};

fn context() -> Option<BenchContext> {
    Some(BenchContext {
        gpu: aograph_graph::test_gpu()?,
        shaders: shader_library(),
        registry: TechniqueRegistry::with_builtins(),
        peaks: None,
    })
}

fn settings(side: u32, frames: u32, warmup: u32, rays: u32) -> BenchSettings {
    BenchSettings {
        score_every_frame: false,
        width: side,
        height: side,
        frames,
        warmup,
        radius: RadiusSetting::Auto,
        rays,
        mode: ReferenceMode::Binary,
        normals: ReferenceNormals::Geometric,
        tracer: aograph_scene::ReferenceTracer::Auto,
        metrics: MetricOptions::default(),
    }
}

fn prepared(name: &str, view: &str) -> PreparedScene {
    let scene = aograph_scene::procedural_scene(name).expect("built-in scene");
    let view = match view {
        "default" => SceneView {
            name: "default".into(),
            camera: scene.camera,
            motion: scene.camera_motion.clone(),
        },
        other => aograph_scene::views::scene_views(&scene)
            .into_iter()
            .find(|v| v.name == other)
            .expect("view exists"),
    };
    PreparedScene::new(&scene, &view, RadiusSetting::Auto)
}

fn set(technique: &str, params: &str) -> ParamSet {
    ParamSet {
        technique: technique.into(),
        params: toml::from_str(params).expect("params parse"),
    }
}

#[test]
fn the_first_frame_of_a_motion_run_is_the_still_frame_bit_for_bit() {
    let Some(ctx) = context() else { return };
    let s = settings(64, 3, 0, 32);
    let m = MotionSettings {
        kind: MotionKind::Orbit,
        fps: 30.0,
        rays: 32,
    };
    let p = prepared("sphere-on-plane", "outside");
    let frames = motion_frames(&ctx, "sphere-on-plane", &p, &s, &m, &mut || {}).unwrap();
    assert_eq!(frames.len(), 3);
    let still = scene_reference(&ctx, "sphere-on-plane", p.clone(), &s).unwrap();
    assert_eq!(frames[0].accessibility, still.accessibility);
    assert_eq!(frames[0].depth, still.depth);
    assert!(
        frames[0].reprojection.is_none(),
        "no frame before the first"
    );
    // The camera turned 2 degrees by the third frame: another image, another reference.
    assert!((frames[2].time - 2.0 / 30.0).abs() < 1e-6);
    assert_ne!(frames[2].depth, frames[0].depth);
    assert_ne!(frames[2].accessibility, frames[0].accessibility);
}

#[test]
fn none_scores_each_frames_mean_occlusion_and_does_not_flicker() {
    // `none` writes accessibility 1 everywhere: its MAE on a frame is that frame's mean
    // reference occlusion, and a surface point keeps its value exactly from frame to frame.
    let Some(ctx) = context() else { return };
    let s = settings(64, 4, 1, 32);
    let m = MotionSettings {
        kind: MotionKind::Path,
        fps: 30.0,
        rays: 32,
    };
    let p = prepared("sphere-on-plane", "outside");
    let frames = motion_frames(&ctx, "sphere-on-plane", &p, &s, &m, &mut || {}).unwrap();
    let (record, _) = run_motion_technique(
        &ctx,
        "sphere-on-plane",
        &p,
        &frames,
        &set("none", ""),
        &s,
        &m,
        &mut || {},
    )
    .unwrap();
    assert_eq!(record.frame_mae.len(), 4);
    for (f, mae) in frames.iter().zip(&record.frame_mae) {
        let occluded: Vec<f64> = f
            .accessibility
            .iter()
            .zip(&f.valid)
            .filter(|(_, v)| **v)
            .map(|(a, _)| 1.0 - f64::from(*a))
            .collect();
        let expected = occluded.iter().sum::<f64>() / occluded.len() as f64;
        assert!((mae - expected).abs() < 1e-9, "{mae} vs {expected}");
    }
    let worst = record.frame_mae.iter().copied().fold(0.0, f64::max);
    assert_eq!(record.mae_worst, worst);
    // Exactly 0 up to the bilinear weights' rounding (they sum to 1 within a few ulps).
    let flicker = record.flicker.expect("frames with history");
    assert!(flicker < 1e-6, "{flicker}");
    // A straight walk of 1/30 s: nearly every surface point was seen in the previous frame.
    assert!(
        record.flicker_coverage.unwrap() > 0.9,
        "{:?}",
        record.flicker_coverage
    );
    assert_eq!(
        record.moving_mae_mean, None,
        "nothing in sphere-on-plane moves"
    );
}

#[test]
fn an_orbit_through_a_wall_is_refused_with_the_frame_it_happens() {
    let Some(ctx) = context() else { return };
    // `columns`' own camera stands among the columns: turning about the target walks it into
    // one within a quarter of a second.
    let s = settings(32, 12, 0, 4);
    let m = MotionSettings {
        kind: MotionKind::Orbit,
        fps: 30.0,
        rays: 4,
    };
    let p = prepared("columns", "default");
    let e = motion_frames(&ctx, "columns", &p, &s, &m, &mut || {})
        .err()
        .expect("refused");
    let text = e.to_string();
    assert!(
        text.contains("passes through a surface") && text.contains("frame 8"),
        "{text}"
    );
}

#[test]
fn dropping_eq_8_leaves_contact_shadows_near_moving_objects() {
    // TSSAO's Fig. 8: with the disocclusion test alone (Eq. 7), a pixel whose neighbourhood
    // changed (an object moved past it) keeps its stale history, so the error near moving
    // objects is higher than with Eq. 8. Measured on `dynamic` with its own camera path.
    let Some(ctx) = context() else { return };
    let s = settings(96, 12, 4, 32);
    let m = MotionSettings {
        kind: MotionKind::Scene,
        fps: 30.0,
        rays: 32,
    };
    let p = prepared("dynamic", "default");
    let frames = motion_frames(&ctx, "dynamic", &p, &s, &m, &mut || {}).unwrap();
    assert!(
        frames.iter().all(|f| f.near_moving.iter().any(|m| *m)),
        "every frame has pixels near moving objects"
    );
    let near = |test: bool| {
        let params = format!("neighbourhood_test = {test}");
        let (r, _) = run_motion_technique(
            &ctx,
            "dynamic",
            &p,
            &frames,
            &set("tssao", &params),
            &s,
            &m,
            &mut || {},
        )
        .unwrap();
        r.moving_mae_mean.expect("pixels near moving objects")
    };
    let (with, without) = (near(true), near(false));
    eprintln!("near moving objects: MAE {with:.4} with Eq. 8, {without:.4} without");
    assert!(
        without > with * 1.1,
        "near moving objects: MAE {with:.4} with Eq. 8, {without:.4} without"
    );
}

fn aograph(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_aograph"))
        .args(args)
        .output()
        .expect("aograph runs")
}

#[test]
fn bench_motion_writes_its_files_and_refuses_bad_flags_by_name() {
    // Refusals come before any GPU work.
    for (flags, expected) in [
        (&["--motion", "dolly"][..], "orbit, path, scene"),
        (&["--motion", "orbit", "--fps", "0"][..], "--fps"),
        (
            &["--motion", "orbit", "--motion-rays", "0"][..],
            "--motion-rays",
        ),
        (&["--motion", "orbit", "--scaling"][..], "--scaling"),
    ] {
        let out = aograph(&[&["bench", "--scenes", "plane"][..], flags].concat());
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{flags:?} accepted");
        assert!(stderr.contains(expected), "{flags:?}: {stderr}");
    }
    if aograph_graph::test_gpu().is_none() {
        return;
    }
    let out = aograph(&["bench", "--motion", "scene", "--scenes", "plane", "--quiet"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && stderr.contains("no animation"),
        "{stderr}"
    );

    let dir = std::env::temp_dir().join(format!("aograph-motion-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let out = aograph(&[
        "bench",
        "--motion",
        "scene",
        "--scenes",
        "dynamic",
        "--techniques",
        "ssao,tssao",
        "--width",
        "96",
        "--height",
        "96",
        "--frames",
        "3",
        "--warmup",
        "1",
        "--motion-rays",
        "8",
        "--out",
        dir.to_str().unwrap(),
        "--quiet",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let csv = std::fs::read_to_string(dir.join("motion.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines.len(), 3, "{csv}");
    assert_eq!(lines[0], aograph_bench::motion::MotionRecord::CSV_HEADER);
    let frames = std::fs::read_to_string(dir.join("motion_frames.csv")).unwrap();
    assert_eq!(frames.lines().count(), 1 + 2 * 3, "{frames}");
    let file = aograph_bench::motion::read_motion(&dir.join("motion.json")).unwrap();
    assert!(
        file.meta.command.starts_with("aograph bench --motion"),
        "{}",
        file.meta.command
    );
    let records = file.runs;
    assert_eq!(records.len(), 2);
    for r in &records {
        assert_eq!(r.frame_mae.len(), 3);
        assert_eq!(r.rays, 8);
        assert!(r.moving_mae_mean.is_some(), "`dynamic` has moving objects");
        let image = dir.join(r.image.as_ref().expect("an image"));
        assert!(image.exists(), "{}", image.display());
    }
    let md = std::fs::read_to_string(dir.join("motion.md")).unwrap();
    assert!(
        md.contains("tssao.sample") && md.contains("motion `scene`"),
        "{md}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
