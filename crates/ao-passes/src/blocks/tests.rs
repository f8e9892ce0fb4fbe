//! GPU-free tests of the blocks: plan shape (pass names, sizes), kernel weights, parameter
//! checks, and compilation against the real shaders (naga validation and binding checks).

use aograph_graph::{
    CompileOptions, Extent, GraphBuilder, ShaderLibrary, SizeClass, TextureDesc, TextureHandle,
    compile,
};

use super::depth_pyramid::reduce_cpu;
use super::*;
use crate::error::AoError;

fn shaders() -> ShaderLibrary {
    crate::shader_library().unwrap()
}

fn depth_input(b: &mut GraphBuilder, size: SizeClass) -> TextureHandle {
    b.import_texture(
        "depth",
        TextureDesc::new(wgpu::TextureFormat::R32Float, size),
    )
}

/// Compiles `b` with `outputs` exported; every pass must be kept.
fn compiles(mut b: GraphBuilder, outputs: &[TextureHandle]) -> Vec<String> {
    outputs.iter().for_each(|h| b.export(*h));
    let plan =
        compile(b.build(), &shaders(), CompileOptions::default()).expect("block graph compiles");
    assert!(
        plan.culled.is_empty(),
        "nothing is culled: {:?}",
        plan.culled_names()
    );
    plan.pass_names().iter().map(|s| s.to_string()).collect()
}

#[test]
fn average_pyramid_has_one_pass_per_level_with_ceil_sizes() {
    for levels in 1..=5u32 {
        let mut b = GraphBuilder::new();
        let d = depth_input(&mut b, SizeClass::FULL);
        let p = depth_pyramid(&mut b, "t", d, DepthReduction::Average3x3, levels).unwrap();
        assert_eq!(p.len(), levels as usize);
        assert_eq!(p.levels[0], d, "level 0 is the input");
        let want: Vec<String> = (1..levels).map(|l| format!("t.depth_level{l}")).collect();
        let last = *p.levels.last().unwrap();
        assert_eq!(compiles(b, &[last]), want);
    }
    let mut b = GraphBuilder::new();
    let d = depth_input(&mut b, SizeClass::FULL);
    let p = depth_pyramid(&mut b, "t", d, DepthReduction::Average3x3, 4).unwrap();
    let sizes: Vec<Extent> = p
        .sizes
        .iter()
        .map(|s| s.resolve(Extent::new(97, 61)))
        .collect();
    assert_eq!(
        sizes,
        [
            Extent::new(97, 61),
            Extent::new(33, 21),
            Extent::new(11, 7),
            Extent::new(5, 3)
        ]
    );
    let e: Vec<Extent> = (0..4)
        .map(|l| centred_level_extent(Extent::new(97, 61), 3, l))
        .collect();
    assert_eq!(e, sizes);
    // The spec's table (§2.2) is ceil-sized: 1280x720 -> 427x240, 143x80, 48x27, 16x9, 6x3,
    // 2x1. The centred grid adds a texel where the overhang 3m - n would be odd (1281 - 1280).
    let e: Vec<Extent> = (1..=6)
        .map(|l| centred_level_extent(Extent::new(1280, 720), 3, l))
        .collect();
    assert_eq!(
        e,
        [(428, 240), (144, 80), (48, 28), (16, 10), (6, 4), (2, 2)].map(|(w, h)| Extent::new(w, h))
    );
}

#[test]
fn min_max_pyramids_halve_and_compose_on_relative_and_fixed_bases() {
    for r in [DepthReduction::Min2x2, DepthReduction::Max2x2] {
        let mut b = GraphBuilder::new();
        let d = depth_input(&mut b, SizeClass::half_pow(1));
        let p = depth_pyramid(&mut b, "m", d, r, 3).unwrap();
        assert_eq!(p.factor(), 2);
        assert_eq!(
            p.sizes,
            [
                SizeClass::half_pow(1),
                SizeClass::half_pow(2),
                SizeClass::half_pow(3)
            ]
        );
        assert_eq!(
            compiles(b, &[p.levels[2]]),
            ["m.depth_level1", "m.depth_level2"]
        );
    }
    let mut b = GraphBuilder::new();
    let d = depth_input(&mut b, SizeClass::fixed(97, 61));
    let p = depth_pyramid(&mut b, "f", d, DepthReduction::Max2x2, 3).unwrap();
    assert_eq!(p.sizes[2], SizeClass::fixed(25, 16));
}

#[test]
fn pyramid_rejects_bad_level_counts_and_formats() {
    let mut b = GraphBuilder::new();
    let d = depth_input(&mut b, SizeClass::FULL);
    for levels in [0, MAX_LEVELS_PLUS_ONE] {
        let e = depth_pyramid(&mut b, "t", d, DepthReduction::Average3x3, levels).unwrap_err();
        assert!(
            e.to_string().contains("`levels`") && e.to_string().contains("1 to 16"),
            "{e}"
        );
    }
    let rgba = b.import_texture(
        "n",
        TextureDesc::new(wgpu::TextureFormat::Rgba16Float, SizeClass::FULL),
    );
    let e = depth_pyramid(&mut b, "t", rgba, DepthReduction::Min2x2, 2).unwrap_err();
    assert!(e.to_string().contains("R32Float"), "{e}");
}
const MAX_LEVELS_PLUS_ONE: u32 = depth_pyramid::MAX_LEVELS + 1;

