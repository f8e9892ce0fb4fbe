//! A user technique gets the technique contract with no code of its own: the one in
//! examples/custom_pipeline.rs, written as any user would, is checked by the same call the
//! built-ins are (`aograph_ao_passes::contract::check_contract`), and its descriptions are what the
//! viewer's controls and `aograph techniques` read.

#[path = "../examples/custom_pipeline/unsharp_depth.rs"]
mod unsharp_depth;

use aograph_ao_passes::contract::check_contract;
use aograph_ao_passes::{ParamKind, TechniqueRegistry};

#[test]
fn the_example_user_technique_keeps_the_contract() {
    let mut registry = TechniqueRegistry::with_builtins();
    registry.register(unsharp_depth::UnsharpDepth);
    let shaders = aograph::shader_library();
    shaders.mount(unsharp_depth::shader_mount()).unwrap();
    let technique = registry.get("unsharp-depth").unwrap();
    let breaches = check_contract(technique, &shaders);
    assert!(breaches.is_empty(), "{}", breaches.join("\n"));
    // What the viewer builds its sliders from: bounded float ranges with their defaults.
    let controls: Vec<(&str, ParamKind, String)> = technique
        .parameters()
        .into_iter()
        .map(|d| (d.name, d.kind.clone(), d.default_text()))
        .collect();
    let float = |min: f64, max: f64| ParamKind::Range {
        min,
        max,
        integer: false,
        odd: false,
        above_min: false,
    };
    assert_eq!(
        controls,
        [
            ("strength", float(0.0, 100.0), "4.0".to_string()),
            ("radius_px", float(1.0, 16.0), "6.0".to_string()),
        ]
    );
}
