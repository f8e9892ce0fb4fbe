//! Size classes, extents and texture byte counts.

use aograph_graph::wgpu::TextureFormat;
use aograph_graph::*;

const ODD: Extent = Extent::new(97, 61);

#[test]
fn full_size_class_resolves_to_the_output() {
    assert_eq!(
        SizeClass::FULL.resolve(Extent::new(1920, 1080)),
        Extent::new(1920, 1080)
    );
    assert_eq!(SizeClass::FULL.resolve(ODD), ODD);
    assert_eq!(SizeClass::half_pow(0), SizeClass::FULL);
}

#[test]
fn half_pow_rounds_odd_sizes_up() {
    assert_eq!(SizeClass::half_pow(1).resolve(ODD), Extent::new(49, 31));
    assert_eq!(SizeClass::half_pow(2).resolve(ODD), Extent::new(25, 16));
    assert_eq!(SizeClass::half_pow(3).resolve(ODD), Extent::new(13, 8));
    assert_eq!(
        SizeClass::half_pow(1).resolve(Extent::new(1920, 1080)),
        Extent::new(960, 540)
    );
}

#[test]
fn pyramid_level_with_factor_three_rounds_up() {
    assert_eq!(SizeClass::pyramid_level(3, 0).resolve(ODD), ODD);
    assert_eq!(
        SizeClass::pyramid_level(3, 1).resolve(ODD),
        Extent::new(33, 21)
    );
    assert_eq!(
        SizeClass::pyramid_level(3, 2).resolve(ODD),
        Extent::new(11, 7)
    );
    assert_eq!(
        SizeClass::pyramid_level(3, 3).resolve(ODD),
        Extent::new(4, 3)
    );
    assert_eq!(
        SizeClass::pyramid_level(3, 4).resolve(ODD),
        Extent::new(2, 1)
    );
    assert_eq!(
        SizeClass::pyramid_level(3, 2),
        SizeClass::Relative { divisor: 9 }
    );
}

#[test]
fn nested_division_equals_division_by_the_product() {
    for w in 1..=300u32 {
        for a in 1..=9u32 {
            for b in 1..=9u32 {
                let nested = w.div_ceil(a).div_ceil(b);
                let direct =
                    SizeClass::Relative { divisor: a * b }.resolve(Extent::new(w, 301 - w));
                assert_eq!(direct.width, nested, "w={w} a={a} b={b}");
                assert_eq!(
                    direct.height,
                    (301 - w).div_ceil(a).div_ceil(b),
                    "h={} a={a} b={b}",
                    301 - w
                );
            }
        }
    }
}

#[test]
fn pyramid_levels_match_repeated_rounding_up() {
    let mut e = ODD;
    for level in 0..8 {
        assert_eq!(
            SizeClass::pyramid_level(3, level).resolve(ODD),
            e,
            "level {level}"
        );
        e = Extent::new(e.width.div_ceil(3), e.height.div_ceil(3));
    }
}

#[test]
fn fixed_size_ignores_the_output() {
    let s = SizeClass::fixed(64, 32);
    assert_eq!(s.resolve(ODD), Extent::new(64, 32));
    assert_eq!(s.resolve(Extent::new(4096, 4096)), Extent::new(64, 32));
}

#[test]
fn resolved_size_is_never_below_one_pixel() {
    assert_eq!(
        SizeClass::half_pow(10).resolve(Extent::new(3, 2)),
        Extent::new(1, 1)
    );
    assert_eq!(SizeClass::half_pow(31).resolve(ODD), Extent::new(1, 1));
    assert_eq!(
        SizeClass::pyramid_level(3, 40).resolve(ODD),
        Extent::new(1, 1)
    );
    assert_eq!(SizeClass::fixed(0, 0).resolve(ODD), Extent::new(1, 1));
    assert_eq!(SizeClass::fixed(0, 7).resolve(ODD), Extent::new(1, 7));
    assert_eq!(
        SizeClass::Relative { divisor: 0 }.resolve(ODD),
        ODD,
        "divisor 0 is treated as 1"
    );
    assert_eq!(
        SizeClass::FULL.resolve(Extent::new(0, 0)),
        Extent::new(1, 1)
    );
}

#[test]
fn extent_mip_rounds_up_and_stops_at_one() {
    assert_eq!(ODD.mip(0), ODD);
    assert_eq!(ODD.mip(1), Extent::new(49, 31));
    assert_eq!(ODD.mip(6), Extent::new(2, 1));
    assert_eq!(ODD.mip(7), Extent::new(1, 1));
    assert_eq!(ODD.mip(40), Extent::new(1, 1));
    assert_eq!(ODD.pixels(), 97 * 61);
}

#[test]
fn size_class_display_names() {
    assert_eq!(SizeClass::FULL.to_string(), "full");
    assert_eq!(SizeClass::half_pow(2).to_string(), "1/4");
    assert_eq!(SizeClass::fixed(8, 4).to_string(), "fixed 8x4");
}

#[test]
fn texel_bytes_per_format() {
    assert_eq!(texel_bytes(TextureFormat::Rgba16Float), 8);
    assert_eq!(texel_bytes(TextureFormat::Rgba8Unorm), 4);
    assert_eq!(texel_bytes(TextureFormat::R32Float), 4);
    assert_eq!(texel_bytes(TextureFormat::Rgba32Float), 16);
    assert_eq!(texel_bytes(TextureFormat::Depth32Float), 4);
    assert_eq!(texel_bytes(TextureFormat::Depth24Plus), 4);
}

