//! Shaders: naga validation, binding reflection, entry points, includes.

use std::sync::Arc;

use aograph_graph::wgpu::{StorageTextureAccess, TextureFormat};
use aograph_graph::*;

const ALL_KINDS: &str = r#"struct Params { radius: f32, dir: vec3<f32> }
@group(0) @binding(0) var src: texture_2d<f32>;
@group(0) @binding(1) var dst: texture_storage_2d<r32float, write>;
@group(0) @binding(2) var<uniform> params: Params;
@group(0) @binding(3) var linear_clamp: sampler;
@group(0) @binding(4) var nearest_clamp: sampler;
@group(1) @binding(0) var<storage, read> weights: array<vec4<f32>, 4>;
@group(1) @binding(1) var accum: texture_storage_2d<rgba16float, read_write>;
@group(1) @binding(2) var depth: texture_depth_2d;
@group(1) @binding(3) var ids: texture_2d<u32>;
@group(2) @binding(0) var<storage, read_write> counters: array<u32, 8>;
@group(2) @binding(1) var ro: texture_storage_2d<r32float, read>;

@compute @workgroup_size(8, 4, 1)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let p = vec2<i32>(id.xy);
    let v = textureLoad(src, p, 0).x * params.radius + weights[0].x;
    textureStore(dst, p, vec4<f32>(v));
}

@compute @workgroup_size(64)
fn reduce() {
}
"#;

fn lib_with(files: &[(&str, &str)]) -> ShaderLibrary {
    let lib = ShaderLibrary::inline_only();
    for (n, s) in files {
        lib.add_inline(n, s);
    }
    lib
}

fn shader_err(lib: &ShaderLibrary, name: &str) -> (String, u32, String) {
    match lib.load(name) {
        Ok(_) => panic!("{name} should not validate"),
        Err(GraphError::Shader {
            file,
            line,
            message,
        }) => (file, line, message),
        Err(other) => panic!("expected a Shader error, got {other:?}"),
    }
}

#[test]
fn reflects_every_binding_with_group_binding_and_kind() {
    let lib = lib_with(&[("all.wgsl", ALL_KINDS)]);
    let info = lib.load("all.wgsl").expect("valid shader");
    let b = |name: &str, group: u32, binding: u32, kind: ShaderBindingKind| ShaderBinding {
        name: name.into(),
        group,
        binding,
        kind,
        members: Vec::new(),
    };
    use ShaderBindingKind as K;
    let expected = vec![
        b(
            "src",
            0,
            0,
            K::SampledTexture {
                depth: false,
                scalar: naga::ScalarKind::Float,
            },
        ),
        b(
            "dst",
            0,
            1,
            K::StorageTexture {
                format: TextureFormat::R32Float,
                access: StorageTextureAccess::WriteOnly,
            },
        ),
        b("params", 0, 2, K::Uniform { size: 32 }),
        b("linear_clamp", 0, 3, K::Sampler),
        b("nearest_clamp", 0, 4, K::Sampler),
        b(
            "weights",
            1,
            0,
            K::StorageBuffer {
                read_only: true,
                size: 64,
            },
        ),
        b(
            "accum",
            1,
            1,
            K::StorageTexture {
                format: TextureFormat::Rgba16Float,
                access: StorageTextureAccess::ReadWrite,
            },
        ),
        b(
            "depth",
            1,
            2,
            K::SampledTexture {
                depth: true,
                scalar: naga::ScalarKind::Float,
            },
        ),
        b(
            "ids",
            1,
            3,
            K::SampledTexture {
                depth: false,
                scalar: naga::ScalarKind::Uint,
            },
        ),
        b(
            "counters",
            2,
            0,
            K::StorageBuffer {
                read_only: false,
                size: 32,
            },
        ),
        b(
            "ro",
            2,
            1,
            K::StorageTexture {
                format: TextureFormat::R32Float,
                access: StorageTextureAccess::ReadOnly,
            },
        ),
    ];
    // The uniform struct's members as WGSL lays them out: a vec3 is 16-byte aligned.
    let mut expected = expected;
    expected[2].members = vec![
        StructMember {
            name: "radius".into(),
            offset: 0,
            size: 4,
        },
        StructMember {
            name: "dir".into(),
            offset: 16,
            size: 12,
        },
    ];
    assert_eq!(info.bindings, expected);
    assert_eq!(info.binding("params").map(|b| b.binding), Some(2));
    assert!(info.binding("nope").is_none());
    assert_eq!(info.name, "all.wgsl");
}

