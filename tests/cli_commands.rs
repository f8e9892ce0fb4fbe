//! The CLI's commands on a fresh output directory: every shipped config prints a DOT graph,
//! `techniques` lists every technique, `reference` writes its three files, `scene export`
//! round-trips through the loader.

use std::path::PathBuf;
use std::process::Command;

fn aograph(args: &[&str]) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_aograph"))
        .args(args)
        .output()
        .expect("aograph runs");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).to_string(),
        String::from_utf8_lossy(&out.stderr).to_string(),
    )
}

fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("aograph-cmd-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn every_shipped_config_prints_a_dot_graph_and_a_plan() {
    let dir = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/configs"));
    let mut n = 0;
    for e in std::fs::read_dir(&dir).unwrap().flatten() {
        let p = e.path();
        if p.extension().is_none_or(|x| x != "toml") {
            continue;
        }
        let (ok, dot, err) = aograph(&["graph", "--config", p.to_str().unwrap(), "--dot"]);
        assert!(
            ok && dot.starts_with("digraph") && dot.contains("gbuffer"),
            "{}: {err}",
            p.display()
        );
        let (ok, plan, err) = aograph(&["graph", "--config", p.to_str().unwrap()]);
        assert!(
            ok && plan.contains("texture bytes"),
            "{}: {err}",
            p.display()
        );
        n += 1;
    }
    assert!(n >= 8, "only {n} configs");
}

#[test]
fn techniques_lists_every_registered_technique_with_parameters() {
    let (ok, out, _) = aograph(&["techniques"]);
    assert!(ok);
    for name in aograph_ao_passes::TechniqueRegistry::with_builtins().names() {
        assert!(
            out.contains(&format!("{name}:")),
            "{name} missing from:\n{out}"
        );
    }
    assert!(out.contains("default") && out.contains("allowed"));
}

