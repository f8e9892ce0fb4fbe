//! XeGTAO's depth MIP prefilter (docs/techniques/gtao.md §4): a linear-depth pyramid of factor 2 whose
//! texels lean towards the farthest child, for techniques that march many pixels with few taps
//! (gtao, and any other that wants it).
//!
//! Rule: level l + 1's texel is the weighted mean of the in-bounds texels of the 2x2 block
//! (2x + i, 2y + j) of level l, with w_i = saturate((r - (z_max - z_i)) / (F r)),
//! r = 0.75 R' ("found empirically", XeGTAO), F the falloff range and z_max the farthest child.
//! Children within (1 - F) r of the farthest weigh 1; the weight reaches 0 at r in front of it.
//! A block with a sky child is sky: XeGTAO's sky is the far plane, so its sky child is the
//! farthest, weighs 1, and every surface more than r in front of it weighs 0. Averaging only the
//! surface children instead made a mean whose point, rebuilt at the block's centre (as gtao
//! does), lay in front of a grazing floor: tests/stability/'s floor at 89.9 degrees at
//! 4096x8 occluded itself to 0.63.
//! XeGTAO's README: the far bias acts as a thin-occluder bias and is steadier under motion than
//! a rotated-grid subsample. Level 0 is the caller's linear depth (XeGTAO linearises hardware
//! depth into its MIP 0; the g-buffer already holds linear depth).
//!
//! Sizes and names as [`mod@super::depth_pyramid`]: level l is ceil(size / 2^l), passes
//! `<prefix>.depth_level<l>`. WebGPU allows 4 storage textures per stage by default, so
//! XeGTAO's single 5-MIP dispatch is one pass per level here (spec §12).
//! Invariant: every level is finite, >= 0, 0 exactly where its block holds sky; a level is
//! within [min, max] of its block (a convex combination), so a plane's depth stays on the plane
//! up to its curvature in screen space.

use aograph_graph::{GraphBuilder, TextureDesc};
use bytemuck::{Pod, Zeroable};

use super::depth_pyramid::{DepthPyramid, DepthReduction, MAX_LEVELS};
use super::{BLOCK_FORMAT, desc_of, invalid, scaled_size};
use crate::error::AoResult;

/// XeGTAO's `depthRangeScaleFactor`: the prefilter's radius is 0.75 R'.
pub const PREFILTER_RADIUS_SCALE: f32 = 0.75;

/// The `params` uniform of shaders/blocks/depth_prefilter.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct PrefilterUniform {
    /// r = 0.75 R' (view units).
    radius: f32,
    /// Falloff range F r (view units, > 0).
    falloff: f32,
    _pad0: f32,
    _pad1: f32,
}

aograph_graph::uniform_layout!(PrefilterUniform {
    radius,
    falloff,
    _pad0,
    _pad1
});

/// Adds the passes building levels 1..`levels` - 1 of the prefiltered pyramid over `depth`
/// (R32Float linear depth, level 0). `effect_radius` is R' (view units) and `falloff_range`
/// F in (0, 1].
pub fn depth_prefilter(
    b: &mut GraphBuilder,
    prefix: &str,
    depth: aograph_graph::TextureHandle,
    levels: u32,
    effect_radius: f32,
    falloff_range: f32,
) -> AoResult<DepthPyramid> {
    if !(1..=MAX_LEVELS).contains(&levels) {
        return Err(invalid(
            prefix,
            "levels",
            levels,
            format!("1 to {MAX_LEVELS} (level 0 included)"),
        ));
    }
    if !(effect_radius.is_finite() && effect_radius > 0.0) {
        return Err(invalid(prefix, "radius", effect_radius, "finite and > 0"));
    }
    if !(falloff_range > 0.0 && falloff_range <= 1.0) {
        return Err(invalid(
            prefix,
            "falloff_range",
            falloff_range,
            "greater than 0 and at most 1",
        ));
    }
    let base = desc_of(b, prefix, "depth", depth)?;
    if base.format != BLOCK_FORMAT {
        return Err(invalid(
            prefix,
            "depth",
            format!("{:?}", base.format),
            "an R32Float linear-depth texture",
        ));
    }
    let r = PREFILTER_RADIUS_SCALE * effect_radius;
    let uniform = PrefilterUniform {
        radius: r,
        falloff: falloff_range * r,
        _pad0: 0.0,
        _pad1: 0.0,
    };
    let mut pyramid = DepthPyramid {
        levels: vec![depth],
        sizes: vec![base.size],
        reduction: DepthReduction::FarWeighted2x2,
    };
    for l in 1..levels {
        let size = scaled_size(base.size, 2, l);
        let name = format!("{prefix}.depth_level{l}");
        let out = b.create_texture(&name, TextureDesc::new(BLOCK_FORMAT, size));
        let mut p = b.compute_pass(&name, "blocks/depth_prefilter.wgsl", "main");
        p.sample("src", pyramid.levels[l as usize - 1]);
        p.uniform_struct("params", &uniform);
        p.loads_per_invocation(4.0); // the 2x2 block
        let out = p.write_storage("dst", out);
        p.dispatch_over(out);
        pyramid.levels.push(out);
        pyramid.sizes.push(size);
    }
    Ok(pyramid)
}

/// CPU mirror of one prefilter step (same arithmetic and order as the shader): `src` is `w` x
/// `h`, row-major; returns the next level and its size.
pub fn prefilter_cpu(
    src: &[f32],
    w: u32,
    h: u32,
    effect_radius: f32,
    falloff_range: f32,
) -> (Vec<f32>, u32, u32) {
    let r = PREFILTER_RADIUS_SCALE * effect_radius;
    let falloff = (falloff_range * r).max(1e-30);
    let (ow, oh) = (w.div_ceil(2), h.div_ceil(2));
    let mut out = Vec::with_capacity((ow * oh) as usize);
    for y in 0..oh {
        for x in 0..ow {
            let mut z = [0.0f32; 4];
            let mut z_max = 0.0f32;
            let mut sky = false;
            for (k, zk) in z.iter_mut().enumerate() {
                let (sx, sy) = (2 * x + (k as u32 & 1), 2 * y + (k as u32 >> 1));
                if sx < w && sy < h {
                    *zk = src[(sy * w + sx) as usize];
                    z_max = z_max.max(*zk);
                    sky |= *zk <= 0.0;
                }
            }
            let (mut sum, mut weights) = (0.0f32, 0.0f32);
            for zk in z.iter().filter(|z| **z > 0.0) {
                let wk = ((r - (z_max - zk)) / falloff).clamp(0.0, 1.0);
                sum += wk * zk;
                weights += wk;
            }
            out.push(if weights > 0.0 && !sky {
                sum / weights.max(1e-30)
            } else {
                0.0
            });
        }
    }
    (out, ow, oh)
}
