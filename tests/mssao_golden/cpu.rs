//! The CPU mirror of MSSAO's shader arithmetic (shaders/common/mssao.wgsl and the pass files),
//! fed with the GPU's own output of the previous pass so each pass is checked on its own.

use super::*;

// ---------------------------------------------------------------------------------------------
// CPU mirror of shaders/common/mssao.wgsl and the pass files (same f32 operations, same order)

/// One pyramid level: what the GPU stores (linear depth `z`, octahedral normals `bits`) and
/// what its passes see (positions rebuilt at texel centres, decoded normals; w = 1 on
/// geometry, 0 on sky).
#[derive(Clone)]
pub(crate) struct Level {
    pub(crate) w: usize,
    pub(crate) h: usize,
    pub(crate) z: Vec<f32>,
    pub(crate) bits: Vec<u32>,
    pub(crate) p: Vec<V4>,
    pub(crate) n: Vec<V4>,
}

/// `MssaoGrid`: the full-resolution pixel-to-view map (`pixel_to_view` in
/// shaders/common/view.wgsl, same f32 operations) and the level's texel size in pixels.
#[derive(Clone, Copy)]
pub(crate) struct Grid {
    pub(crate) scale: [f32; 2],
    pub(crate) offset: [f32; 2],
    pub(crate) perspective: bool,
    pub(crate) texel: f32,
    pub(crate) full: [f32; 2],
}

impl Grid {
    pub(crate) fn new(u: &ViewUniforms, level: u32) -> Self {
        let s = [u.proj[0][0], u.proj[1][1]];
        let inv = u.inv_size;
        let perspective = u.orthographic <= 0.5;
        let shift = if perspective {
            [u.proj[2][0], u.proj[2][1]]
        } else {
            [-u.proj[3][0], -u.proj[3][1]]
        };
        Self {
            scale: [2.0 * inv[0] / s[0], -2.0 * inv[1] / s[1]],
            offset: [(-1.0 + shift[0]) / s[0], (1.0 + shift[1]) / s[1]],
            perspective,
            texel: (1u32 << level) as f32,
            full: u.size,
        }
    }
    /// `mssao_texel_centre`: the centre of the full-resolution pixels texel (x, y) covers.
    pub(crate) fn centre(&self, x: usize, y: usize) -> [f32; 2] {
        let c = |v: usize, full: f32| {
            let lo = v as f32 * self.texel;
            0.5 * (lo + (lo + self.texel).min(full))
        };
        [c(x, self.full[0]), c(y, self.full[1])]
    }
    /// `mssao_position`: texel (x, y) with depth z, rebuilt at the texel's centre.
    pub(crate) fn position(&self, x: usize, y: usize, z: f32) -> V3 {
        let px = self.centre(x, y);
        let k = if self.perspective { z } else { 1.0 };
        [
            (px[0] * self.scale[0] + self.offset[0]) * k,
            (px[1] * self.scale[1] + self.offset[1]) * k,
            -z,
        ]
    }
}

/// `mssao_is_geometry`.
pub(crate) fn is_geometry(z: f32) -> bool {
    z > 0.0 && z < 3.0e38
}

impl Level {
    /// The level the passes see from stored depth and normals.
    pub(crate) fn rebuild(w: usize, h: usize, z: Vec<f32>, bits: Vec<u32>, grid: &Grid) -> Self {
        let mut p = vec![[0.0; 4]; w * h];
        let mut n = vec![[0.0; 4]; w * h];
        for y in 0..h {
            for x in 0..w {
                let i = y * w + x;
                let d = oct_decode(bits[i]);
                n[i] = [d[0], d[1], d[2], 1.0];
                if is_geometry(z[i]) {
                    let q = grid.position(x, y, z[i]);
                    p[i] = [q[0], q[1], q[2], 1.0];
                }
            }
        }
        Self {
            w,
            h,
            z,
            bits,
            p,
            n,
        }
    }
}

