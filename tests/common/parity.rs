//! A test technique for the shared temporal block (`blocks::temporal`): it writes the frame
//! index's parity (0, 1, 0, ...) and passes it through the block, so a test reads exactly
//! whether a pixel's history was kept (a blend) or dropped (the raw parity).

use aograph_frame::ReadsView;
use std::sync::Arc;

use aograph_ao_passes::blocks::temporal::{
    TemporalAccumulation, TemporalMode, add_temporal, temporal_channels,
};
use aograph_ao_passes::{
    AoBuildContext, AoConfig, AoOutput, AoResult, AoTechnique, ParamDesc, TechniqueRegistry,
};
use aograph_frame::GBufferChannels;
use aograph_graph::{Extent, SizeClass, TextureDesc, test_gpu};
use aograph_renderer::FrameOutputs;
use aograph_renderer::Renderer;
use aograph_scene::Scene;

/// A test technique: accessibility (frame index mod 2) per frame, through the shared temporal
/// block (the way MSSAO's temporal filter and any spatial technique use it).
pub struct ParityThroughTemporal(TemporalMode);

#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct NoParams {}

const PARITY_SHADER: &str = "#include \"common/view.wgsl\"
@group(0) @binding(0) var<uniform> view: View;
@group(0) @binding(1) var dst: texture_storage_2d<r32float, write>;
@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(dst);
    if (id.x >= size.x || id.y >= size.y) { return; }
    textureStore(dst, vec2<i32>(id.xy), vec4<f32>(f32(view.frame_index & 1u), 0.0, 0.0, 0.0));
}
";

impl AoTechnique for ParityThroughTemporal {
    type Params = NoParams;
    const NAME: &'static str = "parity-temporal";
    fn description(&self) -> &'static str {
        "test: frame parity through blocks::temporal"
    }
    fn params(&self) -> Vec<ParamDesc> {
        Vec::new()
    }
    fn channels(&self, _: &NoParams) -> GBufferChannels {
        temporal_channels()
    }
    fn is_temporal(&self, _: &NoParams) -> bool {
        true
    }
    fn build(&self, ctx: &mut AoBuildContext<'_>, _: &NoParams) -> AoResult<AoOutput> {
        let t = ctx.builder.create_texture(
            "parity",
            TextureDesc::new(wgpu::TextureFormat::R32Float, SizeClass::FULL),
        );
        let mut p = ctx
            .builder
            .compute_pass("parity.fill", "test/parity.wgsl", "main");
        p.read_view(ctx.view);
        let t = p.write_storage("dst", t);
        p.dispatch_over(t);
        let params = TemporalAccumulation {
            n_max: 4,
            mode: self.0,
            ..Default::default()
        };
        Ok(AoOutput::new(
            add_temporal(
                ctx.builder,
                "parity.temporal",
                t,
                &ctx.gbuffer,
                ctx.view,
                &params,
            )?
            .accumulated,
        ))
    }
}

/// A renderer of `scene` at `size` running the parity technique through the temporal block
/// in `mode`; `None` without a GPU.
pub fn renderer(mode: TemporalMode, scene: Scene, size: Extent) -> Option<Renderer> {
    let gpu = test_gpu()?;
    let mut registry = TechniqueRegistry::with_builtins();
    registry.register(ParityThroughTemporal(mode));
    let shaders = aograph::shader_library();
    shaders.add_inline("test/parity.wgsl", PARITY_SHADER);
    let config = AoConfig {
        technique: "parity-temporal".into(),
        radius: aograph_ao_passes::RadiusSetting::Units(aograph_ao_passes::Radius::UNIT),
        ..AoConfig::default()
    };
    let outputs = FrameOutputs {
        linear_depth: true,
        motion: true,
        ..Default::default()
    };
    Some(
        Renderer::new(
            gpu,
            shaders,
            &registry,
            Arc::new(scene),
            &config,
            outputs,
            size,
        )
        .expect("frame graph builds"),
    )
}
