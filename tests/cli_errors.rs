//! Errors a user can act on, one by one, through the real `aograph` binary: each names the
//! problem and what is allowed, exits non-zero, never panics, and leaves no partial output.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn aograph(args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_aograph"));
    c.args(args);
    for (k, v) in env {
        c.env(k, v);
    }
    c.output().expect("aograph runs")
}

/// Runs a command that must fail; returns its stderr after checking it did not panic.
fn fails(args: &[&str], env: &[(&str, &str)]) -> String {
    let out = aograph(args, env);
    let stderr = String::from_utf8_lossy(&out.stderr).to_string();
    assert!(
        !out.status.success(),
        "{args:?} should fail; stderr: {stderr}"
    );
    assert!(!stderr.contains("panicked"), "{args:?} panicked: {stderr}");
    stderr
}

fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("aograph-cli-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn small(out: &Path) -> Vec<String> {
    vec![
        "--width".into(),
        "32".into(),
        "--height".into(),
        "24".into(),
        "--out".into(),
        out.display().to_string(),
    ]
}

fn render(extra: &[&str], out: &Path, env: &[(&str, &str)]) -> String {
    let mut args: Vec<String> = vec!["render".into()];
    args.extend(extra.iter().map(|s| s.to_string()));
    args.extend(small(out));
    let refs: Vec<&str> = args.iter().map(String::as_str).collect();
    fails(&refs, env)
}

#[test]
fn missing_scene_file_names_the_file() {
    let out = temp_dir("missing");
    let e = render(
        &["--technique", "none", "--scene", "/nonexistent/scene.gltf"],
        &out,
        &[],
    );
    assert!(
        e.contains("/nonexistent/scene.gltf") && e.contains("does not exist"),
        "{e}"
    );
}

#[test]
fn malformed_gltf_names_the_file_and_the_parser_message() {
    let out = temp_dir("malformed");
    let bad = out.join("bad.gltf");
    std::fs::write(&bad, "{ \"asset\": { \"version\": \"2.0\" }, ").unwrap();
    let e = render(
        &["--technique", "none", "--scene", bad.to_str().unwrap()],
        &out,
        &[],
    );
    assert!(
        e.contains("bad.gltf") && e.contains("not valid glTF JSON"),
        "{e}"
    );
}

#[test]
fn a_bench_size_that_is_not_width_x_height_names_the_form() {
    for bad in ["64", "64x", "0x64", "64x36x2"] {
        let e = fails(&["bench", "--sizes", bad, "--quiet"], &[]);
        assert!(
            e.contains("--sizes") && (e.contains("WIDTHxHEIGHT") || e.contains("1 to")),
            "--sizes {bad}: {e}"
        );
    }
}

#[test]
fn every_list_option_of_bench_takes_the_form_its_help_shows() {
    // Each list option's help says "comma-separated" (or shows a comma default), and that form
    // gets past the parser: the run then stops at the radius check, which comes first.
    let help = String::from_utf8_lossy(&aograph(&["bench", "--help"], &[]).stdout).to_string();
    assert!(help.contains("[default: 128,256,512,1024]"), "{help}");
    for (flag, form) in [
        ("--scenes", "plane,corner"),
        ("--techniques", "ssao,gtao"),
        ("--views", "default,outside"),
        ("--sizes", "64x36,32x18"),
        ("--scaling-sizes", "128,256,512,1024"),
        ("--scaling-radii", "0.5,1"),
    ] {
        let line = help
            .lines()
            .find(|l| l.trim_start().starts_with(&format!("{flag} ")))
            .unwrap_or_else(|| panic!("{flag} in bench --help"));
        assert!(
            line.contains("comma-separated") || line.contains(','),
            "{flag}'s help names no form: {line}"
        );
        let e = fails(&["bench", flag, form, "--radius", "-1", "--quiet"], &[]);
        assert!(
            e.contains("--radius") && e.contains("greater than 0"),
            "{flag} {form}: {e}"
        );
    }
}

#[test]
fn unknown_technique_lists_the_known_ones() {
    let out = temp_dir("technique");
    let e = render(&["--technique", "ssoa"], &out, &[]);
    assert!(
        e.contains("unknown technique `ssoa` (did you mean `ssao`?)")
            && e.contains("known techniques:")
            && e.contains("none"),
        "{e}"
    );
}

#[test]
fn an_unknown_scene_view_or_preset_suggests_the_nearest_known_one() {
    let out = temp_dir("nearest");
    let e = render(&["--technique", "none", "--scene", "colums"], &out, &[]);
    assert!(
        e.contains("unknown procedural scene \"colums\" (did you mean `columns`?)"),
        "{e}"
    );
    let e = render(
        &[
            "--technique",
            "none",
            "--scene",
            "columns",
            "--camera",
            "outsde",
        ],
        &out,
        &[],
    );
    assert!(
        e.contains("--camera: outsde") && e.contains("(did you mean `outside`?)"),
        "{e}"
    );
    let config = out.join("typo.toml");
    std::fs::write(
        &config,
        "[ao]\ntechnique = \"gtao\"\n[ao.gtao]\npreset = \"hihg\"\n",
    )
    .unwrap();
    let e = render(&["--config", config.to_str().unwrap()], &out, &[]);
    assert!(
        e.contains("\"hihg\"") && e.contains("(did you mean `high`?)"),
        "{e}"
    );
}

