//! Per-pass GPU timing: a timestamp before and after each pass, resolved into a buffer and
//! read back one frame later (so reading never stalls the frame that wrote it).
//!
//! Where the device has no timestamp queries the executor submits pass by pass and measures
//! CPU wall time instead; [`TimingSource`] says which a table holds.
//!
//! Invariant: the readback buffer is never mapped (nor has a map pending) when a frame copies
//! into it. The map callback runs inside whichever thread polls the device next, which with a
//! device shared between threads may be another thread, after this one's poll returned; so
//! [`TimestampQueries::collect`] waits for the callback of *its* map (tagged with a
//! generation) and cancels a map that never completed instead of leaving it in flight.

use std::fmt::Write;
use std::sync::Arc;
use std::sync::atomic::{AtomicU32, Ordering};

use crate::error::{GraphError, GraphResult};

/// Where the milliseconds come from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TimingSource {
    /// GPU timestamp queries (on a software device these are still CPU time).
    GpuTimestamps,
    /// CPU wall time around a per-pass submit-and-wait.
    CpuWall,
}

/// Milliseconds per executed pass, in execution order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PassTimings {
    pub source: Option<TimingSource>,
    pub passes: Vec<(String, f64)>,
}

impl PassTimings {
    pub fn total_ms(&self) -> f64 {
        self.passes.iter().map(|(_, ms)| ms).sum()
    }
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
}

/// Timestamp query set and buffers, sized for the largest plan seen.
pub(crate) struct TimestampQueries {
    set: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    readback: wgpu::Buffer,
    capacity: u32,
    /// Pass count of the frame whose timestamps are in flight.
    pending: Option<u32>,
    /// Map state of `readback`: generation << 2 | one of the `MAP_*` states.
    map: Arc<AtomicU32>,
    generation: u32,
    period_ns: f32,
}

const MAP_IDLE: u32 = 0;
const MAP_PENDING: u32 = 1;
const MAP_DONE: u32 = 2;
const MAP_FAILED: u32 = 3;
/// Polls that wait for a map callback running on another thread before the map is cancelled.
const MAP_WAIT_POLLS: u32 = 1000;

impl TimestampQueries {
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, passes: u32) -> Self {
        let capacity = (passes * 2).max(2);
        let bytes = capacity as u64 * 8;
        let set = device.create_query_set(&wgpu::QuerySetDescriptor {
            label: Some("aograph timestamps"),
            ty: wgpu::QueryType::Timestamp,
            count: capacity,
        });
        let resolve = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("timestamp resolve"),
            size: bytes,
            usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let readback = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("timestamp readback"),
            size: bytes,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        Self {
            set,
            resolve,
            readback,
            capacity,
            pending: None,
            map: Arc::default(),
            generation: 0,
            period_ns: queue.get_timestamp_period(),
        }
    }
    pub fn fits(&self, passes: u32) -> bool {
        passes * 2 <= self.capacity
    }
    pub fn set(&self) -> &wgpu::QuerySet {
        &self.set
    }
    /// After the last pass: copy the timestamps where the CPU can map them.
    pub fn resolve(&mut self, encoder: &mut wgpu::CommandEncoder, passes: u32) {
        let n = passes * 2;
        if n == 0 {
            return;
        }
        encoder.resolve_query_set(&self.set, 0..n, &self.resolve, 0);
        encoder.copy_buffer_to_buffer(&self.resolve, 0, &self.readback, 0, n as u64 * 8);
        self.pending = Some(passes);
    }
    /// After submit: start mapping the readback buffer.
    pub fn start_map(&mut self) {
        if self.pending.is_none() {
            return;
        }
        self.generation = (self.generation + 1) & (u32::MAX >> 2);
        let tag = self.generation << 2;
        let flag = self.map.clone();
        flag.store(tag | MAP_PENDING, Ordering::Release);
        // Only this generation's map may change the state (a cancelled map's late callback
        // must not overwrite the next one's).
        self.readback
            .slice(..)
            .map_async(wgpu::MapMode::Read, move |r| {
                let done = tag | if r.is_ok() { MAP_DONE } else { MAP_FAILED };
                let _ = flag.compare_exchange(
                    tag | MAP_PENDING,
                    done,
                    Ordering::AcqRel,
                    Ordering::Acquire,
                );
            });
    }
    fn map_state(&self) -> u32 {
        let v = self.map.load(Ordering::Acquire);
        if v >> 2 == self.generation {
            v & 3
        } else {
            MAP_IDLE
        }
    }
    /// Waits for the in-flight timestamps and writes per-pass milliseconds into `out`.
    pub fn collect(&mut self, device: &wgpu::Device, out: &mut [f64]) -> GraphResult<bool> {
        let Some(passes) = self.pending.take() else {
            return Ok(false);
        };
        // The callback may be running on another thread that polled first: wait for it.
        for _ in 0..MAP_WAIT_POLLS {
            device
                .poll(wgpu::PollType::wait_indefinitely())
                .map_err(|e| GraphError::Gpu(e.to_string()))?;
            if self.map_state() != MAP_PENDING {
                break;
            }
            std::thread::yield_now();
        }
        match self.map_state() {
            MAP_DONE => {}
            MAP_PENDING => {
                // Never completed: cancel it so the next frame may copy into the buffer.
                self.readback.unmap();
                self.map.store(MAP_IDLE, Ordering::Release);
                return Ok(false);
            }
            _ => return Ok(false),
        }
        {
            let view = self
                .readback
                .slice(..passes as u64 * 16)
                .get_mapped_range()
                .map_err(|e| GraphError::Gpu(e.to_string()))?;
            let stamp = |i: usize| {
                view.get(i * 8..i * 8 + 8)
                    .and_then(|b| b.try_into().ok())
                    .map(u64::from_le_bytes)
                    .unwrap_or(0)
            };
            for (i, ms) in out.iter_mut().enumerate().take(passes as usize) {
                let (a, b) = (stamp(2 * i), stamp(2 * i + 1));
                *ms = b.saturating_sub(a) as f64 * self.period_ns as f64 / 1.0e6;
            }
        }
        self.readback.unmap();
        self.map.store(MAP_IDLE, Ordering::Release);
        Ok(true)
    }
}
