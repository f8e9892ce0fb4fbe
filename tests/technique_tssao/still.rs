//! `tssao` under a still camera: a plane, sphere-on-plane, convergence against `ssao`, flicker.

use crate::common::plane_at;
use aograph_ao_passes::AoConfig;
use aograph_ao_passes::TechniqueRegistry;
use aograph_graph::Extent;
use aograph_scene::{Camera, procedural_scene};
use glam::Vec3;

use super::*;

#[test]
fn plane_is_unoccluded_from_straight_down_to_80_degrees() {
    for degrees in [0.0, 30.0, 60.0, 80.0] {
        let Some(mut r) = renderer(plane_at(degrees), &tssao(""), Extent::new(64, 64)) else {
            return;
        };
        for frame in 1..=6 {
            r.render(0.0).unwrap();
            let (a, d) = (ao(&r), depth(&r));
            let what = format!("tssao on plane at {degrees} degrees, frame {frame}");
            common::assert_valid_ao(&a, &d, &what);
            assert!(
                d.iter().any(|&z| z > 0.0),
                "{what}: the camera sees the plane"
            );
            let min = a.iter().copied().fold(1.0f32, f32::min);
            assert!(min >= 0.98, "{what}: darkest pixel {min}");
        }
    }
}

#[test]
fn sphere_on_plane_tracks_the_reference() {
    let Some(mut r) = renderer(
        procedural_scene("sphere-on-plane").unwrap(),
        &tssao(""),
        Extent::new(96, 96),
    ) else {
        return;
    };
    for _ in 0..16 {
        r.render(0.0).unwrap();
    }
    let (a, d) = (ao(&r), depth(&r));
    common::assert_valid_ao(&a, &d, "tssao on sphere-on-plane");
    let reference = reference(&r);
    let mae = common::mae(&a, &reference, &d);
    let mae_of_one = common::mae(&vec![1.0; a.len()], &reference, &d);
    println!(
        "tssao on sphere-on-plane 96x96 after 16 frames: MAE {mae:.4} (accessibility 1 everywhere: {mae_of_one:.4})"
    );
    assert!(
        mae < 0.5 * mae_of_one && mae < 0.05,
        "MAE {mae} (returning 1: {mae_of_one})"
    );
}

