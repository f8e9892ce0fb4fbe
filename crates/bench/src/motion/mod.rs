//! `aograph bench --motion orbit|path|scene`: every technique under a moving camera (and the
//! scene's own animation), each frame scored against a reference traced for that frame.
//!
//! Decisions:
//! - Frame i is at time i / fps. `orbit` turns the view's camera about its target's vertical
//!   axis ([`ORBIT_DEGREES_PER_SECOND`]); `path` walks it in a straight line, forward and to the
//!   right, keeping its direction ([`PATH_FORWARD_PER_SECOND`], [`PATH_SIDEWAYS_PER_SECOND`], as
//!   shares of its distance to the target), so geometry approaches along the view axis; `scene`
//!   follows the view's own camera path. Moving instances move in all three.
//! - References: one per measured frame, from a `none` renderer that renders every frame of
//!   the run (so its motion vectors are those of the run), traced with `--motion-rays` rays
//!   and cached on disk like every reference (the key covers the frame's surfaces and
//!   triangles, so a rerun traces nothing).
//! - Error: MAE, edge MAE and SSIM per measured frame; the run reports their mean and the worst
//!   frame's MAE. "Near moving objects": MAE over the pixels within R (projected) of a pixel
//!   whose surface moves on its own (object motion above [`MOVING_PIXELS`] after the camera's
//!   share is taken out), the region where TSSAO's Eq. 8 matters.
//! - Flicker under motion: the same surface point should keep its accessibility from one
//!   frame to the next (the reference's does: it does not depend on the camera). Each pixel is
//!   followed into the previous frame (its world point through the previous camera, or the
//!   g-buffer's 3D motion, previous uv and previous depth, where instances move) and compared with the previous frame's
//!   accessibility there, interpolated bilinearly from four texels that all lie on the same
//!   surface (their interpolated depth within [`SAME_SURFACE_DEPTH`] of the point's, no depth
//!   jump of more than [`SILHOUETTE_RATIO`] among them); pixels without such a history
//!   (disocclusions, screen borders) are left out. With a still camera this is the still
//!   bench's flicker.
//!
//! Invariant: every technique of a run sees the same frames (time, camera) and the same
//! references, bit for bit.
//!
//! Files: this one (paths, frames, runs), `reprojection.rs` (following a pixel into the
//! previous frame, the moving-object band) and `report.rs` (motion.csv, motion.md).

mod report;
mod reprojection;

use report::write_motion_files;
pub use report::{MotionFile, MotionRecord, motion_report, read_motion};
pub use reprojection::{
    BilinearTaps, MOVING_PIXELS, Reprojection, SAME_SURFACE_DEPTH, SILHOUETTE_RATIO, dilate,
    moving_pixels,
};

use std::path::Path;

use aograph_scene::{Camera, Scene, TriangleBvh};
use glam::{Quat, Vec3};

use crate::images::prepare_output_dir;
use crate::metrics::compare;
use crate::report::BenchMeta;
use crate::run::{BenchContext, BenchSettings, FrameTimeSamples, ao_config, check_gpu_errors};
use crate::sweep::ParamSet;
use crate::{BenchPlan, bench_meta, file_safe, progress_bar, run_images};
use aograph_app_config::error::{AppError, AppResult};
use aograph_app_config::prepared_scene::PreparedScene;
use aograph_frame::GBufferChannel;
use aograph_renderer::frame_graph::FrameOutputs;
use aograph_renderer::frame_reference::trace_surfaces;
use aograph_renderer::renderer::Renderer;

/// `orbit`: degrees per second about the target's vertical axis (1 degree a frame at 30 fps).
pub const ORBIT_DEGREES_PER_SECOND: f32 = 30.0;
/// `path`: forward speed as a share of the camera's distance to its target, per second.
pub const PATH_FORWARD_PER_SECOND: f32 = 0.25;
/// `path`: speed to the right, same unit.
pub const PATH_SIDEWAYS_PER_SECOND: f32 = 0.10;
/// Frames per second of a motion run (`--fps`).
pub const DEFAULT_FPS: f32 = 30.0;
/// Reference rays per pixel of a motion run (`--motion-rays`): one reference per frame.
pub const DEFAULT_MOTION_RAYS: u32 = 64;

