//! End-to-end checks of `aograph bench` and `aograph tune` on a small configuration (the
//! binary itself, as a user runs it), and of the metrics on a real traced reference.
//! GPU tests: they skip only when there is no adapter and AOGRAPH_REQUIRE_GPU is unset.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

use aograph_ao_passes::TechniqueRegistry;
use aograph_bench::ResultsFile;
use aograph_bench::metrics::{MetricOptions, compare};
use aograph_bench::report::CSV_HEADER;
use aograph_graph::Extent;

fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("aograph-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// Runs the binary; panics with its output when it fails.
fn aograph(args: &[&str]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_aograph"))
        .args(args)
        .output()
        .expect("aograph runs");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        out.status.success(),
        "aograph {} failed:\n{stderr}",
        args.join(" ")
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

fn decode_png(path: &Path) -> image::DynamicImage {
    image::open(path).unwrap_or_else(|e| panic!("{} does not decode: {e}", path.display()))
}

#[test]
fn bench_sizes_scores_every_run_at_each_size_against_its_own_reference() {
    if aograph_graph::test_gpu().is_none() {
        return;
    }
    let dir = temp_dir("bench-sizes");
    let d = dir.to_str().unwrap();
    aograph(&[
        "bench",
        "--scenes",
        "sphere-on-plane",
        "--techniques",
        "mssao,none",
        "--sizes",
        "48x27,33x40",
        "--frames",
        "1",
        "--warmup",
        "0",
        "--rays",
        "16",
        "--out",
        d,
        "--quiet",
    ]);
    let file: ResultsFile =
        serde_json::from_str(&std::fs::read_to_string(dir.join("results.json")).unwrap()).unwrap();
    let mut got: Vec<(String, u32, u32)> = file
        .runs
        .iter()
        .map(|r| (r.technique.clone(), r.width, r.height))
        .collect();
    got.sort();
    let want = [
        ("mssao", 33, 40),
        ("mssao", 48, 27),
        ("none", 33, 40),
        ("none", 48, 27),
    ];
    assert_eq!(got, want.map(|(t, w, h)| (t.to_string(), w, h)));
    for r in &file.runs {
        // Each run is scored over its own size's pixels, on both fifths.
        assert!(r.metrics.pixels > 0 && r.metrics.pixels <= (r.width * r.height) as usize);
        assert!(r.metrics.signed_error_left.is_some() && r.metrics.signed_error_right.is_some());
        let image = r.image.as_deref().unwrap();
        assert!(
            image.ends_with(&format!("_{}x{}.png", r.width, r.height)),
            "{image}"
        );
        assert_eq!(
            decode_png(&dir.join(image)).width(),
            3 * r.width + 2 * 2,
            "{image}: three panels of the run's width"
        );
    }
    let report = std::fs::read_to_string(dir.join("report.md")).unwrap();
    assert!(report.contains("## By output size"), "{report}");
    for (t, w, h) in want {
        assert!(
            report.contains(&format!("| {t} | defaults | {w}x{h} |")),
            "{t} at {w}x{h} in the size table:\n{report}"
        );
    }
}

#[test]
fn bench_writes_every_output_and_each_parses() {
    if aograph_graph::test_gpu().is_none() {
        return;
    }
    let techniques = TechniqueRegistry::with_builtins().names();
    assert!(techniques.iter().any(|t| t == "none"));
    let dir = temp_dir("bench-smoke");
    let d = dir.to_str().unwrap();
    aograph(&[
        "bench",
        "--scenes",
        "plane,sphere-on-plane",
        "--techniques",
        "all",
        "--width",
        "64",
        "--height",
        "64",
        "--frames",
        "3",
        "--warmup",
        "1",
        "--rays",
        "64",
        "--out",
        d,
        "--quiet",
    ]);
    let runs = 2 * techniques.len();

    let csv = std::fs::read_to_string(dir.join("results.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines[0], CSV_HEADER);
    assert_eq!(lines.len(), 1 + runs, "{csv}");
    let columns = CSV_HEADER.split(',').count();
    for l in &lines[1..] {
        assert!(l.split(',').count() >= columns, "short row: {l}");
    }

    let json: ResultsFile =
        serde_json::from_str(&std::fs::read_to_string(dir.join("results.json")).unwrap())
            .expect("results.json parses");
    assert_eq!(json.runs.len(), runs);
    assert!(!json.meta.device.is_empty());
    // The roofline: the device's peaks measured in the run, every pass of every run under
    // them, and the fractions are the rates over the peaks.
    let peaks = json
        .meta
        .peaks
        .expect("the run measured the device's peaks");
    assert!(
        peaks.loads_per_s > 1e6 && peaks.bytes_per_s > 1e6,
        "{peaks:?}"
    );
    for r in &json.runs {
        let names: Vec<&str> = r.times.passes.iter().map(|p| p.name.as_str()).collect();
        let roof: Vec<&str> = r.roofline.iter().map(|p| p.pass.as_str()).collect();
        assert_eq!(
            roof, names,
            "{} {}: every timed pass has a roofline row",
            r.scene, r.technique
        );
        for p in &r.roofline {
            assert!(p.bytes > 0 || p.invocations == 0, "{}: {p:?}", r.technique);
            assert!((p.byte_fraction - p.bytes_per_s / peaks.bytes_per_s).abs() < 1e-9);
            if let (Some(rate), Some(f)) = (p.loads_per_s, p.load_fraction) {
                assert!((f - rate / peaks.loads_per_s).abs() < 1e-9, "{p:?}");
            }
        }
    }
    let hbao = json.runs.iter().find(|r| r.technique == "hbao").unwrap();
    let blur = hbao
        .roofline
        .iter()
        .find(|p| p.pass == "hbao.blur_x")
        .unwrap();
    // HBAO's 5-tap blur reads the AO and the depth guide at each tap and the centre's depth
    // once more: 11 loads a pixel, over 64x64 invocations.
    assert_eq!(
        (blur.loads_per_invocation, blur.invocations),
        (Some(11.0), 64 * 64)
    );
    let report = std::fs::read_to_string(dir.join("report.md")).unwrap();
    assert!(report.contains("## Roofline") && report.contains("| hbao.blur_x |"));
    for r in &json.runs {
        let what = format!("{} {} {}", r.scene, r.technique, r.label);
        let m = &r.metrics;
        assert!(
            m.pixels > 0 && (0.0..=1.0).contains(&m.mae) && m.rmse >= m.mae - 1e-12,
            "{what}: {m:?}"
        );
        assert!(
            m.ssim.is_finite() && (-1.0..=1.0 + 1e-9).contains(&m.ssim),
            "{what}: {m:?}"
        );
        assert!(
            m.flicker.is_some_and(|f| f.is_finite()),
            "{what}: 3 frames give a flicker"
        );
        assert!(
            r.times.total_ms.median.is_finite()
                && r.times.total_ms.median >= 0.0
                && r.times.total_ms.samples == 3,
            "{what}: {:?}",
            r.times
        );
        assert!(
            r.texture_bytes > 0 && r.texture_bytes <= r.texture_bytes_unshared,
            "{what}"
        );
        let img = decode_png(&dir.join(r.image.as_deref().expect("every run has an image")));
        assert_eq!(
            (img.width(), img.height()),
            (3 * 64 + 4, 64),
            "{what}: AO | error | reference"
        );
    }
    // The plane is unoccluded: `none` (1 everywhere) matches its reference exactly.
    let plane = json
        .runs
        .iter()
        .find(|r| r.scene == "plane" && r.technique == "none")
        .unwrap();
    assert!(
        plane.metrics.mae < 1e-6 && plane.metrics.psnr == f64::INFINITY,
        "{:?}",
        plane.metrics
    );

    let report = std::fs::read_to_string(dir.join("report.md")).unwrap();
    assert!(
        report.contains("| scene | view | technique | parameters | R | R reached | AO ms |")
            && report.contains(&json.meta.device)
    );
    assert_eq!(report.contains("they are CPU times"), json.meta.software);
    let svg = std::fs::read_to_string(dir.join("pareto.svg")).unwrap();
    assert!(svg.starts_with("<svg") || svg.starts_with("<?xml"));
    decode_png(&dir.join("pareto.png"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn scaling_fits_exponents_on_a_small_grid() {
    if aograph_graph::test_gpu().is_none() {
        return;
    }
    let dir = temp_dir("bench-scaling");
    let d = dir.to_str().unwrap();
    aograph(&[
        "bench",
        "--scaling",
        "--scenes",
        "sphere-on-plane",
        "--techniques",
        "none",
        "--scaling-sizes",
        "32,64",
        "--scaling-radii",
        "0.5,1",
        "--frames",
        "2",
        "--warmup",
        "1",
        "--out",
        d,
        "--quiet",
    ]);
    let fits = std::fs::read_to_string(dir.join("scaling.csv")).unwrap();
    let rows: Vec<&str> = fits.lines().collect();
    assert_eq!(rows.len(), 2, "{fits}");
    let cells: Vec<&str> = rows[1].split(',').collect();
    // "NaN" parses as an f64: both exponents must be finite numbers. (Not a range: on a grid
    // this small, timed on a loaded CPU device, the fit's value is noise; its presence is the
    // check.)
    let exponent = |c: &str| c.parse::<f64>().ok().filter(|v| v.is_finite());
    assert!(
        exponent(cells[3]).is_some() && exponent(cells[4]).is_some(),
        "both exponents fitted: {fits}"
    );
    assert_eq!(
        std::fs::read_to_string(dir.join("scaling_points.csv"))
            .unwrap()
            .lines()
            .count(),
        5
    );
    assert!(
        std::fs::read_to_string(dir.join("report.md"))
            .unwrap()
            .contains("## Scaling")
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn tune_prints_a_config_that_loads_and_refuses_an_impossible_budget() {
    if aograph_graph::test_gpu().is_none() {
        return;
    }
    let registry = TechniqueRegistry::with_builtins();
    let file = temp_dir("tune").with_extension("toml");
    let f = file.to_str().unwrap();
    let small = [
        "--scene",
        "sphere-on-plane",
        "--width",
        "48",
        "--height",
        "48",
        "--frames",
        "2",
        "--warmup",
        "0",
        "--rays",
        "32",
        "--quiet",
    ];
    let text = aograph(&[&["tune", "--budget-ms", "100000", "--out", f], &small[..]].concat());
    let config = aograph_app_config::AppConfig::parse(&text, "tune output", &registry)
        .expect("the printed config loads");
    assert_eq!(
        config.scene,
        aograph_app_config::SceneSource::Procedural("sphere-on-plane".into())
    );
    assert_eq!((config.width, config.height), (48, 48));
    assert_eq!(std::fs::read_to_string(&file).unwrap(), text);
    let _ = std::fs::remove_file(&file);
    let out = Command::new(env!("CARGO_BIN_EXE_aograph"))
        .args([&["tune", "--budget-ms", "0.0000001"], &small[..]].concat())
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("--budget-ms"));
}

/// The metrics fed a real traced reference: against itself error 0 and SSIM 1; against a copy
/// darkened to 90% the MAE is 10% of the mean accessibility and the signed error its negative.
#[test]
fn metrics_of_the_real_reference_against_itself_and_a_biased_copy() {
    let scene = aograph_scene::procedural_scene("sphere-on-plane").unwrap();
    let Some(run) = common::render_ao(
        scene,
        &common::ao_config("none", 1.0, ""),
        Extent::new(48, 40),
        1,
    ) else {
        return;
    };
    let reference = common::reference(&run, 1.0, 32);
    let o = MetricOptions::default();
    let m = compare(&reference, &reference, &run.depth, 48, 40, &o).unwrap();
    assert_eq!(
        (m.mae, m.rmse, m.signed_error, m.psnr),
        (0.0, 0.0, 0.0, f64::INFINITY)
    );
    assert!((m.ssim - 1.0).abs() < 1e-12 && m.edge_mae == Some(0.0));
    let biased: Vec<f32> = reference.iter().map(|v| 0.9 * v).collect();
    let (sum, n) = reference
        .iter()
        .zip(&run.depth)
        .filter(|(_, d)| **d > 0.0)
        .fold((0.0f64, 0usize), |(s, n), (v, _)| (s + *v as f64, n + 1));
    let mean = sum / n as f64;
    let m = compare(&biased, &reference, &run.depth, 48, 40, &o).unwrap();
    assert!(
        (m.mae - 0.1 * mean).abs() < 1e-6 && (m.signed_error + 0.1 * mean).abs() < 1e-6,
        "{m:?} (mean accessibility {mean})"
    );
    assert!(m.ssim < 1.0 && m.psnr.is_finite());
}

#[test]
fn bench_runs_each_view_as_a_row_with_its_radius_and_reach() {
    if aograph_graph::test_gpu().is_none() {
        return;
    }
    let dir = temp_dir("bench-views");
    let d = dir.to_str().unwrap();
    aograph(&[
        "bench",
        "--scenes",
        "room",
        "--views",
        "default,interior-1",
        "--techniques",
        "none,mssao",
        "--width",
        "48",
        "--height",
        "32",
        "--frames",
        "1",
        "--warmup",
        "0",
        "--rays",
        "16",
        "--out",
        d,
        "--quiet",
    ]);
    let json: ResultsFile =
        serde_json::from_str(&std::fs::read_to_string(dir.join("results.json")).unwrap()).unwrap();
    let rows: Vec<(String, String)> = json
        .runs
        .iter()
        .map(|r| (r.view.clone(), r.technique.clone()))
        .collect();
    assert_eq!(rows.len(), 4, "{rows:?}");
    for view in ["default", "interior-1"] {
        for technique in ["none", "mssao"] {
            assert!(rows.contains(&(view.into(), technique.into())), "{rows:?}");
        }
    }
    // Both views stand inside the room: `auto` is each view's own R (what it sees), not the
    // room's diagonal / 9.
    let room = aograph_scene::procedural_scene("room").unwrap();
    let scene_rule = aograph_scene::suggested_radius(&room).radius;
    for r in &json.runs {
        let view = aograph_scene::views::find_view(&room, &r.view).unwrap();
        let viewed = aograph_app_config::camera_spec::apply_view(&room, &view);
        let (auto, note) = aograph_app_config::prepared_scene::resolve_radius(
            &viewed,
            aograph_ao_passes::RadiusSetting::Auto,
        );
        assert!(note.contains("an interior view"), "{}: {note}", r.view);
        assert_eq!(
            r.radius,
            auto.get(),
            "every row uses its view's automatic R"
        );
        assert_ne!(r.radius, scene_rule);
        assert!(r.radius_px.is_some_and(|p| p > 0.0) && r.reference_mean.is_some());
        let expect_reach = r.technique == "mssao";
        assert_eq!(r.reach_px.is_some(), expect_reach, "{}", r.technique);
    }
    assert_eq!(json.meta.radius, None, "auto radius in the meta");
    let report = std::fs::read_to_string(dir.join("report.md")).unwrap();
    for needle in [
        "## Scenes and views",
        "| room | interior-1 |",
        "## Summary: over every scene and view",
        "## Best per scene and view",
        "| room / interior-1 |",
        "auto (each scene's content diagonal / 9",
    ] {
        assert!(report.contains(needle), "{needle} missing:\n{report}");
    }
    // The summary opens the report, before the full table.
    let at = |needle: &str| report.find(needle).unwrap();
    assert!(
        at("## Summary") < at("## Best per scene")
            && at("## Best per scene") < at("## Speed and accuracy")
    );
    for r in &json.runs {
        let image = r.image.as_deref().expect("every run has its image");
        assert!(
            image.starts_with(&format!("images/room_{}_", r.view)),
            "{image}"
        );
        decode_png(&dir.join(image));
    }
    let _ = std::fs::remove_dir_all(&dir);
}