#[test]
fn reference_writes_png_raw_and_depth() {
    if aograph_graph::test_gpu().is_none() {
        return;
    }
    let out = temp_dir("reference");
    let (ok, stdout, err) = aograph(&[
        "reference",
        "--scene",
        "plane",
        "--width",
        "24",
        "--height",
        "16",
        "--rays",
        "16",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    for f in ["reference.png", "reference.f32", "gbuffer_depth.png"] {
        assert!(out.join(f).exists(), "{f} missing; {stdout}");
    }
    let raw = aograph_scene::reference::read_raw_f32(out.join("reference.f32")).unwrap();
    assert_eq!((raw.width, raw.height), (24, 16));
    assert!(
        raw.values.iter().all(|&v| v == 1.0),
        "a flat plane is exactly 1"
    );
}

#[test]
fn scene_export_writes_a_glb_the_loader_reads_back() {
    let out = temp_dir("export");
    let file = out.join("stairs.glb");
    let (ok, _, err) = aograph(&["scene", "export", "stairs", file.to_str().unwrap()]);
    assert!(ok, "{err}");
    let back = aograph_scene::load_scene(&file).unwrap();
    assert_eq!(
        back.triangle_count(),
        aograph_scene::procedural_scene("stairs")
            .unwrap()
            .triangle_count()
    );
    let (ok, _, err) = aograph(&["scene", "export", "nope", file.to_str().unwrap()]);
    assert!(!ok && err.contains("unknown procedural scene"), "{err}");
}

#[test]
fn scene_export_bakes_a_skinned_files_pose_at_time_zero() {
    // CesiumMan's skin is baked: the export has no skin, does not move, and its triangles are
    // the walking man's at t = 0 (within f32 rounding of one more matrix product).
    let Some(source) = aograph_scene::test_scene(
        "scene_export_bakes_a_skinned_files_pose_at_time_zero",
        "CesiumMan.glb",
    ) else {
        return;
    };
    let source = source.to_str().unwrap();
    let out = temp_dir("export-skinned");
    let file = out.join("cesium-man-posed.glb");
    let (ok, _, err) = aograph(&["scene", "export", source, file.to_str().unwrap()]);
    assert!(ok, "{err}");
    let original = aograph_scene::load_scene(source).unwrap();
    let back = aograph_scene::load_scene(&file).unwrap();
    assert!(back.instances.iter().all(|i| i.skin.is_none()) && back.is_static());
    let (a, b) = (original.world_triangles(0.0), back.world_triangles(0.0));
    assert_eq!(a.len(), b.len());
    let worst = a
        .iter()
        .zip(&b)
        .flat_map(|(p, q)| p.iter().zip(q).map(|(u, v)| u.distance(*v)))
        .fold(0.0f32, f32::max);
    assert!(worst < 1e-5, "baked pose off by {worst}");
    let (_, info, _) = aograph(&["scene", "info", source]);
    assert!(
        info.contains(
            "skins: skin \"Armature\" (19 joints); 1 mesh instance(s) deformed on the GPU"
        ),
        "{info}"
    );
}

#[test]
fn scene_info_reports_counts_views_and_the_suggested_radius() {
    // A file's counts, views and R (the rest of the test needs no file).
    if let Some(file) = aograph_scene::test_scene(
        "scene_info_reports_counts_views_and_the_suggested_radius",
        "shadowscene_fire.gltf",
    ) {
        let (ok, out, err) = aograph(&["scene", "info", file.to_str().unwrap()]);
        assert!(ok, "{err}");
        for needle in [
            "nodes: 25",
            "triangles: 4656 placed, 3104 in the meshes",
            "cameras: none in the file",
            "outside:",
            "outside-2:",
            "suggested R: 2.000",
            "/ 9",
            "double-sided",
        ] {
            assert!(out.contains(needle), "{needle} missing from:\n{out}");
        }
    }
    let (ok, out, _) = aograph(&["scene", "info", "room"]);
    assert!(
        ok && out.contains("enclosed: yes") && out.contains("interior-2:"),
        "{out}"
    );
    let (ok, _, err) = aograph(&["scene", "info", "/no/such/scene.glb"]);
    assert!(!ok && err.contains("/no/such/scene.glb"), "{err}");
    // --scene, as every other command takes it, says the same as the positional form.
    let (ok, flag, err) = aograph(&["scene", "info", "--scene", "room"]);
    let (_, positional, _) = aograph(&["scene", "info", "room"]);
    assert!(ok && flag == positional, "{err}");
}

#[test]
fn without_a_display_session_the_driver_says_nothing_about_xdg_runtime_dir() {
    if aograph_graph::test_gpu().is_none() {
        return;
    }
    let out = temp_dir("no-xdg");
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_aograph"))
        .args([
            "render", "--scene", "plane", "--width", "16", "--height", "16", "--out",
        ])
        .arg(&out)
        .env_remove("XDG_RUNTIME_DIR")
        .output()
        .expect("aograph runs");
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "{stderr}");
    assert!(!stderr.contains("XDG_RUNTIME_DIR"), "{stderr}");
}

#[test]
fn the_first_image_is_timed_warm_and_named_by_the_scene_file() {
    if aograph_graph::test_gpu().is_none() {
        return;
    }
    let out = temp_dir("first-image");
    let dir = out.to_str().unwrap();
    let (ok, _, err) = aograph(&[
        "render", "--scene", "plane", "--width", "32", "--height", "24", "--frames", "1", "--out",
        dir,
    ]);
    assert!(ok, "{err}");
    let timings = std::fs::read_to_string(out.join("timings.txt")).unwrap();
    assert!(
        timings.contains("# times: a warm repeat of the frame"),
        "{timings}"
    );
    // A bench of a scene file names its images by the file's name, not its absolute path,
    // and report.md names the timing source results.csv records.
    let glb = out.join("nested dir").join("my plane.glb");
    std::fs::create_dir_all(glb.parent().unwrap()).unwrap();
    let (ok, _, err) = aograph(&["scene", "export", "plane", glb.to_str().unwrap()]);
    assert!(ok, "{err}");
    let bench = out.join("bench");
    let (ok, _, err) = aograph(&[
        "bench",
        "--scenes",
        glb.to_str().unwrap(),
        "--techniques",
        "none",
        "--width",
        "24",
        "--height",
        "16",
        "--frames",
        "1",
        "--warmup",
        "0",
        "--rays",
        "4",
        "--quiet",
        "--out",
        bench.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    let results: aograph_bench::ResultsFile =
        serde_json::from_str(&std::fs::read_to_string(bench.join("results.json")).unwrap())
            .unwrap();
    let run = &results.runs[0];
    assert_eq!(
        run.image.as_deref(),
        Some("images/my_plane_default_none_defaults.png")
    );
    let report = std::fs::read_to_string(bench.join("report.md")).unwrap();
    let said = match run.times.timing_source.as_str() {
        "cpu-wall" => "CPU wall time",
        _ => "GPU timestamp queries",
    };
    assert!(
        report.contains(&format!("Times come from {said}")),
        "{report}"
    );
}

#[test]
fn render_from_a_named_view_and_an_inline_camera_prints_the_radius_and_view() {
    let out = temp_dir("views");
    for (camera, view) in [
        ("interior-1", "view interior-1"),
        ("pos=-4,1.6,2 target=1,0.8,-1 fov=70", "view inline"),
    ] {
        let (ok, stdout, err) = aograph(&[
            "render",
            "--scene",
            "room",
            "--technique",
            "ssao",
            "--camera",
            camera,
            "--width",
            "48",
            "--height",
            "32",
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(ok, "{camera}: {err}");
        // Both cameras stand inside the room: `auto` takes R from what each sees (the
        // room's diagonal / 9 would be 1.408).
        assert!(
            stdout.contains(view) && !stdout.contains("R = 1.408"),
            "{stdout}"
        );
        let timings = std::fs::read_to_string(out.join("timings.txt")).unwrap();
        assert!(
            timings.contains("auto: the view's median depth")
                && timings.contains("an interior view"),
            "{timings}"
        );
    }
    // A config's [[views]] entry by name, with a radius in units.
    let config = out.join("views.toml");
    std::fs::write(
        &config,
        "[scene]\nname = \"room\"\n[ao]\ntechnique = \"none\"\nradius = 0.25\n[[views]]\nname = \"door\"\nposition = [-4.5, 1.5, 2.5]\nyaw = -60\npitch = -5\n",
    )
    .unwrap();
    let (ok, plan, err) = aograph(&[
        "graph",
        "--config",
        config.to_str().unwrap(),
        "--camera",
        "door",
    ]);
    assert!(
        ok && plan.contains("view door") && plan.contains("R = 0.2500 (set to"),
        "{plan}{err}"
    );
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn render_writes_each_extra_output_at_its_own_size() {
    // gtao at half resolution with temporal accumulation: the per-frame accessibility is one
    // channel at the output size, the depth it ran on one channel at half size (rounded up).
    let dir = temp_dir("extras");
    let config = dir.join("gtao.toml");
    std::fs::write(
        &config,
        "[ao]\ntechnique = \"gtao\"\n[ao.gtao]\nresolution = \"half\"\ntemporal = true\n",
    )
    .unwrap();
    let out = dir.join("out");
    let (ok, stdout, stderr) = aograph(&[
        "render",
        "--config",
        config.to_str().unwrap(),
        "--scene",
        "columns",
        "--width",
        "67",
        "--height",
        "41",
        "--frames",
        "2",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "render failed\nstdout: {stdout}\nstderr: {stderr}");
    for (name, size) in [
        ("ao.png", (67, 41)),
        ("per_frame_accessibility.png", (67, 41)),
        ("half_linear_depth.png", (34, 21)),
    ] {
        let img = image::open(out.join(name)).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!((img.width(), img.height()), size, "{name}");
    }
}

#[test]
fn render_rtao_says_which_ray_tracer_backend_ran() {
    let out = temp_dir("tracer");
    let render = |technique: &str| {
        aograph(&[
            "render",
            "--scene",
            "columns",
            "--technique",
            technique,
            "--width",
            "40",
            "--height",
            "24",
            "--out",
            out.to_str().unwrap(),
        ])
    };
    let (ok, stdout, err) = render("rtao");
    assert!(ok, "{err}");
    let Some(gpu) = aograph_graph::test_gpu() else {
        return;
    };
    // `tracer = "auto"`: the hardware backend where the driver offers ray queries (CI's
    // lavapipe does: AOGRAPH_REQUIRE_RAY_QUERY=1), the compute one otherwise.
    let expected = if gpu.has_ray_queries() {
        "ray tracer: hardware (ray queries on acceleration structures)"
    } else {
        assert!(std::env::var("AOGRAPH_REQUIRE_RAY_QUERY").as_deref() != Ok("1"));
        "ray tracer: compute"
    };
    assert!(stdout.starts_with(expected), "{stdout}");
    let timings = std::fs::read_to_string(out.join("timings.txt")).unwrap();
    assert!(timings.contains(&format!("# {expected}")), "{timings}");
    // `graph` plans for the same device, so it names the same backend.
    let (ok, plan, err) = aograph(&["graph", "--scene", "columns", "--technique", "rtao"]);
    let backend = expected.split(" (").next().unwrap();
    assert!(
        ok && plan.contains(&format!("{backend} (planned for")),
        "{err}{plan}"
    );
    // A technique that traces nothing says nothing of a tracer.
    let (ok, stdout, _) = render("gtao");
    assert!(ok && !stdout.contains("ray tracer"), "{stdout}");
}