/// How the camera moves.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MotionKind {
    /// Turns the view's camera about its target's vertical axis at
    /// [`ORBIT_DEGREES_PER_SECOND`].
    Orbit,
    /// Moves the view's camera forward and to the right without turning it
    /// ([`PATH_FORWARD_PER_SECOND`], [`PATH_SIDEWAYS_PER_SECOND`]).
    Path,
    /// Follows the view's own camera path (and the scene's animation).
    Scene,
}

impl MotionKind {
    /// The `--motion` names, in variant order ([`MotionKind::name`] indexes it by variant).
    pub const NAMES: [&'static str; 3] = ["orbit", "path", "scene"];

    /// Parses a `--motion` value; an unknown name is an error listing [`MotionKind::NAMES`].
    pub fn parse(s: &str) -> AppResult<Self> {
        match s.trim() {
            "orbit" => Ok(Self::Orbit),
            "path" => Ok(Self::Path),
            "scene" => Ok(Self::Scene),
            other => Err(AppError::InvalidArgument {
                name: "--motion".into(),
                value: other.into(),
                allowed: Self::NAMES.join(", "),
            }),
        }
    }

    /// The kind's `--motion` name.
    pub fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }

    /// The camera at time `t` for `scene` seen through its view (its camera at t = 0).
    pub fn camera_at(self, scene: &Scene, t: f32) -> Camera {
        let base = scene.camera_at(0.0);
        match self {
            MotionKind::Orbit => {
                let axis = base.up.try_normalize().unwrap_or(Vec3::Y);
                let turn = Quat::from_axis_angle(axis, ORBIT_DEGREES_PER_SECOND.to_radians() * t);
                Camera {
                    position: base.target + turn * (base.position - base.target),
                    ..base
                }
            }
            MotionKind::Path => {
                let to_target = base.target - base.position;
                let distance = to_target.length();
                let forward = to_target.try_normalize().unwrap_or(Vec3::NEG_Z);
                let right = forward.cross(base.up).try_normalize().unwrap_or(Vec3::X);
                let shift = distance
                    * t
                    * (forward * PATH_FORWARD_PER_SECOND + right * PATH_SIDEWAYS_PER_SECOND);
                Camera {
                    position: base.position + shift,
                    target: base.target + shift,
                    ..base
                }
            }
            MotionKind::Scene => scene.camera_at(t),
        }
    }
}

/// The motion flags.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MotionSettings {
    /// How the camera moves.
    pub kind: MotionKind,
    /// Frames per second of scene time (`--fps`): frame i is at i / fps seconds.
    pub fps: f32,
    /// Reference rays per pixel (one reference per measured frame).
    pub rays: u32,
}

impl MotionSettings {
    /// Time of frame `i`.
    pub fn time(&self, i: u32) -> f32 {
        i as f32 / self.fps
    }
}

/// One measured frame: where it is seen from and its reference.
pub struct MotionFrame {
    /// Scene time of the frame in seconds.
    pub time: f32,
    /// The camera the frame is seen through.
    pub camera: Camera,
    /// The frame's reference accessibility per pixel, row-major, 0..1.
    pub accessibility: Vec<f32>,
    /// Linear view depth per pixel, row-major (0 = sky).
    pub depth: Vec<f32>,
    /// `depth > 0` per pixel: the non-sky pixels the frame's metrics are taken over.
    pub valid: Vec<bool>,
    /// From the previous frame (the last warm-up frame for the first measured one).
    pub reprojection: Option<Reprojection>,
    /// Pixels within R of a surface that moves on its own (empty: nothing moves on its own).
    pub near_moving: Vec<bool>,
}

