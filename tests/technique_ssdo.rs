//! `ssdo`: the g-buffer writes colour and direct light only for SSDO (GPU-free); on the GPU, no
//! self-occlusion on a plane, valid outputs, colour bleeding from the Cornell box's red wall
//! onto the floor (and none without the bounce), accessibility against the reference next to
//! `ssao` at the same N, `aograph render` writing the radiance PNGs, and the cost of the direct
//! term and of the bounce as ratios to `ssao` (printed; speed targets live in benchmarks).

mod common;

use std::sync::Arc;

use aograph::{FrameOutputs, build_frame_graph};
use aograph_ao::TechniqueRegistry;
use aograph_frame::GBufferChannel;
use aograph_graph::Extent;
use aograph_scene::procedural_scene;

const RADIUS: f32 = 1.0;

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

use common::plane_at;

/// Accessibility valid, radiance finite, non-negative and zero on sky.
fn assert_valid(run: &common::AoRun, what: &str) {
    common::assert_valid_ao(&run.ao, &run.depth, what);
    for name in ["ssdo_direct", "ssdo_indirect"] {
        let rgba = run
            .renderer
            .read_extra(name)
            .expect("extra output reads back");
        assert_eq!(
            rgba.len(),
            run.depth.len() * 4,
            "{what}: {name} is full size"
        );
        for (i, (px, d)) in rgba.chunks_exact(4).zip(&run.depth).enumerate() {
            assert!(
                px.iter().all(|v| v.is_finite() && *v >= 0.0),
                "{what}: {name} pixel {i} = {px:?}"
            );
            if *d <= 0.0 {
                assert_eq!(&px[..3], &[0.0; 3], "{what}: {name} sky pixel {i}");
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
        let config = aograph_ao::AoConfig {
            intermediate_format: aograph_ao::IntermediateFormat::R32Float,
            ..common::ao_config("ssdo", RADIUS, "sky_gradient = 0.0")
        };
        let Some(run) = common::render_ao(scene, &config, Extent::new(48, 48), 1) else {
            return;
        };
        let direct = run.renderer.read_extra("ssdo_direct").unwrap();
        let indirect = run.renderer.read_extra("ssdo_indirect").unwrap();
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

/// Mean (red, green) of `ssdo_indirect` over floor pixels of the Cornell box with x in `xs`.
fn floor_indirect(run: &common::AoRun, xs: std::ops::Range<f32>) -> (f32, f32, usize) {
    let s = common::surfaces(run);
    let rgba = run.renderer.read_extra("ssdo_indirect").unwrap();
    let (mut r, mut g, mut n) = (0.0f64, 0.0f64, 0usize);
    for i in common::cornell_floor_pixels(&s, xs) {
        r += rgba[i * 4] as f64;
        g += rgba[i * 4 + 1] as f64;
        n += 1;
    }
    (
        (r / n.max(1) as f64) as f32,
        (g / n.max(1) as f64) as f32,
        n,
    )
}

#[test]
fn cornell_box_bounce_carries_the_walls_colour_onto_the_floor() {
    let size = Extent::new(96, 96);
    // The paper's distance clamp (1 scene unit) and one scaled to this 2-unit room with R = 0.5.
    let mut first = None;
    for params in ["", "distance_clamp = 0.1"] {
        let Some(run) = common::render_ao(
            procedural_scene("cornell-box").unwrap(),
            &common::ao_config("ssdo", 0.5, params),
            size,
            1,
        ) else {
            return;
        };
        assert_valid(&run, "ssdo on cornell-box");
        let (red_r, red_g, n_red) = floor_indirect(&run, -1.0..-0.75);
        let (green_r, green_g, n_green) = floor_indirect(&run, 0.75..1.0);
        let (mid_r, mid_g, n_mid) = floor_indirect(&run, -0.15..0.15);
        println!(
            "ssdo_indirect on the cornell-box floor (R = 0.5, N = 8, 96x96, [{params}]), mean (red, green):"
        );
        println!(
            "  near the red wall   (x < -0.75, {n_red} px): ({red_r:.4}, {red_g:.4}), red/green {:.2}",
            red_r / red_g.max(1e-9)
        );
        println!(
            "  middle              (|x| < 0.15, {n_mid} px): ({mid_r:.4}, {mid_g:.4}), red/green {:.2}",
            mid_r / mid_g.max(1e-9)
        );
        println!(
            "  near the green wall (x > 0.75, {n_green} px): ({green_r:.4}, {green_g:.4}), red/green {:.2}",
            green_r / green_g.max(1e-9)
        );
        assert!(
            n_red >= 20 && n_green >= 20,
            "the floor near both walls is in view: {n_red}, {n_green} pixels"
        );
        // The colour of the bleed, as ratios with tolerances: measured red/green 1.89 and 1.97
        // near the red wall, 0.38 and 0.35 near the green wall, 1.07 in the middle (both
        // [params] sets). The bounds are those +-25% (the estimator's 8 samples per pixel
        // vary with the device's rounding); the middle sees both walls alike, so its ratio is
        // the floor's own albedo ratio (0.62 / 0.60 = 1.03) shifted a little by the nearer
        // walls: 0.9 to 1.25. A bounce that carried no colour (ratios near 1 everywhere) or
        // the wrong wall's fails.
        let ratio = |r: f32, g: f32| r / g.max(1e-9);
        let (near_red, middle, near_green) = (
            ratio(red_r, red_g),
            ratio(mid_r, mid_g),
            ratio(green_r, green_g),
        );
        assert!(
            red_r > 1e-4 && (1.45..=2.45).contains(&near_red),
            "[{params}] near the red wall red/green {near_red}"
        );
        assert!(
            (0.28..=0.48).contains(&near_green),
            "[{params}] near the green wall red/green {near_green}"
        );
        assert!(
            (0.9..=1.25).contains(&middle),
            "[{params}] middle red/green {middle}"
        );
        first.get_or_insert(run);
    }
    let Some(run) = first else { return };
    let Some(off) = common::render_ao(
        procedural_scene("cornell-box").unwrap(),
        &common::ao_config("ssdo", 0.5, "bounce = false"),
        size,
        1,
    ) else {
        return;
    };
    let indirect = off.renderer.read_extra("ssdo_indirect").unwrap();
    assert!(
        indirect.chunks_exact(4).all(|px| px[..3] == [0.0; 3]),
        "bounce = false: the indirect term is exactly zero"
    );
    assert_eq!(
        off.ao, run.ao,
        "the bounce does not change the accessibility"
    );
    assert_eq!(
        off.renderer.read_extra("ssdo_direct").unwrap(),
        run.renderer.read_extra("ssdo_direct").unwrap(),
        "nor the direct term"
    );
}

#[test]
fn sphere_on_plane_accessibility_is_within_the_error_of_ssao() {
    let size = Extent::new(96, 96);
    let registry = TechniqueRegistry::with_builtins();
    for samples in [8, 16] {
        let Some(run) = common::render_ao(
            procedural_scene("sphere-on-plane").unwrap(),
            &common::ao_config("ssdo", RADIUS, &format!("samples = {samples}")),
            size,
            1,
        ) else {
            return;
        };
        assert_valid(&run, "ssdo on sphere-on-plane");
        assert!(run.ao.iter().any(|&a| a < 0.9), "the contact is occluded");
        let reference = common::reference(&run, RADIUS, 256);
        let mae = common::mae(&run.ao, &reference, &run.depth);
        assert!(
            registry.get("ssao").is_ok(),
            "ssao is a built-in technique: the comparison needs it"
        );
        if registry.get("ssao").is_ok() {
            let ssao = common::render_ao(
                procedural_scene("sphere-on-plane").unwrap(),
                &common::ao_config("ssao", RADIUS, &format!("samples = {samples}")),
                size,
                1,
            )
            .unwrap();
            let ssao_mae = common::mae(
                &ssao.ao,
                &common::reference(&ssao, RADIUS, 256),
                &ssao.depth,
            );
            println!(
                "sphere-on-plane 96x96, R = {RADIUS}, N = {samples}: MAE against the reference (256 rays): ssdo {mae:.4}, ssao {ssao_mae:.4}"
            );
            assert!(
                mae <= ssao_mae * 1.1 + 0.005,
                "N = {samples}: ssdo MAE {mae} is not within ssao's {ssao_mae}"
            );
        } else {
            println!(
                "sphere-on-plane 96x96, R = {RADIUS}, N = {samples}: ssdo MAE {mae:.4} (ssao not registered)"
            );
            assert!(mae < 0.1, "MAE {mae}");
        }
    }
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

/// Per-frame times of one renderer: the technique's passes summed (names starting with
/// `technique.`), the whole frame, and each technique pass.
#[derive(Default)]
struct Times {
    technique: Vec<f64>,
    frame: Vec<f64>,
    passes: Vec<(String, Vec<f64>)>,
}

fn median(v: &[f64]) -> f64 {
    let mut v = v.to_vec();
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied().unwrap_or(f64::NAN)
}

impl Times {
    fn record(&mut self, r: &mut aograph::Renderer, technique: &str) {
        let t = r.timings().unwrap();
        let mine: Vec<_> = t
            .passes
            .iter()
            .filter(|(n, _)| n.starts_with(&format!("{technique}.")))
            .cloned()
            .collect();
        if mine.is_empty() {
            return; // the first frame's timings arrive a frame later
        }
        self.technique.push(mine.iter().map(|(_, ms)| ms).sum());
        self.frame.push(t.total_ms());
        for (n, ms) in mine {
            match self.passes.iter_mut().find(|(p, _)| *p == n) {
                Some((_, v)) => v.push(ms),
                None => self.passes.push((n, vec![ms])),
            }
        }
    }
    fn passes(&self) -> String {
        self.passes
            .iter()
            .map(|(n, v)| format!("{n} {:.3}", median(v)))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

#[test]
fn cost_of_the_direct_term_and_the_bounce_relative_to_ssao() {
    assert!(
        TechniqueRegistry::with_builtins().get("ssao").is_ok(),
        "ssao is a built-in technique: the cost ratios need it"
    );
    const FRAMES: usize = 24;
    let size = Extent::new(128, 128);
    for samples in [8, 16] {
        let n = format!("samples = {samples}");
        // The three run frame by frame in turn, so load on the (shared) machine hits all alike.
        let mut runs = Vec::new();
        for (technique, params) in [
            ("ssao", n.clone()),
            ("ssdo", format!("{n}\nbounce = false")),
            ("ssdo", n.clone()),
        ] {
            let Some(run) = common::render_ao(
                procedural_scene("columns").unwrap(),
                &common::ao_config(technique, RADIUS, &params),
                size,
                1,
            ) else {
                return;
            };
            runs.push((technique, run.renderer, Times::default()));
        }
        for _ in 0..FRAMES {
            for (technique, r, times) in runs.iter_mut() {
                r.render(0.0).unwrap();
                times.record(r, technique);
            }
        }
        let [ssao, direct, bounce] = [&runs[0].2, &runs[1].2, &runs[2].2];
        let ratio = |a: &Times, b: &Times| {
            median(
                &a.technique
                    .iter()
                    .zip(&b.technique)
                    .map(|(x, y)| x / y)
                    .collect::<Vec<_>>(),
            )
        };
        let fps_drop = |a: &Times| {
            median(
                &a.frame
                    .iter()
                    .zip(&ssao.frame)
                    .map(|(x, y)| 1.0 - y / x)
                    .collect::<Vec<_>>(),
            ) * 100.0
        };
        let device = aograph_graph::test_gpu()
            .map(|g| g.describe())
            .unwrap_or_default();
        println!(
            "cost on columns {size}, N = {samples}, medians over {} interleaved frames on {device}:",
            ssao.technique.len()
        );
        println!(
            "  ssao                {:.3} ms, frame {:.3} ms [{}]",
            median(&ssao.technique),
            median(&ssao.frame),
            ssao.passes()
        );
        println!(
            "  ssdo without bounce {:.3} ms = {:.2} x ssao, frame {:.3} ms (fps -{:.1}%) [{}]",
            median(&direct.technique),
            ratio(direct, ssao),
            median(&direct.frame),
            fps_drop(direct),
            direct.passes()
        );
        println!(
            "  ssdo with bounce    {:.3} ms = {:.2} x ssao, frame {:.3} ms (fps -{:.1}%) [{}]",
            median(&bounce.technique),
            ratio(bounce, ssao),
            median(&bounce.frame),
            fps_drop(bounce),
            bounce.passes()
        );
        println!(
            "  the bounce alone: {:.2} x ssao; the paper (Table 1, fps drop of the whole frame against SSAO): 3.6% direct, 31.1% with the bounce",
            ratio(bounce, ssao) - ratio(direct, ssao)
        );
        assert!(
            ssao.technique.len() + 1 >= FRAMES
                && median(&ssao.technique) > 0.0
                && median(&bounce.technique) > 0.0,
            "timings were measured"
        );
    }
}

/// Mean RGB of `rgb(i)` over the Cornell box's floor pixels with x in `xs` (as
/// [`floor_indirect`] picks them).
fn floor_mean(
    s: &aograph_scene::SurfaceBuffer,
    xs: std::ops::Range<f32>,
    rgb: impl Fn(usize) -> glam::Vec3,
) -> glam::Vec3 {
    let picked = common::cornell_floor_pixels(s, xs.clone());
    assert!(
        picked.len() >= 20,
        "{} floor pixels in {xs:?}",
        picked.len()
    );
    picked.iter().map(|&i| rgb(i)).sum::<glam::Vec3>() / picked.len() as f32
}

#[test]
fn cornell_box_bounce_under_the_sky_has_the_references_colour() {
    // SSDO under the built-in sky against the radiance reference (one diffuse bounce from
    // geometry within R, the same sky): the bounce's colour on the floor, as red / green, near
    // each coloured wall. Its strength is E2's business (sender patches, the distance clamp:
    // 0.1 for this 2-unit room, see cornell_box_bounce_carries_the_walls_colour_onto_the_floor);
    // the colour must be the walls'.
    let size = Extent::new(96, 96);
    let Some(run) = common::render_ao(
        procedural_scene("cornell-box").unwrap(),
        &common::ao_config("ssdo", 0.5, "environment = \"sky\"\ndistance_clamp = 0.1"),
        size,
        1,
    ) else {
        return;
    };
    assert_valid(&run, "ssdo under the sky");
    let truth = aograph::frame_reference::radiance_reference(
        run.renderer.gpu.clone(),
        run.renderer.shaders.clone(),
        &aograph::frame_reference::FrameView::of(&run.renderer),
        &aograph::ReferenceSettings::new(0.5, 256),
    )
    .expect("radiance reference traces");
    let s = common::surfaces(&run);
    let gpu = run.renderer.read_extra("ssdo_indirect").unwrap();
    let px = |i: usize| glam::Vec3::new(gpu[4 * i], gpu[4 * i + 1], gpu[4 * i + 2]);
    let ratio = |c: glam::Vec3| c.x / c.y.max(1e-9);
    for (wall, xs) in [("red", -1.0..-0.75), ("green", 0.75..1.0)] {
        let ours = floor_mean(&s, xs.clone(), px);
        let reference = floor_mean(&s, xs, |i| truth.indirect[i]);
        println!(
            "near the {wall} wall: ssdo indirect {ours} (red/green {:.2}), reference {reference} (red/green {:.2})",
            ratio(ours),
            ratio(reference)
        );
        // 25%: the reference's 256 rays and SSDO's 8 samples per pixel, averaged over the
        // band; a bounce of the wrong wall's colour, or of none, is off by 2x or more.
        let off = ratio(ours) / ratio(reference);
        assert!(
            (0.75..=1.33).contains(&off),
            "{wall}: ratio off by {off:.2}"
        );
    }
}