#[test]
fn negative_or_zero_radius_gives_the_allowed_range() {
    let out = temp_dir("radius");
    for r in ["--radius=-1", "--radius=0"] {
        let e = render(&[r], &out, &[]);
        assert!(
            e.contains("--radius") && e.contains("greater than 0"),
            "{e}"
        );
    }
    // As a separate argument, as users type it: the range message, not clap's "unexpected
    // argument '-1'", for render and for bench.
    let e = render(&["--radius", "-1"], &out, &[]);
    assert!(e.contains("greater than 0"), "{e}");
    let e = fails(&["bench", "--radius", "-1", "--quiet"], &[]);
    assert!(e.contains("greater than 0"), "{e}");
}

#[test]
fn zero_output_size_gives_the_allowed_range() {
    let out = temp_dir("size");
    let e = fails(
        &[
            "render",
            "--width",
            "0",
            "--height",
            "24",
            "--out",
            out.to_str().unwrap(),
        ],
        &[],
    );
    assert!(e.contains("--width") && e.contains("1 to 8192"), "{e}");
}

#[test]
fn unknown_config_key_suggests_the_nearest() {
    let out = temp_dir("config");
    let cfg = out.join("c.toml");
    std::fs::write(&cfg, "[ao]\ntechnique = \"none\"\nradus = 2.0\n").unwrap();
    let e = render(&["--config", cfg.to_str().unwrap()], &out, &[]);
    assert!(
        e.contains("unknown key `radus`") && e.contains("did you mean `radius`"),
        "{e}"
    );
}

#[test]
fn unwritable_output_directory_is_reported_and_nothing_is_left_behind() {
    let e = fails(
        &[
            "render",
            "--technique",
            "none",
            "--width",
            "8",
            "--height",
            "8",
            "--out",
            "/proc/aograph-out",
        ],
        &[],
    );
    assert!(
        e.contains("/proc/aograph-out") && e.contains("output directory"),
        "{e}"
    );
    assert!(!Path::new("/proc/aograph-out").exists());
}

#[test]
fn no_gpu_adapter_says_how_to_install_one() {
    let out = temp_dir("nogpu");
    // An empty driver list: the Vulkan loader finds no device.
    let e = render(
        &["--technique", "none"],
        &out,
        &[
            ("VK_ICD_FILENAMES", "/nonexistent/icd.json"),
            ("VK_DRIVER_FILES", "/nonexistent/icd.json"),
        ],
    );
    assert!(
        e.contains("no GPU adapter") && e.contains("apt-get install mesa-vulkan-drivers"),
        "{e}"
    );
    assert!(!out.join("ao.png").exists(), "no partial output");
}

#[test]
fn shader_that_fails_validation_names_file_and_line() {
    // AOGRAPH_SHADERS is a development override: a folder holding only the file being edited
    // shadows that file, and every other shader still comes from the compiled-in mounts.
    let out = temp_dir("shader");
    let shaders = out.join("shaders");
    std::fs::create_dir_all(shaders.join("ao")).unwrap();
    let broken = "// broken on purpose\n@group(0) @binding(0) var ao: texture_storage_2d<r32float, write>;\n\n@compute @workgroup_size(8, 8)\nfn main(@builtin(global_invocation_id) id: vec3<u32>) {\n    let x: f32 = undefined_symbol;\n}\n";
    std::fs::write(shaders.join("ao/none.wgsl"), broken).unwrap();
    let e = render(
        &["--technique", "none"],
        &out.join("o"),
        &[("AOGRAPH_SHADERS", shaders.to_str().unwrap())],
    );
    assert!(e.contains("ao/none.wgsl") && e.contains("line 6"), "{e}");
}

#[test]
fn unknown_camera_lists_the_views_and_a_bad_inline_camera_names_the_key() {
    let out = temp_dir("camera");
    let e = render(&["--scene", "room", "--camera", "attic"], &out, &[]);
    assert!(
        e.contains("--camera")
            && e.contains("attic")
            && e.contains("interior-1")
            && e.contains("outside")
            && e.contains("pos=x,y,z"),
        "{e}"
    );
    let e = render(&["--camera", "pos=1,2 target=0,0,0"], &out, &[]);
    assert!(
        e.contains("`position` = 1,2") && e.contains("three finite numbers"),
        "{e}"
    );
    let e = render(&["--camera", "pos=0,1,5 target=0,0,0 fov=200"], &out, &[]);
    assert!(e.contains("0 < fov < 180"), "{e}");
    let e = render(&["--radius", "big"], &out, &[]);
    assert!(e.contains("--radius") && e.contains("\"auto\""), "{e}");
}

#[test]
fn bad_camera_and_views_tables_in_a_config_name_the_problem() {
    let dir = temp_dir("camera-config");
    for (text, needle) in [
        (
            "[camera]\ntarget = [0, 0, 0]\n",
            "[camera]: `position` is missing",
        ),
        (
            "[[views]]\nposition = [0, 1, 2]\ntarget = [0, 0, 0]\n",
            "needs a `name`",
        ),
        (
            "[[views]]\nname = \"a\"\nposition = [0, 1, 2]\ntarget = [0, 0, 0]\n[[views]]\nname = \"a\"\nposition = [0, 1, 3]\ntarget = [0, 0, 0]\n",
            "used twice",
        ),
        ("[ao]\nradius = \"huge\"\n", "\"auto\""),
    ] {
        let path = dir.join("bad.toml");
        std::fs::write(&path, text).unwrap();
        let e = fails(&["graph", "--config", path.to_str().unwrap()], &[]);
        assert!(e.contains(needle) && e.contains("bad.toml"), "{text}: {e}");
    }
}
