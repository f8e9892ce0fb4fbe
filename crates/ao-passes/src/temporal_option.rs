//! `temporal = true` on a spatial technique (ssao, hbao, pyramid-hbao, gtao, vbao): the shared
//! accumulation block ([`crate::blocks::temporal`], a running mean, [`TemporalMode::Average`])
//! appended to the technique's output, and the technique's noise made to change every frame,
//! so that the mean runs over noise realisations rather than repeating one (as XeGTAO feeds
//! its TAA: its noise index advances with the frame).
//!
//! Invariant: with `temporal = false` (the default) the technique's plan, pipelines and output
//! are exactly those without the option: no pass is added and the pipeline constant
//! [`TEMPORAL_NOISE`] keeps its default (false), so the noise is the same every frame.
//!
//! With it, the plan gains `<technique>.temporal.reproject`, `.accumulate` (and `.zero_motion`
//! on a scene without motion vectors; with `temporal_denoiser = "history"` also
//! `.history_fix` and `.atrous1..3`, `blocks::history_denoise`): reprojection through the camera or the g-buffer's
//! motion, the disocclusion test |1 - d_new/d_old| < `temporal_epsilon` (history dropped where
//! it fails), a per-pixel count capped at `temporal_frames`, and a reset on a camera cut or
//! resize. The technique's own per-frame accessibility stays readable as the extra output
//! [`PER_FRAME_OUTPUT`], so the accumulated image can be checked against the mean of the
//! frames it averaged. `tssao` (whose paper is this accumulation) and `mssao` (whose paper
//! defines its own filter, Eqs. 12-14) keep their own `temporal` parameters; `rtao` has had
//! the same accumulation since it was written.

use aograph_frame::{GBufferChannel, GBufferChannels};
use aograph_graph::PassBuilder;
use serde::{Deserialize, Serialize};

use crate::blocks::history_denoise::{HistoryDenoise, HistoryDenoiseInputs, history_denoise};
use crate::blocks::temporal::{
    DEFAULT_EPSILON, MAX_N_MAX, TemporalAccumulation, TemporalMode, add_temporal, temporal_channels,
};
use crate::error::AoResult;
use crate::param::ParamDesc;
use crate::technique::{AoBuildContext, AoOutput, ExtraOutput};

/// The pipeline constant (shaders/common/noise.wgsl) that makes a technique's noise follow
/// the frame index.
pub const TEMPORAL_NOISE: &str = "TEMPORAL_NOISE";

/// The name, in [`AoOutput::extra`], of the technique's own accessibility of this frame
/// (before accumulation), present when `temporal = true`.
pub const PER_FRAME_OUTPUT: ExtraOutput = ExtraOutput::new("per_frame_accessibility");

/// Default cap of the running mean: the known-answer test's 32 frames average exactly.
pub const DEFAULT_TEMPORAL_FRAMES: u32 = 32;

/// The values of `temporal_denoiser`.
const TEMPORAL_DENOISERS: &[&str] = &["none", "history"];

/// The temporal option, flattened into each spatial technique's parameter table.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct TemporalOption {
    /// Accumulate frames (off by default).
    pub temporal: bool,
    /// Most frames the running mean holds (n_max of TSSAO Eq. 6).
    pub temporal_frames: u32,
    /// The disocclusion test's relative depth tolerance (TSSAO Eq. 7).
    pub temporal_epsilon: f32,
    /// The spatial filter after the running mean: "none" or "history"
    /// (`blocks::history_denoise`: wide where a pixel's history is short, narrowing as it
    /// grows).
    pub temporal_denoiser: TemporalDenoiser,
}

/// The spatial filter the temporal option runs after the running mean.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum TemporalDenoiser {
    /// The running mean as it is.
    None,
    /// `blocks::history_denoise`.
    History,
}

impl Default for TemporalOption {
    fn default() -> Self {
        Self {
            temporal: false,
            temporal_frames: DEFAULT_TEMPORAL_FRAMES,
            temporal_epsilon: DEFAULT_EPSILON,
            temporal_denoiser: TemporalDenoiser::None,
        }
    }
}

impl TemporalOption {
    /// The descriptions of `temporal`, `temporal_frames` and `temporal_epsilon`.
    pub fn params() -> Vec<ParamDesc> {
        vec![
            ParamDesc::flag("temporal").doc(
                "accumulate frames: a running mean, reprojected, reset where the depth test fails; the noise changes every frame",
            ),
            ParamDesc::int("temporal_frames", 1, MAX_N_MAX)
                .doc("most frames the running mean holds (its per-pixel count's cap)"),
            ParamDesc::float("temporal_epsilon", 0.0001, 1.0).doc(
                "history is dropped where |1 - d_new/d_old| reaches this (disocclusion; 0.03)",
            ),
            ParamDesc::choice("temporal_denoiser", TEMPORAL_DENOISERS).doc(
                "after the running mean: none, or history (rtao's history denoiser: wide where a pixel's history is short, narrowing as it grows)",
            ),
        ]
    }

    /// The technique's spatial channels, with the block's when the option is on.
    pub fn channels(&self, spatial: GBufferChannels) -> GBufferChannels {
        if self.temporal {
            spatial.union(temporal_channels())
        } else {
            spatial
        }
    }

    /// Makes the pass's noise follow the frame index when the option is on (the shader
    /// includes common/noise.wgsl); leaves the pipeline as it is otherwise.
    pub fn vary_noise(&self, pass: &mut PassBuilder<'_>) {
        if self.temporal {
            pass.constant(TEMPORAL_NOISE, 1.0);
        }
    }

    /// Appends the accumulation to `spatial` (the technique's output) when the option is on,
    /// under `<technique>.temporal`; the spatial accessibility becomes [`PER_FRAME_OUTPUT`].
    pub fn apply(&self, ctx: &mut AoBuildContext<'_>, spatial: AoOutput) -> AoResult<AoOutput> {
        if !self.temporal {
            return Ok(spatial);
        }
        let t = add_temporal(
            ctx.builder,
            &format!("{}.temporal", ctx.technique),
            spatial.accessibility,
            &ctx.gbuffer,
            ctx.view,
            &TemporalAccumulation {
                epsilon: self.temporal_epsilon,
                n_max: self.temporal_frames,
                mode: TemporalMode::Average,
            },
        )?;
        let mut out = spatial;
        out.extra.push((PER_FRAME_OUTPUT, out.accessibility));
        out.accessibility = t.accumulated;
        if self.temporal_denoiser == TemporalDenoiser::History {
            let depth = ctx.channel(GBufferChannel::LinearDepth)?;
            let normals = ctx.channel(GBufferChannel::Normals)?;
            let d = history_denoise(
                ctx.builder,
                &format!("{}.temporal", ctx.technique),
                &HistoryDenoiseInputs {
                    accumulated: t.accumulated,
                    history: t.history.current,
                    depth,
                    normals,
                    hits: None,
                    view: ctx.view,
                },
                &HistoryDenoise::default(),
            )?;
            out.accessibility = d.accessibility;
        }
        Ok(out)
    }
}