/// The frames of a motion run on `prepared`, with their references.
pub fn motion_frames(
    ctx: &BenchContext,
    label: &str,
    prepared: &PreparedScene,
    s: &BenchSettings,
    m: &MotionSettings,
    tick: &mut dyn FnMut(),
) -> AppResult<Vec<MotionFrame>> {
    let scene = prepared.scene.clone();
    let instances_move = scene.instances.iter().any(|i| i.is_moving());
    let extent = s.extent();
    let mut r = Renderer::gbuffer_only(
        ctx.gpu.clone(),
        ctx.shaders.clone(),
        scene.clone(),
        FrameOutputs {
            surfaces: true,
            surface_normals: s.normals,
            linear_depth: true,
            motion: instances_move,
            ..Default::default()
        },
        extent,
    )?;
    let reference = aograph_renderer::frame_reference::ReferenceSettings {
        rays: m.rays,
        ..s.reference(prepared.radius.get())
    };
    let mut frames = Vec::new();
    let mut prev: Option<(Camera, Vec<f32>)> = None;
    // orbit and path are ours, not the scene author's: refuse a path through a wall.
    let walls =
        (m.kind != MotionKind::Scene).then(|| TriangleBvh::new(&scene.world_triangles(0.0)));
    for i in 0..s.warmup + s.frames {
        let time = m.time(i);
        let camera = m.kind.camera_at(&scene, time);
        if let (Some(bvh), Some((before, _))) = (&walls, &prev) {
            let step = camera.position - before.position;
            if bvh.any_hit(
                before.position,
                step.normalize_or_zero(),
                0.0,
                step.length(),
            ) {
                return Err(AppError::InvalidArgument {
                    name: "--motion".into(),
                    value: format!("{} on {} / {}", m.kind.name(), label, prepared.view),
                    allowed: format!(
                        "a camera path clear of geometry: at frame {i} (t = {time:.3} s) the \
                         camera passes through a surface; try fewer --frames, another \
                         --motion or another view (--views outside)"
                    ),
                });
            }
        }
        r.render_with_camera(time, camera)?;
        let depth = r.read_linear_depth()?;
        if i >= s.warmup {
            let surfaces = r.surfaces()?;
            let image = trace_surfaces(&r.gpu, &scene, time, &surfaces, &reference, false)?;
            let motion = if instances_move {
                Some(r.read_gbuffer(GBufferChannel::Motion)?.to_f32()?)
            } else {
                None
            };
            let (w, h) = (extent.width, extent.height);
            let valid: Vec<bool> = depth.iter().map(|d| *d > 0.0).collect();
            let reprojection = prev.as_ref().map(|(c, d)| {
                Reprojection::new(&surfaces.points, &valid, motion.as_deref(), c, d, w, h)
            });
            let near_moving = match (&motion, &prev) {
                (Some(mv), Some((c, _))) => {
                    let moving = moving_pixels(&surfaces.points, &valid, mv, c, w, h);
                    let moving_depth: Vec<f32> = depth
                        .iter()
                        .zip(&moving)
                        .map(|(d, m)| if *m { *d } else { 0.0 })
                        .collect();
                    let at = crate::scaling::median_depth(&moving_depth);
                    let band = if at > 0.0 {
                        crate::scaling::radius_in_pixels(&camera, h, prepared.radius.get(), at)
                            .ceil()
                            .clamp(1.0, 32.0) as u32
                    } else {
                        0
                    };
                    dilate(&moving, &valid, w, h, band)
                }
                _ => Vec::new(),
            };
            frames.push(MotionFrame {
                time,
                camera,
                accessibility: image.accessibility,
                depth: depth.clone(),
                valid,
                reprojection,
                near_moving,
            });
        }
        prev = Some((camera, depth));
        tick();
    }
    Ok(frames)
}

fn mean(v: &[f64]) -> Option<f64> {
    (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64)
}

