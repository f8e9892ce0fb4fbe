//! Linear-depth pyramid: level 0 is the caller's full-resolution linear depth (R32Float, 0 =
//! sky); level l + 1 reduces a factor x factor block of level l to one texel.
//!
//! Reductions:
//! - [`DepthReduction::Average3x3`] (Pyramid HBAO, spec §2.2): factor K = 3; texel (x, y) of
//!   level l + 1 is the arithmetic mean of the in-bounds, non-sky texels among
//!   (3x + i - o, 3y + j - o), i, j in 0..3, of level l, i.e. the 3x3 block centred on
//!   (3x + 1 - o, 3y + 1 - o) (spec §7 pseudo-code, with the grid centred): the overhang
//!   o = (3m - n) / 2 per axis (n texels become m, `aograph_graph::centred_step`) puts the
//!   same partial block at both edges, so a mirrored image gives the mirrored pyramid. (The
//!   spec's grid from the top-left corner made `columns`' walls 0.024 apart at 320x180.) Following the spec's \[IMPL\] notes (§2.2 "Edge texels", §6.3), the
//!   ceil-sized edge windows average only in-bounds texels (no clamp-to-edge duplicates), and
//!   sky texels (depth 0) never enter a mean, so one sky texel cannot drag a silhouette's mean
//!   to the far plane; a block of sky only stays sky (0). A block holding both sky and
//!   geometry takes its centre texel (3x + 1, 3y + 1, clamped into the image), or is sky when
//!   that is sky: Pyramid HBAO rebuilds a coarse texel at its block's centre, where the mean
//!   of the geometry texels alone does not lie. (Found by tests/stability/: a floor meeting
//!   the horizon at 4096x8 had the mean of its lower rows rebuilt higher up, in front of the
//!   floor, and occluded itself to 0.976.)
//! - [`DepthReduction::Min2x2`] / [`DepthReduction::Max2x2`]: factor 2; the nearest / farthest
//!   non-sky texel of the in-bounds 2x2 block, 0 when all are sky.
//!
//! Sizes: for 2x2 reductions level l is ceil(size / factor^l) per axis (spec §2.2, "K times
//! less (rounded up)"); the 3x3 pyramid adds one texel where the overhang would be odd
//! (`SizeClass::Centred`): for 97x61 its levels are 33x21, 11x7, 5x3. Passes: `<prefix>.depth_level<l>` for l = 1..levels-1, writing textures of the
//! same names. Invariant: every level is finite, >= 0, 0 exactly where its block is all sky.

use aograph_graph::{GraphBuilder, SizeClass, TextureDesc, TextureHandle};

use super::{BLOCK_FORMAT, centred_size, desc_of, invalid, scaled_size};
use crate::error::AoResult;

/// Most levels a pyramid may have (level 0 included).
pub const MAX_LEVELS: u32 = 16;

/// How a block of one level becomes a texel of the next.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum DepthReduction {
    /// Mean of a 3x3 block (factor 3), or its centre texel where it mixes sky and geometry:
    /// Pyramid HBAO's pyramid.
    Average3x3,
    /// Nearest non-sky texel of a 2x2 block (factor 2).
    Min2x2,
    /// Farthest texel of a 2x2 block (factor 2).
    Max2x2,
    /// XeGTAO's far-weighted mean of a 2x2 block (factor 2). Its weights depend on the
    /// technique's radius, so [`fn@super::depth_prefilter`] builds it; [`depth_pyramid`]
    /// refuses it.
    FarWeighted2x2,
}

impl DepthReduction {
    /// Reduction factor per axis and level.
    pub fn factor(self) -> u32 {
        match self {
            Self::Average3x3 => 3,
            Self::Min2x2 | Self::Max2x2 | Self::FarWeighted2x2 => 2,
        }
    }
    /// Entry point in shaders/blocks/depth_pyramid.wgsl.
    fn entry(self) -> Option<&'static str> {
        match self {
            Self::Average3x3 => Some("average_3x3"),
            Self::Min2x2 => Some("min_2x2"),
            Self::Max2x2 => Some("max_2x2"),
            Self::FarWeighted2x2 => None,
        }
    }
}

/// The levels of a depth pyramid.
#[derive(Clone, Debug)]
pub struct DepthPyramid {
    /// Level handles; `levels[0]` is the input depth.
    pub levels: Vec<TextureHandle>,
    /// Size class of each level.
    pub sizes: Vec<SizeClass>,
    /// How each level was reduced from the one before.
    pub reduction: DepthReduction,
}

impl DepthPyramid {
    /// Reduction factor per axis and level (3 for [`DepthReduction::Average3x3`], else 2).
    pub fn factor(&self) -> u32 {
        self.reduction.factor()
    }
    /// Number of levels, level 0 included.
    pub fn len(&self) -> usize {
        self.levels.len()
    }
    /// True when there is no level at all (never for a [`depth_pyramid`] result: level 0 is
    /// the input).
    pub fn is_empty(&self) -> bool {
        self.levels.is_empty()
    }
    /// Level `l`, or the coarsest level when `l` is beyond it.
    pub fn level(&self, l: usize) -> TextureHandle {
        self.levels[l.min(self.levels.len() - 1)]
    }
}