#[test]
fn reflects_compute_entry_points_and_workgroup_sizes() {
    let lib = lib_with(&[("all.wgsl", ALL_KINDS)]);
    let info = lib.load("all.wgsl").unwrap();
    assert_eq!(
        info.entries,
        vec![
            ShaderEntry {
                name: "main".into(),
                stage: naga::ShaderStage::Compute,
                workgroup_size: [8, 4, 1],
                workgroup_storage: 0,
            },
            ShaderEntry {
                name: "reduce".into(),
                stage: naga::ShaderStage::Compute,
                workgroup_size: [64, 1, 1],
                workgroup_storage: 0,
            },
        ]
    );
    assert_eq!(
        info.entry("reduce").map(|e| e.workgroup_size),
        Some([64, 1, 1])
    );
    assert!(info.entry("missing").is_none());
}

#[test]
fn workgroup_storage_counts_the_variables_each_entry_uses_rounded_to_16_bytes() {
    // `tile` is 100 f32s (400 bytes, a multiple of 16); `flag` is one u32 (4 bytes, counted as
    // 16); `unused` is touched by no entry point. `tiled` reaches `flag` through a helper.
    let src = "var<workgroup> tile: array<f32, 100>;\n\
               var<workgroup> flag: u32;\n\
               var<workgroup> unused: array<vec4<f32>, 64>;\n\
               fn raise() { flag = 1u; }\n\
               @compute @workgroup_size(100) fn tiled(@builtin(local_invocation_index) i: u32) {\n\
                   tile[i] = 1.0;\n\
                   raise();\n\
               }\n\
               @compute @workgroup_size(1) fn plain() {}\n";
    let lib = lib_with(&[("wg.wgsl", src)]);
    let info = lib.load("wg.wgsl").unwrap();
    assert_eq!(
        info.entry("tiled").map(|e| e.workgroup_storage),
        Some(400 + 16)
    );
    assert_eq!(info.entry("plain").map(|e| e.workgroup_storage), Some(0));
}

#[test]
fn reflects_vertex_and_fragment_entry_points() {
    let src = "@group(0) @binding(0) var color: texture_2d<f32>;\n\
               @vertex fn vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {\n\
                   return vec4<f32>(f32(i), 0.0, 0.0, 1.0);\n\
               }\n\
               @fragment fn fs(@builtin(position) p: vec4<f32>) -> @location(0) vec4<f32> {\n\
                   return textureLoad(color, vec2<i32>(p.xy), 0);\n\
               }\n";
    let lib = lib_with(&[("fs.wgsl", src)]);
    let info = lib.load("fs.wgsl").unwrap();
    let stages: Vec<_> = info
        .entries
        .iter()
        .map(|e| (e.name.as_str(), e.stage))
        .collect();
    assert_eq!(
        stages,
        vec![
            ("vs", naga::ShaderStage::Vertex),
            ("fs", naga::ShaderStage::Fragment)
        ]
    );
    assert_eq!(info.bindings.len(), 1);
}

#[test]
fn uniform_size_follows_wgsl_layout_rules() {
    let src = "struct A { a: vec3<f32>, b: f32 }\n\
               struct B { m: mat4x4<f32>, c: vec2<f32> }\n\
               @group(0) @binding(0) var<uniform> a: A;\n\
               @group(0) @binding(1) var<uniform> b: B;\n\
               @group(0) @binding(2) var<uniform> s: f32;\n\
               @compute @workgroup_size(1) fn main() { let x = a.b + b.c.x + s; }\n";
    let lib = lib_with(&[("u.wgsl", src)]);
    let info = lib.load("u.wgsl").unwrap();
    let sizes: Vec<_> = info.bindings.iter().map(|b| b.kind.clone()).collect();
    assert_eq!(
        sizes,
        vec![
            ShaderBindingKind::Uniform { size: 16 },
            ShaderBindingKind::Uniform { size: 80 },
            ShaderBindingKind::Uniform { size: 4 }
        ]
    );
}

