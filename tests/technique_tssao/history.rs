//! When `tssao`'s history restarts (camera cuts, resizes), the render command on `dynamic`, the
//! example config, and the temporal block's averaging.

use aograph_ao_passes::TechniqueRegistry;
use aograph_ao_passes::blocks::temporal::TemporalMode;
use aograph_graph::{Extent, test_gpu};
use aograph_renderer::Renderer;
use aograph_scene::{Camera, Scene, procedural_scene};
use glam::{Mat4, Vec3};

use super::*;

/// Scene `b` appended to scene `a`, moved by `offset`; `a`'s camera.
fn merged(mut a: Scene, b: Scene, offset: Mat4) -> Scene {
    let (meshes, materials) = (a.meshes.len(), a.materials.len());
    a.materials.extend(b.materials);
    a.meshes.extend(b.meshes.into_iter().map(|mut m| {
        m.material += materials;
        m
    }));
    a.instances.extend(b.instances.into_iter().map(|mut i| {
        i.mesh += meshes;
        i.transform = offset * i.transform;
        i
    }));
    a
}

#[test]
fn a_camera_cut_restarts_the_history() {
    let size = Extent::new(96, 64);
    // Same camera before and after: without the cut, the history would be reused everywhere.
    let columns = procedural_scene("columns").unwrap();
    let Some(mut r) = renderer(columns.clone(), &tssao(""), size) else {
        return;
    };
    for _ in 0..8 {
        r.render(0.0).unwrap();
    }
    let mut uncut = renderer(columns.clone(), &tssao(""), size).unwrap();
    for _ in 0..9 {
        uncut.render(0.0).unwrap();
    }
    r.cut();
    r.render(0.0).unwrap();
    let after_cut = ao(&r);
    let mut fresh = renderer(columns, &tssao(""), size).unwrap();
    fresh.render(0.0).unwrap();
    assert_eq!(
        after_cut,
        ao(&fresh),
        "the first frame after a cut must equal a fresh first frame"
    );
    assert_ne!(
        after_cut,
        ao(&uncut),
        "without the cut, frame 9 carries history (the check has teeth)"
    );

    // A cut from `plane` (accessibility 1) to `corner` (occluded along its walls), one scene
    // 1000 units apart: the first frame after the cut equals a fresh render of the corner.
    let corner = procedural_scene("corner").unwrap();
    let corner_camera = corner.camera;
    let plane_camera = Camera::perspective(
        Vec3::new(0.0, -998.0, 6.0),
        Vec3::new(0.0, -1000.0, 0.0),
        50f32.to_radians(),
        0.05,
        2000.0,
    );
    let scene = merged(
        corner,
        procedural_scene("plane").unwrap(),
        Mat4::from_translation(Vec3::new(0.0, -1000.0, 0.0)),
    );
    let mut r = renderer(scene.clone(), &tssao(""), size).unwrap();
    for _ in 0..6 {
        r.render_with_camera(0.0, plane_camera).unwrap();
    }
    let before = ao(&r);
    assert!(before.iter().all(|&a| a >= 0.98), "the plane is unoccluded");
    r.cut();
    r.render_with_camera(0.0, corner_camera).unwrap();
    let after_cut = ao(&r);
    let mut fresh = renderer(scene, &tssao(""), size).unwrap();
    fresh.render_with_camera(0.0, corner_camera).unwrap();
    let fresh_ao = ao(&fresh);
    assert!(
        fresh_ao.iter().any(|&a| a < 0.8),
        "the corner is occluded somewhere"
    );
    assert_eq!(
        after_cut, fresh_ao,
        "after the cut to the corner nothing of the plane remains"
    );
}

#[test]
fn a_resize_restarts_the_history() {
    let columns = procedural_scene("columns").unwrap();
    let Some(mut r) = renderer(columns.clone(), &tssao(""), Extent::new(96, 64)) else {
        return;
    };
    for _ in 0..8 {
        r.render(0.0).unwrap();
    }
    let small = Extent::new(64, 48);
    r.resize(small).unwrap();
    r.render(0.0).unwrap();
    let mut fresh = renderer(columns, &tssao(""), small).unwrap();
    fresh.render(0.0).unwrap();
    assert_eq!(
        ao(&r),
        ao(&fresh),
        "the first frame after a resize must equal a fresh first frame"
    );
}

#[test]
fn render_command_writes_every_frame_of_the_dynamic_scene() {
    if test_gpu().is_none() {
        return;
    }
    let out = std::env::temp_dir().join(format!("aograph-tssao-render-{}", std::process::id()));
    let common = aograph::commands::CommonArgs {
        scene: Some("dynamic".into()),
        technique: Some("tssao".into()),
        width: Some(64),
        height: Some(48),
        ..Default::default()
    };
    aograph::commands::render(&aograph::commands::RenderArgs {
        common,
        out: out.clone(),
        frames: Some(4),
        every: true,
    })
    .expect("render runs");
    for f in [
        "ao.png",
        "shaded.png",
        "timings.txt",
        "ao_0000.png",
        "ao_0003.png",
        "shaded_0003.png",
    ] {
        assert!(out.join(f).is_file(), "{f} written");
    }
    let last = std::fs::read(out.join("ao_0003.png")).unwrap();
    assert_eq!(
        last,
        std::fs::read(out.join("ao.png")).unwrap(),
        "ao.png is the last frame"
    );
    std::fs::remove_dir_all(&out).ok();

    // With AO fixed at 1, shaded frames differ only because the camera and objects move.
    let common = aograph::commands::CommonArgs {
        scene: Some("dynamic".into()),
        technique: Some("none".into()),
        width: Some(64),
        height: Some(48),
        ..Default::default()
    };
    aograph::commands::render(&aograph::commands::RenderArgs {
        common,
        out: out.clone(),
        frames: Some(3),
        every: true,
    })
    .expect("render runs");
    let first = std::fs::read(out.join("shaded_0000.png")).unwrap();
    assert_ne!(
        first,
        std::fs::read(out.join("shaded_0002.png")).unwrap(),
        "the dynamic scene moves between frames"
    );
    std::fs::remove_dir_all(&out).ok();
}

