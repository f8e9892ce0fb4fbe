//! Storage-precision variants (`file.wgsl?Alias=f16`): the named alias line is the only thing
//! rewritten, only from a 32-bit float format, and asking for a variant a file does not have
//! is an error naming the file. The graph gives `IntermediateStorage` no meaning; aograph-frame
//! ties it to the AO intermediate precision.

use aograph_graph::{
    GraphError, ShaderBindingKind, ShaderLibrary, storage_precision_variant, wgpu,
};

const WRITER: &str = "// a pass with one intermediate output and one fixed r32float output\n\
alias IntermediateStorage = texture_storage_2d<r32float, write>;\n\
@group(0) @binding(0) var raw: IntermediateStorage;\n\
@group(0) @binding(1) var fixed: texture_storage_2d<r32float, write>;\n\
@compute @workgroup_size(8, 8)\n\
fn main(@builtin(global_invocation_id) id: vec3<u32>) {\n\
    textureStore(raw, vec2<i32>(id.xy), vec4<f32>(0.5));\n\
    textureStore(fixed, vec2<i32>(id.xy), vec4<f32>(0.5));\n\
}\n";

fn lib(files: &[(&str, &str)]) -> ShaderLibrary {
    let lib = ShaderLibrary::inline_only();
    for (n, s) in files {
        lib.add_inline(n, s);
    }
    lib
}

fn storage_format(lib: &ShaderLibrary, name: &str, global: &str) -> wgpu::TextureFormat {
    match &lib.load(name).unwrap().binding(global).unwrap().kind {
        ShaderBindingKind::StorageTexture { format, .. } => *format,
        other => panic!("{global} is {other:?}"),
    }
}

#[test]
fn the_half_variant_rewrites_only_the_alias_line() {
    let lib = lib(&[("w.wgsl", WRITER)]);
    assert_eq!(
        storage_format(&lib, "w.wgsl", "raw"),
        wgpu::TextureFormat::R32Float
    );
    assert_eq!(
        storage_format(&lib, "w.wgsl?IntermediateStorage=f32", "raw"),
        wgpu::TextureFormat::R32Float
    );
    let half = "w.wgsl?IntermediateStorage=f16";
    assert_eq!(
        storage_format(&lib, half, "raw"),
        wgpu::TextureFormat::R16Float
    );
    assert_eq!(
        storage_format(&lib, half, "fixed"),
        wgpu::TextureFormat::R32Float,
        "lines other than the alias keep their format"
    );
    let (a, b) = (lib.load("w.wgsl").unwrap(), lib.load(half).unwrap());
    assert_eq!(a.source.lines().count(), b.source.lines().count());
    let changed: Vec<_> = a
        .source
        .lines()
        .zip(b.source.lines())
        .filter(|(x, y)| x != y)
        .collect();
    assert_eq!(
        changed,
        [(
            "alias IntermediateStorage = texture_storage_2d<r32float, write>;",
            "alias IntermediateStorage = texture_storage_2d<r16float, write>;"
        )]
    );
}

#[test]
fn multi_channel_aliases_halve_to_the_same_channel_count() {
    for (full, half, wgpu_half) in [
        ("rg32float", "rg16float", wgpu::TextureFormat::Rg16Float),
        (
            "rgba32float",
            "rgba16float",
            wgpu::TextureFormat::Rgba16Float,
        ),
    ] {
        let src = WRITER.replace(
            "<r32float, write>;\n@group(0) @binding(0)",
            &format!("<{full}, write>;\n@group(0) @binding(0)"),
        );
        assert!(src.contains(full), "{src}");
        let lib = lib(&[("w.wgsl", &src)]);
        assert_eq!(
            storage_format(&lib, "w.wgsl?IntermediateStorage=f16", "raw"),
            wgpu_half,
            "{full} -> {half}"
        );
    }
}

#[test]
fn the_alias_may_come_from_an_include() {
    let lib = lib(&[
        (
            "common/out.wgsl",
            "alias IntermediateStorage = texture_storage_2d<r32float, write>;\n",
        ),
        (
            "w.wgsl",
            &format!(
                "#include \"common/out.wgsl\"\n{}",
                WRITER.replace(
                    "alias IntermediateStorage = texture_storage_2d<r32float, write>;\n",
                    ""
                )
            ),
        ),
    ]);
    assert_eq!(
        storage_format(&lib, "w.wgsl?IntermediateStorage=f16", "raw"),
        wgpu::TextureFormat::R16Float
    );
}

