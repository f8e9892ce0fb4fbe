//! The Gaussian and bilateral blurs and the bilateral upsample against CPU arithmetic:
//! constants kept, impulses give the weights, no blending across depth or normal edges.

use aograph_ao_passes::blocks::*;
use aograph_graph::{Extent, GraphBuilder, SizeClass, TextureHandle};
use wgpu::TextureFormat::Rgba32Float;

use super::*;

/// CPU mirror of the separable Gaussian (renormalised over in-bounds, non-sky taps; sky = 1).
fn gaussian_cpu(
    src: &[f32],
    depth: Option<&[f32]>,
    w: usize,
    h: usize,
    weights: &[f32],
) -> Vec<f32> {
    let r = (weights.len() / 2) as i32;
    let sky = |i: usize| depth.is_some_and(|d| d[i] <= 0.0);
    let pass = |src: &[f32], ax: (i32, i32)| -> Vec<f32> {
        (0..w * h)
            .map(|i| {
                if sky(i) {
                    return 1.0;
                }
                let (x, y) = ((i % w) as i32, (i / w) as i32);
                let (mut s, mut ws) = (0.0f32, 0.0f32);
                for k in -r..=r {
                    let (qx, qy) = (x + ax.0 * k, y + ax.1 * k);
                    if qx < 0
                        || qy < 0
                        || qx >= w as i32
                        || qy >= h as i32
                        || sky(qy as usize * w + qx as usize)
                    {
                        continue;
                    }
                    s += weights[(k + r) as usize] * src[qy as usize * w + qx as usize];
                    ws += weights[(k + r) as usize];
                }
                s / ws
            })
            .collect()
    };
    pass(&pass(src, (1, 0)), (0, 1))
}

#[test]
fn gaussian_of_a_constant_is_the_constant_and_of_an_impulse_the_weights() {
    let (w, h) = (15u32, 13u32);
    let constant = r32("ao", w, h, vec![0.625; (w * h) as usize]);
    let blur = GaussianBlur::default();
    let Some(out) = run(
        Extent::new(w, h),
        &[(&constant, SizeClass::FULL)],
        |b, hs| vec![gaussian_blur(b, "g", hs[0], None, &blur).unwrap()],
    ) else {
        return;
    };
    assert_close(&out[0], &vec![0.625; (w * h) as usize], 1e-6, "constant");

    let mut impulse = vec![0.0f32; (w * h) as usize];
    let (cx, cy) = (7usize, 6usize);
    impulse[cy * w as usize + cx] = 1.0;
    let input = r32("ao", w, h, impulse);
    let out = run(Extent::new(w, h), &[(&input, SizeClass::FULL)], |b, hs| {
        vec![gaussian_blur(b, "g", hs[0], None, &blur).unwrap()]
    })
    .unwrap();
    let wts = gaussian_weights(1.5, 5);
    let want: Vec<f32> = (0..(w * h) as usize)
        .map(|i| {
            let (dx, dy) = (
                (i % w as usize) as i32 - cx as i32,
                (i / w as usize) as i32 - cy as i32,
            );
            if dx.abs() <= 2 && dy.abs() <= 2 {
                wts[(dx + 2) as usize] * wts[(dy + 2) as usize]
            } else {
                0.0
            }
        })
        .collect();
    assert_close(&out[0], &want, 1e-6, "impulse response = w x w");
}

#[test]
fn gaussian_with_depth_keeps_sky_at_one_and_matches_the_cpu() {
    let (w, h) = (23usize, 17usize);
    let ao = noise(w * h, 3);
    let depth: Vec<f32> = (0..w * h)
        .map(|i| {
            if (i % w) + (i / w) < 9 {
                0.0
            } else {
                2.0 + (i % w) as f32 * 0.1
            }
        })
        .collect();
    let (a, d) = (
        r32("ao", w as u32, h as u32, ao.clone()),
        r32("depth", w as u32, h as u32, depth.clone()),
    );
    let p = GaussianBlur {
        sigma: 2.0,
        taps: 7,
        depth_sigma: None,
    };
    let Some(out) = run(
        Extent::new(w as u32, h as u32),
        &[(&a, SizeClass::FULL), (&d, SizeClass::FULL)],
        |b, hs| vec![gaussian_blur(b, "g", hs[0], Some(hs[1]), &p).unwrap()],
    ) else {
        return;
    };
    let want = gaussian_cpu(&ao, Some(&depth), w, h, &gaussian_weights(2.0, 7));
    assert_close(&out[0], &want, 2e-6, "sky-masked Gaussian");
    assert!(
        depth
            .iter()
            .zip(&out[0])
            .all(|(z, v)| *z > 0.0 || *v == 1.0),
        "sky is exactly 1"
    );
}

/// A depth step at x = w/2 (near left, far right), AO 0.2 left and 0.9 right.
fn step_scene(w: usize, h: usize) -> (Vec<f32>, Vec<f32>) {
    let left = |i: usize| i % w < w / 2;
    (
        (0..w * h)
            .map(|i| if left(i) { 0.2 } else { 0.9 })
            .collect(),
        (0..w * h)
            .map(|i| if left(i) { 1.0 } else { 5.0 })
            .collect(),
    )
}

