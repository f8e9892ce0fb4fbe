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
//! A technique's error then splits three ways: geometry it never sees (reference vs b), the
//! thickness and connectivity of what it sees (b vs a), and its estimator (a vs the
//! technique); a thickness heuristic can beat (a). Invariant: both ceilings trace the very rays
//! the reference traces (same points, normals, seeds), so where their geometry agrees with
//! the scene's within R they equal the reference bit for bit.

use glam::{Vec2, Vec3};

use crate::camera::Camera;
use crate::error::SceneError;
use crate::model::Scene;
use crate::reference::{
    CpuGBuffer, ReferenceImage, ReferenceParams, SurfaceBuffer, TriangleBvh, trace_reference,
};

/// Neighbouring pixels are connected when their linear depths differ by at most this ratio
/// (10 %): a surface seen at 80 degrees from its normal changes depth by less from one pixel to
/// the next at any resolution aograph measures, and a silhouette by more.
pub const DEPTH_BREAK_RATIO: f32 = 1.1;

/// Samples per pixel side for finding the triangles a frame sees (2 x 2 per pixel).
pub const SEEN_SUPERSAMPLING: u32 = 2;

/// The reference re-traced against both ceilings' geometry.
#[derive(Clone, Debug)]
pub struct Ceilings {
    /// (a): against the g-buffer's surfaces only.
    pub gbuffer_surfaces: ReferenceImage,
    /// (b): against the triangles some pixel sees.
    pub seen_triangles: ReferenceImage,
}

/// Triangles through the points of `surfaces`: each 2 x 2 block of pixels gives two triangles,
/// each kept when its three pixels are geometry whose linear depths (along `forward` from
/// `eye`) lie within [`DEPTH_BREAK_RATIO`] of each other.
pub fn gbuffer_surface_mesh(surfaces: &SurfaceBuffer, eye: Vec3, forward: Vec3) -> Vec<[Vec3; 3]> {
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
    triangles
        .into_iter()
        .zip(seen)
        .filter_map(|(tri, s)| s.then_some(tri))
        .collect()
}

/// Both ceilings for the reference of `surfaces` (a frame of `scene` at `t` seen by `camera`)
/// traced with `params`.
pub fn trace_ceilings(
    scene: &Scene,
    camera: &Camera,
    surfaces: &SurfaceBuffer,
    params: &ReferenceParams,
    t: f32,
) -> Result<Ceilings, SceneError> {
    let mesh = gbuffer_surface_mesh(surfaces, camera.position, camera.forward());
    let seen = seen_triangles(scene, camera, surfaces.width, surfaces.height, t);
    Ok(Ceilings {
        gbuffer_surfaces: trace_reference(&TriangleBvh::new(&mesh), surfaces, params)?,
        seen_triangles: trace_reference(&TriangleBvh::new(&seen), surfaces, params)?,
    })
}
