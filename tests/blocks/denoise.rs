//! XeGTAO's edge-aware denoiser against its CPU mirror: constants and sky kept.

use aograph_ao_passes::blocks::*;
use aograph_graph::{Extent, SizeClass};
use wgpu::TextureFormat::R32Float;

use super::*;

/// CPU mirror of shaders/blocks/edge_denoise.wgsl (one pass).
fn edge_denoise_cpu(
    ao: &[f32],
    edges: &[[f32; 4]],
    depth: &[f32],
    w: usize,
    h: usize,
    beta: f32,
    last: bool,
) -> Vec<f32> {
    let inside = |x: i64, y: i64| x >= 0 && y >= 0 && x < w as i64 && y < h as i64;
    let e_at = |x: i64, y: i64| {
        if inside(x, y) {
            edges[y as usize * w + x as usize]
        } else {
            [0.0; 4]
        }
    };
    let tap = |x: i64, y: i64, wt: f32| {
        if inside(x, y) && depth[y as usize * w + x as usize] > 0.0 {
            (wt * ao[y as usize * w + x as usize], wt)
        } else {
            (0.0, 0.0)
        }
    };
    let mut out = Vec::with_capacity(w * h);
    for y in 0..h as i64 {
        for x in 0..w as i64 {
            let i = y as usize * w + x as usize;
            if depth[i] <= 0.0 {
                out.push(1.0);
                continue;
            }
            let (l, r, t, b) = (
                e_at(x - 1, y),
                e_at(x + 1, y),
                e_at(x, y - 1),
                e_at(x, y + 1),
            );
            let c = e_at(x, y);
            let mut e = [c[0] * l[1], c[1] * r[0], c[2] * t[3], c[3] * b[2]];
            let leak = (4.0 - 2.5 - e.iter().sum::<f32>()).clamp(0.0, 1.0) / 1.5;
            e.iter_mut()
                .for_each(|v| *v = (*v + leak * 0.5).clamp(0.0, 1.0));
            let d = 0.425;
            let taps = [
                (x - 1, y, e[0]),
                (x + 1, y, e[1]),
                (x, y - 1, e[2]),
                (x, y + 1, e[3]),
                (x - 1, y - 1, d * (e[0] * l[2] + e[2] * t[0])),
                (x + 1, y - 1, d * (e[2] * t[1] + e[1] * r[2])),
                (x - 1, y + 1, d * (e[3] * b[0] + e[0] * l[3])),
                (x + 1, y + 1, d * (e[1] * r[3] + e[3] * b[1])),
            ];
            let (mut sum, mut wsum) = (beta * ao[i], beta);
            for (tx, ty, wt) in taps {
                let (s, ww) = tap(tx, ty, wt);
                sum += s;
                wsum += ww;
            }
            let v = sum / wsum;
            out.push(if last { v.clamp(0.0, 1.0) } else { v });
        }
    }
    out
}

#[test]
fn edge_denoise_matches_the_cpu_keeps_constants_and_sky() {
    let (w, h) = (11usize, 9usize);
    // Raw AO up to 1.5 (gtao's pre-clamp range), sky in one row, and edge weights from the
    // 2-bit levels {0, 1/3, 2/3, 1}.
    let ao: Vec<f32> = noise(w * h, 3).iter().map(|v| 1.5 * v).collect();
    let depth: Vec<f32> = (0..w * h)
        .map(|i| if i / w == 4 { 0.0 } else { 2.0 })
        .collect();
    let edges: Vec<[f32; 4]> = noise(4 * w * h, 5)
        .chunks(4)
        .map(|c| [0, 1, 2, 3].map(|k| (c[k] * 4.0).floor().min(3.0) / 3.0))
        .collect();
    let e = Input {
        name: "edges",
        size: Extent::new(w as u32, h as u32),
        format: wgpu::TextureFormat::Rgba8Unorm,
        data: edges.iter().flatten().copied().collect(),
    };
    // The GPU reads each level back as round(255 q) / 255.
    let edges_read: Vec<[f32; 4]> = edges
        .iter()
        .map(|c| c.map(|v| (v * 255.0).round() / 255.0))
        .collect();
    for passes in [1u32, 3] {
        let (a, d) = (
            r32("ao", w as u32, h as u32, ao.clone()),
            r32("depth", w as u32, h as u32, depth.clone()),
        );
        let p = EdgeDenoise {
            passes,
            blur_beta: 1.2,
        };
        let Some(out) = run(
            Extent::new(w as u32, h as u32),
            &[
                (&a, SizeClass::FULL),
                (&e, SizeClass::FULL),
                (&d, SizeClass::FULL),
            ],
            |b, hs| vec![edge_denoise(b, "g", hs[0], hs[1], hs[2], &p, R32Float).unwrap()],
        ) else {
            return;
        };
        let mut want = ao.clone();
        for k in 1..=passes {
            let last = k == passes;
            let beta = if last { 1.2 } else { 1.2 / 5.0 };
            want = edge_denoise_cpu(&want, &edges_read, &depth, w, h, beta, last);
        }
        assert_close(
            &out[0],
            &want,
            1e-5,
            &format!("edge denoise, {passes} passes"),
        );
        for (i, v) in out[0].iter().enumerate() {
            if depth[i] <= 0.0 {
                assert_eq!(*v, 1.0, "sky texel {i}");
            }
        }
    }
    // A constant stays that constant whatever the edges.
    let (a, d) = (
        r32("ao", w as u32, h as u32, vec![0.625; w * h]),
        r32("depth", w as u32, h as u32, vec![2.0; w * h]),
    );
    let Some(out) = run(
        Extent::new(w as u32, h as u32),
        &[
            (&a, SizeClass::FULL),
            (&e, SizeClass::FULL),
            (&d, SizeClass::FULL),
        ],
        |b, hs| {
            vec![
                edge_denoise(
                    b,
                    "g",
                    hs[0],
                    hs[1],
                    hs[2],
                    &EdgeDenoise::default(),
                    R32Float,
                )
                .unwrap(),
            ]
        },
    ) else {
        return;
    };
    assert_close(&out[0], &vec![0.625; w * h], 1e-6, "constant");
}
