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
//!   g-buffer's motion vector where instances move) and compared with the previous frame's
//!   accessibility there, interpolated bilinearly from four texels that all lie on the same
//!   surface (their interpolated depth within [`SAME_SURFACE_DEPTH`] of the point's, no depth
//!   jump of more than [`SILHOUETTE_RATIO`] among them); pixels without such a history
//!   (disocclusions, screen borders) are left out. With a still camera this is the still
//!   bench's flicker.
//!
//! Invariant: every technique of a run sees the same frames (time, camera) and the same
//! references, bit for bit.

use std::collections::BTreeMap;
use std::path::Path;

use aograph_ao::AoConfig;
use aograph_scene::{Camera, Scene, TriangleBvh};
use glam::{Quat, Vec2, Vec3};
use serde::{Deserialize, Serialize};

use super::run::{BenchContext, BenchSettings, FrameTimeSamples, FrameTimes, ao_config};
use super::sweep::ParamSet;
use super::{BenchPlan, file_safe, images, progress_bar};
use crate::error::{AppError, AppResult};
use crate::frame_graph::FrameOutputs;
use crate::frame_reference::trace_surfaces;
use crate::images::{prepare_output_dir, write_atomic};
use crate::metrics::compare;
use crate::prepared_scene::PreparedScene;
use crate::renderer::Renderer;
use aograph_frame::GBufferChannel;

/// `orbit`: degrees per second about the target's vertical axis (1 degree a frame at 30 fps).
pub const ORBIT_DEGREES_PER_SECOND: f32 = 30.0;
/// `path`: forward speed as a share of the camera's distance to its target, per second.
pub const PATH_FORWARD_PER_SECOND: f32 = 0.25;
/// `path`: speed to the right, same unit.
pub const PATH_SIDEWAYS_PER_SECOND: f32 = 0.10;
/// Two depths belong to the same surface when they differ by at most this share.
pub const SAME_SURFACE_DEPTH: f32 = 0.01;
/// A bilinear footprint whose farthest depth exceeds its nearest by more than this factor
/// straddles a silhouette.
pub const SILHOUETTE_RATIO: f32 = 1.25;
/// A pixel's surface moves on its own when its motion, less the camera's, exceeds this (px).
pub const MOVING_PIXELS: f32 = 0.25;
/// Frames per second of a motion run (`--fps`).
pub const DEFAULT_FPS: f32 = 30.0;
/// Reference rays per pixel of a motion run (`--motion-rays`): one reference per frame.
pub const DEFAULT_MOTION_RAYS: u32 = 64;

/// How the camera moves.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MotionKind {
    Orbit,
    Path,
    Scene,
}

