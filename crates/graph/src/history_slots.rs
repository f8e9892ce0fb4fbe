//! A plan's histories resolved once, at compile: each history gets a slot, every resource that
//! is one of its halves points at that slot, and the slot carries what a frame needs of it
//! (the usage both halves need, whether the plan writes it). The executor then finds a
//! history by index; no history name is compared on the per-frame path.
//!
//! Invariant: `history_of[r] == Some(s)` exactly when resource `r` is the previous or current
//! half of `histories[s]`, and every history the declaration names has one slot.

use crate::declaration::{GraphDecl, ResourceOrigin};

/// One history of a plan, as the executor binds it each frame.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct HistorySlot {
    /// The history's name (for messages and the by-name query
    /// [`crate::Executor::history_valid`]).
    pub name: String,
    /// The resource of its current half (this frame's write), which gives the descriptor.
    pub current: usize,
    /// Everything its two halves are used for, plus copies and sampling (a clear, a read-back).
    pub usage: wgpu::TextureUsages,
    /// Whether the plan writes it (so it swaps at the end of a frame).
    pub written: bool,
}

/// The slots of `decl`'s histories in order of their current halves, and per resource the
/// slot it is a half of. `usage` is the plan's per-resource usage.
pub(crate) fn resolve_histories(
    decl: &GraphDecl,
    usage: &[wgpu::TextureUsages],
) -> (Vec<HistorySlot>, Vec<Option<usize>>) {
    let history_name = |origin: &ResourceOrigin| match origin {
        ResourceOrigin::HistoryPrevious { history }
        | ResourceOrigin::HistoryCurrent { history } => Some(history.clone()),
        _ => None,
    };
    let mut slots: Vec<HistorySlot> = Vec::new();
    for (r, res) in decl.resources.iter().enumerate() {
        if let ResourceOrigin::HistoryCurrent { history } = &res.origin {
            slots.push(HistorySlot {
                name: history.clone(),
                current: r,
                usage: wgpu::TextureUsages::COPY_SRC
                    | wgpu::TextureUsages::COPY_DST
                    | wgpu::TextureUsages::TEXTURE_BINDING,
                written: res.latest_version() > 0,
            });
        }
    }
    let mut history_of = vec![None; decl.resources.len()];
    for (r, res) in decl.resources.iter().enumerate() {
        let Some(name) = history_name(&res.origin) else {
            continue;
        };
        if let Some(s) = slots.iter().position(|s| s.name == name) {
            history_of[r] = Some(s);
            slots[s].usage |= usage[r];
        }
    }
    (slots, history_of)
}
