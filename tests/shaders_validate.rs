//! Every WGSL file under shaders/ parses and validates with naga (GPU-free), includes expanded,
//! from the sources compiled into the crates (their mounts); shared files under common/ must be
//! valid on their own too. A file declaring the `IntermediateStorage` alias is validated in its
//! r16float variant as well.

#[test]
fn every_embedded_shader_is_mounted_by_exactly_one_crate() {
    // aograph's library mounts each crate's folders, and the web page's crate (no dependency of
    // the CLI) its own; together they are every embedded file.
    let lib = aograph::shader_library();
    lib.mount(aograph_web::shader_mount()).unwrap();
    let mut embedded: Vec<&str> = aograph_shaders::FOLDERS
        .iter()
        .flat_map(|(_, files)| files.iter().map(|(p, _)| *p))
        .collect();
    embedded.sort_unstable();
    assert_eq!(lib.files(), embedded);
    assert_eq!(
        lib.mounts(),
        [
            "aograph-frame",
            "aograph-ao-passes",
            "aograph-tracing",
            "aograph-renderer",
            "aograph-embed",
            "aograph-bench",
            "aograph",
            "aograph-web"
        ]
    );
}

#[test]
fn a_file_of_an_unmounted_crate_is_an_error_naming_the_mounts() {
    // The embedding's adapters without aograph-embed's mount: the file and what was mounted
    // are named, so a packaged crate that forgot its shaders says so.
    let lib = aograph_renderer::shader_library();
    let Err(e) = lib.load("embed/linear_depth.wgsl") else {
        panic!("embed/ is not mounted on the renderer's library");
    };
    let e = e.to_string();
    assert!(e.contains("embed/linear_depth.wgsl"), "{e}");
    assert!(e.contains("`aograph-ao-passes` (ao/, blocks/)"), "{e}");
    assert!(e.contains("ShaderLibrary::mount"), "{e}");
}

#[test]
fn every_shader_file_validates_with_naga() {
    let lib = aograph::shader_library();
    lib.mount(aograph_web::shader_mount()).unwrap();
    let files = lib.files();
    assert!(files.len() >= 5, "found only {files:?}");
    let mut failures = Vec::new();
    let mut variants = Vec::new();
    for f in &files {
        if let Err(e) = lib.load(f) {
            failures.push(e.to_string());
        }
        match lib.variants(f) {
            Ok(v) => variants.extend(v),
            Err(e) => failures.push(e.to_string()),
        }
    }
    for v in &variants {
        if let Err(e) = lib.load(v) {
            failures.push(format!("{v}: {e}"));
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {} shaders fail:\n{}",
        failures.len(),
        files.len() + variants.len(),
        failures.join("\n")
    );
    assert!(
        variants.iter().any(|v| v.starts_with("ao/ssao/ao.wgsl?")),
        "the ssao AO pass has an r16float variant: {variants:?}"
    );
    println!(
        "{} shader files and {} variants (r16float storage, hardware ray tracer) validated: {}",
        files.len(),
        variants.len(),
        variants.join(", ")
    );
}

#[test]
fn example_shaders_validate_with_naga() {
    let lib = aograph::shader_library();
    for (name, src) in [
        (
            "examples/unsharp_depth.wgsl",
            include_str!("../examples/shaders/unsharp_depth.wgsl"),
        ),
        (
            "examples/tint.wgsl",
            include_str!("../examples/shaders/tint.wgsl"),
        ),
    ] {
        lib.add_inline(name, src);
        lib.load(name).unwrap_or_else(|e| panic!("{e}"));
    }
}

#[test]
fn a_ray_tracer_variant_of_a_shader_that_traces_no_rays_is_a_named_error() {
    let lib = aograph::shader_library();
    let e = match lib.load("ao/ssao/ao.wgsl?RayTracer=hardware") {
        Ok(_) => panic!("ssao traces no rays: its hardware variant must be refused"),
        Err(e) => e.to_string(),
    };
    assert!(e.contains("common/scene_trace.wgsl"), "{e}");
    // And the reference's variant is a ray-query module at the compute BVH's bindings.
    let m = lib
        .load("raytrace/reference.wgsl?RayTracer=hardware")
        .expect("validates");
    assert!(m.source.starts_with("enable wgpu_ray_query;"));
    assert!(
        m.bindings.iter().any(|b| b.binding == 12
            && b.kind == aograph_graph::ShaderBindingKind::AccelerationStructure)
    );
}
