//! Depth pyramids on the GPU against the CPU: the 3x3 average exactly on integer data, min and
//! max at odd sizes, and XeGTAO's depth prefilter.

use aograph_ao_passes::blocks::depth_pyramid::reduce_cpu;
use aograph_ao_passes::blocks::*;
use aograph_graph::{Extent, SizeClass};

use super::*;

#[test]
fn average_pyramid_of_a_9x9_image_is_exact() {
    // Block b (3x3) holds c_b + offsets summing to 0 over its non-sky taps; block 4 is all sky.
    let mut data = vec![0.0f32; 81];
    let offsets: [f32; 9] = [-4.0, -3.0, -2.0, -1.0, 0.0, 1.0, 2.0, 3.0, 4.0];
    for by in 0..3 {
        for bx in 0..3 {
            let b = by * 3 + bx;
            let c = 10.0 * (b + 1) as f32;
            for (k, o) in offsets.iter().enumerate() {
                let (x, y) = (bx * 3 + k % 3, by * 3 + k / 3);
                // In block 0 the +-4 taps are sky: a block mixing sky and geometry takes its
                // centre tap, c.
                let sky = b == 4 || (b == 0 && o.abs() == 4.0);
                data[y * 9 + x] = if sky { 0.0 } else { c + o };
            }
        }
    }
    let input = r32("depth", 9, 9, data.clone());
    let Some(out) = run(Extent::new(9, 9), &[(&input, SizeClass::FULL)], |b, h| {
        depth_pyramid(b, "t", h[0], DepthReduction::Average3x3, 3)
            .unwrap()
            .levels[1..]
            .to_vec()
    }) else {
        return;
    };
    let (l1, ..) = reduce_cpu(&data, 9, 9, DepthReduction::Average3x3);
    assert_eq!(l1, [10.0, 20.0, 30.0, 40.0, 0.0, 60.0, 70.0, 80.0, 90.0]);
    assert_eq!(out[0], l1, "level 1 (3x3) equals the CPU mean exactly");
    assert_eq!(
        out[1],
        [0.0],
        "level 2 (1x1): its block mixes sky and geometry and its centre (block 4) is sky"
    );
}

#[test]
fn pyramids_of_odd_sizes_match_the_cpu_per_level() {
    let (w, h) = (97u32, 61u32);
    let mut data: Vec<f32> = noise((w * h) as usize, 7)
        .iter()
        .map(|v| 1.0 + 20.0 * v)
        .collect();
    for (i, v) in data.iter_mut().enumerate() {
        if ((i as u32 % w) < 20 && (i as u32 / w) < 15) || i % 7 == 0 {
            *v = 0.0; // sky: a corner block and scattered texels
        }
    }
    let input = r32("depth", w, h, data.clone());
    for r in [
        DepthReduction::Average3x3,
        DepthReduction::Min2x2,
        DepthReduction::Max2x2,
    ] {
        let Some(out) = run(Extent::new(w, h), &[(&input, SizeClass::FULL)], |b, hs| {
            depth_pyramid(b, "t", hs[0], r, 4).unwrap().levels[1..].to_vec()
        }) else {
            return;
        };
        let (mut cur, mut cw, mut ch) = (data.clone(), w, h);
        for (l, got) in out.iter().enumerate() {
            (cur, cw, ch) = reduce_cpu(&cur, cw, ch, r);
            assert_eq!(
                Extent::new(cw, ch),
                level_size(r, Extent::new(w, h), l as u32 + 1)
            );
            if r == DepthReduction::Average3x3 {
                assert_close(got, &cur, 1e-6, &format!("{r:?} level {}", l + 1));
                cur = got.clone(); // continue from the GPU's level (rounding may differ by an ulp)
            } else {
                assert_eq!(got, &cur, "{r:?} level {} is exact", l + 1);
            }
        }
        let sizes: Vec<Extent> = (1..4)
            .map(|l| level_size(r, Extent::new(w, h), l))
            .collect();
        if r == DepthReduction::Average3x3 {
            // Centred: 11 -> 5, since ceil(11 / 3) = 4 would leave an odd overhang of 1.
            assert_eq!(
                sizes,
                [Extent::new(33, 21), Extent::new(11, 7), Extent::new(5, 3)]
            );
        }
    }
}

#[test]
fn depth_prefilter_matches_the_cpu_per_level_and_keeps_sky() {
    use aograph_ao_passes::blocks::depth_prefilter::prefilter_cpu;
    // 13x7: odd sizes, partial edge blocks; depths 1..3 with a sky column, so some blocks mix
    // children near and far (weights below 1) and some are all sky.
    let (w, h) = (13u32, 7u32);
    let data: Vec<f32> = noise((w * h) as usize, 7)
        .iter()
        .enumerate()
        .map(|(i, v)| {
            if i as u32 % w == 4 {
                0.0
            } else {
                1.0 + 2.0 * v
            }
        })
        .collect();
    let input = r32("depth", w, h, data.clone());
    let (radius, falloff) = (0.8f32, 0.615f32);
    let Some(out) = run(Extent::new(w, h), &[(&input, SizeClass::FULL)], |b, hs| {
        depth_prefilter(b, "p", hs[0], 4, radius, falloff)
            .unwrap()
            .levels[1..]
            .to_vec()
    }) else {
        return;
    };
    let (mut level, mut lw, mut lh) = (data, w, h);
    for (l, got) in out.iter().enumerate() {
        let (next, nw, nh) = prefilter_cpu(&level, lw, lh, radius, falloff);
        assert_close(got, &next, 1e-6, &format!("prefilter level {}", l + 1));
        (level, lw, lh) = (next, nw, nh);
    }
    // A near child far in front of the farthest gets weight 0: texel (0, 0) of a block
    // {1, 5, 5, 5} at r = 0.75 x 0.8 = 0.6 is 5 exactly, where a plain mean would be 4.
    let block = r32("depth", 2, 2, vec![1.0, 5.0, 5.0, 5.0]);
    let Some(out) = run(Extent::new(2, 2), &[(&block, SizeClass::FULL)], |b, hs| {
        vec![
            depth_prefilter(b, "p", hs[0], 2, radius, falloff)
                .unwrap()
                .levels[1],
        ]
    }) else {
        return;
    };
    assert_eq!(out[0], vec![5.0]);
}