#[test]
fn cpu_reduction_averages_in_bounds_taps_and_takes_the_centre_of_blocks_with_sky() {
    // 4x4 -> 2x2 (3x3 average, centred: one texel of overhang on each side, so every window
    // holds 2 columns and 2 rows of the image).
    #[rustfmt::skip]
    let src = [
        1.0, 2.0, 3.0, 10.0,
        4.0, 5.0, 0.0, 20.0,
        6.0, 7.0, 8.0, 30.0,
        0.0, 9.0, 2.0, 0.0,
    ];
    let (out, w, h) = reduce_cpu(&src, 4, 4, DepthReduction::Average3x3);
    assert_eq!((w, h), (2, 2));
    // The all-geometry top-left block is averaged ((1 + 2 + 4 + 5) / 4); blocks with sky take
    // their centre texel (3x + 1 - 1, clamped): (3, 0) = 10, (0, 3) = 0 (sky), (3, 3) = 0.
    assert_eq!(out, [3.0, 10.0, 0.0, 0.0]);
    let (lo, ..) = reduce_cpu(&src, 4, 4, DepthReduction::Min2x2);
    let (hi, ..) = reduce_cpu(&src, 4, 4, DepthReduction::Max2x2);
    assert_eq!(lo, [1.0, 3.0, 6.0, 2.0]);
    assert_eq!(hi, [5.0, 20.0, 9.0, 30.0]);
    // A block of geometry is its mean; with one sky texel it is its centre; with a sky centre
    // it is sky.
    let block = [1.0, 1.0, 1.0, 1.0, 10.0, 1.0, 1.0, 1.0, 1.0];
    assert_eq!(
        reduce_cpu(&block, 3, 3, DepthReduction::Average3x3).0,
        [2.0]
    );
    let mut corner = block;
    corner[0] = 0.0;
    assert_eq!(
        reduce_cpu(&corner, 3, 3, DepthReduction::Average3x3).0,
        [10.0]
    );
    let mut centre = block;
    centre[4] = 0.0;
    assert_eq!(
        reduce_cpu(&centre, 3, 3, DepthReduction::Average3x3).0,
        [0.0]
    );
}

#[test]
fn the_average_pyramid_of_a_mirrored_image_is_the_mirrored_pyramid() {
    for (w, h) in [(97u32, 61u32), (98, 5), (4, 4), (2, 3), (1, 1), (320, 7)] {
        let src: Vec<f32> = (0..w * h)
            .map(|i| {
                if i % 7 == 3 {
                    0.0
                } else {
                    1.0 + (i * 37 % 101) as f32
                }
            })
            .collect();
        let mirrored: Vec<f32> = (0..w * h)
            .map(|i| src[((i / w) * w + w - 1 - i % w) as usize])
            .collect();
        let (a, ow, oh) = reduce_cpu(&src, w, h, DepthReduction::Average3x3);
        let (b, ..) = reduce_cpu(&mirrored, w, h, DepthReduction::Average3x3);
        for y in 0..oh {
            for x in 0..ow {
                assert_eq!(
                    a[(y * ow + x) as usize],
                    b[(y * ow + ow - 1 - x) as usize],
                    "{w}x{h}: texel ({x}, {y})"
                );
            }
        }
    }
}

#[test]
fn gaussian_weights_are_normalised_and_match_sigma_1_5_five_taps() {
    let w = gaussian_weights(1.5, 5);
    let want = [0.120078, 0.233881, 0.292082, 0.233881, 0.120078];
    for (a, b) in w.iter().zip(want) {
        assert!((a - b).abs() < 1e-6, "{w:?}");
    }
    for (sigma, taps) in [(1.5, 5), (0.5, 3), (4.0, 31), (30.0, 63), (1.0, 1)] {
        let w = gaussian_weights(sigma, taps);
        assert_eq!(w.len(), taps as usize);
        assert!((w.iter().sum::<f32>() - 1.0).abs() < 1e-6);
        assert!(
            w.iter().zip(w.iter().rev()).all(|(a, b)| a == b),
            "symmetric"
        );
    }
    let u = BlurUniform::new([1, 0], &gaussian_weights(1.5, 5), 0.0, 0.0);
    assert_eq!(u.radius, 2);
    assert_eq!(&u.weights[..3], &[w_at(2), w_at(3), w_at(4)]);
    assert_eq!(std::mem::size_of::<BlurUniform>(), 32 + 128);
}
fn w_at(i: usize) -> f32 {
    gaussian_weights(1.5, 5)[i]
}

