//! The reference of a rendered frame: the ray-traced accessibility every technique in a run is
//! scored against.
//!
//! The reference starts its rays from the GPU g-buffer's own points, so it sees the surfaces
//! the techniques see (the g-buffer is checked against the CPU's primary hits in
//! `tests/gbuffer_matches_cpu.rs`). Its hemisphere is a stated choice ([`ReferenceNormals`]):
//! the geometric normal by default, or the shading normal. That choice must not depend on the
//! technique being scored (mssao reads face normals, ssao interpolated ones), so the surfaces
//! always come from a g-buffer of their own: a `none` renderer drawing the same scene at the
//! same time, from the same camera, at the same size, writing positions and the chosen normals.
//! Invariant: for one frame and one [`ReferenceSettings`], every technique gets the same
//! reference, bit for bit (and the disk cache serves it once traced; see
//! `aograph_tracing::CacheKey` for what the key covers).

use std::path::PathBuf;
use std::sync::Arc;

use aograph_graph::{Extent, GpuContext, ShaderLibrary};
use aograph_scene::reference::ProgressMode;
use aograph_scene::{
    Camera, ReferenceImage, ReferenceMode, ReferenceNormals, ReferenceParams, ReferenceTracer,
    Scene, SurfaceBuffer, TriangleBvh,
};
use aograph_tracing::TracingError;
use aograph_tracing::gpu::{
    GPU_MAX_RAYS_PER_PIXEL, GpuReferenceTracer, GpuSceneBvh, HardwareSceneAs,
};
use aograph_tracing::{CacheKey, ReferenceCache};
use glam::Vec3;

use crate::error::RenderResult;
use crate::frame_graph::FrameOutputs;
use crate::renderer::Renderer;

/// How a reference is traced.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReferenceSettings {
    /// The shared world-space radius R.
    pub radius: f32,
    /// Rays per pixel.
    pub rays: u32,
    /// Binary visibility (AO) or distance-weighted obscurance.
    pub mode: ReferenceMode,
    /// Which normal orients each pixel's hemisphere.
    pub normals: ReferenceNormals,
    /// CPU, GPU compute or GPU hardware tracer (`[reference] tracer`; `ReferenceTracer::resolve`).
    pub tracer: ReferenceTracer,
}

impl ReferenceSettings {
    /// Binary mode, geometric normals: the defaults.
    pub fn new(radius: f32, rays: u32) -> Self {
        Self {
            radius,
            rays,
            mode: ReferenceMode::Binary,
            normals: ReferenceNormals::Geometric,
            tracer: ReferenceTracer::Auto,
        }
    }
}

/// One frame to trace: what is drawn, when, from where and at what size.
#[derive(Clone)]
pub struct FrameView {
    /// The scene drawn.
    pub scene: Arc<Scene>,
    /// The camera it is seen from.
    pub camera: Camera,
    /// Scene time in seconds (animations and moving instances at this time).
    pub time: f32,
    /// The output size in pixels.
    pub extent: Extent,
}

impl FrameView {
    /// The last frame `r` rendered.
    pub fn of(r: &Renderer) -> Self {
        Self {
            scene: r.scene.clone(),
            camera: r.camera(),
            time: r.time(),
            extent: r.output,
        }
    }
}

/// The g-buffer surfaces of `view` with `normals`, from a g-buffer of their own (see the
/// module docs), plus its linear depth (0 = sky).
pub fn reference_surfaces(
    gpu: Arc<GpuContext>,
    shaders: Arc<ShaderLibrary>,
    view: &FrameView,
    normals: ReferenceNormals,
) -> RenderResult<(SurfaceBuffer, Vec<f32>)> {
    let outputs = FrameOutputs {
        surfaces: true,
        surface_normals: normals,
        linear_depth: true,
        ..Default::default()
    };
    let r = gbuffer_frame(gpu, shaders, view, outputs)?;
    Ok((r.surfaces()?, r.read_linear_depth()?))
}

/// A g-buffer-only renderer that has drawn `view` once with `outputs`: the g-buffer every
/// reference starts its rays from.
fn gbuffer_frame(
    gpu: Arc<GpuContext>,
    shaders: Arc<ShaderLibrary>,
    view: &FrameView,
    outputs: FrameOutputs,
) -> RenderResult<Renderer> {
    let mut r = Renderer::gbuffer_only(gpu, shaders, view.scene.clone(), outputs, view.extent)?;
    r.render_with_camera(view.time, view.camera)?;
    Ok(r)
}

