//! The one plugin mechanism: an AO technique is a subgraph with typed parameters, declared
//! inputs (the g-buffer channels it reads, the View block) and outputs (accessibility plus
//! named extras), registered by name and configured by the `[ao]` table. GPU-free: the
//! technique is built into a graph and compiled. (These cases replace the graph crate's
//! former `GraphPlugin` tests: the graph no longer has a plugin system of its own.)

use aograph_ao_passes::{
    AoBuildContext, AoConfig, AoError, AoOutput, AoResult, AoTechnique, ParamDesc,
    TechniqueRegistry,
};
use aograph_frame::ReadsView;
use aograph_frame::{GBufferChannel, GBufferChannels, GBufferTextures, VIEW_BUFFER, ViewUniforms};
use aograph_graph::{BufferDesc, CompileOptions, GraphBuilder, SizeClass, TextureDesc, compile};
use serde::{Deserialize, Serialize};

/// Darkens by depth differences; optionally also writes a debug image (an extra output).
struct DepthContrast;

#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
struct DepthContrastParams {
    strength: f32,
    debug_image: bool,
}

impl Default for DepthContrastParams {
    fn default() -> Self {
        Self {
            strength: 4.0,
            debug_image: false,
        }
    }
}

const SHADER: &str = r#"
#include "common/view.wgsl"
struct Params { strength: f32, pad0: f32, pad1: f32, pad2: f32 }
@group(0) @binding(0) var depth: texture_2d<f32>;
@group(0) @binding(1) var<uniform> view: View;
@group(0) @binding(2) var<uniform> params: Params;
@group(0) @binding(3) var ao: texture_storage_2d<r32float, write>;
@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let d = textureLoad(depth, vec2<i32>(id.xy), 0).r;
    textureStore(ao, vec2<i32>(id.xy), vec4<f32>(clamp(1.0 - d * params.strength * view.inv_size.x, 0.0, 1.0)));
}
"#;

impl AoTechnique for DepthContrast {
    type Params = DepthContrastParams;
    const NAME: &'static str = "depth-contrast";
    fn description(&self) -> &'static str {
        "a user technique"
    }
    fn params(&self) -> Vec<ParamDesc> {
        vec![
            ParamDesc::float("strength", 0.0, 100.0).doc("darkening per unit depth"),
            ParamDesc::flag("debug_image").doc("also output a debug image"),
        ]
    }
    fn channels(&self, _: &Self::Params) -> GBufferChannels {
        GBufferChannels::of(&[GBufferChannel::LinearDepth])
    }
    fn build(&self, ctx: &mut AoBuildContext<'_>, p: &Self::Params) -> AoResult<AoOutput> {
        let depth = ctx.channel(GBufferChannel::LinearDepth)?;
        let out = ctx.accessibility_texture("contrast.ao");
        let mut pass = ctx
            .builder
            .compute_pass("contrast.ao", "contrast.wgsl", "main");
        pass.sample("depth", depth).read_view(ctx.view);
        let bytes: Vec<u8> = [p.strength, 0.0, 0.0, 0.0]
            .iter()
            .flat_map(|f| f.to_le_bytes())
            .collect();
        pass.uniform("params", &bytes);
        let out = pass.write_storage("ao", out);
        pass.dispatch_over(out);
        let mut output = AoOutput::new(out);
        if p.debug_image {
            let copy = ctx.builder.create_texture(
                "contrast.debug",
                TextureDesc::new(wgpu::TextureFormat::R32Float, SizeClass::FULL),
            );
            let copy = ctx.builder.copy_pass("contrast.debug", out, copy);
            output
                .extra
                .push((aograph_ao_passes::ExtraOutput::new("debug"), copy));
        }
        Ok(output)
    }
}

fn registry() -> TechniqueRegistry {
    let mut r = TechniqueRegistry::with_builtins();
    r.register(DepthContrast);
    r
}

fn ao_config(text: &str) -> AoResult<AoConfig> {
    let table: toml::Table = text.parse().expect("test TOML parses");
    AoConfig::from_table(&table, &registry())
}

/// Builds the technique named by `config` on a graph whose g-buffer channels are imported
/// (what the g-buffer node would write), exports its outputs and compiles it without a GPU.
fn build_and_compile(
    config: &AoConfig,
    provided: &[GBufferChannel],
) -> AoResult<aograph_graph::CompiledGraph> {
    let registry = registry();
    let technique = config.resolve(&registry)?;
    let mut b = GraphBuilder::new();
    let view = b.import_buffer(
        VIEW_BUFFER,
        BufferDesc {
            size: std::mem::size_of::<ViewUniforms>() as u64,
        },
    );
    let mut gbuffer = GBufferTextures::default();
    for c in provided {
        let h = b.import_texture(
            &format!("gbuffer.{}", c.name()),
            TextureDesc::new(c.format(), SizeClass::FULL),
        );
        gbuffer.set(*c, h);
    }
    let mut ctx = AoBuildContext {
        builder: &mut b,
        gbuffer,
        view,
        radius: config.radius.units().unwrap_or(1.0),
        intermediate_format: config.intermediate_format.wgpu(),
        technique: technique.name(),
        radius_pixels: None,
        declared: Default::default(),
        tracing: Default::default(),
    };
    let out = technique.build(&mut ctx)?;
    b.export(out.accessibility);
    for (_, h) in &out.extra {
        b.export(*h);
    }
    let lib = aograph_ao_passes::shader_library().unwrap();
    lib.add_inline("contrast.wgsl", SHADER);
    Ok(compile(b.build(), &lib, CompileOptions::default())?)
}

