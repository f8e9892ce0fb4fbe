//! Numerical stability at the extremes (issue 9), for every registered technique (plus the
//! temporal variant of every technique that has a `temporal` switch), on the GPU at small sizes.
//!
//! Cases: near planes 1e-4 to 10 and far planes 10 to 1e7 with Depth32Float and Depth24Plus,
//! an infinite reversed-Z far plane (on a reversed scene, and as a frame's camera on a plain
//! one) and an orthographic camera; scene scale 1e-3 to 1e4 with R scaled alike, a scene 1e5
//! units from the origin; R = 1e-4 (no occlusion expected) to R far larger than the scene;
//! output sizes 1x1, 2x3, 97x61, 4096x8, 8x4096 with resizes between frames; a camera inside
//! a box, in the floor's plane, 1e-3 above it, seeing only sky; a plane at 89.9 degrees to the
//! view; degenerate triangles and coincident vertices; for every technique (temporal or not)
//! a camera jump of 1e4 units, a 180-degree turn and zero-length frame times.
//!
//! Every rig uses the default intermediate format except one that repeats the near/far sweep
//! at the other (r32float or r16float). Every case asserts: no panic, `execute` returns Ok,
//! no wgpu error (an error scope around the case, and the device's uncaptured-error sink);
//! every pixel finite and in [0, 1]; sky exactly 1; and where the view holds only an
//! unoccluded plane, or R is too small for anything to occlude (the `Flat` cases), every
//! non-sky pixel at least 0.98. Failures are collected and reported together, one line each.
//!
//! Speed: lavapipe compiles pipelines on the CPU, so one renderer per (technique, scene, R,
//! depth format) is built and cameras and sizes vary through `render_with_camera` and
//! `resize`. The three tests split the rigs so the harness runs them on both cores.
//!
//! Files: `harness.rs` (variants, checks, report, `Rig`), `scenes.rs` (scenes and cameras), and
//! one per test: `depth_ranges.rs`, `scale_and_radius.rs`, `sizes_cameras_time.rs`; the
//! tolerances shared by them are here.

#[path = "../common/mod.rs"]
mod common;

mod depth_ranges;
mod harness;
mod scale_and_radius;
mod scenes;
mod sizes_cameras_time;

use aograph_graph::Extent;
use harness::*;
use scenes::*;

pub(crate) const SIZE: Extent = Extent {
    width: 32,
    height: 32,
};
/// Invariance tolerances (MAE against the baseline frame over all pixels), from the measured
/// values printed by the tests with about 3x headroom; see each check.
/// Scale 1e-3 to 1e4: measured at most 0.0032 (mssao at 1e-3: its fp16 tuples round sums of
/// scaled distances differently).
pub(crate) const TOL_SCALE: f32 = 0.01;
/// 1e5 units from the origin: measured at most 0.0012 (points rebuilt from linear depth lose
/// a few bits against the origin's).
pub(crate) const TOL_OFFSET: f32 = 0.004;
/// The same for a technique that traces the real geometry (rtao): measured 0.0042. Its rays
/// leave the surface by the reference's offset, 1e-4 R + 4e-6 |p| (reference/tracer.rs), which
/// at 1e5 units is 0.57 units instead of 0.0001: contact occlusion closer than that is lost,
/// by the reference as much as by rtao (the offset is the reference's rule, not rtao's).
pub(crate) const TOL_OFFSET_TRACED: f32 = 0.012;
/// Share of an unoccluded view's pixels a technique tracing the real geometry may find
/// occluded: crease pixels whose point lies within R of the other face even at R = 1e-4
/// (box-on-plane at 32x32: pixel 815, 0.848 in both rtao and the reference).
pub(crate) const TRACED_CREASE_SHARE: f32 = 0.01;
/// Depth24Plus against Depth32Float: measured exactly 0. Techniques read linear depth and
/// positions from colour targets; the depth format only decides visibility ties.
pub(crate) const TOL_DEPTH24: f32 = 1e-4;
/// A reversed-Z camera against the plain one (both ways): measured at most 0.0055 (tssao, whose
/// history sees a frame of the other convention between the two).
pub(crate) const TOL_REVERSED_Z: f32 = 0.015;
/// Where the temporal island floor lies (scene units, scale 1): the camera jump's length.
pub(crate) const JUMP: f32 = 1.0e4;
/// The frame time of every case (s).
pub(crate) const FRAME: f32 = 1.0 / 60.0;