#[test]
fn static_camera_converges_and_matches_ssao_with_32_samples() {
    let size = Extent::new(96, 64);
    let scene = procedural_scene("columns").unwrap();
    let Some(mut r) = renderer(scene.clone(), &tssao("k2 = 8"), size) else {
        return;
    };
    let mut maes = Vec::new();
    let mut kept = Vec::new();
    let mut reference_image = None;
    for frame in 1..=32 {
        r.render(0.0).unwrap();
        let (a, d) = (ao(&r), depth(&r));
        common::assert_valid_ao(&a, &d, &format!("tssao on columns, frame {frame}"));
        if [1, 2, 4, 8, 16, 32].contains(&frame) {
            let reference = reference_image.get_or_insert_with(|| reference(&r));
            maes.push((frame, common::mae(&a, reference, &d)));
            kept.push((frame, a));
        }
    }
    let reference = reference_image.unwrap();
    let d = depth(&r);
    let tssao_final = ao(&r);
    let mae_at = |f: u32| maes.iter().find(|(g, _)| *g == f).unwrap().1;
    let line: Vec<String> = maes
        .iter()
        .map(|(f, m)| format!("frame {f}: {m:.4}"))
        .collect();
    println!(
        "tssao (k1 = 32, k2 = 8) on columns {size}, static camera, MAE against the reference ({RAYS} rays): {}",
        line.join(", ")
    );
    assert!(
        mae_at(1) > mae_at(8) && mae_at(8) > mae_at(32),
        "the error must fall as frames accumulate: {line:?}"
    );
    // What is left after frame 2 is the estimator's screen-space bias; the sampling error
    // itself keeps falling: the distance to the estimate after 128 frames.
    for _ in 32..128 {
        r.render(0.0).unwrap();
    }
    let limit = ao(&r);
    let to_limit: Vec<(u32, f32)> = kept
        .iter()
        .map(|(f, a)| (*f, common::mae(a, &limit, &d)))
        .collect();
    println!(
        "mean |A_f - A_128|: {}",
        to_limit
            .iter()
            .map(|(f, m)| format!("frame {f}: {m:.5}"))
            .collect::<Vec<_>>()
            .join(", ")
    );
    assert!(
        to_limit.windows(2).all(|w| w[0].1 > w[1].1),
        "the sampling error must fall frame after frame: {to_limit:?}"
    );
    let (tssao_total, tssao_tech) = frame_times(&mut r, 9, 0.0);

    // The baseline: ssao with 32 samples per frame, or (if it is not registered) TSSAO's own
    // single-frame estimate with 32 samples.
    let ssao_registered = TechniqueRegistry::with_builtins().get("ssao").is_ok();
    assert!(
        ssao_registered,
        "ssao is a built-in technique: the baseline needs it"
    );
    let (name, config) = if ssao_registered {
        (
            "ssao (32 samples)",
            common::ao_config("ssao", RADIUS, "samples = 32"),
        )
    } else {
        ("single-frame tssao (32 samples)", tssao("k1 = 32"))
    };
    let mut b = renderer(scene, &config, size).unwrap();
    b.render(0.0).unwrap();
    let base = ao(&b);
    common::assert_valid_ao(&base, &d, name);
    let base_mae = common::mae(&base, &reference, &d);
    let (base_total, base_tech) = frame_times(&mut b, 9, 0.0);
    let tssao_mae = common::mae(&tssao_final, &reference, &d);
    println!("after 32 frames: tssao MAE {tssao_mae:.4}, {name} MAE {base_mae:.4}");
    println!(
        "per-frame time (median of 9 converged frames, {:?}): tssao {tssao_total:.3} ms (technique {tssao_tech:.3} ms), {name} {base_total:.3} ms (technique {base_tech:.3} ms); ratio {name} / tssao: {:.2} total, {:.2} technique",
        b.timings().unwrap().source,
        base_total / tssao_total,
        base_tech / tssao_tech
    );
    assert!(
        tssao_mae <= base_mae,
        "tssao after 32 frames ({tssao_mae}) must be at least as accurate as {name} ({base_mae})"
    );
}