impl MotionKind {
    pub const NAMES: [&'static str; 3] = ["orbit", "path", "scene"];

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
    pub kind: MotionKind,
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

/// Four texels of the previous frame and their bilinear weights.
pub type BilinearTaps = ([u32; 4], [f32; 4]);

/// Where each pixel's surface was in the previous frame (`None`: no history there).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Reprojection {
    pub taps: Vec<Option<BilinearTaps>>,
}

impl Reprojection {
    /// `points` (world space, valid where `valid`) seen in the previous frame: through
    /// `prev_camera`, or at uv + `motion` (pairs, previous uv - current uv) where given; kept
    /// where the four texels around it lie on one surface (no depth jump beyond
    /// [`SILHOUETTE_RATIO`]) whose depth there, interpolated as 1 / depth, is within
    /// [`SAME_SURFACE_DEPTH`] of the point's depth from the previous camera.
    pub fn new(
        points: &[Vec3],
        valid: &[bool],
        motion: Option<&[f32]>,
        prev_camera: &Camera,
        prev_depth: &[f32],
        width: u32,
        height: u32,
    ) -> Self {
        let (w, h) = (width as usize, height as usize);
        let aspect = width as f32 / height as f32;
        let view = prev_camera.view();
        let view_projection = prev_camera.view_projection(aspect);
        let taps = (0..w * h)
            .map(|i| {
                if !valid[i] {
                    return None;
                }
                let p = points[i];
                let expected = -view.transform_point3(p).z;
                let uv = match motion {
                    Some(m) => pixel_uv(i, w, h) + Vec2::new(m[2 * i], m[2 * i + 1]),
                    None => clip_uv(view_projection * p.extend(1.0))?,
                };
                // Texel-centre coordinates; a point within half a texel of the image's edge is
                // on screen and takes the edge texels.
                let x = uv.x * width as f32 - 0.5;
                let y = uv.y * height as f32 - 0.5;
                let (wf, hf) = (width as f32, height as f32);
                if !(x >= -0.5 && y >= -0.5 && x <= wf - 0.5 && y <= hf - 0.5)
                    || width < 2
                    || height < 2
                {
                    return None;
                }
                let (x, y) = (x.clamp(0.0, wf - 1.0), y.clamp(0.0, hf - 1.0));
                let (x0, y0) = (x.floor().min(wf - 2.0), y.floor().min(hf - 2.0));
                let (fx, fy) = (x - x0, y - y0);
                let base = y0 as u32 * width + x0 as u32;
                let index = [base, base + 1, base + width, base + width + 1];
                let weight = [
                    (1.0 - fx) * (1.0 - fy),
                    fx * (1.0 - fy),
                    (1.0 - fx) * fy,
                    fx * fy,
                ];
                // A plane's 1 / depth is affine in screen space, so the bilinear blend of 1 /
                // depth is exact on one; a footprint across a silhouette has a depth jump.
                let depths = index.map(|j| prev_depth[j as usize]);
                let (near, far) = depths
                    .iter()
                    .fold((f32::MAX, 0.0f32), |(a, b), &d| (a.min(d), b.max(d)));
                let inverse: f32 = depths.iter().zip(&weight).map(|(d, w)| w / d).sum();
                let same = near > 0.0
                    && far <= SILHOUETTE_RATIO * near
                    && (1.0 / inverse - expected).abs() <= SAME_SURFACE_DEPTH * expected;
                same.then_some((index, weight))
            })
            .collect();
        Reprojection { taps }
    }

