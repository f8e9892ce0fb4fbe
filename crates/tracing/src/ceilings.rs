//! Two ceilings for a screen-space technique: the reference re-traced from the same points,
//! hemispheres and rays against less geometry than the scene has.
//!
//! - (a) [`gbuffer_surface_mesh`]: the surfaces the g-buffer holds, a mesh through
//!   neighbouring pixels' points, broken where linear depth jumps by more than
//!   [`DEPTH_BREAK_RATIO`]. What one depth layer can know at best (no thickness, no
//!   connectivity across silhouettes).
//! - (b) [`seen_triangles`]: the scene's real triangles restricted to those some sample of a
//!   [`SEEN_SUPERSAMPLING`] x [`SEEN_SUPERSAMPLING`] grid per pixel sees. What any technique
//!   limited to visible geometry can know at best.
//!
//! - (a) with a guard band ([`GUARD_BAND`]): the g-buffer rendered over a wider field (the
//!   same pixel pitch, [`guard_band_camera`]), so surfaces just outside the frame count; scored
//!   on the frame's own pixels. What rendering a guard band would gain a technique.
//!
//! - (a) with a second depth layer ([`second_layer_mesh`]): the frame's mesh plus one through
//!   each pixel's next surface at least [`SECOND_LAYER_SEPARATION`] R behind the first (Mara,
//!   McGuire, Nowrouzezahrai and Luebke, "Deep G-Buffers for Stable Global Illumination
//!   Approximation", 2016). What a two-layer g-buffer could give at best.
//!
//! A technique's error then splits three ways: geometry it never sees (reference vs b), the
//! thickness and connectivity of what it sees (b vs a), and its estimator (a vs the
//! technique); a thickness heuristic can beat (a). Invariant: both ceilings trace the very rays
//! the reference traces (same points, normals, seeds), so where their geometry agrees with
//! the scene's within R they equal the reference bit for bit.

use crate::error::TracingError;
use glam::{Vec2, Vec3};

use aograph_scene::camera::Camera;
use aograph_scene::model::Scene;
use aograph_scene::reference::{
    CpuGBuffer, ReferenceImage, ReferenceParams, SurfaceBuffer, TriangleBvh, trace_reference,
};

/// Neighbouring pixels are connected when their linear depths differ by at most this ratio
/// (10 %): a surface seen at 80 degrees from its normal changes depth by less from one pixel to
/// the next at any resolution aograph measures, and a silhouette by more.
pub const DEPTH_BREAK_RATIO: f32 = 1.1;

/// Samples per pixel side for finding the triangles a frame sees (4 x 4 per pixel: dense
/// meshes put several triangles in a pixel, and 2 x 2 samples left holes in suzanne, 15,744
/// triangles in about 900 pixels at 128x72, through which rays escaped).
pub const SEEN_SUPERSAMPLING: u32 = 4;

/// The guard band on every side, as a share of the image's height (a quarter).
pub const GUARD_BAND: f32 = 0.25;

/// The second layer's minimum separation behind the first, in units of R (the deep g-buffer
/// paper's Delta, as a share of the AO radius).
pub const SECOND_LAYER_SEPARATION: f32 = 0.05;

/// The reference re-traced against both ceilings' geometry.
#[derive(Clone, Debug)]
pub struct Ceilings {
    /// (a): against the g-buffer's surfaces only.
    pub gbuffer_surfaces: ReferenceImage,
    /// (b): against the triangles some pixel sees.
    pub seen_triangles: ReferenceImage,
    /// (a) with a guard band: against the g-buffer's surfaces over a wider field.
    pub guard_band: ReferenceImage,
    /// (a) with a second depth layer.
    pub two_layers: ReferenceImage,
}