/// Frame-to-frame change of `config` on `columns` (96x64) over `frames` frames after `warmup`,
/// with the camera at `camera(f)`: (plain, motion-compensated). Plain = mean |A_f - A_f-1| over
/// non-sky pixels. Motion-compensated = mean |A_f(x) - A_f-1(x')|, x' = where the surface at x
/// was in the previous frame (bilinear), over pixels that were visible there: it leaves out the
/// image's true motion and keeps the changes that do not follow the surfaces (flicker).
fn flicker(
    config: &AoConfig,
    warmup: u32,
    frames: u32,
    camera: impl Fn(u32) -> Camera,
) -> Option<(f32, f32)> {
    let (w, h) = (96u32, 64u32);
    let mut r = renderer(
        procedural_scene("columns").unwrap(),
        config,
        Extent::new(w, h),
    )?;
    let mut prev: Option<(Vec<f32>, Vec<f32>, Camera)> = None;
    let (mut plain, mut n_plain, mut warped, mut n_warped) = (0.0f64, 0usize, 0.0f64, 0usize);
    for f in 0..warmup + frames {
        let c = camera(f);
        r.render_with_camera(0.0, c).unwrap();
        let (a, d) = (ao(&r), depth(&r));
        if let (true, Some((pa, pd, pc))) = (f > warmup, &prev) {
            let s = aograph_renderer::frame_reference::reference_surfaces(
                r.gpu.clone(),
                r.shaders.clone(),
                &aograph_renderer::FrameView::of(&r),
                aograph_scene::ReferenceNormals::Geometric,
            )
            .unwrap()
            .0;
            let (vp, view) = (pc.view_projection(w as f32 / h as f32), pc.view());
            for i in 0..a.len() {
                if d[i] <= 0.0 {
                    continue;
                }
                plain += (a[i] - pa[i]).abs() as f64;
                n_plain += 1;
                let q = vp * s.points[i].extend(1.0);
                let (x, y) = (
                    (0.5 + 0.5 * q.x / q.w) * w as f32 - 0.5,
                    (0.5 - 0.5 * q.y / q.w) * h as f32 - 0.5,
                );
                if !(x >= 0.0 && y >= 0.0 && x < (w - 1) as f32 && y < (h - 1) as f32) {
                    continue;
                }
                let (x0, y0, tx, ty) =
                    (x.floor() as usize, y.floor() as usize, x.fract(), y.fract());
                let at = |img: &[f32], dx: usize, dy: usize| img[(y0 + dy) * w as usize + x0 + dx];
                let z_then = -(view * s.points[i].extend(1.0)).z;
                if (0..4).any(|k| (1.0 - z_then / at(pd, k & 1, k >> 1)).abs() > 0.01) {
                    continue; // not visible there last frame (or an edge)
                }
                let then = (at(pa, 0, 0) * (1.0 - tx) + at(pa, 1, 0) * tx) * (1.0 - ty)
                    + (at(pa, 0, 1) * (1.0 - tx) + at(pa, 1, 1) * tx) * ty;
                warped += (a[i] - then).abs() as f64;
                n_warped += 1;
            }
        }
        prev = Some((a, d, c));
    }
    Some((
        (plain / n_plain.max(1) as f64) as f32,
        (warped / n_warped.max(1) as f64) as f32,
    ))
}

#[test]
fn flicker_is_lower_than_ssao() {
    let still = procedural_scene("columns").unwrap().camera;
    // A slow dolly sideways, 1 cm per frame (about a tenth of a pixel).
    let dolly = move |f: u32| {
        let mut c = still;
        let o = Vec3::new(0.0, 0.0, 0.01 * f as f32);
        c.position += o;
        c.target += o;
        c
    };
    let Some((t_still, _)) = flicker(&tssao(""), 32, 16, |_| still) else {
        return;
    };
    let (t_plain, t_moving) = flicker(&tssao(""), 32, 16, dolly).unwrap();
    println!(
        "tssao flicker on columns 96x64, frames 33-48: static camera {t_still:.5}; camera moving 1 cm/frame {t_plain:.5}, motion-compensated {t_moving:.5}"
    );
    // Under a static camera a converged pixel changes only by the weight k2 / (n_t + k2) of its
    // new samples.
    assert!(
        t_still < 0.001,
        "converged tssao under a static camera changes by {t_still} per frame"
    );
    if TechniqueRegistry::with_builtins().get("ssao").is_ok() {
        let ssao = common::ao_config("ssao", RADIUS, "samples = 32");
        let (s_still, _) = flicker(&ssao, 32, 16, |_| still).unwrap();
        let (s_plain, s_moving) = flicker(&ssao, 32, 16, dolly).unwrap();
        println!(
            "ssao (32 samples) flicker: static camera {s_still:.5}; camera moving 1 cm/frame {s_plain:.5}, motion-compensated {s_moving:.5}"
        );
        // ssao's noise is a fixed per-pixel pattern, so under a static camera it does not change
        // at all (0 cannot be beaten); its flicker is the pattern sliding over the surfaces once
        // the camera moves, which the motion-compensated measure isolates.
        assert!(
            t_moving < s_moving,
            "tssao's motion-compensated flicker {t_moving} must be below ssao's {s_moving}"
        );
    }
}
