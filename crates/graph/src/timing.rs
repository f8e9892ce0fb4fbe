//! Per-pass timing without stalls: a ring of pending frames, each with its own query set,
//! resolve buffer and read-back buffer (wgpu-profiler's pattern, written here because the
//! executor needs results tagged with their frame, no allocation per frame, and a CPU-time
//! mode behind the same table; see [`TimingMode`]).
//!
//! A frame takes a free slot, writes a timestamp before and after each pass, resolves them and
//! starts mapping the read-back buffer after submit; the map callback only sets an atomic. A
//! later frame's non-blocking poll (or the application's own) runs the callback, and
//! [`TimestampRing::harvest`] then copies the finished frame's milliseconds into the newest
//! result. When every slot is still pending the frame is not timed (counted as dropped) rather
//! than waiting: newer frames are dropped first, so the oldest keep arriving.
//!
//! Invariant: a slot's read-back buffer is never mapped, nor has a map pending, while a frame
//! copies into it: a slot is reused only once its map completed (or failed) and it was
//! unmapped. The map callback may run on whichever thread polls the device next, so the state
//! is an atomic tagged with the slot's generation, and a late callback of an older map can never
//! overwrite a newer one.

use std::fmt::Write;
use std::sync::Arc;
use std::sync::atomic::{AtomicU32, Ordering};

use crate::compile::CompiledGraph;
use crate::error::{GraphError, GraphResult};

/// Where the milliseconds come from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TimingSource {
    /// GPU timestamp queries (on a software device these are still CPU time).
    GpuTimestamps,
    /// CPU wall time around a per-pass submit-and-wait.
    CpuWall,
}

/// How the executor times passes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TimingMode {
    /// No timing: no queries, no waits.
    Off,
    /// GPU timestamps read back a few frames late, never waiting (the default where the
    /// device has timestamp queries).
    GpuTimestamps,
    /// CPU wall time per pass: every pass is submitted and waited for. It stalls by design,
    /// for benchmarks on devices without timestamp queries; never use it in a real-time loop.
    CpuWall,
}

/// The number of a frame an executor ran, counted from 0; timings carry the frame they
/// measured.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct FrameId(pub u64);

impl std::fmt::Display for FrameId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "frame {}", self.0)
    }
}

/// Milliseconds per executed pass of one frame, in execution order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PassTimings {
    /// The frame measured (`None` before any frame's timings arrived).
    pub frame: Option<FrameId>,
    /// Where the milliseconds came from (`None` before any frame's timings arrived).
    pub source: Option<TimingSource>,
    /// (pass name, milliseconds) for each kept pass, in execution order.
    pub passes: Vec<(String, f64)>,
}

impl PassTimings {
    /// Sum of the passes' milliseconds: the passes' own time, without the gaps between them.
    pub fn total_ms(&self) -> f64 {
        self.passes.iter().map(|(_, ms)| ms).sum()
    }
    /// Milliseconds of the pass named `pass` (the first, if several share the name).
    pub fn get(&self, pass: &str) -> Option<f64> {
        self.passes
            .iter()
            .find(|(n, _)| n == pass)
            .map(|(_, ms)| *ms)
    }
    /// A two-column table: pass, milliseconds.
    pub fn table(&self) -> String {
        let mut s = String::new();
        let width = self
            .passes
            .iter()
            .map(|(n, _)| n.len())
            .max()
            .unwrap_or(4)
            .max(4);
        let _ = writeln!(s, "{:<width$}  {:>10}", "pass", "ms");
        for (n, ms) in &self.passes {
            let _ = writeln!(s, "{n:<width$}  {ms:>10.4}");
        }
        let _ = writeln!(s, "{:<width$}  {:>10.4}", "total", self.total_ms());
        s
    }
    /// Fills this table with `ms` for `plan`'s passes measured in `frame`. The pass names are
    /// rewritten only when the plan's pass list differs, so steady-state frames allocate
    /// nothing.
    pub(crate) fn fill(
        &mut self,
        frame: FrameId,
        source: TimingSource,
        plan: &CompiledGraph,
        ms: &[f64],
    ) {
        let same = self.passes.len() == plan.order.len()
            && self
                .passes
                .iter()
                .zip(&plan.order)
                .all(|((n, _), p)| *n == plan.decl.passes[p.0].name);
        if !same {
            self.passes.clear();
            self.passes.extend(
                plan.order
                    .iter()
                    .map(|p| (plan.decl.passes[p.0].name.clone(), 0.0)),
            );
        }
        for (slot, v) in self.passes.iter_mut().zip(ms) {
            slot.1 = *v;
        }
        self.frame = Some(frame);
        self.source = Some(source);
    }
}

const SLOT_IDLE: u32 = 0;
const SLOT_PENDING: u32 = 1;
const SLOT_DONE: u32 = 2;
const SLOT_FAILED: u32 = 3;
/// Blocking waits for a map callback that another thread's poll is running.
const MAP_WAIT_POLLS: u32 = 1000;

