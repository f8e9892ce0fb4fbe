//! History (ping-pong) textures: last frame's value readable while this frame's is written.
//!
//! Invariant: `valid` is false on the first frame, after the size or format changed, and after
//! a reset (a camera cut); the previous texture is cleared to zero whenever it is invalid, so
//! an invalid history never leaks stale values even if a shader ignores the flag.

use std::collections::HashMap;

use crate::pool::{PoolKey, PooledTexture, create_texture};

/// Both textures of one history and which one is written this frame.
pub struct HistoryPair {
    pub textures: [PooledTexture; 2],
    pub current: usize,
    pub valid: bool,
    pub key: PoolKey,
}

/// Histories by name.
#[derive(Default)]
pub struct HistoryStore {
    pairs: HashMap<String, HistoryPair>,
    reset_all: bool,
}

impl HistoryStore {
    /// Whether `name`'s previous value will be valid for a frame with textures of `key`.
    pub fn is_valid(&self, name: &str, key: &PoolKey) -> bool {
        !self.reset_all
            && self.pairs.get(name).is_some_and(|p| {
                p.valid && p.key.format == key.format && p.key.extent == key.extent
            })
    }
    /// Invalidates every history (a camera cut).
    pub fn reset(&mut self) {
        self.reset_all = true;
    }
    /// The pair for this frame, created or recreated when its descriptor changed. Returns the
    /// pair and whether its previous value is valid.
    pub fn prepare(
        &mut self,
        device: &wgpu::Device,
        name: &str,
        key: PoolKey,
        serials: &mut impl FnMut() -> u64,
    ) -> (&mut HistoryPair, bool) {
        let reset = self.reset_all;
        let fits = self.pairs.get(name).is_some_and(|p| p.key == key);
        if !fits {
            let label = format!("history {name}");
            let textures = [
                create_texture(device, &label, key, serials()),
                create_texture(device, &label, key, serials()),
            ];
            self.pairs.insert(
                name.to_string(),
                HistoryPair {
                    textures,
                    current: 0,
                    valid: false,
                    key,
                },
            );
        }
        let pair = self.pairs.get_mut(name).expect("inserted above");
        if reset {
            pair.valid = false;
        }
        let valid = pair.valid;
        (pair, valid)
    }
    /// After a frame's submission: this frame's value becomes next frame's previous one.
    pub fn end_frame<'a>(&mut self, written: impl Iterator<Item = &'a str>) {
        for name in written {
            if let Some(p) = self.pairs.get_mut(name) {
                p.current = 1 - p.current;
                p.valid = true;
            }
        }
        self.reset_all = false;
    }
    /// Number of history textures held (two per history).
    pub fn texture_count(&self) -> usize {
        self.pairs.len() * 2
    }
}
