//! The CPU mirror of shaders/ao/ssdo/{direct,indirect,blur_x,blur_y}.wgsl: the same taps,
//! verdicts, sums and blur, pixel by pixel, on the g-buffer the GPU drew (read back into
//! [`Frame`]). The shaders' `!(x > y)` tests are kept, false for NaN as in WGSL.
//!
//! Invariant: each factor of E1, the light's vote and E2 enters here exactly once, as in the
//! shaders, so a factor changed on either side moves the comparison.

// The mirror keeps the shaders' `!(x > y)` tests, which are false for NaN as in WGSL.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use aograph_ao_passes::techniques::ssdo::kernel::SsdoUniform;
use glam::{Mat3, Mat4, Vec3, Vec4};

/// What the shaders read, read back from the GPU frame.
pub(crate) struct Frame {
    pub(crate) w: i32,
    pub(crate) h: i32,
    /// View-space positions, w = 1 on geometry.
    pub(crate) positions: Vec<Vec4>,
    /// The g-buffer's (shading) normals, view space.
    pub(crate) normals: Vec<Vec3>,
    pub(crate) albedo: Vec<Vec3>,
    /// The g-buffer's unshadowed directional light, rho E max(0, n.l).
    pub(crate) direct_light: Vec<Vec3>,
    /// Towards the directional light, view space.
    pub(crate) to_light: Vec3,
    pub(crate) proj: Mat4,
    /// World up in view space (the sky gradient's axis).
    pub(crate) up: Vec3,
    pub(crate) ambient: Vec3,
}

/// What the CPU computes per pixel: the raw passes, then the blur.
#[derive(Clone, Copy, Default)]
pub(crate) struct Raw {
    /// rgb = L_dir, a = accessibility (ssdo.direct).
    pub(crate) direct: Vec4,
    /// L_ind (ssdo.indirect).
    pub(crate) indirect: Vec3,
}

pub(crate) fn normalize(v: Vec3) -> Vec3 {
    let l = v.length();
    if l > 1e-20 { v / l } else { Vec3::ZERO }
}

