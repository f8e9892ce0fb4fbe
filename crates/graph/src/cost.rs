//! What each pass of a plan must cost at an output size, from its declaration alone: the
//! invocations it runs, the texel loads it states it makes, and the bytes it must touch
//! (every texture it reads read once, every texture it writes written once). A roofline
//! divides these by the pass's time and compares the rates with the device's peaks.
//!
//! Invariant: pure, no GPU; the bytes are a lower bound of the traffic (caches can only add
//! re-reads), so an achieved byte rate above the device's copy rate means a measurement error.

use crate::compile::CompiledGraph;
use crate::declaration::{Dispatch, PassKind};
use crate::resource::{Extent, TextureAccess, texel_bytes};

/// One pass's cost at an output size.
#[derive(Clone, Debug, PartialEq)]
pub struct PassCost {
    /// Name of the pass, as in timings.
    pub pass: String,
    /// Threads of a compute pass, fragments of a full-screen pass (its attachments' pixels);
    /// 0 for copies and custom passes, whose work the graph does not see.
    pub invocations: u64,
    /// Loads per invocation, as the pass declares them (`PassBuilder::loads_per_invocation`).
    pub loads_per_invocation: Option<f32>,
    /// Bytes of the textures it reads (the mips it reads), each counted once.
    pub bytes_read: u64,
    /// Bytes of the textures it writes (the mips it writes), each counted once.
    pub bytes_written: u64,
}

impl PassCost {
    /// Texel loads the pass makes in all, when it declares them.
    pub fn loads(&self) -> Option<f64> {
        self.loads_per_invocation
            .map(|l| l as f64 * self.invocations as f64)
    }
    /// Bytes the pass must touch in all: `bytes_read + bytes_written`, a lower bound of its
    /// memory traffic.
    pub fn bytes(&self) -> u64 {
        self.bytes_read + self.bytes_written
    }
}

/// The cost of every kept pass of `plan` at `output`, in execution order.
pub fn pass_costs(plan: &CompiledGraph, output: Extent) -> Vec<PassCost> {
    let decl = &plan.decl;
    plan.order
        .iter()
        .map(|p| {
            let pass = &decl.passes[p.0];
            let mut bytes_read = 0;
            let mut bytes_written = 0;
            let mut attachment_pixels = 0;
            let mut seen_read: Vec<(usize, Option<u32>)> = Vec::new();
            for u in &pass.textures {
                let Some(desc) = decl.resources[u.resource()].texture_desc() else {
                    continue;
                };
                let base = desc.size.resolve(output);
                let texel = texel_bytes(desc.format);
                let bytes = match u.mip {
                    Some(m) => base.mip(m).pixels() * texel,
                    None => (0..desc.mip_levels)
                        .map(|m| base.mip(m).pixels() * texel)
                        .sum(),
                };
                let reads = u.access.reads()
                    || (u.read.is_some() && u.access != TextureAccess::StorageWrite);
                if reads && !seen_read.contains(&(u.resource(), u.mip)) {
                    seen_read.push((u.resource(), u.mip));
                    bytes_read += bytes;
                }
                if u.written.is_some() {
                    bytes_written += bytes;
                }
                if matches!(
                    u.access,
                    TextureAccess::ColorAttachment | TextureAccess::DepthAttachment
                ) {
                    attachment_pixels = base.mip(u.mip.unwrap_or(0)).pixels();
                }
            }
            let invocations = match &pass.kind {
                PassKind::Compute {
                    dispatch: Some(Dispatch::Threads { size, mip }),
                    ..
                } => size.resolve(output).mip(*mip).pixels(),
                PassKind::Compute {
                    dispatch: Some(Dispatch::Workgroups(w)),
                    entry,
                    ..
                } => {
                    let group = plan.shaders[p.0]
                        .as_ref()
                        .and_then(|s| s.entry(entry))
                        .map(|e| e.workgroup_size)
                        .unwrap_or([1, 1, 1]);
                    w.iter()
                        .zip(group)
                        .map(|(a, b)| *a as u64 * b as u64)
                        .product()
                }
                PassKind::Fullscreen { .. } => attachment_pixels,
                _ => 0,
            };
            PassCost {
                pass: pass.name.clone(),
                invocations,
                loads_per_invocation: pass.loads_per_invocation,
                bytes_read,
                bytes_written,
            }
        })
        .collect()
}