/// A mesh through each pixel's second surface: along the pixel's primary ray, the nearest
/// hit whose depth lies at least `separation` (world units, along the view direction) behind
/// the first hit's; connected as [`gbuffer_surface_mesh`] connects the first layer.
pub fn second_layer_mesh(
    scene: &Scene,
    camera: &Camera,
    width: u32,
    height: u32,
    t: f32,
    separation: f32,
) -> Vec<[Vec3; 3]> {
    let triangles = scene.world_triangles(t);
    let bvh = TriangleBvh::new(&triangles);
    let aspect = width as f32 / height.max(1) as f32;
    let forward = camera.forward();
    let (w, h) = (width as usize, height as usize);
    let mut points = vec![Vec3::ZERO; w * h];
    let mut valid = vec![false; w * h];
    for i in 0..w * h {
        let ndc = Vec2::new(
            ((i % w) as f32 + 0.5) / width as f32 * 2.0 - 1.0,
            1.0 - ((i / w) as f32 + 0.5) / height as f32 * 2.0,
        );
        let ray = camera.primary_ray(ndc, aspect);
        let Some(first) = bvh.closest_hit(ray.origin, ray.direction, ray.t_min, ray.t_max) else {
            continue;
        };
        // Depth along the view direction grows by `cos` per unit of ray length.
        let cos = ray.direction.dot(forward).max(1e-6);
        let t_min = first.distance + separation / cos;
        if let Some(second) = bvh.closest_hit(ray.origin, ray.direction, t_min, ray.t_max) {
            points[i] = ray.origin + ray.direction * second.distance;
            valid[i] = true;
        }
    }
    let layer = SurfaceBuffer {
        width,
        height,
        normals: vec![Vec3::ZERO; w * h],
        points,
        valid,
    };
    gbuffer_surface_mesh(&layer, camera.position, forward)
}

/// `camera` widened by `pad` pixels on every side of a `width` x `height` image, keeping the
/// pixel pitch, so pixel (x, y) of the frame is pixel (x + pad, y + pad) of the wider image;
/// with that image's size.
pub fn guard_band_camera(camera: &Camera, width: u32, height: u32, pad: u32) -> (Camera, u32, u32) {
    use aograph_scene::camera::Projection;
    let grow = (height + 2 * pad) as f32 / height.max(1) as f32;
    let mut wide = *camera;
    match &mut wide.projection {
        Projection::Perspective { fov_y, .. } => {
            *fov_y = 2.0 * ((0.5 * *fov_y).tan() * grow).atan();
        }
        Projection::Orthographic { height: h, .. } => *h *= grow,
    }
    (wide, width + 2 * pad, height + 2 * pad)
}

/// Triangles through the points of `surfaces`: each 2 x 2 block of pixels gives two triangles,
/// each kept when its three pixels are geometry whose linear depths (along `forward` from
/// `eye`) lie within [`DEPTH_BREAK_RATIO`] of each other.
pub fn gbuffer_surface_mesh(surfaces: &SurfaceBuffer, eye: Vec3, forward: Vec3) -> Vec<[Vec3; 3]> {
    surface_mesh_where(surfaces, eye, forward, |_, _| true)
}

/// [`gbuffer_surface_mesh`] of the 2 x 2 blocks whose top-left pixel passes `keep(x, y)`.
fn surface_mesh_where(
    surfaces: &SurfaceBuffer,
    eye: Vec3,
    forward: Vec3,
    keep: impl Fn(usize, usize) -> bool,
) -> Vec<[Vec3; 3]> {
    let (w, h) = (surfaces.width as usize, surfaces.height as usize);
    let depth = |i: usize| (surfaces.points[i] - eye).dot(forward);
    let connected = |ids: [usize; 3]| {
        if !ids.iter().all(|&i| surfaces.valid[i] && depth(i) > 0.0) {
            return false;
        }
        let d = ids.map(depth);
        let (lo, hi) = (d[0].min(d[1]).min(d[2]), d[0].max(d[1]).max(d[2]));
        hi <= DEPTH_BREAK_RATIO * lo
    };
    let mut mesh = Vec::new();
    for y in 0..h.saturating_sub(1) {
        for x in 0..w.saturating_sub(1) {
            if !keep(x, y) {
                continue;
            }
            let (p00, p10, p01, p11) = (
                y * w + x,
                y * w + x + 1,
                (y + 1) * w + x,
                (y + 1) * w + x + 1,
            );
            for ids in [[p00, p10, p11], [p00, p11, p01]] {
                if connected(ids) {
                    mesh.push(ids.map(|i| surfaces.points[i]));
                }
            }
        }
    }
    mesh
}

