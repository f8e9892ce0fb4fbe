//! Hand-made inputs of the MSSAO golden tests: the octahedral encoding of the normals (as
//! shaders/common/normal_oct.wgsl), g-buffers built on the CPU (a box scene cast ray by ray:
//! exact world points and normals) and the cameras that view them.

use super::*;

// ---------------------------------------------------------------------------------------------
// Octahedral normals (the g-buffer's `normals_oct` and the pyramid's normals are R32Uint)

/// `normal_oct_encode` (aograph_frame::normal_oct, the shader's CPU side).
pub(crate) fn oct_encode(n: V3) -> u32 {
    aograph_frame::normal_oct::encode(n)
}

/// `normal_oct_decode`: a unit vector (0 decodes to +z).
pub(crate) fn oct_decode(b: u32) -> V3 {
    aograph_frame::normal_oct::decode(b)
}

/// f32 to f16 bits, round to nearest even (values in the normal f16 range or below): the
/// temporal filter's `Normals` channel is Rgba16Float.
pub(crate) fn f16_bits(x: f32) -> u16 {
    let b = x.to_bits();
    let sign = ((b >> 16) & 0x8000) as u16;
    if x == 0.0 {
        return sign;
    }
    let e = ((b >> 23) & 0xff) as i32 - 127 + 15;
    assert!(e < 31, "{x} overflows f16");
    if e <= 0 {
        // Subnormal: units of 2^-24 (x * 2^24 is exact).
        return sign | (x.abs() * 16_777_216.0).round_ties_even() as u16;
    }
    let m = b & 0x7f_ffff;
    let mut h = ((e as u32) << 10) | (m >> 13);
    let rest = m & 0x1fff;
    if rest > 0x1000 || (rest == 0x1000 && h & 1 == 1) {
        h += 1;
    }
    sign | h as u16
}

// ---------------------------------------------------------------------------------------------
// Hand-made g-buffers

/// View-space positions (w = 1 on geometry, 0 on sky) and normals, octahedral as the GPU
/// holds them (`normals_oct`; `normals` their decoded unit vectors), row-major. The GPU gets
/// the positions' linear depth only and rebuilds positions on their pixels' centre rays.
#[derive(Clone)]
pub(crate) struct GBuffer {
    pub(crate) w: usize,
    pub(crate) h: usize,
    pub(crate) positions: Vec<V4>,
    pub(crate) normals: Vec<V4>,
    pub(crate) normals_oct: Vec<u32>,
}

impl GBuffer {
    pub(crate) fn sky(w: usize, h: usize) -> Self {
        Self {
            w,
            h,
            positions: vec![[0.0; 4]; w * h],
            normals: vec![[0.0; 4]; w * h],
            normals_oct: vec![0; w * h],
        }
    }
    pub(crate) fn set(&mut self, x: usize, y: usize, p: V3, n: V3) {
        let i = y * self.w + x;
        self.positions[i] = [p[0], p[1], p[2], 1.0];
        self.normals_oct[i] = oct_encode(n);
        let d = oct_decode(self.normals_oct[i]);
        self.normals[i] = [d[0], d[1], d[2], 1.0];
    }
    /// Linear depth as the g-buffer writes it: -z on geometry, 0 on sky.
    pub(crate) fn linear_depth(&self) -> Vec<f32> {
        self.positions
            .iter()
            .map(|p| {
                if p[3] > 0.5 && -p[2] > 0.0 {
                    -p[2]
                } else {
                    0.0
                }
            })
            .collect()
    }
    /// Level 0 as the GPU sees it: depth and octahedral normals, positions rebuilt on `grid`.
    pub(crate) fn level(&self, grid: &Grid) -> Level {
        Level::rebuild(
            self.w,
            self.h,
            self.linear_depth(),
            self.normals_oct.clone(),
            grid,
        )
    }
}