#[derive(Clone, Copy)]
pub(crate) struct Surface {
    pub(crate) p: V3,
    pub(crate) n: V3,
}

impl Level {
    pub(crate) fn inside(&self, x: i32, y: i32) -> bool {
        x >= 0 && y >= 0 && x < self.w as i32 && y < self.h as i32
    }
    pub(crate) fn index(&self, x: i32, y: i32) -> usize {
        y as usize * self.w + x as usize
    }
    /// `mssao_surface`: geometry where w > 0.5 and the point is in front of the camera.
    pub(crate) fn surface(&self, x: i32, y: i32) -> Option<Surface> {
        let (p, n) = (self.p[self.index(x, y)], self.n[self.index(x, y)]);
        (p[3] > 0.5 && -p[2] > 0.0).then_some(Surface {
            p: [p[0], p[1], p[2]],
            n: [n[0], n[1], n[2]],
        })
    }
}

#[derive(Clone, Copy)]
pub(crate) struct Consts {
    pub(crate) d_max: f32,
    pub(crate) r_max: f32,
    pub(crate) t_n: f32,
    pub(crate) t_z: f32,
    pub(crate) bilateral_blur: bool,
    /// Fig. 8's upsampling: 0 nearest, 1 bilinear, 2 bilateral.
    pub(crate) upsampling: u32,
    /// The view block's proj[1][1] and viewport height (Eq. 5's s / (2 tan(alpha / 2))).
    pub(crate) proj11: f32,
    pub(crate) height: f32,
}

pub(crate) fn dot(a: V3, b: V3) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub(crate) fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// Eqs. 6-7 for one sample: rho(d) * clamp(n . normalize(q - p), 0, 1).
pub(crate) fn sample_ao(p: V3, n: V3, q: V3, d_max: f32) -> f32 {
    let v = sub(q, p);
    let d = dot(v, v).sqrt();
    if d <= 1e-6 * d_max {
        return 0.0;
    }
    let cos_t = dot(n, [v[0] / d, v[1] / d, v[2] / d]).clamp(0.0, 1.0);
    let x = d / d_max;
    let rho = 1.0 - (x * x).min(1.0);
    rho * cos_t
}

/// Eq. 5 (0-based level): min(r_max, d_max * pixels_per_unit(z) / 2^l).
pub(crate) fn kernel_radius(k: &Consts, z: f32, level: u32) -> f32 {
    let scale = k.proj11 * 0.5 * k.height;
    let r0 = k.d_max * (scale / z.max(1e-30));
    k.r_max.min(r0 / (1u32 << level) as f32)
}

/// One tap: (ao, counted). Off screen: skipped; sky: an unoccluding sample.
pub(crate) fn tap(l: &Level, x: i32, y: i32, s: &Surface, d_max: f32) -> (f32, f32) {
    if !l.inside(x, y) {
        return (0.0, 0.0);
    }
    match l.surface(x, y) {
        None => (0.0, 1.0),
        Some(q) => (sample_ao(s.p, s.n, q.p, d_max), 1.0),
    }
}

pub(crate) fn add(a: (f32, f32), b: (f32, f32)) -> (f32, f32) {
    (a.0 + b.0, a.1 + b.1)
}

/// The weight of ring k (the odd offsets with max(|o.x|, |o.y|) = k) at kernel radius R:
/// rising from 0 at R = k - 2 to 1 at R = k (ring 1: from R = 0 to 1).
pub(crate) fn ring_weight(k: i32, radius: f32) -> f32 {
    if k == 1 {
        radius.clamp(0.0, 1.0)
    } else {
        ((radius - k as f32) * 0.5 + 1.0).clamp(0.0, 1.0)
    }
}