/// The triangles of `scene` at time `t` that some sample of a [`SEEN_SUPERSAMPLING`]^2 grid
/// per pixel of `camera`'s `width` x `height` view hits first.
pub fn seen_triangles(
    scene: &Scene,
    camera: &Camera,
    width: u32,
    height: u32,
    t: f32,
) -> Vec<[Vec3; 3]> {
    let seen = seen_triangle_mask(scene, camera, width, height, t);
    scene
        .world_triangles(t)
        .into_iter()
        .zip(seen)
        .filter_map(|(tri, s)| s.then_some(tri))
        .collect()
}

/// Per triangle of `scene.world_triangles(t)`, whether some sample of a
/// [`SEEN_SUPERSAMPLING`]^2 grid per pixel of the view hits it first ([`seen_triangles`]
/// keeps those; a caller with per-triangle data, such as albedo, filters it the same way).
pub fn seen_triangle_mask(
    scene: &Scene,
    camera: &Camera,
    width: u32,
    height: u32,
    t: f32,
) -> Vec<bool> {
    let triangles = scene.world_triangles(t);
    let normals = scene.world_vertex_normals(t);
    let bvh = TriangleBvh::new(&triangles);
    let mut seen = vec![false; triangles.len()];
    let s = SEEN_SUPERSAMPLING as f32;
    for sy in 0..SEEN_SUPERSAMPLING {
        for sx in 0..SEEN_SUPERSAMPLING {
            // Sample centres of the s x s grid, as offsets from the pixel centre.
            let offset = Vec2::new((sx as f32 + 0.5) / s - 0.5, (sy as f32 + 0.5) / s - 0.5);
            let g = CpuGBuffer::trace_with_bvh(
                &bvh, &triangles, &normals, camera, width, height, offset,
            );
            for (tri, valid) in g.triangles.iter().zip(&g.valid) {
                if *valid && let Some(flag) = seen.get_mut(*tri as usize) {
                    *flag = true;
                }
            }
        }
    }
    seen
}

/// Both ceilings for the reference of `surfaces` (a frame of `scene` at `t` seen by `camera`)
/// traced with `params`.
pub fn trace_ceilings(
    scene: &Scene,
    camera: &Camera,
    surfaces: &SurfaceBuffer,
    params: &ReferenceParams,
    t: f32,
) -> Result<Ceilings, TracingError> {
    let mesh = gbuffer_surface_mesh(surfaces, camera.position, camera.forward());
    let seen = seen_triangles(scene, camera, surfaces.width, surfaces.height, t);
    let guarded = guard_band_mesh(scene, camera, surfaces, t);
    let mut layered = mesh.clone();
    layered.extend(second_layer_mesh(
        scene,
        camera,
        surfaces.width,
        surfaces.height,
        t,
        SECOND_LAYER_SEPARATION * params.radius,
    ));
    Ok(Ceilings {
        gbuffer_surfaces: trace_reference(&TriangleBvh::new(&mesh), surfaces, params)?,
        seen_triangles: trace_reference(&TriangleBvh::new(&seen), surfaces, params)?,
        guard_band: trace_reference(&TriangleBvh::new(&guarded), surfaces, params)?,
        two_layers: trace_reference(&TriangleBvh::new(&layered), surfaces, params)?,
    })
}

/// Ceiling (a)'s mesh with a guard band: the frame's own mesh from `surfaces`, plus the ring
/// of a [`GUARD_BAND`]-wide g-buffer (traced on the CPU at the same pixel pitch) outside it.
pub fn guard_band_mesh(
    scene: &Scene,
    camera: &Camera,
    surfaces: &SurfaceBuffer,
    t: f32,
) -> Vec<[Vec3; 3]> {
    let (w, h) = (surfaces.width as usize, surfaces.height as usize);
    let pad = (GUARD_BAND * h as f32).ceil() as usize;
    let (wide, ww, wh) = guard_band_camera(camera, surfaces.width, surfaces.height, pad as u32);
    let wide_surfaces = CpuGBuffer::trace(scene, &wide, ww, wh, t)
        .surfaces(aograph_scene::reference::ReferenceNormals::Geometric);
    // Blocks not wholly inside the frame (the frame's own come from `surfaces`).
    let inside = |x: usize, y: usize| x >= pad && y >= pad && x + 1 < pad + w && y + 1 < pad + h;
    let mut mesh = gbuffer_surface_mesh(surfaces, camera.position, camera.forward());
    mesh.extend(surface_mesh_where(
        &wide_surfaces,
        camera.position,
        camera.forward(),
        |x, y| !inside(x, y),
    ));
    mesh
}