#[test]
fn loaded_modules_are_cached_until_replaced() {
    let lib = lib_with(&[("all.wgsl", ALL_KINDS)]);
    let a = lib.load("all.wgsl").unwrap();
    let b = lib.load("all.wgsl").unwrap();
    assert!(Arc::ptr_eq(&a, &b));
    lib.add_inline("all.wgsl", "@compute @workgroup_size(2) fn only() {}\n");
    let c = lib.load("all.wgsl").unwrap();
    assert!(!Arc::ptr_eq(&a, &c));
    assert_eq!(c.entries.len(), 1);
    assert!(c.bindings.is_empty());
}

#[test]
fn include_is_expanded_before_the_file_and_keeps_its_line_numbers() {
    let common = "// shared helpers\nfn helper(v: f32) -> f32 {\n    return v * 2.0;\n}\n";
    let main = "#include \"common/x.wgsl\"\n\n@compute @workgroup_size(1)\nfn main() {\n    let y = helper(1.0);\n}\n";
    let lib = lib_with(&[("common/x.wgsl", common), ("inc.wgsl", main)]);
    let info = lib.load("inc.wgsl").expect("include resolves");
    assert!(info.source.starts_with(common), "include text comes first");
    assert!(!info.source.contains("#include"));
    // The including file's line 5 is still at offset (include lines) + 5.
    let lines: Vec<&str> = info.source.lines().collect();
    assert_eq!(lines[4 + 4], "    let y = helper(1.0);");
    assert_eq!(info.entries.len(), 1);
}

#[test]
fn missing_shader_is_a_shader_file_error() {
    let lib = ShaderLibrary::inline_only();
    assert!(
        matches!(lib.load("nope.wgsl"), Err(GraphError::ShaderFile { file, .. }) if file == "nope.wgsl")
    );
    assert!(lib.files().is_empty());
    assert!(lib.root().is_none());
}

#[test]
fn missing_include_is_a_shader_file_error_naming_the_include() {
    let lib = lib_with(&[(
        "a.wgsl",
        "#include \"common/gone.wgsl\"\n@compute @workgroup_size(1) fn main() {}\n",
    )]);
    assert!(
        matches!(lib.load("a.wgsl"), Err(GraphError::ShaderFile { file, .. }) if file == "common/gone.wgsl")
    );
}

#[test]
fn include_without_a_name_is_an_error_at_its_line() {
    let lib = lib_with(&[(
        "a.wgsl",
        "// header\n#include \"\"\n@compute @workgroup_size(1) fn main() {}\n",
    )]);
    let (file, line, message) = shader_err(&lib, "a.wgsl");
    assert_eq!((file.as_str(), line), ("a.wgsl", 2));
    assert!(message.contains("#include"), "{message}");
}

#[test]
fn syntax_error_reports_file_and_line() {
    let src = "@compute @workgroup_size(1)\nfn main() {\n    let x: f32 = 1.0 +;\n}\n";
    let lib = lib_with(&[("bad.wgsl", src)]);
    let (file, line, message) = shader_err(&lib, "bad.wgsl");
    assert_eq!(file, "bad.wgsl");
    assert_eq!(line, 3);
    assert!(!message.is_empty());
    let e = lib.load("bad.wgsl").unwrap_err();
    assert!(
        e.to_string().starts_with("shader `bad.wgsl` line 3:"),
        "{e}"
    );
}

const COMMON: &str = "// shared helpers\nfn helper(v: f32) -> f32 {\n    return v * 2.0;\n}\n";

#[test]
fn syntax_error_after_an_include_reports_the_including_file_line() {
    let main = "#include \"common/x.wgsl\"\n\n@compute @workgroup_size(1)\nfn main() {\n    let y = helper(1.0) +;\n}\n";
    let lib = lib_with(&[("common/x.wgsl", COMMON), ("inc_bad.wgsl", main)]);
    let (file, line, _) = shader_err(&lib, "inc_bad.wgsl");
    assert_eq!((file.as_str(), line), ("inc_bad.wgsl", 5));
}