#[test]
fn texture_bytes_count_every_mip_level() {
    let one = TextureDesc::new(TextureFormat::Rgba8Unorm, SizeClass::fixed(8, 8));
    assert_eq!(one.bytes(ODD), 8 * 8 * 4);
    // 8x8 + 4x4 + 2x2 + 1x1 = 85 texels.
    assert_eq!(one.with_mips(4).bytes(ODD), 85 * 4);
    // 5x3 + 3x2 + 2x1 = 23 texels.
    let odd = TextureDesc::new(TextureFormat::R32Float, SizeClass::fixed(5, 3)).with_mips(3);
    assert_eq!(odd.bytes(ODD), 23 * 4);
    // half of 97x61 is 49x31; its mip 1 is 25x16.
    let half = TextureDesc::new(TextureFormat::Rgba16Float, SizeClass::half_pow(1)).with_mips(2);
    assert_eq!(half.bytes(ODD), (49 * 31 + 25 * 16) * 8);
}

#[test]
fn with_mips_never_goes_below_one_level() {
    let d = TextureDesc::new(TextureFormat::R32Float, SizeClass::FULL).with_mips(0);
    assert_eq!(d.mip_levels, 1);
    assert_eq!(d.bytes(Extent::new(10, 10)), 400);
}

#[test]
fn centred_pyramid_levels_overhang_both_edges_alike() {
    use aograph_graph::centred_step;
    // n % 3 == 0: no overhang; == 1: ceil, overhang 2 (one each side); == 2: ceil would leave
    // an overhang of 1, so one texel more: overhang 4 (two each side).
    assert_eq!(centred_step(99, 3), 33);
    assert_eq!(centred_step(97, 3), 33);
    assert_eq!(centred_step(11, 3), 5);
    assert_eq!(centred_step(1, 3), 1);
    assert_eq!(
        centred_step(2, 3),
        2,
        "a 2-texel level stays 2: overhang 2 each side"
    );
    for n in 1..500u32 {
        let m = centred_step(n, 3);
        assert!(
            m >= n.div_ceil(3) && (3 * m - n).is_multiple_of(2),
            "{n} -> {m}"
        );
    }
    assert_eq!(
        SizeClass::centred_pyramid_level(3, 3).resolve(Extent::new(97, 61)),
        Extent::new(5, 3)
    );
    assert_eq!(
        SizeClass::centred_pyramid_level(3, 0).resolve(Extent::new(97, 61)),
        Extent::new(97, 61)
    );
    let half = SizeClass::Centred {
        base_divisor: 2,
        factor: 3,
        level: 1,
    };
    assert_eq!(half.resolve(Extent::new(194, 122)), Extent::new(33, 21));
    assert_eq!(half.to_string(), "centred level 1 of 1/3 over 1/2");
}

#[test]
fn a_size_divisor_scales_what_is_created_under_it_and_nothing_else() {
    let size = |b: &GraphBuilder, h: TextureHandle| b.texture_desc(h).unwrap().size.resolve(ODD);
    let mut b = GraphBuilder::new();
    let desc = |size| TextureDesc::new(TextureFormat::R32Float, size);
    let imported = b.import_texture("depth", desc(SizeClass::FULL));
    assert_eq!(b.set_size_divisor(2), 1);
    let full = b.create_texture("full", desc(SizeClass::FULL));
    let quarter = b.create_texture("quarter", desc(SizeClass::half_pow(1)));
    let centred = b.create_texture("centred", desc(SizeClass::centred_pyramid_level(3, 1)));
    let fixed = b.create_texture("fixed", desc(SizeClass::fixed(5, 3)));
    let history = b.history_texture("history", desc(SizeClass::FULL));
    assert_eq!(b.set_size_divisor(1), 2);
    let after = b.create_texture("after", desc(SizeClass::FULL));
    // 97x61 halves to 49x31 (rounded up), as SizeClass::half_pow(1) does.
    assert_eq!(size(&b, imported), ODD);
    assert_eq!(size(&b, full), Extent::new(49, 31));
    assert_eq!(size(&b, quarter), Extent::new(25, 16));
    // The centred 3x3 pyramid's first level over 49x31: 17x11 (ceil, one more where the
    // overhang would be odd: 3 x 17 - 49 = 2, 3 x 11 - 31 = 2).
    assert_eq!(size(&b, centred), Extent::new(17, 11));
    assert_eq!(size(&b, fixed), Extent::new(5, 3));
    assert_eq!(size(&b, history.previous), Extent::new(49, 31));
    // Inside the scope a texture's size reads as the scope names it, so a texture made "the
    // size of" another is that size.
    b.set_size_divisor(2);
    assert_eq!(b.texture_desc(full).unwrap().size, SizeClass::FULL);
    let copy = b.create_texture("copy", b.texture_desc(quarter).unwrap());
    b.set_size_divisor(1);
    assert_eq!(size(&b, copy), size(&b, quarter));
    assert_eq!(size(&b, history.current), Extent::new(49, 31));
    assert_eq!(size(&b, after), ODD);
}