/// Coarse levels: the odd offsets +-1, +-3, ... of every ring with a weight (the largest odd
/// k < R + 2), each tap's (ao, counted) times its ring's weight.
pub(crate) fn near_interleaved(
    l: &Level,
    x: i32,
    y: i32,
    s: &Surface,
    radius: f32,
    d_max: f32,
) -> (f32, f32) {
    if radius <= 0.0 || radius.is_nan() {
        return (0.0, 0.0);
    }
    let k = (((radius + 1.0) * 0.5).ceil() as i32 * 2 - 1).min(9);
    let mut acc = (0.0, 0.0);
    for oy in (-k..=k).step_by(2) {
        for ox in (-k..=k).step_by(2) {
            let w = ring_weight(ox.abs().max(oy.abs()), radius);
            let t = tap(l, x + ox, y + oy, s, d_max);
            acc = add(acc, (w * t.0, w * t.1));
        }
    }
    acc
}

/// The finest level's disk (shaders/common/mssao.wgsl, `MSSAO_POISSON`).
pub(crate) const POISSON: [[f32; 2]; 16] = [
    [0.1177, -0.1292],
    [-0.9247, 0.2728],
    [-0.0589, 0.9798],
    [-0.5662, -0.7433],
    [0.8773, 0.4504],
    [0.8872, -0.4327],
    [0.2211, -0.9547],
    [-0.3048, 0.3436],
    [0.2877, 0.4300],
    [-0.4884, -0.1777],
    [-0.6826, 0.7173],
    [0.5895, -0.0524],
    [-0.9586, -0.2593],
    [0.4495, 0.8898],
    [-0.0859, -0.5837],
    [0.3782, -0.5166],
];

/// The finest level: the disk scaled by the radius, rounded (WGSL `round`: ties to even); a
/// point on the pixel itself is skipped.
pub(crate) fn near_poisson(
    l: &Level,
    x: i32,
    y: i32,
    s: &Surface,
    radius: f32,
    d_max: f32,
) -> (f32, f32) {
    if radius < 1.0 {
        return (0.0, 0.0);
    }
    let mut acc = (0.0, 0.0);
    for d in POISSON {
        let o = (
            (d[0] * radius).round_ties_even() as i32,
            (d[1] * radius).round_ties_even() as i32,
        );
        if o == (0, 0) {
            continue;
        }
        acc = add(acc, tap(l, x + o.0, y + o.1, s, d_max));
    }
    acc
}

pub(crate) fn pow01(x: f32, e: f32) -> f32 {
    (e * x.max(1e-30).log2()).exp2()
}

/// Eq. 8 times Eq. 9.
pub(crate) fn bilateral_weight(n: V3, z: f32, ni: V3, zi: f32, t_n: f32, t_z: f32) -> f32 {
    let wn = pow01(((dot(n, ni) + 1.0) * 0.5).clamp(0.0, 1.0), t_n);
    let wz = pow01(1.0 / (1.0 + (zi - z).abs()), t_z);
    wn * wz
}

pub(crate) fn xyz(v: V4) -> V3 {
    [v[0], v[1], v[2]]
}

/// Fig. 9: the 2x2 nearest coarse texels with 9/16, 3/16, 3/16, 1/16 times Eqs. 8-9 (`k.upsampling`
/// 2); the bilinear weights alone (1); the enclosing coarse texel alone (0).
pub(crate) fn upsample(coarse: &[V4], cl: &Level, x: i32, y: i32, s: &Surface, k: &Consts) -> V3 {
    let (mx, my) = (x / 2, y / 2);
    let (dx, dy) = (
        if x & 1 == 1 { 1 } else { -1 },
        if y & 1 == 1 { 1 } else { -1 },
    );
    let taps = [(mx, my), (mx + dx, my), (mx, my + dy), (mx + dx, my + dy)];
    let wb = if k.upsampling == 0 {
        [1.0, 0.0, 0.0, 0.0]
    } else {
        [9.0 / 16.0, 3.0 / 16.0, 3.0 / 16.0, 1.0 / 16.0]
    };
    let (mut sum_bl, mut w_bl, mut sum_lin, mut w_lin) = ([0.0f32; 3], 0.0f32, [0.0f32; 3], 0.0f32);
    for j in 0..4 {
        let (tx, ty) = (
            taps[j].0.clamp(0, cl.w as i32 - 1),
            taps[j].1.clamp(0, cl.h as i32 - 1),
        );
        let Some(q) = cl.surface(tx, ty) else {
            continue;
        };
        if wb[j] <= 0.0 {
            continue;
        }
        let a = xyz(coarse[cl.index(tx, ty)]);
        // Eq. 9 on the coarse point's distance from the fine surface's tangent plane.
        let w = wb[j] * bilateral_weight(s.n, 0.0, q.n, dot(s.n, sub(q.p, s.p)), k.t_n, k.t_z);
        for c in 0..3 {
            sum_bl[c] += w * a[c];
            sum_lin[c] += wb[j] * a[c];
        }
        w_bl += w;
        w_lin += wb[j];
    }
    if k.upsampling == 2 && w_bl > 1e-30 {
        sum_bl.map(|v| v / w_bl)
    } else if w_lin > 0.0 {
        sum_lin.map(|v| v / w_lin)
    } else {
        [0.0; 3]
    }
}