    /// Mean |current - previous at the same surface| over the pixels with a history, and their
    /// count.
    pub fn change(&self, current: &[f32], previous: &[f32]) -> (f64, usize) {
        let (mut sum, mut n) = (0.0f64, 0usize);
        for (i, t) in self.taps.iter().enumerate() {
            if let Some((index, weight)) = t {
                let before: f32 = index
                    .iter()
                    .zip(weight)
                    .map(|(&j, &w)| previous[j as usize] * w)
                    .sum();
                sum += f64::from((current[i] - before).abs());
                n += 1;
            }
        }
        (sum, n)
    }
}

fn pixel_uv(i: usize, w: usize, h: usize) -> Vec2 {
    Vec2::new(
        ((i % w) as f32 + 0.5) / w as f32,
        ((i / w) as f32 + 0.5) / h as f32,
    )
}

fn clip_uv(clip: glam::Vec4) -> Option<Vec2> {
    (clip.w > 1e-12).then(|| {
        let ndc = clip.truncate().truncate() / clip.w;
        Vec2::new(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5)
    })
}

/// Pixels whose surface moves on its own: `motion` less what the camera alone explains.
pub fn moving_pixels(
    points: &[Vec3],
    valid: &[bool],
    motion: &[f32],
    prev_camera: &Camera,
    width: u32,
    height: u32,
) -> Vec<bool> {
    let (w, h) = (width as usize, height as usize);
    let vp = prev_camera.view_projection(width as f32 / height as f32);
    let size = Vec2::new(width as f32, height as f32);
    (0..w * h)
        .map(|i| {
            if !valid[i] {
                return false;
            }
            let uv = pixel_uv(i, w, h);
            let moved = uv + Vec2::new(motion[2 * i], motion[2 * i + 1]);
            match clip_uv(vp * points[i].extend(1.0)) {
                Some(camera_only) => ((moved - camera_only) * size).length() > MOVING_PIXELS,
                None => true,
            }
        })
        .collect()
}

/// `mask` grown by `radius` pixels (a square), kept to `valid` pixels.
pub fn dilate(mask: &[bool], valid: &[bool], width: u32, height: u32, radius: u32) -> Vec<bool> {
    let (w, h, r) = (width as usize, height as usize, radius as usize);
    let mut rows = vec![false; w * h];
    for y in 0..h {
        for x in 0..w {
            if mask[y * w + x] {
                for xx in x.saturating_sub(r)..(x + r + 1).min(w) {
                    rows[y * w + xx] = true;
                }
            }
        }
    }
    let mut out = vec![false; w * h];
    for y in 0..h {
        for x in 0..w {
            if rows[y * w + x] {
                for yy in y.saturating_sub(r)..(y + r + 1).min(h) {
                    out[yy * w + x] = true;
                }
            }
        }
    }
    out.iter().zip(valid).map(|(m, v)| *m && *v).collect()
}

/// One measured frame: where it is seen from and its reference.
pub struct MotionFrame {
    pub time: f32,
    pub camera: Camera,
    pub accessibility: Vec<f32>,
    pub depth: Vec<f32>,
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
    let none = AoConfig {
        technique: "none".into(),
        ..AoConfig::default()
    };
    let extent = s.extent();
    let mut r = Renderer::new(
        ctx.gpu.clone(),
        ctx.shaders.clone(),
        &ctx.registry,
        scene.clone(),
        &none,
        FrameOutputs {
            surfaces: true,
            surface_normals: s.normals,
            linear_depth: true,
            motion: instances_move,
            ..Default::default()
        },
        extent,
    )?;
    let reference = crate::frame_reference::ReferenceSettings {
        rays: m.rays,
        ..s.reference(prepared.radius)
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
            let image = trace_surfaces(&scene, time, &surfaces, &reference, false)?;
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
                    let at = super::scaling::median_depth(&moving_depth);
                    let band = if at > 0.0 {
                        super::scaling::radius_in_pixels(&camera, h, prepared.radius, at)
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

/// One row of motion.csv: a technique and parameter set over a motion run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MotionRecord {
    pub scene: String,
    pub view: String,
    pub motion: String,
    pub technique: String,
    pub label: String,
    pub params: BTreeMap<String, toml::Value>,
    pub width: u32,
    pub height: u32,
    pub radius: f32,
    pub rays: u32,
    pub fps: f32,
    pub frames: u32,
    pub warmup: u32,
    /// The technique's passes ("total", g-buffer excluded), the whole frame ("frame", what a
    /// frame rate is made of) and each pass, over the measured frames.
    #[serde(flatten)]
    pub times: FrameTimes,
    pub mae_mean: f64,
    pub mae_worst: f64,
    pub edge_mae_mean: Option<f64>,
    pub ssim_mean: f64,
    /// MAE near surfaces that move on their own (`None`: nothing moves on its own).
    pub moving_mae_mean: Option<f64>,
    /// Mean change of a surface point's accessibility from frame to frame (module docs).
    pub flicker: Option<f64>,
    /// Share of the measured pixels that had a history to compare with.
    pub flicker_coverage: Option<f64>,
    /// Per measured frame: MAE.
    pub frame_mae: Vec<f64>,
    pub image: Option<String>,
}

impl MotionRecord {
    pub const CSV_HEADER: &'static str = "scene,view,motion,technique,label,width,height,radius,rays,fps,frames,warmup,timing_source,total_ms_median,total_ms_q1,total_ms_q3,frame_ms_median,mae_mean,mae_worst,edge_mae_mean,ssim_mean,moving_mae_mean,flicker,flicker_coverage";

    pub fn csv_row(&self) -> String {
        let opt = |v: Option<f64>| v.map(|v| format!("{v:.6}")).unwrap_or_default();
        format!(
            "{},{},{},{},\"{}\",{},{},{},{},{},{},{},{},{:.4},{:.4},{:.4},{:.4},{:.6},{:.6},{},{:.6},{},{},{}",
            self.scene,
            self.view,
            self.motion,
            self.technique,
            self.label.replace('"', "\"\""),
            self.width,
            self.height,
            self.radius,
            self.rays,
            self.fps,
            self.frames,
            self.warmup,
            self.times.timing_source,
            self.times.total_ms.median,
            self.times.total_ms.q1,
            self.times.total_ms.q3,
            self.times.frame_ms.median,
            self.mae_mean,
            self.mae_worst,
            opt(self.edge_mae_mean),
            self.ssim_mean,
            opt(self.moving_mae_mean),
            opt(self.flicker),
            opt(self.flicker_coverage),
        )
    }
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
            times.push(&t);
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
    let errors = ctx.gpu.take_errors();
    if !errors.is_empty() {
        return Err(AppError::InvalidArgument {
            name: format!("{} ({})", set.technique, set.label()),
            value: format!("GPU validation errors: {}", errors.join("; ")),
            allowed: "a run without validation errors".into(),
        });
    }
    let record = MotionRecord {
        scene: label.to_string(),
        view: prepared.view.clone(),
        motion: m.kind.name().into(),
        technique: set.technique.clone(),
        label: set.label(),
        params: set.params.clone().into_iter().collect(),
        width: extent.width,
        height: extent.height,
        radius: prepared.radius,
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
    if let Some(dir) = out {
        prepare_output_dir(dir)?;
        let images = dir.join("images");
        std::fs::create_dir_all(&images).map_err(|e| AppError::io("create", &images, e))?;
    }
    let per_run = (s.warmup + s.frames) as u64;
    let pb = progress_bar(0, progress);
    let mut records: Vec<MotionRecord> = Vec::new();
    for source in &plan.scenes {
        let scene = crate::load_scene(source)?;
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
                        file_safe(&label),
                        file_safe(&view.name),
                        set.slug()
                    );
                    images::write_side_by_side(
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
                    write_motion_files(dir, &records)?;
                }
            }
        }
    }
    pb.finish_and_clear();
    Ok(records)
}

fn write_motion_files(dir: &Path, records: &[MotionRecord]) -> AppResult<()> {
    let mut csv = format!("{}\n", MotionRecord::CSV_HEADER);
    let mut per_frame = String::from("scene,view,motion,technique,label,frame,mae\n");
    for r in records {
        csv.push_str(&r.csv_row());
        csv.push('\n');
        for (i, mae) in r.frame_mae.iter().enumerate() {
            per_frame.push_str(&format!(
                "{},{},{},{},\"{}\",{},{:.6}\n",
                r.scene,
                r.view,
                r.motion,
                r.technique,
                r.label.replace('"', "\"\""),
                i,
                mae
            ));
        }
    }
    write_atomic(&dir.join("motion.csv"), csv.as_bytes())?;
    write_atomic(&dir.join("motion_frames.csv"), per_frame.as_bytes())?;
    let json = serde_json::to_string_pretty(records)
        .map_err(|e| AppError::io("serialise", dir.join("motion.json"), e))?;
    write_atomic(&dir.join("motion.json"), json.as_bytes())?;
    write_atomic(&dir.join("motion.md"), motion_report(records).as_bytes())
}

/// motion.md: one table per scene, view and motion.
pub fn motion_report(records: &[MotionRecord]) -> String {
    let mut md = String::from("# aograph bench: techniques under motion\n\n");
    md.push_str(
        "Every measured frame is scored against its own reference. Flicker: mean change of a \
         surface point's accessibility from one frame to the next (pixels with a history on \
         the same surface; coverage = their share). Near moving: MAE within R of surfaces that \
         move on their own.\n",
    );
    let mut keys: Vec<(String, String, String)> = Vec::new();
    for r in records {
        let k = (r.scene.clone(), r.view.clone(), r.motion.clone());
        if !keys.contains(&k) {
            keys.push(k);
        }
    }
    let opt = |v: Option<f64>| v.map(|v| format!("{v:.4}")).unwrap_or_else(|| "-".into());
    for (scene, view, motion) in keys {
        let rows: Vec<&MotionRecord> = records
            .iter()
            .filter(|r| r.scene == scene && r.view == view && r.motion == motion)
            .collect();
        let first = rows[0];
        md.push_str(&format!(
            "\n## {scene} / {view}, motion `{motion}`\n\n{}x{}, {} frames at {} fps after {} warm-up, R = {}, {} rays/pixel, {}\n\n",
            first.width, first.height, first.frames, first.fps, first.warmup, first.radius,
            first.rays, first.times.timing_source
        ));
        md.push_str("| technique | parameters | total ms | frame ms | MAE mean | MAE worst | edge MAE | SSIM | near moving MAE | flicker | coverage |\n|---|---|---|---|---|---|---|---|---|---|---|\n");
        for r in rows {
            md.push_str(&format!(
                "| {} | {} | {:.2} | {:.2} | {:.4} | {:.4} | {} | {:.3} | {} | {} | {} |\n",
                r.technique,
                r.label,
                r.times.total_ms.median,
                r.times.frame_ms.median,
                r.mae_mean,
                r.mae_worst,
                opt(r.edge_mae_mean),
                r.ssim_mean,
                opt(r.moving_mae_mean),
                opt(r.flicker),
                r.flicker_coverage
                    .map(|c| format!("{:.0}%", 100.0 * c))
                    .unwrap_or_else(|| "-".into()),
            ));
        }
        md.push_str("\nPer pass (median ms over the measured frames, in execution order):\n\n");
        for r in records
            .iter()
            .filter(|r| r.scene == scene && r.view == view && r.motion == motion)
        {
            let passes: Vec<String> = r
                .times
                .passes
                .iter()
                .map(|p| format!("{} {:.2}", p.name, p.ms.median))
                .collect();
            md.push_str(&format!(
                "- {} {}: {}\n",
                r.technique,
                r.label,
                passes.join(", ")
            ));
        }
    }
    md
}

#[cfg(test)]
mod tests {
    use super::*;

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