/// One pending frame's queries and buffers.
struct Slot {
    set: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    readback: wgpu::Buffer,
    /// Timestamps the set holds (two per pass).
    capacity: u32,
    /// generation << 2 | one of the `SLOT_*` states, set by the map callback.
    state: Arc<AtomicU32>,
    generation: u32,
    /// Recorded but not yet submitted (between `begin` and `submitted`).
    recording: bool,
    frame: FrameId,
    plan: Option<Arc<CompiledGraph>>,
    passes: u32,
}

impl Slot {
    fn new(device: &wgpu::Device, passes: u32) -> Self {
        let capacity = (passes * 2).max(2);
        let bytes = capacity as u64 * 8;
        Self {
            set: device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("aograph timestamps"),
                ty: wgpu::QueryType::Timestamp,
                count: capacity,
            }),
            resolve: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("timestamp resolve"),
                size: bytes,
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            }),
            readback: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("timestamp readback"),
                size: bytes,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            capacity,
            state: Arc::default(),
            generation: 0,
            recording: false,
            frame: FrameId(0),
            plan: None,
            passes: 0,
        }
    }
    /// This slot's state for its current generation (`SLOT_IDLE` when no map is out).
    fn state(&self) -> u32 {
        let v = self.state.load(Ordering::Acquire);
        if v >> 2 == self.generation {
            v & 3
        } else {
            SLOT_IDLE
        }
    }
    fn is_free(&self) -> bool {
        !self.recording && self.state() == SLOT_IDLE
    }
}

/// The ring of pending frames and the newest finished result.
pub(crate) struct TimestampRing {
    slots: Vec<Slot>,
    pending_frames: usize,
    /// The slot to try first for the next frame.
    next: usize,
    period_ns: f64,
    ms: Vec<f64>,
    latest: PassTimings,
    dropped: u64,
}

impl TimestampRing {
    /// Frames that may wait for their timings at once by default.
    pub const DEFAULT_PENDING_FRAMES: usize = 3;

    pub fn new(queue: &wgpu::Queue, pending_frames: usize) -> Self {
        Self {
            slots: Vec::new(),
            pending_frames: pending_frames.max(1),
            next: 0,
            period_ns: queue.get_timestamp_period() as f64,
            ms: Vec::new(),
            latest: PassTimings::default(),
            dropped: 0,
        }
    }

