//! The technique contract (`aograph_ao_passes::contract`) over every built-in technique, and proof
//! that it catches a technique that breaks it. A user technique runs the same check with one
//! call (tests/user_technique_contract.rs does it for examples/custom_pipeline.rs's).

use std::sync::Arc;

use aograph_ao_passes::contract::check_contract;
use aograph_ao_passes::{
    AoBuildContext, AoOutput, AoResult, AoTechnique, DynAoTechnique, ParamDesc, TechniqueRegistry,
};
use aograph_frame::{GBufferChannel, GBufferChannels};
use aograph_graph::ShaderLibrary;
use serde::{Deserialize, Serialize};

fn shaders() -> ShaderLibrary {
    aograph_ao_passes::shader_library().unwrap()
}

#[test]
fn every_builtin_technique_keeps_the_contract() {
    let registry = TechniqueRegistry::with_builtins();
    let shaders = shaders();
    let mut breaches = Vec::new();
    for t in registry.iter() {
        breaches.extend(check_contract(t, &shaders));
    }
    assert!(breaches.is_empty(), "{}", breaches.join("\n"));
    assert_eq!(registry.iter().count(), 10);
}

/// A technique that breaks the contract four ways: `hidden` has no description, `ghost` is
/// described but is no key of its parameters, `count`'s default lies outside its range, and
/// its shader does not exist. `gain` keeps it.
struct Broken;

#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(default)]
struct BrokenParams {
    gain: f32,
    count: u32,
    hidden: bool,
}

impl Default for BrokenParams {
    fn default() -> Self {
        Self {
            gain: 1.0,
            count: 9,
            hidden: false,
        }
    }
}

impl AoTechnique for Broken {
    type Params = BrokenParams;
    const NAME: &'static str = "broken";
    fn description(&self) -> &'static str {
        "breaks the contract"
    }
    fn params(&self) -> Vec<ParamDesc> {
        vec![
            ParamDesc::float("gain", 0.0, 2.0).doc("a gain"),
            ParamDesc::int("count", 1, 4).doc("a count whose default is 9"),
            ParamDesc::flag("ghost").doc("no such key"),
        ]
    }
    fn channels(&self, _: &BrokenParams) -> GBufferChannels {
        GBufferChannels::of(&[GBufferChannel::LinearDepth])
    }
    fn build(&self, ctx: &mut AoBuildContext<'_>, _: &BrokenParams) -> AoResult<AoOutput> {
        let out = ctx.accessibility_texture("broken.ao");
        let mut pass = ctx
            .builder
            .compute_pass("broken.ao", "ao/no_such_file.wgsl", "main");
        let out = pass.write_storage("ao", out);
        pass.dispatch_over(out);
        Ok(AoOutput::new(out))
    }
}

#[test]
fn the_contract_names_each_breach() {
    let broken: Arc<dyn DynAoTechnique> = Arc::new(Broken);
    let breaches = check_contract(&broken, &shaders());
    let has = |text: &str| breaches.iter().any(|b| b.contains(text));
    assert!(
        has("parameter `hidden` has no description"),
        "{breaches:#?}"
    );
    assert!(
        has("broken.ghost: described, but `Params` has no such key"),
        "{breaches:#?}"
    );
    assert!(
        has("broken.count: default 9 is outside its description (1 to 4)"),
        "{breaches:#?}"
    );
    assert!(has("the plan does not build"), "{breaches:#?}");
    // `gain` keeps it: nothing is said of it.
    assert!(!has("broken.gain"), "{breaches:#?}");
}
