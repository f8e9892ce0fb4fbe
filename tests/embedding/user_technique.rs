//! A user technique in both of aograph's front ends: the one in examples/custom_pipeline,
//! registered with aograph's renderer (its WGSL mounted on the renderer's library) and with an
//! application's `AmbientOcclusion` (its WGSL mounted through `with_registry`), gives the same
//! AO from the same frame.

#[path = "../../examples/custom_pipeline/unsharp_depth.rs"]
mod unsharp_depth;

use aograph_ao_passes::{AoConfig, TechniqueRegistry};
use aograph_embed::{AmbientOcclusion, AoInputs, DepthInput};
use aograph_graph::test_gpu;

use super::*;

fn user_registry() -> TechniqueRegistry {
    let mut registry = TechniqueRegistry::with_builtins();
    registry.register(unsharp_depth::UnsharpDepth);
    registry
}

fn user_config(registry: &TechniqueRegistry) -> AoConfig {
    let table: toml::Table =
        "technique = \"unsharp-depth\"\nradius = 1.0\n[unsharp-depth]\nstrength = 6.0\n"
            .parse()
            .unwrap();
    AoConfig::from_table(&table, registry).unwrap()
}

/// The embedding choosing among `registry`'s techniques, with the user's `mount` if any.
fn user_embedding(
    gpu: &aograph_graph::GpuContext,
    config: &AoConfig,
    registry: TechniqueRegistry,
    mount: Option<aograph_graph::ShaderMount>,
) -> AmbientOcclusion {
    AmbientOcclusion::with_registry(
        &gpu.adapter,
        &gpu.device,
        &gpu.queue,
        config,
        registry,
        mount,
    )
    .unwrap()
}

#[test]
fn a_user_technique_gives_the_renderers_ao_through_the_embedding() {
    let Some(gpu) = test_gpu() else { return };
    let registry = user_registry();
    let config = user_config(&registry);
    let shaders = aograph::shader_library();
    shaders.mount(unsharp_depth::shader_mount()).unwrap();
    let scene = aograph_scene::procedural_scene("columns").unwrap();
    let own = own_frame_with(&scene, &config, None, &registry, shaders).unwrap();
    // The technique darkens creases: an image that is not all ones.
    let dark = own.ao.iter().filter(|a| **a < 0.95).count();
    assert!(dark > own.ao.len() / 50, "{dark} pixels darkened");

    let (depth, proj) = reversed_z_depth(&gpu, &own);
    let mut ao = user_embedding(&gpu, &config, registry, Some(unsharp_depth::shader_mount()));
    let inputs = AoInputs::new(DepthInput::Hardware(&depth), proj, own.view);
    let got = embed_frame(&gpu, &mut ao, &inputs).unwrap();
    // Same depth to f32 rounding through the application's reversed-Z buffer: SAME_INPUTS.
    assert_eq!(
        compare("unsharp-depth on columns", &got, &own, SAME_INPUTS),
        None
    );
}

#[test]
fn a_user_technique_without_its_mount_is_an_error_naming_its_shader() {
    let Some(gpu) = test_gpu() else { return };
    let registry = user_registry();
    let config = user_config(&registry);
    let mut ao = user_embedding(&gpu, &config, registry, None);
    let (depth, proj, view, _) = plane_frame(&gpu);
    let inputs = AoInputs::new(DepthInput::Hardware(&depth), proj, view);
    let e = embed_frame(&gpu, &mut ao, &inputs)
        .expect_err("the technique's shader is not mounted")
        .to_string();
    assert!(e.contains(unsharp_depth::SHADER), "{e}");
    assert!(e.contains("ShaderLibrary::mount"), "{e}");
}