    /// A free slot for a frame of `passes` passes, created or grown as needed; `None` when
    /// every slot is pending (the frame goes untimed and is counted as dropped). Slots are
    /// taken in turn, from the one after the last taken: reusing the read-back buffer that was
    /// just unmapped costs more (on lavapipe, ~0.1 ms a frame) than rotating through the ring.
    pub fn begin(&mut self, device: &wgpu::Device, passes: u32) -> Option<usize> {
        let n = self.pending_frames;
        let i = (0..n)
            .map(|k| (self.next + k) % n)
            .find(|&i| self.slots.get(i).is_none_or(Slot::is_free));
        let Some(i) = i else {
            self.dropped += 1;
            return None;
        };
        while self.slots.len() <= i {
            self.slots.push(Slot::new(device, passes));
        }
        if self.slots[i].capacity < passes * 2 {
            self.slots[i] = Slot::new(device, passes);
        }
        self.slots[i].recording = true;
        self.next = (i + 1) % n;
        Some(i)
    }
    pub fn query_set(&self, slot: usize) -> &wgpu::QuerySet {
        &self.slots[slot].set
    }
    /// After the last pass: copy the timestamps where the CPU can map them.
    pub fn resolve(&mut self, encoder: &mut wgpu::CommandEncoder, slot: usize, passes: u32) {
        let s = &self.slots[slot];
        let n = passes * 2;
        if n > 0 {
            encoder.resolve_query_set(&s.set, 0..n, &s.resolve, 0);
            encoder.copy_buffer_to_buffer(&s.resolve, 0, &s.readback, 0, n as u64 * 8);
        }
    }
    /// After submit: start mapping the slot's read-back buffer for `frame` of `plan`.
    pub fn submitted(&mut self, slot: usize, frame: FrameId, plan: &Arc<CompiledGraph>) {
        let s = &mut self.slots[slot];
        s.recording = false;
        s.frame = frame;
        s.passes = plan.order.len() as u32;
        if s.plan.as_ref().is_none_or(|p| !Arc::ptr_eq(p, plan)) {
            s.plan = Some(plan.clone());
        }
        s.generation = (s.generation + 1) & (u32::MAX >> 2);
        let tag = s.generation << 2;
        let flag = s.state.clone();
        flag.store(tag | SLOT_PENDING, Ordering::Release);
        if s.passes == 0 {
            flag.store(tag | SLOT_DONE, Ordering::Release);
            return;
        }
        // Only this generation's callback may change the state.
        s.readback
            .slice(..s.passes as u64 * 16)
            .map_async(wgpu::MapMode::Read, move |r| {
                let done = tag | if r.is_ok() { SLOT_DONE } else { SLOT_FAILED };
                let _ = flag.compare_exchange(
                    tag | SLOT_PENDING,
                    done,
                    Ordering::AcqRel,
                    Ordering::Acquire,
                );
            });
    }
    /// A frame that began but was not submitted (an error while recording): its slot is free.
    pub fn abandon(&mut self, slot: usize) {
        if let Some(s) = self.slots.get_mut(slot) {
            s.recording = false;
        }
    }
    /// Copies every finished frame, oldest first, into the newest result and frees its slot.
    /// Never polls or waits. Returns whether a new result arrived.
    pub fn harvest(&mut self) -> GraphResult<bool> {
        let mut arrived = false;
        loop {
            let next = self
                .slots
                .iter()
                .enumerate()
                .filter(|(_, s)| !s.recording && matches!(s.state(), SLOT_DONE | SLOT_FAILED))
                .min_by_key(|(_, s)| s.frame)
                .map(|(i, _)| i);
            let Some(i) = next else {
                return Ok(arrived);
            };
            let s = &mut self.slots[i];
            let ok = s.state() == SLOT_DONE;
            if ok && s.passes > 0 {
                let view = s
                    .readback
                    .slice(..s.passes as u64 * 16)
                    .get_mapped_range()
                    .map_err(|e| GraphError::ReadbackFailed {
                        during: "reading timestamp queries",
                        message: e.to_string(),
                    })?;
                let stamp = |k: usize| {
                    view.get(k * 8..k * 8 + 8)
                        .and_then(|b| b.try_into().ok())
                        .map(u64::from_le_bytes)
                        .unwrap_or(0)
                };
                self.ms.clear();
                for p in 0..s.passes as usize {
                    let (a, b) = (stamp(2 * p), stamp(2 * p + 1));
                    self.ms
                        .push(b.saturating_sub(a) as f64 * self.period_ns / 1.0e6);
                }
            }
            if ok && s.passes > 0 {
                s.readback.unmap();
            }
            s.state.store(SLOT_IDLE, Ordering::Release);
            s.generation = (s.generation + 1) & (u32::MAX >> 2);
            let newer = self.latest.frame.is_none_or(|f| f < s.frame);
            if let (true, true, Some(plan)) = (ok, newer, &s.plan) {
                let ms = if s.passes > 0 { &self.ms[..] } else { &[] };
                self.latest
                    .fill(s.frame, TimingSource::GpuTimestamps, plan, ms);
                arrived = true;
            }
        }
    }
    /// True while some frame up to `frame` still waits for its timestamps.
    fn pending_up_to(&self, frame: FrameId) -> bool {
        self.slots
            .iter()
            .any(|s| !s.recording && s.state() == SLOT_PENDING && s.frame <= frame)
    }
    /// Blocks until no frame up to `frame` is pending, then harvests. Explicitly a wait:
    /// for benchmarks and one-shot tools, never for a real-time loop.
    pub fn wait_for(&mut self, device: &wgpu::Device, frame: FrameId) -> GraphResult<()> {
        for _ in 0..MAP_WAIT_POLLS {
            self.harvest()?;
            if !self.pending_up_to(frame) {
                return Ok(());
            }
            device
                .poll(wgpu::PollType::wait_indefinitely())
                .map_err(|e| GraphError::ReadbackFailed {
                    during: "reading timestamp queries",
                    message: e.to_string(),
                })?;
            // The callback may be running on another thread that polled first.
            std::thread::yield_now();
        }
        // A map that never completed: cancel it so the slot can be reused.
        for s in &mut self.slots {
            if !s.recording && s.state() == SLOT_PENDING && s.frame <= frame {
                s.readback.unmap();
                s.generation = (s.generation + 1) & (u32::MAX >> 2);
                s.state.store(SLOT_IDLE, Ordering::Release);
            }
        }
        self.harvest().map(|_| ())
    }
    /// The newest finished frame's timings.
    pub fn latest(&self) -> &PassTimings {
        &self.latest
    }
    /// Records a frame measured on the CPU (CPU-wall mode).
    pub fn record_cpu(&mut self, frame: FrameId, plan: &CompiledGraph, ms: &[f64]) {
        self.latest.fill(frame, TimingSource::CpuWall, plan, ms);
    }
    /// Frames left untimed because every slot was pending.
    pub fn dropped(&self) -> u64 {
        self.dropped
    }
    /// Frames whose timings are still on their way.
    pub fn pending(&self) -> usize {
        self.slots
            .iter()
            .filter(|s| !s.recording && s.state() == SLOT_PENDING)
            .count()
    }
}