#[test]
fn bilateral_blur_keeps_constants_and_stops_at_depth_and_normal_edges() {
    let (w, h) = (20usize, 12usize);
    let (ao, depth) = step_scene(w, h);
    // Normals: +z on the top half, +x on the bottom half (a crease at constant depth there).
    let normals: Vec<f32> = (0..w * h)
        .flat_map(|i| {
            if i / w < h / 2 {
                [0.0, 0.0, 1.0, 1.0]
            } else {
                [1.0, 0.0, 0.0, 1.0]
            }
        })
        .collect();
    let flat_ao: Vec<f32> = (0..w * h)
        .map(|i| if i / w < h / 2 { 0.3 } else { 0.7 })
        .collect();
    let n = Input {
        name: "normals",
        size: Extent::new(w as u32, h as u32),
        format: Rgba32Float,
        data: normals,
    };
    let p = BilateralBlur::default();
    for (ao, depth, what) in [
        (ao, depth, "depth edge"),
        (flat_ao, vec![3.0; w * h], "normal edge"),
    ] {
        let (a, d) = (
            r32("ao", w as u32, h as u32, ao.clone()),
            r32("depth", w as u32, h as u32, depth),
        );
        let Some(out) = run(
            Extent::new(w as u32, h as u32),
            &[
                (&a, SizeClass::FULL),
                (&d, SizeClass::FULL),
                (&n, SizeClass::FULL),
            ],
            |b, hs| vec![bilateral_blur(b, "b", hs[0], hs[1], hs[2], &p).unwrap()],
        ) else {
            return;
        };
        assert_close(&out[0], &ao, 1e-5, what);
    }
}

#[test]
fn upsample_is_bilinear_on_a_continuous_surface_and_does_not_blend_across_edges() {
    let (w, h) = (16usize, 10usize);
    let (lw, lh) = (w / 2, h / 2);
    let low = noise(lw * lh, 11);
    let (a, dl, df) = (
        r32("ao", lw as u32, lh as u32, low.clone()),
        r32("depth_low", lw as u32, lh as u32, vec![4.0; lw * lh]),
        r32("depth_full", w as u32, h as u32, vec![4.0; w * h]),
    );
    let ins = [
        (&a, SizeClass::half_pow(1)),
        (&dl, SizeClass::half_pow(1)),
        (&df, SizeClass::FULL),
    ];
    let up = |b: &mut GraphBuilder, hs: &[TextureHandle]| {
        vec![
            bilateral_upsample(
                b,
                "u",
                &UpsampleInputs {
                    ao: hs[0],
                    depth_low: hs[1],
                    depth_full: hs[2],
                    normals: None,
                },
                &BilateralUpsample::default(),
            )
            .unwrap(),
        ]
    };
    let Some(out) = run(Extent::new(w as u32, h as u32), &ins, up) else {
        return;
    };
    // Bilinear with clamp-to-edge taps: u = (p + 0.5) / 2 - 0.5.
    let at = |x: i32, y: i32| {
        low[y.clamp(0, lh as i32 - 1) as usize * lw + x.clamp(0, lw as i32 - 1) as usize]
    };
    let want: Vec<f32> = (0..w * h)
        .map(|i| {
            let (ux, uy) = (
                ((i % w) as f32 + 0.5) / 2.0 - 0.5,
                ((i / w) as f32 + 0.5) / 2.0 - 0.5,
            );
            let (bx, by) = (ux.floor(), uy.floor());
            let (tx, ty) = (ux - bx, uy - by);
            let (bx, by) = (bx as i32, by as i32);
            (1.0 - tx) * (1.0 - ty) * at(bx, by)
                + tx * (1.0 - ty) * at(bx + 1, by)
                + (1.0 - tx) * ty * at(bx, by + 1)
                + tx * ty * at(bx + 1, by + 1)
        })
        .collect();
    assert_close(&out[0], &want, 1e-5, "bilinear on a flat depth");

    // A depth step: each full-res pixel takes only the low-res AO of its own side.
    let (ao_full, depth_full) = step_scene(w, h);
    let (ao_low, depth_low): (Vec<f32>, Vec<f32>) = (0..lw * lh)
        .map(|i| {
            (
                ao_full[(i / lw) * 2 * w + (i % lw) * 2],
                depth_full[(i / lw) * 2 * w + (i % lw) * 2],
            )
        })
        .unzip();
    let (a, dl, df) = (
        r32("ao", lw as u32, lh as u32, ao_low),
        r32("depth_low", lw as u32, lh as u32, depth_low),
        r32("depth_full", w as u32, h as u32, depth_full),
    );
    let out = run(
        Extent::new(w as u32, h as u32),
        &[
            (&a, SizeClass::half_pow(1)),
            (&dl, SizeClass::half_pow(1)),
            (&df, SizeClass::FULL),
        ],
        up,
    )
    .unwrap();
    assert_close(&out[0], &ao_full, 1e-5, "no blending across the depth edge");
}