#[test]
fn a_user_technique_is_registered_beside_the_builtins_by_name() {
    let names = registry().names();
    assert!(names.contains(&"depth-contrast".to_string()));
    assert!(names.contains(&"mssao".to_string()));
    let mut sorted = names.clone();
    sorted.sort();
    assert_eq!(names, sorted, "listed by name");
}

#[test]
fn it_is_configured_like_a_builtin_and_builds_its_declared_outputs() {
    let config = ao_config(
        "technique = \"depth-contrast\"\nradius = 2.0\n[depth-contrast]\nstrength = 8.0\ndebug_image = true\n",
    )
    .unwrap();
    assert_eq!(config.technique, "depth-contrast");
    let plan = build_and_compile(&config, &[GBufferChannel::LinearDepth]).unwrap();
    assert_eq!(plan.pass_names(), ["contrast.ao", "contrast.debug"]);
    assert_eq!(plan.decl.uniforms[0].initial[..4], 8.0f32.to_le_bytes());
    // Without the extra output its pass is not declared.
    let config = ao_config("technique = \"depth-contrast\"\n").unwrap();
    let plan = build_and_compile(&config, &[GBufferChannel::LinearDepth]).unwrap();
    assert_eq!(plan.pass_names(), ["contrast.ao"]);
}

#[test]
fn parameters_default_from_the_struct_when_omitted() {
    let registry = registry();
    let specs = registry.get("depth-contrast").unwrap().parameters();
    let by_name = |n: &str| specs.iter().find(|s| s.name == n).unwrap().default_text();
    assert_eq!(by_name("strength"), "4.0");
    assert_eq!(by_name("debug_image"), "false");
}

#[test]
fn an_unknown_technique_lists_the_known_ones_including_the_users() {
    match ao_config("technique = \"vxao\"\n").unwrap_err() {
        AoError::UnknownTechnique { name, known } => {
            assert_eq!(name, "vxao");
            assert!(known.contains(&"depth-contrast".to_string()), "{known:?}");
        }
        e => panic!("{e}"),
    }
}

#[test]
fn bad_parameters_name_the_technique_the_key_and_what_is_allowed() {
    let e = ao_config("[depth-contrast]\nstrenght = 2.0\n")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("depth-contrast") && e.contains("strenght") && e.contains("strength"),
        "{e}"
    );
    let e = ao_config("[depth-contrast]\nstrength = \"a lot\"\n")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("depth-contrast") && e.contains("strength"),
        "{e}"
    );
    assert_eq!(
        ao_config("[depth-contrast]\nstrength = 500.0\n").unwrap_err(),
        AoError::InvalidParameter {
            technique: "depth-contrast".into(),
            name: "strength".into(),
            value: "500".into(),
            allowed: "0 to 100".into(),
        }
    );
}

#[test]
fn a_missing_input_channel_is_an_error_naming_technique_and_channel() {
    let config = ao_config("technique = \"depth-contrast\"\n").unwrap();
    let e = build_and_compile(&config, &[GBufferChannel::Normals]).unwrap_err();
    assert_eq!(
        e,
        AoError::MissingChannel {
            technique: "depth-contrast".into(),
            channel: "linear_depth".into(),
        }
    );
}

#[test]
fn registering_the_same_name_replaces_the_technique() {
    struct Other;
    impl AoTechnique for Other {
        type Params = DepthContrastParams;
        const NAME: &'static str = "depth-contrast";
        fn description(&self) -> &'static str {
            "a replacement"
        }
        fn params(&self) -> Vec<ParamDesc> {
            Vec::new()
        }
        fn channels(&self, _: &Self::Params) -> GBufferChannels {
            GBufferChannels::none()
        }
        fn build(&self, _: &mut AoBuildContext<'_>, _: &Self::Params) -> AoResult<AoOutput> {
            Err(AoError::Config("not built in this test".into()))
        }
    }
    let mut r = registry();
    let n = r.names().len();
    r.register(Other);
    assert_eq!(r.names().len(), n);
    assert_eq!(
        r.get("depth-contrast").unwrap().description(),
        "a replacement"
    );
}
