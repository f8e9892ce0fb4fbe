//! The ray-traced reference for the viewer's current view, traced progressively on a
//! background thread: the CPU g-buffer of the view (primary rays at pixel centres, checked
//! against the GPU g-buffer in tests/gbuffer_matches_cpu.rs), then passes of 8, 64 and 256
//! rays per pixel, each in bands of rows (`trace_reference_rows`: the same rays the whole
//! image would get), the picture refined band by band. A new job (the
//! camera moved, the size, radius or scene changed) cancels the one running between bands.
//!
//! With a GPU tracer (`[reference] tracer` resolving to "gpu": a hardware device), the bands
//! are traced by `ray_tracing::GpuReferenceTracer` against the scene's GPU BVH instead, the
//! same rays.
//!
//! After the last pass the worker traces the two ceilings of the bench (`trace_ceilings`:
//! the reference's own rays against (a) the g-buffer's surfaces and (b) the triangles the
//! frame sees) at the middle pass's ray count, and publishes their MAE and SSIM against the
//! middle pass's reference (same rays, so the noise cancels): the error display says how
//! much of a technique's error any screen-space technique would keep.
//!
//! Invariant: the published image belongs to the newest job (`generation`); a band of an
//! older job is never published. Rays run on a thread pool of their own, one thread fewer than
//! the machine has (at least one), so the render loop keeps a core.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Condvar, Mutex};

use aograph_graph::{GpuContext, ShaderLibrary};
use aograph_scene::{
    Camera, CpuGBuffer, ReferenceImage, ReferenceNormals, ReferenceParams, Scene, SceneRays,
    SurfaceBuffer, reference::ProgressMode,
};
use aograph_tracing::TracingError;
use aograph_tracing::gpu::{GpuReferenceTracer, GpuSceneBvh, HardwareSceneAs};

/// The device the reference is traced on, when it is the GPU.
#[derive(Clone)]
pub struct GpuReferenceDevice {
    pub gpu: Arc<GpuContext>,
    pub shaders: Arc<ShaderLibrary>,
    /// Trace on the hardware backend (acceleration structures, ray queries) rather than the
    /// compute BVH.
    pub hardware: bool,
}

/// Rays per pixel of each refinement pass.
pub const PASSES: [u32; 3] = [8, 64, 256];
/// Rows traced between checks for a newer job.
const BAND_ROWS: u32 = 8;

/// What to trace.
#[derive(Clone)]
pub struct ReferenceJob {
    pub scene: Arc<Scene>,
    pub camera: Camera,
    pub time: f32,
    pub width: u32,
    pub height: u32,
    pub radius: f32,
}

impl ReferenceJob {
    /// True when `other` needs a new trace (another view, size, radius or scene).
    pub fn differs(&self, other: &ReferenceJob) -> bool {
        !Arc::ptr_eq(&self.scene, &other.scene)
            || self.camera != other.camera
            || self.time != other.time
            || (self.width, self.height) != (other.width, other.height)
            || self.radius != other.radius
    }
}

/// The newest traced picture.
#[derive(Default)]
pub struct ReferenceState {
    pub generation: u64,
    /// Accessibility per pixel, -1 where nothing is traced yet.
    pub values: Vec<f32>,
    pub width: u32,
    pub height: u32,
    /// Rays per pixel of the newest complete pass (0 before the first).
    pub rays_complete: u32,
    /// Share of all passes' rays done, 0..1.
    pub progress: f32,
    /// Set when `values` changed since the viewer last took them.
    pub dirty: bool,
    /// The last error (a tracing failure), shown in the panel.
    pub error: Option<String>,
    /// The ceilings of this view, once traced after the last pass.
    pub ceilings: Option<CeilingSummary>,
}

/// The bench's ceilings for the viewer's view, scored against the reference traced with the
/// same rays.
#[derive(Clone, Copy, Debug)]
pub struct CeilingSummary {
    /// Rays per pixel they were traced with.
    pub rays: u32,
    /// (a) the g-buffer's surfaces: MAE and SSIM against the reference.
    pub gbuffer: (f64, f64),
    /// (b) the triangles the frame sees: MAE and SSIM against the reference.
    pub seen: (f64, f64),
}

struct Shared {
    device: Option<GpuReferenceDevice>,
    job: Mutex<Option<(u64, ReferenceJob)>>,
    wake: Condvar,
    generation: AtomicU64,
    state: Mutex<ReferenceState>,
    quit: std::sync::atomic::AtomicBool,
}

/// The worker thread and what it shares with the viewer.
pub struct ReferenceWorker {
    shared: Arc<Shared>,
    thread: Option<std::thread::JoinHandle<()>>,
    last: Option<ReferenceJob>,
}

impl ReferenceWorker {
    /// Starts the worker: tracing on `device` when given, else on the CPU.
    pub fn start(device: Option<GpuReferenceDevice>) -> Self {
        let shared = Arc::new(Shared {
            device,
            job: Mutex::new(None),
            wake: Condvar::new(),
            generation: AtomicU64::new(0),
            state: Mutex::new(ReferenceState::default()),
            quit: Default::default(),
        });
        let s = shared.clone();
        let thread = std::thread::Builder::new()
            .name("aograph reference".into())
            .spawn(move || run(&s))
            .ok();
        Self {
            shared,
            thread,
            last: None,
        }
    }

