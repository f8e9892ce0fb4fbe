//! "Model only what a scene requires", checked GPU-free on declarations and plans: the g-buffer
//! writes only the channels its consumers asked for, a static scene gets no motion vectors, and
//! only SSDO (or shading) brings colour into the graph.

const SIZE: aograph_graph::Extent = aograph_graph::Extent {
    width: 64,
    height: 48,
};
use std::sync::Arc;

use aograph_ao_passes::ParamDesc;
use aograph_ao_passes::{
    AoBuildContext, AoConfig, AoOutput, AoResult, AoTechnique, TechniqueRegistry,
};
use aograph_frame::{GBufferChannel, GBufferChannels};
use aograph_graph::{CompileOptions, compile};
use aograph_renderer::FrameOutputs;
use aograph_renderer::build_frame_graph;
use serde::{Deserialize, Serialize};

/// A technique that reads linear depth only.
struct DepthOnly;

#[derive(Clone, Debug, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct NoParams {}

impl AoTechnique for DepthOnly {
    type Params = NoParams;
    const NAME: &'static str = "depth-only";
    fn description(&self) -> &'static str {
        "test technique reading linear depth only"
    }
    fn params(&self) -> Vec<ParamDesc> {
        Vec::new()
    }
    fn channels(&self, _: &NoParams) -> GBufferChannels {
        GBufferChannels::of(&[GBufferChannel::LinearDepth])
    }
    fn build(&self, ctx: &mut AoBuildContext<'_>, _: &NoParams) -> AoResult<AoOutput> {
        let depth = ctx.channel(GBufferChannel::LinearDepth)?;
        let out = ctx.accessibility_texture("ao");
        let mut p = ctx
            .builder
            .compute_pass("depth-only.copy", "test/depth_only.wgsl", "main");
        p.sample("depth", depth);
        let out = p.write_storage("ao", out);
        p.dispatch_over(out);
        Ok(AoOutput::new(out))
    }
}

const DEPTH_ONLY: &str = "@group(0) @binding(0) var depth: texture_2d<f32>;\n@group(0) @binding(1) var ao: texture_storage_2d<r32float, write>;\n@compute @workgroup_size(8, 8)\nfn main(@builtin(global_invocation_id) id: vec3<u32>) {\n    let d = textureLoad(depth, vec2<i32>(id.xy), 0).r;\n    textureStore(ao, vec2<i32>(id.xy), vec4<f32>(select(1.0, 0.5, d > 0.0)));\n}\n";

fn resource_names(decl: &aograph_graph::GraphDecl) -> Vec<String> {
    decl.resources.iter().map(|r| r.name.clone()).collect()
}

#[test]
fn depth_only_technique_plan_has_no_normal_colour_or_motion_attachment() {
    let mut registry = TechniqueRegistry::with_builtins();
    registry.register(DepthOnly);
    let ao = AoConfig {
        technique: "depth-only".into(),
        ..AoConfig::default()
    };
    for scene in ["columns", "dynamic"] {
        let s = Arc::new(aograph_scene::procedural_scene(scene).unwrap());
        let fg = build_frame_graph(&registry, s, &ao, FrameOutputs::default(), SIZE).unwrap();
        let shaders = aograph::shader_library();
        shaders.add_inline("test/depth_only.wgsl", DEPTH_ONLY);
        let plan = compile(fg.decl.clone(), &shaders, CompileOptions::default()).unwrap();
        let names = resource_names(&plan.decl);
        for absent in [
            "gbuffer.normals",
            "gbuffer.positions",
            "gbuffer.albedo",
            "gbuffer.direct_light",
            "gbuffer.motion",
        ] {
            assert!(
                !names.iter().any(|n| n == absent),
                "{scene}: {absent} in {names:?}"
            );
        }
        assert!(
            names.iter().any(|n| n == "gbuffer.linear_depth"),
            "{names:?}"
        );
        assert_eq!(plan.pass_names(), ["gbuffer", "depth-only.copy"]);
    }
}

#[test]
fn static_scene_gets_no_motion_vectors_but_a_moving_one_does() {
    let registry = TechniqueRegistry::with_builtins();
    let ao = AoConfig {
        technique: "tssao".into(),
        ..AoConfig::default()
    };
    let channels = |scene: &str| {
        let s = Arc::new(aograph_scene::procedural_scene(scene).unwrap());
        build_frame_graph(&registry, s, &ao, FrameOutputs::default(), SIZE)
            .unwrap()
            .channels
    };
    assert!(
        !channels("columns").contains(GBufferChannel::Motion),
        "static scene"
    );
    assert!(
        channels("dynamic").contains(GBufferChannel::Motion),
        "moving scene"
    );
}

#[test]
fn only_ssdo_and_shading_bring_colour_into_the_graph() {
    let registry = TechniqueRegistry::with_builtins();
    let scene = Arc::new(aograph_scene::procedural_scene("columns").unwrap());
    for name in registry.names() {
        let ao = AoConfig {
            technique: name.clone(),
            ..AoConfig::default()
        };
        let fg = build_frame_graph(&registry, scene.clone(), &ao, FrameOutputs::default(), SIZE)
            .unwrap();
        let has_colour = fg.channels.contains(GBufferChannel::Albedo)
            || fg.channels.contains(GBufferChannel::DirectLight);
        assert_eq!(
            has_colour,
            name == "ssdo",
            "{name}: channels {:?}",
            fg.channels.iter().collect::<Vec<_>>()
        );
        let shaded = build_frame_graph(
            &registry,
            scene.clone(),
            &ao,
            FrameOutputs {
                shaded: true,
                ..Default::default()
            },
            SIZE,
        )
        .unwrap();
        assert!(
            shaded.channels.contains(GBufferChannel::Albedo),
            "{name}: shading needs albedo"
        );
    }
}

#[test]
fn every_technique_plan_culls_nothing_and_compiles_against_the_real_shaders() {
    let registry = TechniqueRegistry::with_builtins();
    let scene = Arc::new(aograph_scene::procedural_scene("columns").unwrap());
    for name in registry.names() {
        let ao = AoConfig {
            technique: name.clone(),
            ..AoConfig::default()
        };
        let fg = build_frame_graph(
            &registry,
            scene.clone(),
            &ao,
            FrameOutputs {
                shaded: true,
                ..Default::default()
            },
            SIZE,
        )
        .unwrap();
        let plan = compile(
            fg.decl,
            &aograph::shader_library(),
            CompileOptions::default(),
        )
        .unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(
            plan.culled.is_empty(),
            "{name}: culled {:?}",
            plan.culled_names()
        );
        assert_eq!(
            plan.pass_names().first().copied(),
            Some("gbuffer"),
            "{name}"
        );
    }
}
