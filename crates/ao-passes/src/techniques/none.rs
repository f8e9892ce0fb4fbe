//! `none`: accessibility 1 everywhere. The cost floor every technique is compared with: one
//! full-screen write and nothing else, reading no g-buffer channel.

use aograph_frame::GBufferChannels;
use serde::{Deserialize, Serialize};

use crate::error::AoResult;
use crate::param::ParamDesc;
use crate::technique::{AoBuildContext, AoOutput, AoTechnique};

/// The `none` technique ([`BASELINE`]): writes accessibility 1 everywhere and reads no
/// channel, the cost floor other techniques are measured above.
pub struct NoAo;

/// The registry name of the cost floor: what a frame that needs only the g-buffer renders.
pub const BASELINE: &str = "none";

/// `none` has no parameters.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NoParams {}

impl AoTechnique for NoAo {
    type Params = NoParams;
    const NAME: &'static str = BASELINE;
    fn description(&self) -> &'static str {
        "accessibility 1 everywhere: the cost floor"
    }
    fn params(&self) -> Vec<ParamDesc> {
        Vec::new()
    }
    fn is_baseline(&self) -> bool {
        true
    }
    fn channels(&self, _: &NoParams) -> GBufferChannels {
        GBufferChannels::none()
    }
    fn build(&self, ctx: &mut AoBuildContext<'_>, _: &NoParams) -> AoResult<AoOutput> {
        let out = ctx.accessibility_texture("ao");
        let mut p = ctx
            .builder
            .compute_pass("none.fill", "ao/none.wgsl", "main");
        let out = p.write_storage("ao", out);
        p.dispatch_over(out);
        Ok(AoOutput::new(out))
    }
}