pub(crate) fn smoothstep(e0: f32, e1: f32, x: f32) -> f32 {
    let t = ((x - e0) / (e1 - e0).max(1e-20)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// common.wgsl `ssdo_frame`: (t, b, n) as columns (Duff et al. 2017).
pub(crate) fn frame_of(n: Vec3) -> Mat3 {
    let s = if n.z >= 0.0 { 1.0 } else { -1.0 };
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    Mat3::from_cols(
        Vec3::new(1.0 + s * n.x * n.x * a, s * b, -s * n.x),
        Vec3::new(b, s + n.y * n.y * a, -n.y),
        n,
    )
}

/// noise.wgsl `interleave_4x4`.
pub(crate) fn interleave(x: i32, y: i32) -> usize {
    const BAYER: [usize; 16] = [0, 8, 2, 10, 12, 4, 14, 6, 3, 11, 1, 9, 15, 7, 13, 5];
    BAYER[((y & 3) * 4 + (x & 3)) as usize]
}

/// common.wgsl `ssdo_ray_plane` from the eye (perspective).
pub(crate) fn ray_plane(d: Vec3, p: Vec3, n: Vec3) -> f32 {
    let den = d.dot(n);
    if !(den.abs() > 1e-4) {
        return -1.0;
    }
    let t = p.dot(n) / den;
    if t > 0.0 && t < 1e30 { t } else { -1.0 }
}

/// common.wgsl `ssdo_tap` (perspective): (occlusion 1 - V, the blocker's pixel index).
pub(crate) fn tap(f: &Frame, u: &SsdoUniform, p: Vec3, n: Vec3, s: Vec3) -> (f32, usize) {
    let c = f.proj * s.extend(1.0);
    if !(c.w > 1e-6) {
        return (0.0, 0);
    }
    let (nx, ny) = (c.x / c.w, c.y / c.w);
    let uv = (nx * 0.5 + 0.5, 0.5 - ny * 0.5);
    if !(uv.0 >= 0.0 && uv.1 >= 0.0 && uv.0 < 1.0 && uv.1 < 1.0) {
        return (0.0, 0);
    }
    let qx = ((uv.0 * f.w as f32).floor() as i32).clamp(0, f.w - 1);
    let qy = ((uv.1 * f.h as f32).floor() as i32).clamp(0, f.h - 1);
    let q = (qy * f.w + qx) as usize;
    let qp = f.positions[q];
    if qp.w < 0.5 {
        return (0.0, q);
    }
    let sq = qp.truncate();
    if n.dot(sq - p) <= u.bias {
        return (0.0, q);
    }
    let (ds, dq) = (normalize(s), normalize(sq));
    let (t_s, t_q) = (s.dot(ds), sq.dot(dq));
    let (plane_s, plane_q) = (ray_plane(ds, p, n), ray_plane(dq, p, n));
    let mut nearer = t_s - t_q;
    if plane_s > 0.0 && plane_q > 0.0 {
        nearer = (plane_q - t_q) - (plane_s - t_s);
    }
    if nearer > u.bias {
        (
            1.0 - smoothstep(u.fade_start, u.r_max, (sq - p).length()),
            q,
        )
    } else {
        (0.0, q)
    }
}

/// The samples of pixel (x, y) as (occlusion, blocker pixel, unit direction, cos theta).
pub(crate) fn samples(f: &Frame, u: &SsdoUniform, x: i32, y: i32) -> Vec<(f32, usize, Vec3, f32)> {
    let i = (y * f.w + x) as usize;
    let (p, n) = (f.positions[i].truncate(), f.normals[i]);
    let frame = frame_of(n);
    let set = interleave(x, y);
    (0..u.sample_count.min(16) as usize)
        .map(|k| {
            let s = u.samples[set * 16 + k];
            let offset = frame * Vec3::new(s[0], s[1], s[2]);
            let (occ, q) = tap(f, u, p, n, p + offset * u.r_max);
            (occ, q, normalize(offset), s[3])
        })
        .collect()
}

/// What the CPU mirror counts on the way: the share of the bounce's sender taps closer than
/// `distance_clamp` (where the clamp binds), and the share of lit pixels whose directional
/// light the samples find blocked by a tenth or more (sun visibility under 0.9).
#[derive(Clone, Copy, Default)]
pub(crate) struct MirrorCounts {
    pub(crate) clamped: f64,
    pub(crate) sun_shadowed: f64,
}

/// direct.wgsl (ambient environment, with the directional light's vote) and indirect.wgsl at
/// every pixel.
pub(crate) fn raw_passes(f: &Frame, u: &SsdoUniform) -> (Vec<Raw>, MirrorCounts) {
    let n_px = (f.w * f.h) as usize;
    let mut raw = vec![Raw::default(); n_px];
    let mut taps = vec![Vec::new(); n_px];
    let (mut lit, mut shadowed) = (0usize, 0usize);
    for y in 0..f.h {
        for x in 0..f.w {
            let i = (y * f.w + x) as usize;
            if f.positions[i].w < 0.5 {
                raw[i].direct = Vec4::new(0.0, 0.0, 0.0, 1.0);
                continue;
            }
            let rho = f.albedo[i];
            let sun = f.direct_light[i];
            if !(f.normals[i].length_squared() > 0.5) {
                raw[i].direct = (rho * f.ambient + sun).extend(1.0);
                continue;
            }
            let t = samples(f, u, x, y);
            // E1, dw normalised per set: L_dir = rho sum L_in V cos / sum cos; the directional
            // light's vote: sum V max(0, w.l)^k / sum max(0, w.l)^k.
            let (mut env, mut sum_cos, mut visible_cos) = (Vec3::ZERO, 0.0f32, 0.0f32);
            let (mut sun_weight, mut sun_visible) = (0.0f32, 0.0f32);
            for &(occ, _, w, cos_t) in &t {
                let v = 1.0 - occ;
                let l_in = f.ambient * (1.0 + u.sky_gradient * w.dot(f.up)).max(0.0);
                env += l_in * (v * cos_t);
                sum_cos += cos_t;
                visible_cos += v * cos_t;
                let lw = w.dot(f.to_light).max(0.0).powf(u.light_lobe);
                sun_weight += lw;
                sun_visible += lw * v;
            }
            let (a, env_mean) = if sum_cos > 1e-6 {
                (visible_cos / sum_cos, env / sum_cos)
            } else {
                (1.0, f.ambient)
            };
            let sun_visibility = if sun_weight > 1e-6 {
                sun_visible / sun_weight
            } else {
                1.0
            };
            lit += (sun.max_element() > 1e-3) as usize;
            shadowed += (sun.max_element() > 1e-3 && sun_visibility < 0.9) as usize;
            raw[i].direct = (rho * env_mean + sun * sun_visibility).extend(a);
            taps[i] = t;
        }
    }
    // E2 on the unblurred pass-1 radiance of each blocker's pixel.
    let (mut senders, mut clamped) = (0usize, 0usize);
    for i in 0..n_px {
        let (p, n) = (f.positions[i].truncate(), f.normals[i]);
        let mut gathered = Vec3::ZERO;
        for &(occ, q, _, _) in &taps[i] {
            if occ <= 0.0 {
                continue;
            }
            let t = f.positions[q].truncate() - p;
            let d = t.length();
            if d > 1e-6 {
                let dir = t / d;
                let cos_s = f.normals[q].dot(-dir).max(0.0);
                let cos_r = n.dot(dir).max(0.0);
                let dc = d.max(u.distance_clamp);
                senders += 1;
                clamped += (d < u.distance_clamp) as usize;
                gathered += raw[q].direct.truncate() * (occ * cos_s * cos_r / (dc * dc));
            }
        }
        raw[i].indirect = f.albedo[i] * (u.sender_area / std::f32::consts::PI) * gathered;
    }
    let counts = MirrorCounts {
        clamped: clamped as f64 / senders.max(1) as f64,
        sun_shadowed: shadowed as f64 / lit.max(1) as f64,
    };
    (raw, counts)
}

/// common.wgsl `ssdo_blur` along `axis` at every pixel.
pub(crate) fn blur(f: &Frame, u: &SsdoUniform, src: &[Raw], axis: (i32, i32)) -> Vec<Raw> {
    let tol = u.blur_plane_tolerance.max(1e-20);
    (0..f.w * f.h)
        .map(|i| {
            let (x, y) = (i % f.w, i / f.w);
            let mut out = src[i as usize];
            let pw = f.positions[i as usize];
            if pw.w < 0.5 {
                return out;
            }
            let n = f.normals[i as usize];
            let mut sum_w = 1.0;
            for k in -2..=2i32 {
                let (qx, qy) = (x + axis.0 * k, y + axis.1 * k);
                if k == 0 || qx < 0 || qy < 0 || qx >= f.w || qy >= f.h {
                    continue;
                }
                let q = (qy * f.w + qx) as usize;
                let qp = f.positions[q];
                if qp.w < 0.5 {
                    continue;
                }
                let w = if k.abs() == 2 { 0.5 } else { 1.0 }
                    * n.dot(f.normals[q]).max(0.0).powf(8.0)
                    * (1.0 - (qp.truncate() - pw.truncate()).dot(n).abs() / tol).max(0.0);
                if w > 0.0 {
                    out.direct += w * src[q].direct;
                    out.indirect += w * src[q].indirect;
                    sum_w += w;
                }
            }
            out.direct /= sum_w;
            out.indirect /= sum_w;
            out
        })
        .collect()
}
