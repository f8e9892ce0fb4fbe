//! `none`: accessibility 1 everywhere. The cost floor every technique is compared with: one
//! full-screen write and nothing else, reading no g-buffer channel.

use crate::ParamSpec;
use aograph_frame::GBufferChannels;
use serde::{Deserialize, Serialize};

use crate::error::AoResult;
use crate::technique::{AoBuildContext, AoOutput, AoTechnique};

pub struct NoAo;

/// `none` has no parameters.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NoParams {}

impl AoTechnique for NoAo {
    type Params = NoParams;
    fn name(&self) -> &'static str {
        "none"
    }
    fn description(&self) -> &'static str {
        "accessibility 1 everywhere: the cost floor"
    }
    fn param_specs(&self) -> Vec<ParamSpec> {
        Vec::new()
    }
    fn validate(&self, _: &NoParams) -> AoResult<()> {
        Ok(())
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
