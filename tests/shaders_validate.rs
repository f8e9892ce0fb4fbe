//! Every WGSL file under shaders/ parses and validates with naga (GPU-free), includes expanded;
//! shared files under common/ must be valid on their own too.

#[test]
fn every_shader_file_validates_with_naga() {
    let lib = aograph_graph::ShaderLibrary::new(aograph::shader_dir());
    let files = lib.files();
    assert!(files.len() >= 5, "found only {files:?}");
    let mut failures = Vec::new();
    for f in &files {
        if let Err(e) = lib.load(f) {
            failures.push(e.to_string());
        }
    }
    assert!(failures.is_empty(), "{} of {} shaders fail:\n{}", failures.len(), files.len(), failures.join("\n"));
    println!("{} shader files validated", files.len());
}

#[test]
fn example_shaders_validate_with_naga() {
    let lib = aograph_graph::ShaderLibrary::new(aograph::shader_dir());
    for (name, src) in [("examples/unsharp_depth.wgsl", include_str!("../examples/shaders/unsharp_depth.wgsl")), ("examples/tint.wgsl", include_str!("../examples/shaders/tint.wgsl"))] {
        lib.add_inline(name, src);
        lib.load(name).unwrap_or_else(|e| panic!("{e}"));
    }
}