#[test]
fn syntax_error_inside_an_include_reports_the_included_file_line() {
    let broken = "// broken helper\nfn broken() -> f32 {\n    return 1.0 +;\n}\n";
    let main = "#include \"common/broken.wgsl\"\n@compute @workgroup_size(1)\nfn main() {\n    let y = broken();\n}\n";
    let lib = lib_with(&[("common/broken.wgsl", broken), ("uses_broken.wgsl", main)]);
    let (file, line, _) = shader_err(&lib, "uses_broken.wgsl");
    assert_eq!((file.as_str(), line), ("common/broken.wgsl", 3));
}

#[test]
fn errors_map_through_several_includes() {
    let second = "fn twice(v: f32) -> f32 {\n    return v + v;\n}\n";
    let third = "// three lines\n// of comments\nfn bad() -> f32 { return 1.0 +; }\n";
    let lib = lib_with(&[
        ("common/x.wgsl", COMMON),
        ("common/y.wgsl", second),
        ("common/z.wgsl", third),
        (
            "two.wgsl",
            "#include \"common/x.wgsl\"\n#include \"common/y.wgsl\"\n// body\n@compute @workgroup_size(1)\nfn main() {\n    let a = twice(helper(1.0));\n    let b: f32 = a +;\n}\n",
        ),
        (
            "three.wgsl",
            "#include \"common/x.wgsl\"\n#include \"common/y.wgsl\"\n#include \"common/z.wgsl\"\n@compute @workgroup_size(1) fn main() {}\n",
        ),
    ]);
    assert_eq!(shader_err(&lib, "two.wgsl").0, "two.wgsl");
    assert_eq!(shader_err(&lib, "two.wgsl").1, 7);
    let (file, line, _) = shader_err(&lib, "three.wgsl");
    assert_eq!((file.as_str(), line), ("common/z.wgsl", 3));
}

#[test]
fn type_error_reports_file_and_line() {
    let src =
        "@compute @workgroup_size(1)\nfn main() {\n    let a = 1.0;\n    let b: f32 = 1u;\n}\n";
    let lib = lib_with(&[("types.wgsl", src)]);
    let (file, line, _) = shader_err(&lib, "types.wgsl");
    assert_eq!((file.as_str(), line), ("types.wgsl", 4));
}

#[test]
fn unsupported_binding_type_names_the_global() {
    let src = "@group(0) @binding(0) var volume: texture_3d<f32>;\n@compute @workgroup_size(1) fn main() {}\n";
    let lib = lib_with(&[("vol.wgsl", src)]);
    let (file, _, message) = shader_err(&lib, "vol.wgsl");
    assert_eq!(file, "vol.wgsl");
    assert!(message.contains("`volume`"), "{message}");
}

#[test]
fn shaders_directory_lists_wgsl_files_sorted() {
    let dir = std::env::temp_dir().join(format!("aograph_shader_test_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("common")).unwrap();
    std::fs::write(dir.join("b.wgsl"), "#include \"common/x.wgsl\"\n@compute @workgroup_size(4) fn main() { let v = helper(2.0); }\n").unwrap();
    std::fs::write(dir.join("common/x.wgsl"), COMMON).unwrap();
    std::fs::write(
        dir.join("a.wgsl"),
        "@compute @workgroup_size(1) fn main() {}\n",
    )
    .unwrap();
    std::fs::write(dir.join("notes.txt"), "not a shader").unwrap();
    let lib = ShaderLibrary::new(&dir);
    assert_eq!(lib.files(), vec!["a.wgsl", "b.wgsl", "common/x.wgsl"]);
    for f in lib.files() {
        lib.load(&f).unwrap_or_else(|e| panic!("{f}: {e}"));
    }
    assert_eq!(
        lib.load("b.wgsl").unwrap().entries[0].workgroup_size,
        [4, 1, 1]
    );
    // An inline source shadows the file of the same name.
    lib.add_inline("a.wgsl", "@compute @workgroup_size(16) fn main() {}\n");
    assert_eq!(
        lib.load("a.wgsl").unwrap().entries[0].workgroup_size,
        [16, 1, 1]
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