/// The cache directory: `AOGRAPH_REFERENCE_CACHE` if set, else `aograph/reference` in the
/// user's cache location (`$XDG_CACHE_HOME` or `~/.cache` on Linux, `~/Library/Caches` on
/// macOS, `%LOCALAPPDATA%` on Windows), else under the system's temporary directory. Never
/// the source tree: an installed binary's crates are read-only registry sources.
pub fn cache_dir() -> PathBuf {
    match std::env::var_os("AOGRAPH_REFERENCE_CACHE") {
        Some(dir) if !dir.is_empty() => PathBuf::from(dir),
        _ => dirs::cache_dir()
            .unwrap_or_else(std::env::temp_dir)
            .join("aograph")
            .join("reference"),
    }
}

/// Traces the reference of `surfaces` against `scene` at `time` (from the disk cache when the
/// same surfaces, geometry, settings and tracer were traced before), with the tracer
/// `s.tracer` resolves to on `gpu`.
pub fn trace_surfaces(
    gpu: &Arc<GpuContext>,
    scene: &Scene,
    time: f32,
    surfaces: &SurfaceBuffer,
    s: &ReferenceSettings,
    progress: bool,
) -> RenderResult<ReferenceImage> {
    let tris = scene.world_triangles(time);
    let params = ReferenceParams {
        radius: s.radius,
        rays_per_pixel: s.rays,
        mode: s.mode,
        progress: if progress {
            ProgressMode::Auto
        } else {
            ProgressMode::Never
        },
    };
    let key = CacheKey::new(&tris, surfaces, &params);
    let cache = ReferenceCache::new(cache_dir());
    let auto = s.tracer == ReferenceTracer::Auto;
    let gpu_takes_it = !auto || s.rays <= GPU_MAX_RAYS_PER_PIXEL;
    let tracer = s.tracer.resolve(gpu.is_software(), gpu.has_ray_queries());
    if tracer != ReferenceTracer::Cpu && gpu_takes_it {
        let traced = if tracer == ReferenceTracer::Hardware {
            cache.get_or_trace(key.hardware_traced(), || {
                let accel = HardwareSceneAs::build(gpu, scene, time)?;
                GpuReferenceTracer::new(gpu.clone(), &crate::shader_mount::shader_library())?
                    .trace(&accel, surfaces, &params)
            })
        } else {
            cache.get_or_trace(key.gpu_traced(), || {
                let bvh = GpuSceneBvh::new(gpu.clone(), scene, time)?;
                GpuReferenceTracer::new(gpu.clone(), &crate::shader_mount::shader_library())?
                    .trace(&bvh, surfaces, &params)
            })
        };
        match traced {
            Ok(image) => return Ok(image),
            // `auto` falls back to the CPU where the scene or image is over the device's
            // limits; an explicit "gpu" reports it.
            Err(
                TracingError::BvhTooLarge { .. }
                | TracingError::BvhTooDeep { .. }
                | TracingError::OverDeviceLimit { .. },
            ) if auto => {}
            Err(e) => return Err(e.into()),
        }
    }
    Ok(cache.get_or_trace(key, || {
        // Two levels: shared meshes are not flattened; the same image as a flat BVH over `tris`.
        let rays = aograph_scene::SceneRays::new(scene, time);
        Ok(aograph_scene::trace_reference(&rays, surfaces, &params)?)
    })?)
}

/// The radiance reference of `view` (issue 19): the scene's built-in sky
/// ([`aograph_scene::SkyEnvironment::for_scene`]) integrated from the g-buffer's points with
/// `s`'s radius and rays, one diffuse bounce from geometry within R
/// ([`aograph_tracing::trace_radiance`]). Receivers' albedo is the g-buffer's. Cached on disk
/// like the AO reference ([`CacheKey::radiance`]).
pub fn radiance_reference(
    gpu: Arc<GpuContext>,
    shaders: Arc<ShaderLibrary>,
    view: &FrameView,
    s: &ReferenceSettings,
) -> RenderResult<aograph_tracing::RadianceImage> {
    radiance_traced(gpu, shaders, view, s, false)
}

/// The radiance reference's ceiling (b) (`aograph_tracing::seen_triangle_mask`):
/// [`radiance_reference`] re-traced with the same rays against only the triangles some pixel
/// sees, so that both its occluders and its bounce's senders are what the frame shows. What
/// it lacks against the reference is what a screen-space bounce (SSDO's) cannot see; what a
/// technique lacks against it is its estimator's. Cached like the reference.
pub fn radiance_seen_ceiling(
    gpu: Arc<GpuContext>,
    shaders: Arc<ShaderLibrary>,
    view: &FrameView,
    s: &ReferenceSettings,
) -> RenderResult<aograph_tracing::RadianceImage> {
    radiance_traced(gpu, shaders, view, s, true)
}