/// Eq. 10: (max(sum / N, far.max), sum + far.sum, N + far.count).
pub(crate) fn combine(near: (f32, f32), far: V3) -> V3 {
    let mean = if near.1 > 0.0 {
        (near.0 / near.1).clamp(0.0, 1.0)
    } else {
        0.0
    };
    [mean.max(far[0]), near.0 + far[1], near.1 + far[2]]
}

/// Eq. 11 as accessibility: (1 - AO_max)(1 - sum / count).
pub(crate) fn accessibility(t: V3) -> f32 {
    let ao_max = t[0].clamp(0.0, 1.0);
    let ao_avg = if t[2] > 1e-6 {
        (t[1] / t[2]).clamp(0.0, 1.0)
    } else {
        0.0
    };
    ((1.0 - ao_max) * (1.0 - ao_avg)).clamp(0.0, 1.0)
}

/// Table 4's 3x3 blur, 1 / ((|dx| + 1)(|dy| + 1)), times Eqs. 8-9 when bilateral, normalised.
pub(crate) fn blur(src: &[V4], l: &Level, k: &Consts) -> Vec<V3> {
    let mut out = vec![[0.0; 3]; l.w * l.h];
    for y in 0..l.h as i32 {
        for x in 0..l.w as i32 {
            let Some(s) = l.surface(x, y) else {
                continue;
            };
            let z = -s.p[2];
            let (mut sum, mut wsum) = ([0.0f32; 3], 0.0f32);
            for dy in -1..=1i32 {
                for dx in -1..=1i32 {
                    let (tx, ty) = (x + dx, y + dy);
                    if !l.inside(tx, ty) {
                        continue;
                    }
                    let Some(q) = l.surface(tx, ty) else {
                        continue;
                    };
                    let mut w = 1.0 / ((dx.abs() + 1) as f32 * (dy.abs() + 1) as f32);
                    if k.bilateral_blur {
                        w *= bilateral_weight(s.n, z, q.n, -q.p[2], k.t_n, k.t_z);
                    }
                    let a = xyz(src[l.index(tx, ty)]);
                    for c in 0..3 {
                        sum[c] += w * a[c];
                    }
                    wsum += w;
                }
            }
            out[l.index(x, y)] = sum.map(|v| v / wsum.max(1e-30));
        }
    }
    out
}

/// `mssao_plane_depth`: where the line of sight through texel (x, y)'s centre meets the plane
/// through p with normal n; 0 where it misses.
pub(crate) fn plane_depth(g: &Grid, x: usize, y: usize, p: V3, n: V3) -> f32 {
    let r = g.position(x, y, 1.0);
    let t = if g.perspective {
        dot(n, p) / dot(n, r)
    } else {
        (n[0] * r[0] + n[1] * r[1] - dot(n, p)) / n[2]
    };
    if t > 0.0 && t < 3.0e38 { t } else { 0.0 }
}

