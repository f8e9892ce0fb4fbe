//! One camera's aograph state in bevy's render world: its `AmbientOcclusion`, the settings its
//! frames use, settings being prepared off the render thread, and the AO texture bevy's PBR
//! pass reads (group 0, binding 17).
//!
//! Invariants: the render thread never waits for a preparation (it takes the lock only with
//! `try_lock`, and a frame that finds it taken keeps the previous AO); settings are applied
//! only once prepared for the camera's current input layout or already seen with it, so a
//! switch never builds pipelines on the render thread after the first frame.

use std::sync::{Arc, Mutex, TryLockError};

use aograph_embed::{AmbientOcclusion, AoOutputFormat, EmbedResult, InputLayout};
use bevy::tasks::{AsyncComputeTaskPool, Task, block_on, poll_once};

use crate::component::AoSettings;

/// A preparation under way on bevy's async compute pool.
struct Pending {
    settings: Arc<AoSettings>,
    task: Task<EmbedResult<()>>,
}

/// What [`CameraAo::follow`] did this frame.
pub(crate) enum Switch {
    /// The frames use the wanted settings.
    Current,
    /// The wanted settings are being prepared; the previous ones render meanwhile.
    Preparing,
    /// The wanted settings were refused by the device now (the previous ones render on).
    Refused(String),
    /// The wanted settings were refused on an earlier frame.
    StillRefused,
}

pub(crate) struct CameraAo {
    pub(crate) ao: Arc<Mutex<AmbientOcclusion>>,
    /// The settings the frames use.
    applied: Arc<AoSettings>,
    /// Settings the device refused, not tried again until the component changes.
    refused: Option<Arc<AoSettings>>,
    pending: Option<Pending>,
    /// (settings, layout) pairs whose plan exists: switching to one builds nothing.
    ready: Vec<(Arc<AoSettings>, InputLayout)>,
    /// The input layout of the newest frame, once there was one.
    pub(crate) layout: Option<InputLayout>,
    /// The texture aograph writes and bevy's PBR pass reads.
    pub(crate) output: Option<(wgpu::Texture, wgpu::TextureView)>,
}

impl CameraAo {
    pub(crate) fn new(ao: AmbientOcclusion, settings: Arc<AoSettings>) -> Self {
        Self {
            ao: Arc::new(Mutex::new(ao)),
            applied: settings,
            refused: None,
            pending: None,
            ready: Vec::new(),
            layout: None,
            output: None,
        }
    }

    /// The technique the frames run now.
    pub(crate) fn technique(&self) -> &str {
        &self.applied.config.technique
    }

    /// Moves towards `wanted`: at once when it is what runs, was seen with this layout, or no
    /// frame has run yet; otherwise by preparing it on the async compute pool and applying it
    /// on a later frame, once prepared.
    pub(crate) fn follow(&mut self, wanted: &Arc<AoSettings>, output: AoOutputFormat) -> Switch {
        if Arc::ptr_eq(wanted, &self.applied) || **wanted == *self.applied {
            self.applied = wanted.clone();
            self.pending = None;
            return Switch::Current;
        }
        if let Some(refused) = &self.refused
            && Arc::ptr_eq(refused, wanted)
        {
            return Switch::StillRefused;
        }
        let Some(layout) = self.layout else {
            return self.apply(wanted);
        };
        if self.is_ready(wanted, layout) {
            return self.apply(wanted);
        }
        match self.pending.take() {
            Some(mut pending) if Arc::ptr_eq(&pending.settings, wanted) => {
                match block_on(poll_once(&mut pending.task)) {
                    None => {
                        self.pending = Some(pending);
                        Switch::Preparing
                    }
                    Some(Ok(())) => {
                        self.ready.push((wanted.clone(), layout));
                        self.apply(wanted)
                    }
                    Some(Err(e)) => {
                        self.refused = Some(wanted.clone());
                        Switch::Refused(e.to_string())
                    }
                }
            }
            // None pending, or one for settings no longer wanted (it finishes on the pool and
            // its plan is kept; nothing waits for it).
            _ => {
                let ao = self.ao.clone();
                let config = wanted.config.clone();
                let task = AsyncComputeTaskPool::get().spawn(async move {
                    let mut ao = ao.lock().unwrap_or_else(|p| p.into_inner());
                    ao.prepare(&config, layout, output)
                });
                self.pending = Some(Pending {
                    settings: wanted.clone(),
                    task,
                });
                Switch::Preparing
            }
        }
    }

    /// Records that the frames ran the applied settings with `layout` (its plan now exists).
    pub(crate) fn ran(&mut self, layout: InputLayout) {
        self.layout = Some(layout);
        if !self.is_ready(&self.applied.clone(), layout) {
            self.ready.push((self.applied.clone(), layout));
        }
    }

    fn is_ready(&self, settings: &Arc<AoSettings>, layout: InputLayout) -> bool {
        self.ready
            .iter()
            .any(|(s, l)| *l == layout && (Arc::ptr_eq(s, settings) || **s == **settings))
    }

    fn apply(&mut self, wanted: &Arc<AoSettings>) -> Switch {
        let mut ao = match self.ao.try_lock() {
            Ok(ao) => ao,
            // A preparation for other settings holds it: try again next frame.
            Err(TryLockError::WouldBlock) => return Switch::Preparing,
            Err(TryLockError::Poisoned(p)) => p.into_inner(),
        };
        match ao.set_config(&wanted.config) {
            Ok(()) => {
                drop(ao);
                self.applied = wanted.clone();
                self.pending = None;
                Switch::Current
            }
            Err(e) => {
                drop(ao);
                self.refused = Some(wanted.clone());
                Switch::Refused(e.to_string())
            }
        }
    }
}