/// Adds the passes building levels 1..`levels` - 1 of a `reduction` pyramid over `depth`
/// (level 0, R32Float linear depth). `levels` counts level 0: 1 adds no pass.
pub fn depth_pyramid(
    b: &mut GraphBuilder,
    prefix: &str,
    depth: TextureHandle,
    reduction: DepthReduction,
    levels: u32,
) -> AoResult<DepthPyramid> {
    if !(1..=MAX_LEVELS).contains(&levels) {
        return Err(invalid(
            prefix,
            "levels",
            levels,
            format!("1 to {MAX_LEVELS} (level 0 included)"),
        ));
    }
    let Some(entry) = reduction.entry() else {
        return Err(invalid(
            prefix,
            "reduction",
            format!("{reduction:?}"),
            "Average3x3, Min2x2 or Max2x2 (FarWeighted2x2 needs a radius: blocks::depth_prefilter)",
        ));
    };
    let base = desc_of(b, prefix, "depth", depth)?;
    if base.format != BLOCK_FORMAT {
        return Err(invalid(
            prefix,
            "depth",
            format!("{:?}", base.format),
            "an R32Float linear-depth texture",
        ));
    }
    let mut pyramid = DepthPyramid {
        levels: vec![depth],
        sizes: vec![base.size],
        reduction,
    };
    for l in 1..levels {
        let size = match reduction {
            DepthReduction::Average3x3 => centred_size(base.size, 3, l),
            _ => scaled_size(base.size, reduction.factor(), l),
        };
        let name = format!("{prefix}.depth_level{l}");
        let out = b.create_texture(&name, TextureDesc::new(BLOCK_FORMAT, size));
        let mut p = b.compute_pass(&name, "blocks/depth_pyramid.wgsl", entry);
        p.sample("src", pyramid.levels[l as usize - 1]);
        // The 3x3 average reads 9 texels (and the centre again); min and max read 2x2.
        p.loads_per_invocation(if reduction.factor() == 3 { 10.0 } else { 4.0 });
        let out = p.write_storage("dst", out);
        p.dispatch_over(out);
        pyramid.levels.push(out);
        pyramid.sizes.push(size);
    }
    Ok(pyramid)
}

/// CPU mirror of one reduction step (same arithmetic and order as the shader), for tests and
/// tools: `src` is `w` x `h`, row-major; returns the next level and its size. Panics on
/// [`DepthReduction::FarWeighted2x2`], whose mirror is `depth_prefilter::prefilter_cpu`.
pub fn reduce_cpu(src: &[f32], w: u32, h: u32, reduction: DepthReduction) -> (Vec<f32>, u32, u32) {
    let k = reduction.factor();
    // The 3x3 grid is centred: o texels of overhang on each side; the 2x2 ones start at 0.
    let (ow, oh, ox, oy) = match reduction {
        DepthReduction::Average3x3 => {
            let (ow, oh) = (
                aograph_graph::centred_step(w, 3),
                aograph_graph::centred_step(h, 3),
            );
            (ow, oh, (3 * ow - w) / 2, (3 * oh - h) / 2)
        }
        _ => (w.div_ceil(k), h.div_ceil(k), 0, 0),
    };
    let mut out = Vec::with_capacity((ow * oh) as usize);
    for y in 0..oh {
        for x in 0..ow {
            let (mut sum, mut n, mut sky, mut lo, mut hi) =
                (0.0f32, 0u32, 0u32, f32::INFINITY, 0.0f32);
            for j in 0..k {
                for i in 0..k {
                    let (sx, sy) = (
                        (x * k + i) as i64 - ox as i64,
                        (y * k + j) as i64 - oy as i64,
                    );
                    if sx < 0 || sy < 0 || sx >= w as i64 || sy >= h as i64 {
                        continue;
                    }
                    let z = src[(sy as u32 * w + sx as u32) as usize];
                    if z > 0.0 {
                        sum += z;
                        n += 1;
                        lo = lo.min(z);
                    } else {
                        sky += 1;
                    }
                    hi = hi.max(z);
                }
            }
            let clamp = |v: i64, size: u32| v.clamp(0, size as i64 - 1) as u32;
            let centre = || {
                let cx = clamp((x * k + 1) as i64 - ox as i64, w);
                let cy = clamp((y * k + 1) as i64 - oy as i64, h);
                src[(cy * w + cx) as usize].max(0.0)
            };
            out.push(match reduction {
                DepthReduction::Average3x3 if n > 0 && sky > 0 => centre(),
                DepthReduction::Average3x3 if n > 0 => sum / n as f32,
                DepthReduction::Min2x2 if n > 0 => lo,
                DepthReduction::Max2x2 => hi,
                DepthReduction::FarWeighted2x2 => {
                    panic!("FarWeighted2x2 needs a radius: use depth_prefilter::prefilter_cpu")
                }
                _ => 0.0,
            });
        }
    }
    (out, ow, oh)
}