/// Table 2 (downsample.wgsl): sort the 2x2 sub-pixels by depth (sky last, stable), keep the
/// mean position and renormalised mean normal of the middle two when the range is at most
/// d_threshold, else the second-nearest's, and store the depth of that point's plane at the
/// new texel's centre within the block's geometry depths, or sky where a block with sky looks
/// past it there (`src_grid`, `grid`: the levels' grids).
pub(crate) fn downsample(src: &Level, d_threshold: f32, src_grid: &Grid, grid: &Grid) -> Level {
    const SKY: f32 = 3.0e38;
    let (w, h) = (src.w.div_ceil(2), src.h.div_ceil(2));
    let mut depth = vec![0.0f32; w * h];
    let mut bits = vec![0u32; w * h];
    for y in 0..h {
        for x in 0..w {
            let mut nrm = [0u32; 4];
            let mut z = [0.0f32; 4];
            let mut at = [(0usize, 0usize); 4];
            for i in 0..4 {
                let cx = (2 * x + (i & 1)).min(src.w - 1);
                let cy = (2 * y + (i >> 1)).min(src.h - 1);
                let d = src.z[cy * src.w + cx];
                nrm[i] = src.bits[cy * src.w + cx];
                z[i] = if is_geometry(d) { d } else { SKY };
                at[i] = (cx, cy);
            }
            let mut idx = [0usize, 1, 2, 3];
            for i in 1..4 {
                let mut j = i;
                while j > 0 && z[idx[j - 1]] > z[idx[j]] {
                    idx.swap(j, j - 1);
                    j -= 1;
                }
            }
            let (i1, i2) = (idx[1], idx[2]);
            if z[i1] >= SKY {
                continue; // sky: depth 0, code 0
            }
            let p1 = src_grid.position(at[i1].0, at[i1].1, z[i1]);
            let n1 = oct_decode(nrm[i1]);
            let (mut p, mut nv, mut n, mut d) = (p1, n1, nrm[i1], z[i1]);
            // The median candidate and the block's spread about its plane (sky: unbounded).
            let p2 = src_grid.position(at[i2].0, at[i2].1, z[i2]);
            let p_med = [
                0.5 * (p1[0] + p2[0]),
                0.5 * (p1[1] + p2[1]),
                0.5 * (p1[2] + p2[2]),
            ];
            let b = oct_decode(nrm[i2]);
            let s = [n1[0] + b[0], n1[1] + b[1], n1[2] + b[2]];
            let l = dot(s, s).sqrt();
            let n_med = if l > 1e-6 {
                [s[0] / l, s[1] / l, s[2] / l]
            } else {
                n1
            };
            let spread = if z[idx[3]] < SKY {
                let p0 = src_grid.position(at[idx[0]].0, at[idx[0]].1, z[idx[0]]);
                let p3 = src_grid.position(at[idx[3]].0, at[idx[3]].1, z[idx[3]]);
                [p0, p1, p2, p3]
                    .iter()
                    .map(|q| dot(n_med, sub(*q, p_med)).abs())
                    .fold(0.0f32, f32::max)
            } else {
                f32::INFINITY
            };
            if spread <= d_threshold {
                d = 0.5 * (z[i1] + z[i2]);
                p = p_med;
                if l > 1e-6 {
                    nv = n_med;
                    n = oct_encode(nv);
                }
            }
            let hi = if z[i2] < SKY {
                if z[idx[3]] < SKY { z[idx[3]] } else { z[i2] }
            } else {
                z[i1]
            };
            let t = plane_depth(grid, x, y, p, nv);
            if z[idx[3]] >= SKY && !(t > 0.0 && t <= hi) {
                continue; // the centre looks past the surface into the sky
            }
            depth[y * w + x] = if t > 0.0 { t.clamp(z[idx[0]], hi) } else { d };
            bits[y * w + x] = n;
        }
    }
    Level::rebuild(w, h, depth, bits, grid)
}
