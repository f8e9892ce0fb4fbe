//! What the render world tells the application about each aograph camera: the technique its
//! frames run now, the AO passes' GPU time, pipelines created, and any error. One shared value
//! sits in both worlds, so the main world reads it without extraction.
//!
//! Invariant: the render world holds its lock only to copy a few values in or out, never
//! across GPU work; a camera's entry goes when its AographAo does.

use std::collections::HashMap;
use std::sync::{Arc, Mutex};

use bevy::prelude::*;

/// Per-camera state of aograph's AO, keyed by the main world's camera entity. A resource in
/// both the main and the render world (one shared value).
#[derive(Resource, Clone, Default)]
pub struct AographAoStatus {
    inner: Arc<Mutex<HashMap<Entity, CameraAoStatus>>>,
}

/// One camera's AO, as of the newest frame the render world ran.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CameraAoStatus {
    /// The technique the frames run now (a switch to new settings shows once it is prepared).
    pub technique: String,
    /// Settings are being prepared off the render thread; meanwhile the AO texture keeps the
    /// last frame's AO.
    pub preparing: bool,
    /// GPU milliseconds of the AO passes of a recent frame (timestamp queries; `None` where
    /// the device has none, or before the first timings arrive).
    pub gpu_ms: Option<f64>,
    /// Compute and render pipelines aograph created for this camera since its AographAo was
    /// added.
    pub pipelines_created: u64,
    /// Frames whose AO aograph wrote.
    pub frames: u64,
    /// The last error, if any, until a frame runs the wanted settings (a frame with an error
    /// keeps the previous AO).
    pub error: Option<String>,
}

impl AographAoStatus {
    /// The status of `camera` (a main-world entity), if aograph has run on it.
    pub fn camera(&self, camera: Entity) -> Option<CameraAoStatus> {
        self.lock().get(&camera).cloned()
    }

    /// Every error recorded so far, one per camera at most (the newest).
    pub fn errors(&self) -> Vec<(Entity, String)> {
        self.lock()
            .iter()
            .filter_map(|(e, s)| s.error.clone().map(|m| (*e, m)))
            .collect()
    }

    /// Drops the status of every camera not in `cameras` (their AographAo is gone).
    pub(crate) fn retain(&self, cameras: &[Entity]) {
        self.lock().retain(|camera, _| cameras.contains(camera));
    }

    pub(crate) fn update(&self, camera: Entity, f: impl FnOnce(&mut CameraAoStatus)) {
        f(self.lock().entry(camera).or_default());
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, HashMap<Entity, CameraAoStatus>> {
        // A panic elsewhere while the map was held leaves it usable: it holds plain values.
        self.inner.lock().unwrap_or_else(|p| p.into_inner())
    }
}