#[test]
fn example_config_parses_with_paper_defaults() {
    let path = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/configs/tssao.toml"));
    let config = aograph_app_config::AppConfig::load(path, &TechniqueRegistry::with_builtins())
        .expect("configs/tssao.toml is valid");
    assert_eq!(config.ao.technique, "tssao");
    assert_eq!(config.frames, 32);
    let table = config.ao.params_for("tssao");
    for (key, value) in [
        ("k1", 32),
        ("k2", 8),
        ("n_max", 500),
        ("n_smooth", 32),
        ("filter_width", 5),
    ] {
        assert_eq!(
            table.get(key).and_then(|v| v.as_integer()),
            Some(value),
            "{key}"
        );
    }
}

/// The accumulated value on every non-sky pixel of the last frame (they must all agree).
fn uniform_value(r: &Renderer) -> f32 {
    let (a, d) = (ao(r), depth(r));
    common::assert_valid_ao(&a, &d, "temporal block output");
    let values: Vec<f32> = a
        .iter()
        .zip(&d)
        .filter(|(_, z)| **z > 0.0)
        .map(|(v, _)| *v)
        .collect();
    assert!(!values.is_empty());
    assert!(
        values.iter().all(|v| (v - values[0]).abs() < 1e-6),
        "non-sky pixels differ: {:?}",
        &values[..8.min(values.len())]
    );
    values[0]
}

#[test]
fn temporal_block_averages_blends_and_resets() {
    // Average (TSSAO Eqs. 5-6, one sample per frame), n_max = 4: inputs 0, 1, 0, 1, 0, 1, ...
    let Some(mut r) = common::parity::renderer(
        TemporalMode::Average,
        procedural_scene("columns").unwrap(),
        Extent::new(64, 48),
    ) else {
        return;
    };
    let mut expected = Vec::new();
    let (mut mean, mut n) = (0.0f32, 0.0f32);
    for f in 0..8u32 {
        r.render(0.0).unwrap();
        let x = (f & 1) as f32;
        mean = (n * mean + x) / (n + 1.0);
        n = (n + 1.0).min(4.0);
        expected.push(mean);
        assert!(
            (uniform_value(&r) - mean).abs() < 1e-5,
            "Average, frame {f}: {} expected {mean}",
            uniform_value(&r)
        );
    }
    println!("temporal block, Average (n_max 4) over inputs 0, 1, 0, 1, ...: {expected:?}");
    // A cut: the next frame is its input alone.
    r.cut();
    r.render(0.0).unwrap();
    assert_eq!(uniform_value(&r), 0.0, "frame 8 (input 0) after a cut");

    // FixedBlend(0.5) (MSSAO Eq. 14): A = 0.5 A_prev + 0.5 x.
    let mut r = common::parity::renderer(
        TemporalMode::FixedBlend(0.5),
        procedural_scene("columns").unwrap(),
        Extent::new(64, 48),
    )
    .unwrap();
    let mut a = 0.0f32;
    for f in 0..6u32 {
        r.render(0.0).unwrap();
        let x = (f & 1) as f32;
        a = if f == 0 { x } else { 0.5 * a + 0.5 * x };
        assert!(
            (uniform_value(&r) - a).abs() < 1e-6,
            "FixedBlend, frame {f}: {} expected {a}",
            uniform_value(&r)
        );
    }
    // A resize invalidates the history: the first frame at the new size is its input.
    r.resize(Extent::new(48, 32)).unwrap();
    r.render(0.0).unwrap();
    assert_eq!(uniform_value(&r), 0.0, "frame 6 (input 0) after a resize");
}

#[test]
fn point_visibility_weighs_occluders_by_distance_so_it_reads_lighter_than_the_march() {
    // "point" tests one point s_i = p + R (1 - u) w per sample: an occluder at distance d
    // along w blocks it with probability 1 - d/R, while the march blocks it whenever d < R.
    // So converged, on a scene full of occluders, the point test is lighter pixel by pixel
    // (up to sampling noise), and both agree where nothing is within R.
    let size = Extent::new(64, 64);
    let converged = |visibility: &str| -> Option<(Vec<f32>, Vec<f32>)> {
        let config = tssao(&format!("visibility = \"{visibility}\""));
        let mut r = renderer(procedural_scene("cornell-box").unwrap(), &config, size)?;
        for _ in 0..24 {
            r.render(0.0).unwrap();
        }
        Some((ao(&r), depth(&r)))
    };
    let Some((march, d)) = converged("march") else {
        return;
    };
    let (point, _) = converged("point").unwrap();
    let geometry: Vec<usize> = (0..d.len()).filter(|i| d[*i] > 0.0).collect();
    let mean = |a: &[f32]| geometry.iter().map(|i| a[*i]).sum::<f32>() / geometry.len() as f32;
    let (m_march, m_point) = (mean(&march), mean(&point));
    eprintln!("mean accessibility: march {m_march:.4}, point {m_point:.4}");
    assert!(m_point > m_march + 0.02, "march {m_march}, point {m_point}");
    // Noise: 24 frames of k = 32 then 8 samples is about 300 samples a pixel (sigma < 0.03).
    let darker = geometry
        .iter()
        .filter(|i| point[**i] < march[**i] - 0.1)
        .count();
    assert!(
        darker * 100 < geometry.len(),
        "{darker} of {} pixels",
        geometry.len()
    );
}