#[test]
fn a_variant_the_file_does_not_have_is_an_error() {
    let plain = WRITER
        .replace(
            "alias IntermediateStorage = texture_storage_2d<r32float, write>;\n",
            "\n",
        )
        .replace(
            "var raw: IntermediateStorage",
            "var raw: texture_storage_2d<r32float, write>",
        );
    let already_half = WRITER.replace(
        "<r32float, write>;\n@group(0) @binding(0)",
        "<r16float, write>;\n@group(0) @binding(0)",
    );
    let lib = lib(&[
        ("plain.wgsl", &plain),
        ("half.wgsl", &already_half),
        ("w.wgsl", WRITER),
    ]);
    assert!(lib.load("plain.wgsl").is_ok() && lib.load("half.wgsl").is_ok());
    for name in ["plain.wgsl", "half.wgsl"] {
        let e = lib
            .load(&format!("{name}?IntermediateStorage=f16"))
            .unwrap_err();
        assert!(
            matches!(&e, GraphError::Shader { file, .. } if file == name),
            "{e}"
        );
        assert!(e.to_string().contains("alias IntermediateStorage"), "{e}");
    }
    let e = lib
        .load("w.wgsl?IntermediateStorage=rgba8unorm")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("unknown shader variant") && e.contains("`Alias=f16`"),
        "{e}"
    );
    let e = lib.load("w.wgsl?precision").unwrap_err().to_string();
    assert!(e.contains("unknown shader variant"), "{e}");
    // An alias the file does not declare is an error too, not a silent no-op.
    let e = lib.load("w.wgsl?OtherStorage=f16").unwrap_err().to_string();
    assert!(e.contains("alias OtherStorage"), "{e}");
}

#[test]
fn variants_lists_the_half_variant_of_files_with_the_alias() {
    let plain = "@compute @workgroup_size(1) fn main() {}\n";
    let lib = lib(&[("plain.wgsl", plain), ("w.wgsl", WRITER)]);
    assert_eq!(
        lib.variants("w.wgsl").unwrap(),
        ["w.wgsl?IntermediateStorage=f16"]
    );
    assert!(lib.variants("plain.wgsl").unwrap().is_empty());
}

#[test]
fn errors_keep_their_line_numbers_in_the_variant() {
    let broken = WRITER.replace("textureStore(fixed", "let oops = ;\n    textureStore(fixed");
    let lib = lib(&[("w.wgsl", &broken)]);
    let line = |name: &str| match lib.load(name).unwrap_err() {
        GraphError::Shader { file, line, .. } => (file, line),
        e => panic!("{e}"),
    };
    assert_eq!(line("w.wgsl"), ("w.wgsl".to_string(), 8));
    assert_eq!(
        line("w.wgsl?IntermediateStorage=f16"),
        ("w.wgsl".to_string(), 8)
    );
}

#[test]
fn variant_names_and_two_aliases_in_one_file() {
    assert_eq!(
        storage_precision_variant("ao/ssao/ao.wgsl", "IntermediateStorage", true),
        "ao/ssao/ao.wgsl?IntermediateStorage=f16"
    );
    assert_eq!(
        storage_precision_variant("ao/ssao/ao.wgsl", "IntermediateStorage", false),
        "ao/ssao/ao.wgsl"
    );
    let two = WRITER
        .replace(
            "alias IntermediateStorage = texture_storage_2d<r32float, write>;\n",
            "alias IntermediateStorage = texture_storage_2d<r32float, write>;\n\
             alias FixedStorage = texture_storage_2d<r32float, write>;\n",
        )
        .replace(
            "var fixed: texture_storage_2d<r32float, write>",
            "var fixed: FixedStorage",
        );
    let lib = lib(&[("w.wgsl", &two)]);
    assert_eq!(
        lib.variants("w.wgsl").unwrap(),
        ["w.wgsl?IntermediateStorage=f16", "w.wgsl?FixedStorage=f16"]
    );
    let both = "w.wgsl?IntermediateStorage=f16&FixedStorage=f16";
    assert_eq!(
        storage_format(&lib, both, "raw"),
        wgpu::TextureFormat::R16Float
    );
    assert_eq!(
        storage_format(&lib, both, "fixed"),
        wgpu::TextureFormat::R16Float
    );
    let one = "w.wgsl?FixedStorage=f16";
    assert_eq!(
        storage_format(&lib, one, "raw"),
        wgpu::TextureFormat::R32Float
    );
    assert_eq!(
        storage_format(&lib, one, "fixed"),
        wgpu::TextureFormat::R16Float
    );
}
