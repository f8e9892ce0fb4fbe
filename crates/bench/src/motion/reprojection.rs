//! Following each pixel's surface into the previous frame (the flicker of a moving camera)
//! and finding the pixels near surfaces that move on their own.
//!
//! Invariant: a pixel gets a history only where all four bilinear taps in the previous frame
//! lie on the surface it shows now, so a disocclusion or a silhouette never counts as change.

use aograph_scene::Camera;
use glam::{Vec2, Vec3};

/// Two depths belong to the same surface when they differ by at most this share.
pub const SAME_SURFACE_DEPTH: f32 = 0.01;
/// A bilinear footprint whose farthest depth exceeds its nearest by more than this factor
/// straddles a silhouette.
pub const SILHOUETTE_RATIO: f32 = 1.25;
/// A pixel's surface moves on its own when its motion, less the camera's, exceeds this (px).
pub const MOVING_PIXELS: f32 = 0.25;

/// Four texels of the previous frame and their bilinear weights.
pub type BilinearTaps = ([u32; 4], [f32; 4]);

/// Where each pixel's surface was in the previous frame (`None`: no history there).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Reprojection {
    /// Per pixel of the current frame, row-major: the four previous-frame texels its surface
    /// lands among and their bilinear weights; `None` where it has no history (sky, off screen,
    /// disoccluded, or across a silhouette).
    pub taps: Vec<Option<BilinearTaps>>,
}

impl Reprojection {
    /// `points` (world space, valid where `valid`) seen in the previous frame: through
    /// `prev_camera`, or at uv + `motion` (the g-buffer's RGBA: previous uv - current uv,
    /// previous linear depth) where given; kept
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
                // The point's previous depth: the g-buffer's 3D motion where given, else through
                // the previous camera (exact for static geometry).
                let expected = match motion {
                    Some(m) if m[4 * i + 2] > 0.0 => m[4 * i + 2],
                    _ => -view.transform_point3(p).z,
                };
                let uv = match motion {
                    Some(m) => pixel_uv(i, w, h) + Vec2::new(m[4 * i], m[4 * i + 1]),
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

/// Pixels whose surface moves on its own: `motion` (the g-buffer's RGBA) less what the camera
/// alone explains, across the screen (more than [`MOVING_PIXELS`]) or along the view axis (a
/// previous depth off the camera-only one by more than [`SAME_SURFACE_DEPTH`]).
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
    let view = prev_camera.view();
    let size = Vec2::new(width as f32, height as f32);
    (0..w * h)
        .map(|i| {
            if !valid[i] {
                return false;
            }
            let uv = pixel_uv(i, w, h);
            let moved = uv + Vec2::new(motion[4 * i], motion[4 * i + 1]);
            let depth = -view.transform_point3(points[i]).z;
            let previous = motion[4 * i + 2];
            let along = previous > 0.0 && (previous - depth).abs() > SAME_SURFACE_DEPTH * depth;
            match clip_uv(vp * points[i].extend(1.0)) {
                Some(camera_only) => {
                    along || ((moved - camera_only) * size).length() > MOVING_PIXELS
                }
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

#[cfg(test)]
mod tests {
    use super::*;

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