/// The box scene of the kernel and upsampling tests, in world space: a floor, a back wall
/// (sky above it) and three boxes, so that depths run from 2.1 to 9.2 and every level sees
/// concave corners, depth edges and sky.
pub(crate) fn boxes() -> Vec<(DVec3, DVec3)> {
    vec![
        (DVec3::new(-20.0, -1.4, -30.0), DVec3::new(20.0, -1.2, -1.0)),
        (DVec3::new(-20.0, -1.4, -9.2), DVec3::new(20.0, 2.0, -9.0)),
        (DVec3::new(-1.5, -1.2, -5.0), DVec3::new(0.3, -0.2, -3.5)),
        (DVec3::new(1.0, -1.2, -3.2), DVec3::new(2.2, 0.6, -2.4)),
        (DVec3::new(-3.2, -1.2, -7.0), DVec3::new(-2.4, 1.5, -6.2)),
    ]
}

/// Entry distance and face normal of the ray `o + t d` into an axis-aligned box.
pub(crate) fn hit_box(o: DVec3, d: DVec3, lo: DVec3, hi: DVec3) -> Option<(f64, DVec3)> {
    let (mut t0, mut t1, mut n) = (f64::NEG_INFINITY, f64::INFINITY, DVec3::ZERO);
    for a in 0..3 {
        if d[a].abs() < 1e-12 {
            if o[a] < lo[a] || o[a] > hi[a] {
                return None;
            }
            continue;
        }
        let (ta, tb) = ((lo[a] - o[a]) / d[a], (hi[a] - o[a]) / d[a]);
        if ta.min(tb) > t0 {
            t0 = ta.min(tb);
            n = DVec3::ZERO;
            n[a] = -d[a].signum();
        }
        t1 = t1.min(ta.max(tb));
    }
    (t0 <= t1 && t0 > 0.0).then_some((t0, n))
}

/// The g-buffer of `scene` seen by the perspective `camera` (rays through pixel centres, in
/// f64), and the world point of every pixel (None on sky).
pub(crate) fn cast(
    camera: &Camera,
    w: usize,
    h: usize,
    scene: &[(DVec3, DVec3)],
) -> (GBuffer, Vec<Option<DVec3>>) {
    let t = (camera.fov_y().expect("perspective") as f64 * 0.5).tan();
    let aspect = w as f64 / h as f64;
    let (right, up, forward) = camera.basis();
    let (right, up, forward) = (right.as_dvec3(), up.as_dvec3(), forward.as_dvec3());
    let view = camera.view().as_dmat4();
    let origin = camera.position.as_dvec3();
    let mut g = GBuffer::sky(w, h);
    let mut world = vec![None; w * h];
    for y in 0..h {
        for x in 0..w {
            let ndc_x = (x as f64 + 0.5) / w as f64 * 2.0 - 1.0;
            let ndc_y = 1.0 - (y as f64 + 0.5) / h as f64 * 2.0;
            let d = right * (ndc_x * t * aspect) + up * (ndc_y * t) + forward;
            let hit = scene
                .iter()
                .filter_map(|(lo, hi)| hit_box(origin, d, *lo, *hi))
                .min_by(|a, b| a.0.total_cmp(&b.0));
            if let Some((t_hit, n)) = hit {
                let p = origin + d * t_hit;
                let pv = view.transform_point3(p).as_vec3();
                let nv = view.transform_vector3(n).normalize().as_vec3();
                g.set(x, y, pv.to_array(), nv.to_array());
                world[y * w + x] = Some(p);
            }
        }
    }
    (g, world)
}

/// The kernel tests' camera: at the origin looking down -Z (view = world), 60 degrees.
pub(crate) fn front_camera() -> Camera {
    Camera::perspective(Vec3::ZERO, Vec3::NEG_Z, 60f32.to_radians(), 0.1, 100.0)
}

/// Odd sizes on purpose: the pyramid is 50x38, 25x19, 13x10, 7x5 (clamped 2x2 fetches).
pub(crate) const W: usize = 50;
pub(crate) const H: usize = 38;
