//! History (ping-pong) textures: last frame's value readable while this frame's is written,
//! kept per plan and history slot (the index compile gave the history:
//! [`crate::HistorySlot`]), so a frame finds them without comparing names.
//!
//! Invariant: a history's previous value is valid only when the same plan wrote it in the
//! executor's immediately preceding frame, at the same size and format, and no reset (camera
//! cut) came in between. So it is false on a plan's first frame, after a resize or format
//! change, after a reset, and when the plan comes back after another plan ran (its value is
//! then stale by at least a frame). The previous texture is cleared to zero whenever it is
//! invalid, so an invalid history never leaks stale values even if a shader ignores the flag.
//! A history no frame bound for [`HistoryStore::IDLE_FRAMES`] frames is evicted: its textures
//! go back to the pool.

use std::collections::HashMap;

use crate::compile::PlanKey;
use crate::pool::{PoolKey, PooledTexture, TexturePool};

/// Both textures of one history and which one is written this frame.
pub struct HistoryPair {
    /// The plan's history slot ([`crate::CompiledGraph::histories`]).
    pub slot: usize,
    pub textures: [PooledTexture; 2],
    pub current: usize,
    pub key: PoolKey,
    /// The frame that last wrote `textures[1 - current]` (the previous value).
    written: Option<u64>,
    /// The last frame that bound this history.
    bound: u64,
}

impl HistoryPair {
    /// The texture holding last frame's value.
    pub fn previous(&self) -> &PooledTexture {
        &self.textures[1 - self.current]
    }
    /// The texture this frame writes.
    pub fn current(&self) -> &PooledTexture {
        &self.textures[self.current]
    }
}

/// Histories by plan, then by slot.
#[derive(Default)]
pub struct HistoryStore {
    plans: HashMap<PlanKey, Vec<HistoryPair>>,
    /// A reset waits for the next frame.
    reset: bool,
}

/// Whether a pair with `key` fits a frame needing `want` (same texels; usage may grow).
fn fits(key: &PoolKey, want: &PoolKey) -> bool {
    key.format == want.format && key.extent == want.extent && key.mip_levels == want.mip_levels
}

impl HistoryStore {
    /// Frames a history waits, unbound, before its textures return to the pool.
    pub const IDLE_FRAMES: u64 = 8;

    /// Whether `plan`'s history `slot` will hold a valid previous value in `frame`, for
    /// textures of `key` (see the module invariant).
    pub fn is_valid(&self, plan: PlanKey, slot: usize, key: &PoolKey, frame: u64) -> bool {
        !self.reset
            && self
                .pair(plan, slot)
                .is_some_and(|p| fits(&p.key, key) && p.written.is_some_and(|w| w + 1 == frame))
    }
    fn pair(&self, plan: PlanKey, slot: usize) -> Option<&HistoryPair> {
        self.plans.get(&plan)?.iter().find(|p| p.slot == slot)
    }
    /// Invalidates every history (a camera cut) for the next frame.
    pub fn reset(&mut self) {
        self.reset = true;
    }
    /// The pair for `frame`, taken from the pool (or replaced) when its descriptor changed.
    /// Returns the pair and whether its previous value is valid.
    pub fn prepare(
        &mut self,
        device: &wgpu::Device,
        pool: &mut TexturePool,
        plan: PlanKey,
        slot: usize,
        key: PoolKey,
        frame: u64,
    ) -> (&HistoryPair, bool) {
        let valid = self.is_valid(plan, slot, &key, frame);
        let list = self.plans.entry(plan).or_default();
        let i = match list.iter().position(|p| p.slot == slot) {
            Some(i) if list[i].key == key => i,
            Some(i) => {
                let old = list.swap_remove(i);
                let [a, b] = old.textures;
                pool.release(a);
                pool.release(b);
                list.push(new_pair(device, pool, slot, key));
                list.len() - 1
            }
            None => {
                list.push(new_pair(device, pool, slot, key));
                list.len() - 1
            }
        };
        let pair = &mut list[i];
        pair.bound = frame;
        (pair, valid)
    }
    /// After `plan`'s frame was submitted: each history it wrote swaps, so this frame's value
    /// becomes the next frame's previous one.
    pub fn end_frame(&mut self, plan: PlanKey, written: impl Iterator<Item = usize>, frame: u64) {
        if let Some(list) = self.plans.get_mut(&plan) {
            for slot in written {
                if let Some(p) = list.iter_mut().find(|p| p.slot == slot) {
                    p.current = 1 - p.current;
                    p.written = Some(frame);
                }
            }
        }
        self.reset = false;
    }
    /// Returns the textures of histories unbound for [`Self::IDLE_FRAMES`] frames to the pool.
    pub fn evict_idle(&mut self, pool: &mut TexturePool, frame: u64) {
        for list in self.plans.values_mut() {
            let mut i = 0;
            while i < list.len() {
                if list[i].bound + Self::IDLE_FRAMES <= frame {
                    let [a, b] = list.swap_remove(i).textures;
                    pool.release(a);
                    pool.release(b);
                } else {
                    i += 1;
                }
            }
        }
        self.plans.retain(|_, l| !l.is_empty());
    }
    /// True when `plan`'s history `slot` still holds what `frame` bound (not evicted or
    /// replaced since), so a read-back of that frame's history texture is what it wrote.
    pub fn holds_frame(&self, plan: PlanKey, slot: usize, frame: u64) -> bool {
        self.pair(plan, slot).is_some_and(|p| p.bound == frame)
    }
    /// Number of history textures held (two per history).
    pub fn texture_count(&self) -> usize {
        self.plans.values().map(|l| l.len() * 2).sum()
    }
}

fn new_pair(
    device: &wgpu::Device,
    pool: &mut TexturePool,
    slot: usize,
    key: PoolKey,
) -> HistoryPair {
    HistoryPair {
        slot,
        textures: [pool.acquire(device, key, 0), pool.acquire(device, key, 0)],
        current: 0,
        key,
        written: None,
        bound: 0,
    }
}
