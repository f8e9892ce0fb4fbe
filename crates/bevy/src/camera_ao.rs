//! One camera's aograph state in bevy's render world: its `AmbientOcclusion`, the settings its
//! frames use, settings being prepared off the render thread, and the AO texture bevy's PBR
//! pass reads (group 0, binding 17).
//!
//! Invariants: the render thread never waits for a preparation (it takes the lock only with
//! `try_lock`; a frame that finds it taken keeps the previous frame's AO in the texture);
//! settings are applied only once aograph-embed holds their plan for the camera's current input
//! layout (`is_prepared`), or before the camera's first frame, so a switch builds no pipeline
//! on the render thread after the first frame.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::{Arc, Mutex, MutexGuard, TryLockError};

use aograph_embed::{AmbientOcclusion, AoOutputFormat, InputLayout};
use bevy::tasks::{AsyncComputeTaskPool, Task, block_on, poll_once};

use crate::component::AoSettings;
use crate::error::AographBevyError;

/// A preparation under way on bevy's async compute pool.
struct Pending {
    settings: Arc<AoSettings>,
    layout: InputLayout,
    task: Task<Result<(), AographBevyError>>,
}

/// What [`CameraAo::follow`] did this frame.
pub(crate) enum Switch {
    /// The frames use the wanted settings.
    Current,
    /// The wanted settings are being prepared; the texture keeps the previous settings' AO.
    Preparing,
    /// The wanted settings were refused now (the previous ones render on).
    Refused(AographBevyError),
    /// The wanted settings were refused on an earlier frame.
    StillRefused,
}

pub(crate) struct CameraAo {
    ao: Arc<Mutex<AmbientOcclusion>>,
    /// The settings the frames use.
    applied: Arc<AoSettings>,
    /// Settings refused, not tried again until the component changes.
    refused: Option<Arc<AoSettings>>,
    pending: Option<Pending>,
    /// The input layout of the newest frame, once there was one.
    layout: Option<InputLayout>,
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
            layout: None,
            output: None,
        }
    }

    /// The technique the frames run now.
    pub(crate) fn technique(&self) -> &str {
        &self.applied.config.technique
    }

    /// Whether settings the device refused are wanted (the frames run older ones).
    pub(crate) fn refusing(&self) -> bool {
        self.refused.is_some()
    }

    /// The `AmbientOcclusion` for this frame, unless a preparation holds it.
    pub(crate) fn try_ao(&self) -> Option<MutexGuard<'_, AmbientOcclusion>> {
        match self.ao.try_lock() {
            Ok(ao) => Some(ao),
            Err(TryLockError::WouldBlock) => None,
            // A preparation panicked holding it: `follow` has recorded that; the instance's
            // state is whole (`prepare` builds a plan or returns an error), so frames go on.
            Err(TryLockError::Poisoned(p)) => Some(p.into_inner()),
        }
    }

    /// Records that the frames ran with `layout`.
    pub(crate) fn ran(&mut self, layout: InputLayout) {
        self.layout = Some(layout);
    }

    /// Moves towards `wanted`: at once when it is what runs, when its plan for the current
    /// layout exists, or before the first frame; otherwise by preparing it on the async
    /// compute pool and applying it on a later frame, once prepared.
    pub(crate) fn follow(&mut self, wanted: &Arc<AoSettings>, output: AoOutputFormat) -> Switch {
        if Arc::ptr_eq(wanted, &self.applied) || **wanted == *self.applied {
            self.applied = wanted.clone();
            self.refused = None;
            self.cancel_pending();
            return Switch::Current;
        }
        if self
            .refused
            .as_ref()
            .is_some_and(|r| Arc::ptr_eq(r, wanted))
        {
            return Switch::StillRefused;
        }
        let Some(layout) = self.layout else {
            return self.apply(wanted);
        };
        match self.pending.take() {
            Some(mut pending)
                if Arc::ptr_eq(&pending.settings, wanted) && pending.layout == layout =>
            {
                match block_on(poll_once(&mut pending.task)) {
                    None => {
                        self.pending = Some(pending);
                        Switch::Preparing
                    }
                    Some(Ok(())) => self.apply(wanted),
                    Some(Err(e)) => {
                        self.refused = Some(wanted.clone());
                        Switch::Refused(e)
                    }
                }
            }
            superseded => {
                if let Some(old) = superseded {
                    // It finishes on the pool (its plan is kept); nothing waits for it.
                    old.task.detach();
                }
                let ready = self
                    .try_ao()
                    .is_some_and(|ao| ao.is_prepared(&wanted.config, layout, output));
                if ready {
                    return self.apply(wanted);
                }
                let ao = self.ao.clone();
                let config = wanted.config.clone();
                let task = AsyncComputeTaskPool::get().spawn(async move {
                    let mut ao = ao.lock().unwrap_or_else(|p| p.into_inner());
                    catch_unwind(AssertUnwindSafe(|| ao.prepare(&config, layout, output)))
                        .map_err(|panic| {
                            let message = panic
                                .downcast_ref::<&str>()
                                .map(|s| s.to_string())
                                .or_else(|| panic.downcast_ref::<String>().cloned())
                                .unwrap_or_default();
                            AographBevyError::PreparePanicked(message)
                        })?
                        .map_err(AographBevyError::from)
                });
                self.pending = Some(Pending {
                    settings: wanted.clone(),
                    layout,
                    task,
                });
                Switch::Preparing
            }
        }
    }

    fn cancel_pending(&mut self) {
        if let Some(old) = self.pending.take() {
            old.task.detach();
        }
    }

    fn apply(&mut self, wanted: &Arc<AoSettings>) -> Switch {
        let Some(mut ao) = self.try_ao() else {
            // A preparation for other settings holds it: try again next frame.
            return Switch::Preparing;
        };
        let result = ao.set_config(&wanted.config);
        drop(ao);
        match result {
            Ok(()) => {
                self.applied = wanted.clone();
                self.refused = None;
                self.cancel_pending();
                Switch::Current
            }
            Err(e) => {
                self.refused = Some(wanted.clone());
                Switch::Refused(e.into())
            }
        }
    }
}
