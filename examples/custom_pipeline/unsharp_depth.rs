//! The user technique of examples/custom_pipeline.rs: depth-buffer unsharp masking (Luft et
//! al. 2006), written as any user would, with no code for its controls, listing or tests (the
//! viewer and `aograph_ao_passes::contract` read its parameter descriptions; the contract runs over it
//! in tests/user_technique_contract.rs).

use aograph_ao_passes::{AoBuildContext, AoOutput, AoResult, AoTechnique, ParamDesc};
use aograph_frame::{GBufferChannel, GBufferChannels, ReadsView};
use aograph_graph::ShaderMount;
use serde::{Deserialize, Serialize};

/// The name its shader is mounted under (it lives outside aograph's shaders/ and includes
/// aograph's `common/view.wgsl` through the frame crate's mount).
pub const SHADER: &str = "examples/unsharp_depth.wgsl";

/// The technique's WGSL, compiled in, as a mount for any shader library: aograph's renderer
/// (`shaders.mount(shader_mount())`) or an application's `AmbientOcclusion::with_registry`.
pub fn shader_mount() -> ShaderMount {
    ShaderMount::new("unsharp-depth")
        .with_file(SHADER, include_str!("../shaders/unsharp_depth.wgsl"))
}

/// Depth-buffer unsharp masking (Luft et al. 2006) as a user technique.
pub struct UnsharpDepth;

#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(default)]
pub struct UnsharpParams {
    strength: f32,
    radius_px: f32,
}

impl Default for UnsharpParams {
    fn default() -> Self {
        Self {
            strength: 4.0,
            radius_px: 6.0,
        }
    }
}

impl AoTechnique for UnsharpDepth {
    type Params = UnsharpParams;
    const NAME: &'static str = "unsharp-depth";
    fn description(&self) -> &'static str {
        "depth-buffer unsharp masking (a user plugin)"
    }
    /// One description per parameter: validation, `aograph techniques`, the viewer's
    /// sliders and the contract test all come from these lines.
    fn params(&self) -> Vec<ParamDesc> {
        vec![
            ParamDesc::float("strength", 0.0, 100.0)
                .doc("darkening per unit relative depth difference"),
            ParamDesc::float("radius_px", 1.0, 16.0).doc("blur radius in pixels"),
        ]
    }
    fn channels(&self, _: &UnsharpParams) -> GBufferChannels {
        GBufferChannels::of(&[GBufferChannel::LinearDepth])
    }
    fn build(&self, ctx: &mut AoBuildContext<'_>, p: &UnsharpParams) -> AoResult<AoOutput> {
        let depth = ctx.channel(GBufferChannel::LinearDepth)?;
        let out = ctx.accessibility_texture("unsharp.ao");
        let mut pass = ctx.builder.compute_pass("unsharp-depth.ao", SHADER, "main");
        pass.sample("depth", depth).read_view(ctx.view);
        let bytes: Vec<u8> = [p.strength, p.radius_px, 0.0, 0.0]
            .iter()
            .flat_map(|f| f.to_le_bytes())
            .collect();
        pass.uniform("params", &bytes);
        let out = pass.write_storage("ao", out);
        pass.dispatch_over(out);
        Ok(AoOutput::new(out))
    }
}