/// [`radiance_reference`], against every triangle or (`seen_only`) the seen ones.
fn radiance_traced(
    gpu: Arc<GpuContext>,
    shaders: Arc<ShaderLibrary>,
    view: &FrameView,
    s: &ReferenceSettings,
    seen_only: bool,
) -> RenderResult<aograph_tracing::RadianceImage> {
    let outputs = FrameOutputs {
        surfaces: true,
        surface_normals: s.normals,
        albedo: true,
        ..Default::default()
    };
    let r = gbuffer_frame(gpu, shaders, view, outputs)?;
    let surfaces = r.surfaces()?;
    let albedo: Vec<Vec3> = r
        .read_gbuffer(aograph_frame::GBufferChannel::Albedo)?
        .to_f32()?
        .chunks_exact(4)
        .map(|c| Vec3::new(c[0], c[1], c[2]))
        .collect();
    let mut tris = view.scene.world_triangles(view.time);
    let mut tri_albedo = view.scene.world_triangle_albedo(view.time);
    if seen_only {
        let seen = aograph_tracing::seen_triangle_mask(
            &view.scene,
            &view.camera,
            view.extent.width,
            view.extent.height,
            view.time,
        );
        fn keep<T>(v: Vec<T>, seen: &[bool]) -> Vec<T> {
            v.into_iter()
                .zip(seen)
                .filter_map(|(x, s)| s.then_some(x))
                .collect()
        }
        tris = keep(tris, &seen);
        tri_albedo = keep(tri_albedo, &seen);
    }
    let params = ReferenceParams {
        radius: s.radius,
        rays_per_pixel: s.rays,
        mode: s.mode,
        progress: ProgressMode::Never,
    };
    let sky = aograph_scene::SkyEnvironment::for_scene(&view.scene);
    let key = CacheKey::radiance(&tris, &surfaces, &params, &tri_albedo, &albedo, &sky);
    Ok(
        ReferenceCache::new(cache_dir()).get_or_trace_radiance(key, || {
            aograph_tracing::trace_radiance(
                &TriangleBvh::new(&tris),
                &aograph_tracing::BounceSurfaces {
                    triangles: &tris,
                    albedo: &tri_albedo,
                },
                &surfaces,
                &albedo,
                &sky,
                &params,
            )
        })?,
    )
}

/// The two ceilings of the reference of `surfaces` (a frame of `scene` at `time` seen by
/// `camera`; `aograph_tracing::trace_ceilings`): the reference re-traced against the
/// g-buffer's surfaces and against the triangles the frame sees. Always traced on the CPU with
/// the CPU reference's rays (where the reference itself was traced on the GPU, the two agree
/// statistically, not ray for ray); cached on disk like the reference, by each ceiling's own
/// triangles.
pub fn trace_ceilings(
    scene: &Scene,
    camera: &aograph_scene::Camera,
    time: f32,
    surfaces: &SurfaceBuffer,
    s: &ReferenceSettings,
) -> RenderResult<aograph_tracing::Ceilings> {
    use aograph_tracing::{
        SECOND_LAYER_SEPARATION, gbuffer_surface_mesh, guard_band_mesh, second_layer_mesh,
        seen_triangles,
    };
    let params = ReferenceParams {
        radius: s.radius,
        rays_per_pixel: s.rays,
        mode: s.mode,
        progress: ProgressMode::Never,
    };
    let cache = ReferenceCache::new(cache_dir());
    let traced = |tris: Vec<[Vec3; 3]>| {
        cache.get_or_trace(CacheKey::new(&tris, surfaces, &params), || {
            Ok(aograph_scene::trace_reference(
                &TriangleBvh::new(&tris),
                surfaces,
                &params,
            )?)
        })
    };
    let mesh = gbuffer_surface_mesh(surfaces, camera.position, camera.forward());
    let mut layered = mesh.clone();
    layered.extend(second_layer_mesh(
        scene,
        camera,
        surfaces.width,
        surfaces.height,
        time,
        SECOND_LAYER_SEPARATION * s.radius,
    ));
    let gbuffer_surfaces = traced(mesh)?;
    let two_layers = traced(layered)?;
    let seen = seen_triangles(scene, camera, surfaces.width, surfaces.height, time);
    let seen_triangles = traced(seen)?;
    let guard_band = traced(guard_band_mesh(scene, camera, surfaces, time))?;
    Ok(aograph_tracing::Ceilings {
        gbuffer_surfaces,
        seen_triangles,
        guard_band,
        two_layers,
    })
}

/// The reference of the last frame `r` rendered, whatever normals `r`'s technique reads.
pub fn frame_reference(
    r: &Renderer,
    s: &ReferenceSettings,
    progress: bool,
) -> RenderResult<ReferenceImage> {
    let view = FrameView::of(r);
    let (surfaces, _) = reference_surfaces(r.gpu.clone(), r.shaders.clone(), &view, s.normals)?;
    trace_surfaces(&r.gpu, &view.scene, view.time, &surfaces, s, progress)
}