    /// A wall at z = 0 seen from cameras on the +z side: its points, valid everywhere.
    fn wall(cam: &Camera, w: u32, h: u32) -> (Vec<Vec3>, Vec<f32>) {
        plane(cam, Vec3::Z, w, h)
    }

    /// The plane through the origin with normal `n`, seen from `cam` (every ray hits it).
    fn plane(cam: &Camera, n: Vec3, w: u32, h: u32) -> (Vec<Vec3>, Vec<f32>) {
        let aspect = w as f32 / h as f32;
        let (mut points, mut depth) = (Vec::new(), Vec::new());
        for y in 0..h {
            for x in 0..w {
                let ndc = Vec2::new(
                    (x as f32 + 0.5) / w as f32 * 2.0 - 1.0,
                    1.0 - (y as f32 + 0.5) / h as f32 * 2.0,
                );
                let ray = cam.primary_ray(ndc, aspect);
                let t = -ray.origin.dot(n) / ray.direction.dot(n);
                let p = ray.origin + ray.direction * t;
                points.push(p);
                depth.push(-cam.view().transform_point3(p).z);
            }
        }
        (points, depth)
    }

    #[test]
    fn a_still_camera_maps_every_pixel_onto_itself() {
        let cam = Camera::perspective(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO, 1.0, 0.1, 50.0);
        let (w, h) = (16, 12);
        let (points, depth) = wall(&cam, w, h);
        let valid = vec![true; (w * h) as usize];
        let rp = Reprojection::new(&points, &valid, None, &cam, &depth, w, h);
        for (i, t) in rp.taps.iter().enumerate() {
            let (index, weight) = t.expect("every pixel keeps its history, the edges' too");
            // The pixel itself carries the weight (it may sit in any corner of the footprint:
            // at the edges, or when its centre rounds to the texel below).
            let own = index.iter().position(|&j| j == i as u32).expect("itself");
            assert!((weight[own] - 1.0).abs() < 1e-3, "{weight:?}");
        }
        let ao: Vec<f32> = (0..w * h).map(|i| i as f32 / 100.0).collect();
        let (sum, n) = rp.change(&ao, &ao);
        assert!(n > 0 && sum < 1e-3 * n as f64);
    }