#[test]
fn blurs_declare_two_passes_and_compile() {
    let mut b = GraphBuilder::new();
    let d = depth_input(&mut b, SizeClass::FULL);
    let ao = b.import_texture(
        "ao",
        TextureDesc::new(wgpu::TextureFormat::R32Float, SizeClass::FULL),
    );
    let plain = gaussian_blur(&mut b, "g", ao, None, &GaussianBlur::default()).unwrap();
    let masked = gaussian_blur(
        &mut b,
        "gd",
        ao,
        Some(d),
        &GaussianBlur {
            depth_sigma: Some(0.1),
            ..Default::default()
        },
    )
    .unwrap();
    let n = b.import_texture(
        "normals",
        TextureDesc::new(wgpu::TextureFormat::Rgba16Float, SizeClass::FULL),
    );
    let bil = bilateral_blur(&mut b, "b", ao, d, n, &BilateralBlur::default()).unwrap();
    assert_eq!(
        b.texture_desc(bil).unwrap(),
        TextureDesc::new(BLOCK_FORMAT, SizeClass::FULL)
    );
    let names = compiles(b, &[plain, masked, bil]);
    assert_eq!(
        names,
        [
            "g.blur_x",
            "g.blur_y",
            "gd.blur_x",
            "gd.blur_y",
            "b.bilateral_x",
            "b.bilateral_y"
        ]
    );
}

#[test]
fn blur_parameters_are_checked_with_ranges() {
    let mut b = GraphBuilder::new();
    let ao = b.import_texture(
        "ao",
        TextureDesc::new(wgpu::TextureFormat::R32Float, SizeClass::FULL),
    );
    let cases: [(GaussianBlur, &str); 4] = [
        (
            GaussianBlur {
                taps: 4,
                ..Default::default()
            },
            "an odd number from 1 to 63",
        ),
        (
            GaussianBlur {
                taps: 65,
                ..Default::default()
            },
            "an odd number from 1 to 63",
        ),
        (
            GaussianBlur {
                sigma: 0.0,
                ..Default::default()
            },
            "greater than 0",
        ),
        (
            GaussianBlur {
                depth_sigma: Some(0.1),
                ..Default::default()
            },
            "only with a depth input",
        ),
    ];
    for (p, allowed) in cases {
        let e = gaussian_blur(&mut b, "g", ao, None, &p).unwrap_err();
        assert!(
            matches!(&e, AoError::InvalidParameter { technique, .. } if technique == "g"),
            "{e}"
        );
        assert!(e.to_string().contains(allowed), "{e}");
    }
    let e = BilateralBlur {
        normal_power: -1.0,
        ..Default::default()
    }
    .validate("b")
    .unwrap_err();
    assert!(e.to_string().contains("0 (off) to 128"), "{e}");
}

#[test]
fn upsample_derives_the_factor_from_size_classes_and_compiles() {
    assert_eq!(
        bilateral_upsample::upsample_factor(SizeClass::half_pow(1), SizeClass::FULL),
        Some(2)
    );
    assert_eq!(
        bilateral_upsample::upsample_factor(
            SizeClass::pyramid_level(3, 2),
            SizeClass::pyramid_level(3, 1)
        ),
        Some(3)
    );
    assert_eq!(
        bilateral_upsample::upsample_factor(SizeClass::fixed(4, 4), SizeClass::FULL),
        None
    );
    assert_eq!(
        bilateral_upsample::upsample_factor(
            SizeClass::Relative { divisor: 3 },
            SizeClass::half_pow(1)
        ),
        None
    );

    let mut b = GraphBuilder::new();
    let full = depth_input(&mut b, SizeClass::FULL);
    let p = depth_pyramid(&mut b, "u", full, DepthReduction::Min2x2, 2).unwrap();
    let ao = b.import_texture(
        "ao",
        TextureDesc::new(wgpu::TextureFormat::R32Float, SizeClass::half_pow(1)),
    );
    let nf = b.import_texture(
        "nf",
        TextureDesc::new(wgpu::TextureFormat::Rgba16Float, SizeClass::FULL),
    );
    let nl = b.import_texture(
        "nl",
        TextureDesc::new(wgpu::TextureFormat::Rgba16Float, SizeClass::half_pow(1)),
    );
    let inputs = UpsampleInputs {
        ao,
        depth_low: p.levels[1],
        depth_full: full,
        normals: None,
    };
    let a = bilateral_upsample(&mut b, "u", &inputs, &BilateralUpsample::default()).unwrap();
    let c = bilateral_upsample(
        &mut b,
        "un",
        &UpsampleInputs {
            normals: Some((nl, nf)),
            ..inputs
        },
        &BilateralUpsample::default(),
    )
    .unwrap();
    assert_eq!(b.texture_desc(a).unwrap().size, SizeClass::FULL);
    let bad = UpsampleInputs {
        depth_low: full,
        ..inputs
    };
    assert!(
        bilateral_upsample(&mut b, "x", &bad, &BilateralUpsample::default())
            .unwrap_err()
            .to_string()
            .contains("depth_low")
    );
    assert_eq!(
        compiles(b, &[a, c]),
        ["u.depth_level1", "u.upsample", "un.upsample"]
    );
}
