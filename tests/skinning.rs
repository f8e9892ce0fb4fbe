//! GPU skinning's motion (issue 19): CesiumMan walks in front of a still camera, so every
//! pixel's motion comes from the skin alone. The g-buffer's motion (previous uv - uv, previous
//! linear depth) must be where the CPU puts the same surface point a frame earlier: the CPU
//! g-buffer's hit at this frame, its barycentric coordinates carried to the same triangle of
//! `Scene::world_triangles` at the previous frame, projected. Positions and normals mid-walk
//! are checked in tests/gbuffer_matches_cpu.rs.
//!
//! Tolerances, with reasons: both sides interpolate one affine image of the triangle with the
//! same barycentrics (the GPU perspective-correctly), so they differ by float rounding of the
//! skinning sum and the projection, ~1e-4 px; pixels whose CPU probes 1/256 px off the centre
//! hit different triangles (edges, where the rasteriser may pick either) are left out.
//! GPU tests: they skip only when there is no adapter and AOGRAPH_REQUIRE_GPU is unset.

use std::sync::Arc;

use aograph::shader_library;
use aograph_ao_passes::{AoConfig, TechniqueRegistry};
use aograph_frame::GBufferChannel;
use aograph_graph::{Extent, test_gpu};
use aograph_renderer::FrameOutputs;
use aograph_renderer::Renderer;
use aograph_scene::{Camera, CpuGBuffer, TriangleBvh, load_scene};
use glam::{Vec2, Vec3};

const SIZE: Extent = Extent {
    width: 96,
    height: 128,
};
const FRAME: f32 = 1.0 / 30.0;

/// CesiumMan (vendored in tests/scenes), `None` (skipped) where `test` cannot find it.
fn cesium_man(test: &str) -> Option<aograph_scene::Scene> {
    let path = aograph_scene::test_scene(test, "CesiumMan.glb")?;
    Some(load_scene(path).expect("CesiumMan loads"))
}

/// A still camera beside the man, framing him head to foot.
fn side_camera() -> Camera {
    Camera::perspective(
        Vec3::new(2.4, 0.8, 0.4),
        Vec3::new(0.0, 0.72, 0.0),
        45f32.to_radians(),
        0.1,
        20.0,
    )
}

/// Barycentric coordinates of `p` in triangle `t` (p assumed in its plane).
fn barycentric(p: Vec3, t: [Vec3; 3]) -> Vec3 {
    let (e1, e2, d) = (t[1] - t[0], t[2] - t[0], p - t[0]);
    let (d11, d12, d22) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
    let (dp1, dp2) = (d.dot(e1), d.dot(e2));
    let den = d11 * d22 - d12 * d12;
    let v = (d22 * dp1 - d12 * dp2) / den;
    let w = (d11 * dp2 - d12 * dp1) / den;
    Vec3::new(1.0 - v - w, v, w)
}

/// Texture uv and linear depth of world point `p` seen by `camera`.
fn project(camera: &Camera, p: Vec3) -> (Vec2, f32) {
    let aspect = SIZE.width as f32 / SIZE.height as f32;
    let clip = camera.view_projection(aspect) * p.extend(1.0);
    let ndc = clip.truncate() / clip.w;
    let depth = -(camera.view() * p.extend(1.0)).z;
    (Vec2::new(0.5 + 0.5 * ndc.x, 0.5 - 0.5 * ndc.y), depth)
}

#[test]
fn skinned_motion_vectors_follow_each_surface_point_to_the_previous_frame() {
    let Some(gpu) = test_gpu() else { return };
    let camera = side_camera();
    let Some(man) =
        cesium_man("skinned_motion_vectors_follow_each_surface_point_to_the_previous_frame")
    else {
        return;
    };
    let scene = Arc::new(man.with_camera(camera));
    let none = AoConfig {
        technique: "none".into(),
        ..AoConfig::default()
    };
    let outputs = FrameOutputs {
        linear_depth: true,
        motion: true,
        ..Default::default()
    };
    let mut r = Renderer::new(
        gpu,
        shader_library(),
        &TechniqueRegistry::with_builtins(),
        scene.clone(),
        &none,
        outputs,
        SIZE,
    )
    .expect("renderer");
    // Mid-stride, where the legs swing fastest.
    let (before, now) = (0.6, 0.6 + FRAME);
    r.render(before).unwrap();
    r.render(now).unwrap();
    let motion = r
        .read_gbuffer(GBufferChannel::Motion)
        .unwrap()
        .to_f32()
        .unwrap();
    let depth = r.read_linear_depth().unwrap();

    let (tris_now, tris_before) = (scene.world_triangles(now), scene.world_triangles(before));
    let bvh = TriangleBvh::new(&tris_now);
    let trace = |offset: Vec2| {
        CpuGBuffer::trace_with_bvh(
            &bvh,
            &tris_now,
            &scene.world_vertex_normals(now),
            &camera,
            SIZE.width,
            SIZE.height,
            offset,
        )
    };
    let s = 1.0 / 256.0;
    let centre = trace(Vec2::ZERO);
    let probes: Vec<CpuGBuffer> = [(s, s), (-s, s), (s, -s), (-s, -s)]
        .into_iter()
        .map(|(x, y)| trace(Vec2::new(x, y)))
        .collect();
    let (w, h) = (SIZE.width as f32, SIZE.height as f32);
    let (mut compared, mut moving) = (0, 0);
    let (mut worst_uv, mut worst_depth) = (0.0f32, 0.0f32);
    for i in 0..centre.valid.len() {
        if !centre.valid[i] || depth[i] <= 0.0 {
            continue;
        }
        let tri = centre.triangles[i];
        if probes.iter().any(|p| !p.valid[i] || p.triangles[i] != tri) {
            continue;
        }
        let b = barycentric(centre.points[i], tris_now[tri as usize]);
        let t = tris_before[tri as usize];
        let previous = t[0] * b.x + t[1] * b.y + t[2] * b.z;
        let (uv_before, depth_before) = project(&camera, previous);
        let (uv_now, _) = project(&camera, centre.points[i]);
        let want = uv_before - uv_now;
        let got = Vec2::new(motion[4 * i], motion[4 * i + 1]);
        let off_px = ((got - want) * Vec2::new(w, h)).length();
        let off_depth = (motion[4 * i + 2] - depth_before).abs() / depth_before;
        worst_uv = worst_uv.max(off_px);
        worst_depth = worst_depth.max(off_depth);
        compared += 1;
        if (want * Vec2::new(w, h)).length() > 0.5 {
            moving += 1;
        }
    }
    eprintln!(
        "{compared} pixels compared, {moving} moving over half a pixel; worst motion error \
         {worst_uv:.2e} px, worst previous-depth error {worst_depth:.2e} (relative)"
    );
    assert!(compared > 400, "only {compared} pixels compared");
    assert!(
        moving > compared / 10,
        "the walk should move many pixels: {moving} of {compared}"
    );
    assert!(worst_uv < 0.01, "motion off by {worst_uv} px");
    assert!(worst_depth < 1e-4, "previous depth off by {worst_depth}");
}