    /// Traces `job` unless it is the one being traced; returns whether a new trace started.
    pub fn request(&mut self, job: ReferenceJob) -> bool {
        if self.last.as_ref().is_some_and(|l| !l.differs(&job)) {
            return false;
        }
        let generation = self.shared.generation.fetch_add(1, Ordering::AcqRel) + 1;
        if let Ok(mut st) = self.shared.state.lock() {
            let n = (job.width * job.height) as usize;
            *st = ReferenceState {
                generation,
                values: vec![-1.0; n],
                width: job.width,
                height: job.height,
                dirty: true,
                ..Default::default()
            };
        }
        if let Ok(mut j) = self.shared.job.lock() {
            *j = Some((generation, job.clone()));
        }
        self.shared.wake.notify_one();
        self.last = Some(job);
        true
    }

    /// Runs `f` on the newest state (under its lock).
    pub fn with_state<R>(&self, f: impl FnOnce(&mut ReferenceState) -> R) -> Option<R> {
        self.shared.state.lock().ok().map(|mut s| f(&mut s))
    }
}

impl Drop for ReferenceWorker {
    fn drop(&mut self) {
        self.shared.quit.store(true, Ordering::Release);
        self.shared.generation.fetch_add(1, Ordering::AcqRel);
        self.shared.wake.notify_one();
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

fn run(shared: &Shared) {
    let threads = std::thread::available_parallelism()
        .map(|n| n.get().saturating_sub(1).max(1))
        .unwrap_or(1);
    let Ok(pool) = rayon::ThreadPoolBuilder::new().num_threads(threads).build() else {
        return;
    };
    loop {
        let (generation, job) = {
            let Ok(mut j) = shared.job.lock() else { return };
            loop {
                if shared.quit.load(Ordering::Acquire) {
                    return;
                }
                if let Some(job) = j.take() {
                    break job;
                }
                j = match shared.wake.wait(j) {
                    Ok(j) => j,
                    Err(_) => return,
                };
            }
        };
        let current = || shared.generation.load(Ordering::Acquire) == generation;
        pool.install(|| trace_job(shared, generation, &job, &current));
    }
}

/// Traces `job` pass by pass and band by band, publishing as it goes, until done or stale.
fn trace_job(shared: &Shared, generation: u64, job: &ReferenceJob, current: &dyn Fn() -> bool) {
    let gbuffer = CpuGBuffer::trace(&job.scene, &job.camera, job.width, job.height, job.time);
    if !current() {
        return;
    }
    let surfaces = gbuffer.surfaces(ReferenceNormals::Geometric);
    let tracer = match BandTracer::new(shared.device.as_ref(), job) {
        Ok(t) => t,
        Err(e) => {
            if let Ok(mut st) = shared.state.lock() {
                st.error = Some(e.to_string());
            }
            return;
        }
    };
    let total: u64 = PASSES.iter().map(|&r| r as u64).sum::<u64>() * job.height as u64;
    let mut done: u64 = 0;
    // The middle pass's image, which the ceilings are scored against.
    let mut middle = Vec::new();
    for &rays in &PASSES {
        let params = ReferenceParams {
            radius: job.radius,
            rays_per_pixel: rays,
            progress: ProgressMode::Never,
            ..Default::default()
        };
        let mut y0 = 0;
        while y0 < job.height {
            if !current() {
                return;
            }
            let rows = BAND_ROWS.min(job.height - y0);
            let traced = tracer.trace_rows(&surfaces, &params, y0..y0 + rows);
            let Ok(mut st) = shared.state.lock() else {
                return;
            };
            if st.generation != generation {
                return;
            }
            match traced {
                Ok(image) => {
                    let start = (y0 * job.width) as usize;
                    st.values[start..start + image.accessibility.len()]
                        .copy_from_slice(&image.accessibility);
                    st.dirty = true;
                }
                Err(e) => {
                    st.error = Some(e.to_string());
                    return;
                }
            }
            done += rays as u64 * rows as u64;
            st.progress = done as f32 / total as f32;
            y0 += rows;
        }
        if let Ok(mut st) = shared.state.lock() {
            if st.generation == generation {
                st.rays_complete = rays;
                if rays == CEILING_RAYS {
                    middle = st.values.clone();
                }
            }
        }
    }
    if !current() || middle.is_empty() {
        return;
    }
    let summary = ceilings(job, &surfaces, &middle);
    if let Ok(mut st) = shared.state.lock() {
        if st.generation == generation {
            match summary {
                Ok(c) => st.ceilings = Some(c),
                Err(e) => st.error = Some(e),
            }
        }
    }
}

/// Rays per pixel of the ceilings: the middle pass's, so the four traces cost about one
/// last pass.
const CEILING_RAYS: u32 = PASSES[1];

/// Traces the ceilings of `job` with the reference's rays at [`CEILING_RAYS`] and scores them
/// against `reference`, that pass's image.
fn ceilings(
    job: &ReferenceJob,
    surfaces: &SurfaceBuffer,
    reference: &[f32],
) -> Result<CeilingSummary, String> {
    let settings = aograph_renderer::ReferenceSettings::new(job.radius, CEILING_RAYS);
    let c = aograph_renderer::frame_reference::trace_ceilings(
        &job.scene,
        &job.camera,
        job.time,
        surfaces,
        &settings,
    )
    .map_err(|e| e.to_string())?;
    // Sky pixels (no surface) are left out of the scores, as the bench leaves them out.
    let depth: Vec<f32> = surfaces.valid.iter().map(|&v| v as u32 as f32).collect();
    let score = |image: &[f32]| {
        aograph_bench::metrics::compare(
            image,
            reference,
            &depth,
            job.width,
            job.height,
            &aograph_bench::metrics::MetricOptions::default(),
        )
        .map(|m| (m.mae, m.ssim))
        .map_err(|e| e.to_string())
    };
    Ok(CeilingSummary {
        rays: CEILING_RAYS,
        gbuffer: score(&c.gbuffer_surfaces.accessibility)?,
        seen: score(&c.seen_triangles.accessibility)?,
    })
}

/// The CPU BVH or the GPU tracer and its scene (compute BVH or acceleration structures), for
/// one job.
enum BandTracer {
    /// The scene as a two-level BVH: shared meshes are not flattened.
    Cpu(SceneRays),
    Gpu(GpuReferenceTracer, GpuSceneBvh),
    Hardware(GpuReferenceTracer, HardwareSceneAs),
}

impl BandTracer {
    fn new(device: Option<&GpuReferenceDevice>, job: &ReferenceJob) -> Result<Self, TracingError> {
        let cpu = || BandTracer::Cpu(SceneRays::new(&job.scene, job.time));
        let Some(d) = device else {
            return Ok(cpu());
        };
        if d.hardware {
            let accel = HardwareSceneAs::build(&d.gpu, &job.scene, job.time)?;
            return Ok(BandTracer::Hardware(
                GpuReferenceTracer::new(d.gpu.clone(), &d.shaders)?,
                accel,
            ));
        }
        match GpuSceneBvh::new(d.gpu.clone(), &job.scene, job.time) {
            Ok(bvh) => Ok(BandTracer::Gpu(
                GpuReferenceTracer::new(d.gpu.clone(), &d.shaders)?,
                bvh,
            )),
            // A scene over the device's limits is traced on the CPU instead.
            Err(TracingError::BvhTooLarge { .. } | TracingError::BvhTooDeep { .. }) => Ok(cpu()),
            Err(e) => Err(e),
        }
    }

    fn trace_rows(
        &self,
        surfaces: &SurfaceBuffer,
        params: &ReferenceParams,
        rows: std::ops::Range<u32>,
    ) -> Result<ReferenceImage, TracingError> {
        match self {
            BandTracer::Cpu(bvh) => Ok(aograph_scene::trace_reference_rows(
                bvh, surfaces, params, rows,
            )?),
            BandTracer::Gpu(tracer, bvh) => tracer.trace_rows(bvh, surfaces, params, rows),
            BandTracer::Hardware(tracer, accel) => tracer.trace_rows(accel, surfaces, params, rows),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use aograph_scene::TriangleBvh;

    #[test]
    fn an_open_corners_seen_triangle_ceiling_is_its_reference_and_a_wrong_size_is_an_error() {
        // The corner: every occluder is seen, so (b) traces the reference's rays against the
        // reference's own occluders and scores exactly 0 MAE and SSIM 1 (same rays, so no
        // noise: tests/ceilings.rs checks the images pixel by pixel).
        let scene = Arc::new(aograph_scene::procedural_scene("corner").unwrap());
        let job = ReferenceJob {
            scene: scene.clone(),
            camera: scene.camera,
            time: 0.0,
            width: 33,
            height: 21,
            radius: 1.0,
        };
        let surfaces = CpuGBuffer::trace(&scene, &job.camera, job.width, job.height, 0.0)
            .surfaces(ReferenceNormals::Geometric);
        let params = ReferenceParams {
            radius: job.radius,
            rays_per_pixel: CEILING_RAYS,
            progress: ProgressMode::Never,
            ..Default::default()
        };
        let reference = aograph_scene::trace_reference(
            &TriangleBvh::new(&scene.world_triangles(0.0)),
            &surfaces,
            &params,
        )
        .unwrap();
        let c = ceilings(&job, &surfaces, &reference.accessibility).unwrap();
        assert_eq!(c.rays, CEILING_RAYS);
        assert_eq!(c.seen.0, 0.0, "(b) MAE");
        assert!((c.seen.1 - 1.0).abs() < 1e-9, "(b) SSIM {}", c.seen.1);
        // A reference of another view's size is an error the panel shows, not a panic.
        assert!(ceilings(&job, &surfaces, &reference.accessibility[1..]).is_err());
    }
}
