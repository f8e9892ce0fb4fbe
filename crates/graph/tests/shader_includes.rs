//! Nested `#include`s: expanded depth first, each file once, and errors still name the file
//! and line they come from.

use aograph_graph::{GraphError, ShaderLibrary};

#[test]
fn nested_includes_are_expanded_once_each() {
    let lib = ShaderLibrary::inline_only();
    lib.add_inline("common/a.wgsl", "fn a() -> f32 { return 1.0; }\n");
    lib.add_inline(
        "common/b.wgsl",
        "#include \"common/a.wgsl\"\nfn b() -> f32 { return a() + 1.0; }\n",
    );
    lib.add_inline("main.wgsl", "#include \"common/a.wgsl\"\n#include \"common/b.wgsl\"\n@compute @workgroup_size(1)\nfn main() { let x = a() + b(); }\n");
    let info = lib.load("main.wgsl").unwrap();
    assert_eq!(info.source.matches("fn a()").count(), 1, "{}", info.source);
    assert_eq!(info.source.matches("fn b()").count(), 1);
}

#[test]
fn error_in_a_nested_include_names_that_file_and_line() {
    let lib = ShaderLibrary::inline_only();
    lib.add_inline(
        "common/a.wgsl",
        "// a\nfn a() -> f32 { return missing_name; }\n",
    );
    lib.add_inline(
        "common/b.wgsl",
        "#include \"common/a.wgsl\"\nfn b() -> f32 { return a(); }\n",
    );
    lib.add_inline(
        "main.wgsl",
        "#include \"common/b.wgsl\"\n@compute @workgroup_size(1)\nfn main() { let x = b(); }\n",
    );
    match lib.load("main.wgsl") {
        Err(GraphError::Shader { file, line, .. }) => {
            assert_eq!((file.as_str(), line), ("common/a.wgsl", 2))
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn replacing_an_included_source_reloads_the_modules_that_include_it() {
    let lib = ShaderLibrary::inline_only();
    lib.add_inline("common/a.wgsl", "fn a() -> f32 { return 1.0; }\n");
    lib.add_inline(
        "main.wgsl",
        "#include \"common/a.wgsl\"\n@compute @workgroup_size(1)\nfn main() { let x = a(); }\n",
    );
    let before = lib.load("main.wgsl").unwrap();
    let revision = lib.revision();
    lib.add_inline("common/a.wgsl", "fn a() -> f32 { return 2.0; }\n");
    let after = lib.load("main.wgsl").unwrap();
    assert!(before.source.contains("return 1.0"), "{}", before.source);
    assert!(after.source.contains("return 2.0"), "{}", after.source);
    assert_ne!(before.source_hash, after.source_hash);
    assert_ne!(lib.revision(), revision);
}