    #[test]
    fn a_sideways_step_of_one_pixel_finds_the_neighbour_and_measures_no_change_on_a_ramp() {
        // Moving the camera one pixel's width to the right moves the wall one pixel left on
        // screen: pixel x now shows what pixel x + 1 showed. A horizontal ramp of
        // accessibility that moves with the surface changes by nothing.
        let (w, h) = (16u32, 8u32);
        let prev = Camera::perspective(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO, 1.0, 0.1, 50.0);
        let pixel = 2.0 * 4.0 * (0.5f32).tan() / h as f32;
        let step = Vec3::new(pixel, 0.0, 0.0);
        let cur = Camera {
            position: prev.position + step,
            target: prev.target + step,
            ..prev
        };
        let (prev_points, prev_depth) = wall(&prev, w, h);
        let (points, _) = wall(&cur, w, h);
        let valid = vec![true; (w * h) as usize];
        let rp = Reprojection::new(&points, &valid, None, &prev, &prev_depth, w, h);
        let ramp = |p: &Vec3| p.x * 0.1 + 0.5;
        let before: Vec<f32> = prev_points.iter().map(ramp).collect();
        let now: Vec<f32> = points.iter().map(ramp).collect();
        let (index, weight) = rp.taps[(2 * w + 3) as usize].expect("history");
        assert_eq!(index[0], 2 * w + 4);
        assert!(weight[0] > 0.999, "{weight:?}");
        let (sum, n) = rp.change(&now, &before);
        assert!(n >= ((w - 1) * h) as usize, "{n}");
        assert!(sum / (n as f64) < 1e-5, "{}", sum / n as f64);
        // The same frames with the accessibility left where it was on screen (a technique
        // that does not follow its surface) measure the ramp's step per pixel.
        let (sum, n) = rp.change(&before, &before);
        assert!((sum / n as f64 - f64::from(0.1 * pixel)).abs() < 1e-5);
    }