/// Renders `set` through `frames` (with `s.warmup` unmeasured frames first) and scores it.
#[allow(clippy::too_many_arguments)]
pub fn run_motion_technique(
    ctx: &BenchContext,
    label: &str,
    prepared: &PreparedScene,
    frames: &[MotionFrame],
    set: &ParamSet,
    s: &BenchSettings,
    m: &MotionSettings,
    tick: &mut dyn FnMut(),
) -> AppResult<(MotionRecord, Vec<f32>)> {
    let extent = s.extent();
    let mut r = Renderer::new(
        ctx.gpu.clone(),
        ctx.shaders.clone(),
        &ctx.registry,
        prepared.scene.clone(),
        &ao_config(set, prepared.radius),
        FrameOutputs::default(),
        extent,
    )?;
    let (mut maes, mut edges, mut ssims, mut moving) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let mut times = FrameTimeSamples::default();
    let (mut change, mut followed, mut measured_pixels) = (0.0f64, 0usize, 0usize);
    let mut previous: Option<Vec<f32>> = None;
    let mut last = Vec::new();
    for i in 0..s.warmup + s.frames {
        let time = m.time(i);
        r.render_with_camera(time, m.kind.camera_at(&prepared.scene, time))?;
        let t = r.timings()?;
        let keep = i + 1 >= s.warmup;
        let ao = if keep { r.read_ao()? } else { Vec::new() };
        if i >= s.warmup {
            let f = &frames[(i - s.warmup) as usize];
            times.push(&t, &r.graph.owners);
            let metrics = compare(
                &ao,
                &f.accessibility,
                &f.depth,
                extent.width,
                extent.height,
                &s.metrics,
            )?;
            maes.push(metrics.mae);
            edges.extend(metrics.edge_mae);
            ssims.push(metrics.ssim);
            if !f.near_moving.is_empty() {
                let near: Vec<f64> = f
                    .near_moving
                    .iter()
                    .enumerate()
                    .filter(|(_, m)| **m)
                    .map(|(j, _)| f64::from((ao[j] - f.accessibility[j]).abs()))
                    .collect();
                moving.extend(mean(&near));
            }
            if let (Some(rp), Some(prev)) = (&f.reprojection, &previous) {
                let (sum, n) = rp.change(&ao, prev);
                change += sum;
                followed += n;
                measured_pixels += f.valid.iter().filter(|v| **v).count();
            }
        }
        if keep {
            last = ao.clone();
            previous = Some(ao);
        }
        tick();
    }
    check_gpu_errors(ctx, set)?;
    let record = MotionRecord {
        scene: label.to_string(),
        view: prepared.view.clone(),
        motion: m.kind.name().into(),
        technique: set.technique.clone(),
        label: set.label(),
        params: set.params.clone().into_iter().collect(),
        width: extent.width,
        height: extent.height,
        radius: prepared.radius.get(),
        rays: m.rays,
        fps: m.fps,
        frames: s.frames,
        warmup: s.warmup,
        times: times.finish(),
        mae_mean: mean(&maes).unwrap_or(f64::NAN),
        mae_worst: maes.iter().copied().fold(f64::NAN, f64::max),
        edge_mae_mean: mean(&edges),
        ssim_mean: mean(&ssims).unwrap_or(f64::NAN),
        moving_mae_mean: mean(&moving),
        flicker: (followed > 0).then(|| change / followed as f64),
        flicker_coverage: (measured_pixels > 0).then(|| followed as f64 / measured_pixels as f64),
        frame_mae: maes,
        image: None,
    };
    Ok((record, last))
}

/// Checks that `kind` can move `scene`: `scene` needs an animation or a camera path.
pub fn check_motion(kind: MotionKind, label: &str, scene: &Scene) -> AppResult<()> {
    if kind == MotionKind::Scene && scene.is_static() {
        return Err(AppError::InvalidArgument {
            name: "--motion".into(),
            value: "scene".into(),
            allowed: format!(
                "orbit or path for `{label}`: it has no animation and no camera path of its own"
            ),
        });
    }
    Ok(())
}

