//! 3D motion (issue 19): the g-buffer's motion carries each surface's previous linear depth,
//! so the temporal block's disocclusion test (TSSAO Eq. 7, MSSAO Eq. 13) compares a moving
//! surface with its own previous depth. An object flying straight at the camera, 10% of its
//! depth a frame (three times Eq. 7's tolerance), keeps its history.
//! GPU tests: they skip only when there is no adapter and AOGRAPH_REQUIRE_GPU is unset.

mod common;

use aograph_ao_passes::blocks::temporal::TemporalMode;
use aograph_frame::GBufferChannel;
use aograph_graph::Extent;
use aograph_scene::primitives::cuboid;
use aograph_scene::{
    AnimatedTransform, Animation, Camera, Interpolation, Scene, SceneBuilder, Track, TrsKeyframes,
};
use glam::{Quat, Vec3};

const FPS: f32 = 30.0;
/// Units per second the wall moves towards the camera (one unit a frame at depth 10 to 7).
const SPEED: f32 = 30.0;

/// A wall filling the view at depth 10, flying straight at the camera.
fn approaching_wall() -> Scene {
    let mut b = SceneBuilder::new();
    let m = b.material([0.8, 0.8, 0.8]);
    let mesh = b.mesh(cuboid(Vec3::new(60.0, 60.0, 0.2), m));
    let track = Track::new(
        vec![0.0, 1.0],
        vec![Vec3::ZERO, Vec3::new(0.0, 0.0, SPEED)],
        Interpolation::Linear,
    )
    .expect("a valid track");
    let keys = TrsKeyframes {
        rest_translation: Vec3::ZERO,
        rest_rotation: Quat::IDENTITY,
        rest_scale: Vec3::ONE,
        translation: Some(track),
        rotation: None,
        scale: None,
    };
    b.place_animated(
        mesh,
        Animation::new(vec![AnimatedTransform::Keyframes(keys)]),
    );
    // The wall's front face is at z = 0.1; the camera at z = 10.1 sees it at depth 10.
    b.build(Camera::perspective(
        Vec3::new(0.0, 0.0, 10.1),
        Vec3::new(0.0, 0.0, 0.1),
        0.8,
        0.1,
        100.0,
    ))
}

#[test]
fn the_gbuffer_motion_carries_the_previous_depth_of_a_surface_moving_along_the_view_axis() {
    let size = Extent::new(48, 32);
    let Some(mut r) =
        common::parity::renderer(TemporalMode::FixedBlend(0.5), approaching_wall(), size)
    else {
        return;
    };
    for f in 0..3 {
        r.render(f as f32 / FPS).unwrap();
    }
    // Frame 2: the wall at depth 8, last frame at 9; straight ahead, so no screen motion at
    // the centre.
    let motion = r
        .read_gbuffer(GBufferChannel::Motion)
        .unwrap()
        .to_f32()
        .unwrap();
    let depth = r.read_linear_depth().unwrap();
    let c = (16 * 48 + 24) as usize;
    assert!((depth[c] - 8.0).abs() < 1e-3, "depth {}", depth[c]);
    assert!(
        (motion[4 * c + 2] - 9.0).abs() < 1e-3,
        "previous depth {}",
        motion[4 * c + 2]
    );
    assert!(motion[4 * c].abs() < 0.02 && motion[4 * c + 1].abs() < 0.02);
}

#[test]
fn an_object_flying_at_the_camera_keeps_its_history() {
    // The parity technique writes 0, 1, 0, 1 through the temporal block with a fixed blend of
    // 0.5 (MSSAO Eq. 14): a kept history gives 0, 0.5, 0.25, 0.625; a dropped one the raw
    // parity. Camera-only previous depths would see the wall 10% nearer than its history
    // every frame and drop it (the raw 1 at frame 1).
    let size = Extent::new(48, 32);
    let Some(mut r) =
        common::parity::renderer(TemporalMode::FixedBlend(0.5), approaching_wall(), size)
    else {
        return;
    };
    let mut a = 0.0f32;
    for f in 0..4u32 {
        r.render(f as f32 / FPS).unwrap();
        let x = (f & 1) as f32;
        a = if f == 0 { x } else { 0.5 * a + 0.5 * x };
        let out = r.read_ao().unwrap();
        let depth = r.read_linear_depth().unwrap();
        assert!(depth.iter().all(|d| *d > 0.0), "the wall fills the view");
        let off = out.iter().map(|v| (v - a).abs()).fold(0.0f32, f32::max);
        assert!(
            off < 1e-5,
            "frame {f} (depth {:.1}): expected {a} everywhere, off by {off}",
            depth[0]
        );
    }
}