    #[test]
    fn a_depth_jump_leaves_the_pixel_without_history() {
        let cam = Camera::perspective(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO, 1.0, 0.1, 50.0);
        let (w, h) = (8, 8);
        let (points, mut depth) = wall(&cam, w, h);
        depth[(3 * w + 3) as usize] *= 0.5; // something at half the depth was there
        let valid = vec![true; (w * h) as usize];
        let rp = Reprojection::new(&points, &valid, None, &cam, &depth, w, h);
        assert!(rp.taps[(3 * w + 3) as usize].is_none());
        assert!(
            rp.taps[(2 * w + 2) as usize].is_none(),
            "its bilinear footprint holds it"
        );
        assert!(rp.taps[(5 * w + 5) as usize].is_some());
    }

    #[test]
    fn a_floor_seen_at_a_grazing_angle_keeps_its_history() {
        // Looking down at 15 degrees onto a floor: linear depth changes by several percent from
        // row to row, which is one surface, not a silhouette.
        let cam = Camera::perspective(
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(0.0, 1.0 - (15f32).to_radians().tan() * 10.0, -10.0),
            0.2,
            0.1,
            500.0,
        );
        let (w, h) = (32, 32);
        let (points, depth) = plane(&cam, Vec3::Y, w, h);
        let rows = depth[0] / depth[w as usize];
        assert!(rows > 1.03, "the test needs a steep depth gradient: {rows}");
        let valid = vec![true; (w * h) as usize];
        let rp = Reprojection::new(&points, &valid, None, &cam, &depth, w, h);
        let kept = rp.taps.iter().filter(|t| t.is_some()).count();
        assert_eq!(kept, (w * h) as usize);
    }

    #[test]
    fn dilation_grows_a_pixel_into_a_square_inside_the_valid_pixels() {
        let (w, h) = (7, 5);
        let mut mask = vec![false; 35];
        mask[2 * 7 + 3] = true;
        let mut valid = vec![true; 35];
        valid[7 + 2] = false;
        let d = dilate(&mask, &valid, w, h, 1);
        let set: Vec<usize> = (0..35).filter(|i| d[*i]).collect();
        assert_eq!(set, vec![10, 11, 16, 17, 18, 23, 24, 25]);
    }
}