/// Runs every set of `plan` under motion `m`; with `out`, writes motion.csv, motion.json,
/// motion_frames.csv, motion.md and the last frames' images as runs finish.
pub fn run_motion_bench(
    ctx: &BenchContext,
    plan: &BenchPlan,
    m: &MotionSettings,
    out: Option<&Path>,
    progress: bool,
) -> AppResult<Vec<MotionRecord>> {
    let s = &plan.settings;
    let meta = BenchMeta {
        rays: m.rays,
        ..bench_meta(&ctx.gpu, s)
    };
    if let Some(dir) = out {
        prepare_output_dir(dir)?;
        let images = dir.join("images");
        std::fs::create_dir_all(&images).map_err(|e| AppError::io("create", &images, e))?;
    }
    let per_run = (s.warmup + s.frames) as u64;
    let pb = progress_bar(0, progress);
    let mut records: Vec<MotionRecord> = Vec::new();
    for source in &plan.scenes {
        let scene = aograph_app_config::load_scene(source)?;
        let label = source.label();
        check_motion(m.kind, &label, &scene)?;
        for view in plan.views.views(&scene)? {
            let prepared = PreparedScene::new(&scene, &view, s.radius);
            check_motion(m.kind, &label, &prepared.scene)?;
            pb.inc_length(per_run * (1 + plan.sets.len() as u64));
            pb.set_message(format!(
                "tracing {} references of {label} / {} ({} rays/pixel)",
                s.frames, view.name, m.rays
            ));
            let frames = motion_frames(ctx, &label, &prepared, s, m, &mut || pb.inc(1))?;
            for set in &plan.sets {
                pb.set_message(format!("{label}: {} {}", set.technique, set.label()));
                let (mut record, last) =
                    run_motion_technique(ctx, &label, &prepared, &frames, set, s, m, &mut || {
                        pb.inc(1)
                    })?;
                if let (Some(dir), Some(f)) = (out, frames.last()) {
                    let name = format!(
                        "images/motion_{}_{}_{}_{}.png",
                        m.kind.name(),
                        file_safe(&source.short_name()),
                        file_safe(&view.name),
                        set.slug()
                    );
                    run_images::write_side_by_side(
                        &dir.join(&name),
                        &last,
                        &f.accessibility,
                        &f.valid,
                        s.width,
                        s.height,
                    )?;
                    record.image = Some(name);
                }
                records.push(record);
                if let Some(dir) = out {
                    write_motion_files(dir, &meta, &records)?;
                }
            }
        }
    }
    pb.finish_and_clear();
    Ok(records)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec2;

    fn camera() -> Camera {
        Camera::perspective(
            Vec3::new(0.0, 1.0, 5.0),
            Vec3::ZERO,
            60f32.to_radians(),
            0.1,
            100.0,
        )
    }

    fn scene() -> Scene {
        let mut s = aograph_scene::procedural_scene("sphere-on-plane").expect("built-in scene");
        s.camera = camera();
        s.camera_motion = None;
        s
    }

    #[test]
    fn orbit_keeps_the_distance_to_the_target_and_turns_thirty_degrees_a_second() {
        let s = scene();
        let c0 = MotionKind::Orbit.camera_at(&s, 0.0);
        let c1 = MotionKind::Orbit.camera_at(&s, 1.0);
        assert_eq!(c0.position, camera().position);
        let (a, b) = (c0.position - c0.target, c1.position - c1.target);
        assert!((a.length() - b.length()).abs() < 1e-5);
        assert!((a.y - b.y).abs() < 1e-5, "turns about the vertical");
        let angle = Vec2::new(a.x, a.z).angle_to(Vec2::new(b.x, b.z)).abs();
        assert!((angle.to_degrees() - 30.0).abs() < 1e-3, "{angle}");
    }

    #[test]
    fn path_translates_the_camera_forward_and_right_without_turning_it() {
        let s = scene();
        let c0 = MotionKind::Path.camera_at(&s, 0.0);
        let c1 = MotionKind::Path.camera_at(&s, 2.0);
        assert!((c0.forward() - c1.forward()).length() < 1e-6);
        let d = (c0.target - c0.position).length();
        let moved = c1.position - c0.position;
        assert!((moved.dot(c0.forward()) - 2.0 * PATH_FORWARD_PER_SECOND * d).abs() < 1e-4);
        let (right, _, _) = c0.basis();
        assert!((moved.dot(right) - 2.0 * PATH_SIDEWAYS_PER_SECOND * d).abs() < 1e-4);
    }

    #[test]
    fn scene_motion_of_a_static_scene_is_refused_with_the_choices() {
        let e = check_motion(MotionKind::Scene, "still", &scene()).unwrap_err();
        let text = e.to_string();
        assert!(
            text.contains("orbit or path") && text.contains("still"),
            "{text}"
        );
        assert!(check_motion(MotionKind::Orbit, "still", &scene()).is_ok());
        assert!(MotionKind::parse("dolly").is_err());
        assert_eq!(MotionKind::parse("path").unwrap(), MotionKind::Path);
    }
}
