//! The two options every screen-space technique that runs one image per frame shares
//! (ssao, hbao, pyramid-hbao, gtao, vbao): `resolution` ([`Resolution`]) and the temporal
//! option ([`TemporalOption`]), as one field flattened into the technique's parameters.
//!
//! Invariant: a technique holding [`SpatialOptions`] writes its own passes once and calls
//! [`SpatialOptions::build`] once; at the defaults (full resolution, no accumulation) the plan
//! is exactly the technique's own passes.

use aograph_frame::GBufferChannels;
use aograph_graph::PassBuilder;
use serde::{Deserialize, Serialize};

use crate::error::AoResult;
use crate::param::ParamDesc;
use crate::resolution::Resolution;
use crate::technique::{AoBuildContext, AoOutput};
use crate::temporal_option::TemporalOption;

/// `resolution`, `temporal`, `temporal_frames`, `temporal_epsilon` and `temporal_denoiser`:
/// flatten it into a technique's parameter struct (`#[serde(flatten)]`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct SpatialOptions {
    /// The size the technique's own passes run at.
    pub resolution: Resolution,
    /// The running mean over frames appended to the technique's output.
    #[serde(flatten)]
    pub accumulation: TemporalOption,
}

impl SpatialOptions {
    /// The descriptions of the five keys, in table order.
    pub fn params() -> Vec<ParamDesc> {
        let mut d = vec![Resolution::param()];
        d.extend(TemporalOption::params());
        d
    }

    /// `spatial` (the channels the technique's own passes read) with those the upsample and
    /// the accumulation read when they are on.
    pub fn channels(&self, spatial: GBufferChannels) -> GBufferChannels {
        self.accumulation
            .channels(self.resolution.channels(spatial))
    }

    /// Whether the output accumulates over frames.
    pub fn is_temporal(&self) -> bool {
        self.accumulation.temporal
    }

    /// The technique's reach in output pixels from its reach at the size its passes run at
    /// ([`Resolution::reach`]).
    pub fn reach(
        &self,
        height: u32,
        radius_pixels: Option<f32>,
        reach: impl Fn(u32, Option<f32>) -> Option<f32>,
    ) -> Option<f32> {
        self.resolution.reach(height, radius_pixels, reach)
    }

    /// Makes a noisy pass's noise follow the frame index when accumulating
    /// ([`TemporalOption::vary_noise`]).
    pub fn vary_noise(&self, pass: &mut PassBuilder<'_>) {
        self.accumulation.vary_noise(pass);
    }

    /// Builds `spatial` (the technique's own passes, reading `channels`) at the resolution,
    /// then the accumulation over frames when it is on.
    pub fn build(
        &self,
        ctx: &mut AoBuildContext<'_>,
        channels: GBufferChannels,
        spatial: impl FnOnce(&mut AoBuildContext<'_>) -> AoResult<AoOutput>,
    ) -> AoResult<AoOutput> {
        let out = self.resolution.build(ctx, channels, spatial)?;
        self.accumulation.apply(ctx, out)
    }
}
