//! `resolution = "full" | "half"` on a spatial technique: at half, the technique's own passes
//! run unchanged on a half-size g-buffer and view block ([`crate::blocks::half_resolution`]:
//! each 2x2 block's nearest surface, moved to the block's centre along its tangent plane), and
//! the shared bilateral upsample ([`crate::blocks::bilateral_upsample`], depth and normals)
//! brings the accessibility back to the output size. CACAO, Godot's ASSAO and Unreal's GTAO
//! offer the same knob.
//!
//! Invariant: at `full` (the default) nothing is added or changed. At `half` every texture the
//! technique creates is half size (the graph builder's size divisor, so a technique written
//! for the full output needs no change), and its output is full size again; its extra outputs
//! (bent normals, ...) stay at half size, and the half-size depth it ran on is the extra output
//! [`HALF_DEPTH_OUTPUT`].

use aograph_frame::{GBufferChannel, GBufferChannels};
use serde::{Deserialize, Serialize};

use crate::blocks::half_resolution::{HALF_CHANNELS, half_gbuffer};
use crate::blocks::{BilateralUpsample, UpsampleInputs, bilateral_upsample};
use crate::error::{AoError, AoResult};
use crate::param::ParamDesc;
use crate::technique::{AoBuildContext, AoOutput, ExtraOutput};

/// The name, in [`AoOutput::extra`], of the half-size linear depth the technique ran on
/// (present at `half`), for inspection and tests.
pub const HALF_DEPTH_OUTPUT: ExtraOutput = ExtraOutput::new("half_linear_depth");

/// The size a technique's own passes run at.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Resolution {
    /// The output size.
    #[default]
    Full,
    /// Half the output size (rounded up), upsampled to the output.
    Half,
}

impl Resolution {
    /// The serde names, in order.
    pub const NAMES: &'static [&'static str] = &["full", "half"];

    /// The description of `resolution`.
    pub fn param() -> ParamDesc {
        ParamDesc::choice("resolution", Self::NAMES).doc(
            "full, or half: the technique runs on a half-size g-buffer (each 2x2 block's nearest surface) and a bilateral upsample (depth, normals) brings it back",
        )
    }

    /// Output pixels per pixel of the technique's own passes, along each axis.
    pub fn factor(self) -> u32 {
        match self {
            Resolution::Full => 1,
            Resolution::Half => 2,
        }
    }

    /// The technique's spatial channels, with those the upsample reads at half.
    pub fn channels(self, spatial: GBufferChannels) -> GBufferChannels {
        match self {
            Resolution::Full => spatial,
            Resolution::Half => spatial.union(GBufferChannels::of(&[
                GBufferChannel::LinearDepth,
                GBufferChannel::Normals,
            ])),
        }
    }

    /// The reach, in output pixels, of a technique whose reach at an image `height` tall with R
    /// projecting to `radius_pixels` is `reach(height, radius_pixels)`: at half, its passes see
    /// an image half as tall, where R is half as many pixels, and each of their pixels is two.
    pub fn reach(
        self,
        height: u32,
        radius_pixels: Option<f32>,
        reach: impl Fn(u32, Option<f32>) -> Option<f32>,
    ) -> Option<f32> {
        let f = self.factor();
        reach(height.div_ceil(f), radius_pixels.map(|r| r / f as f32)).map(|r| r * f as f32)
    }

    /// Builds `spatial` (the technique's own passes) at this resolution. `channels` are the
    /// g-buffer channels those passes read: at half, each must be one the half g-buffer holds.
    pub fn build(
        self,
        ctx: &mut AoBuildContext<'_>,
        channels: GBufferChannels,
        spatial: impl FnOnce(&mut AoBuildContext<'_>) -> AoResult<AoOutput>,
    ) -> AoResult<AoOutput> {
        if self == Resolution::Full {
            return spatial(ctx);
        }
        if let Some(c) = channels.iter().find(|c| !HALF_CHANNELS.contains(c)) {
            return Err(AoError::ParameterRule {
                technique: ctx.technique.into(),
                rule: format!(
                    "resolution = \"half\" downsamples linear depth, normals, octahedral normals, motion and positions, and this technique also reads {}: use resolution = \"full\"",
                    c.name()
                ),
            });
        }
        let prefix = format!("{}.half", ctx.technique);
        let half = half_gbuffer(ctx.builder, &prefix, &ctx.gbuffer, ctx.view)?;
        let previous = ctx.builder.set_size_divisor(2 * ctx.builder.size_divisor());
        let mut inner = AoBuildContext {
            builder: &mut *ctx.builder,
            gbuffer: half.gbuffer,
            view: half.view,
            radius: ctx.radius,
            intermediate_format: ctx.intermediate_format,
            technique: ctx.technique,
            radius_pixels: ctx.radius_pixels.map(|r| r * 0.5),
            declared: std::mem::take(&mut ctx.declared),
            tracing: ctx.tracing.clone(),
        };
        let out = spatial(&mut inner);
        ctx.declared = inner.declared;
        ctx.builder.set_size_divisor(previous);
        let out = out?;
        let full_depth = ctx.channel(GBufferChannel::LinearDepth)?;
        let full_normals = ctx.channel(GBufferChannel::Normals)?;
        let (half_depth, half_normals) = (half.depth, half.normals);
        let accessibility = bilateral_upsample(
            ctx.builder,
            &prefix,
            &UpsampleInputs {
                ao: out.accessibility,
                depth_low: half_depth,
                depth_full: full_depth,
                normals: Some((half_normals, full_normals)),
            },
            &BilateralUpsample::default(),
        )?;
        let mut out = out;
        out.accessibility = accessibility;
        out.extra.push((HALF_DEPTH_OUTPUT, half_depth));
        Ok(out)
    }
}
