//! Temporal reprojection and accumulation: the history-backed block behind TSSAO's AO buffer
//! (docs/techniques/tssao.md §4-§6, Eqs. 3, 5-7) and MSSAO's optional temporal filter (docs/techniques/mssao.md §7,
//! Eqs. 12-14, the special case of a fixed blend k = 0.5). It runs on top of any technique
//! that produces a full-size accessibility texture each frame.
//!
//! # Using it
//!
//! ```ignore
//! // In a technique's build(), after its spatial passes produced `ao` (full size, R32Float):
//! let t = add_temporal(ctx.builder, "mssao.temporal", ao, &ctx.gbuffer, ctx.view, &TemporalAccumulation::mssao())?;
//! Ok(AoOutput::new(t.accumulated))
//! // and in channels(): my_channels.union(temporal_channels())
//! // and in is_temporal(): true
//! ```
//!
//! [`add_temporal`] adds two passes (three on a scene without motion vectors):
//! - `<prefix>.reproject` ([`add_reprojection`], shaders/blocks/temporal_reproject.wgsl):
//!   reverse reprojection (TSSAO Eq. 3 / MSSAO Eq. 12) through the g-buffer's motion vectors
//!   where the scene moves (prev_uv = uv + motion), through `view_to_prev_clip` (camera only)
//!   where the g-buffer has no Motion channel; then the disocclusion test |1 - d_new/d_old| < epsilon
//!   (TSSAO Eq. 7 / MSSAO Eq. 13) and the bilinear fetch of the previous value;
//! - `<prefix>.accumulate` (shaders/blocks/temporal_accumulate.wgsl): the blend
//!   ([`TemporalMode`]), writing the history and the accumulated accessibility;
//! - `<prefix>.zero_motion` (only when the g-buffer has no Motion channel): a 1x1 stand-in for
//!   the motion texture, which the shaders then never read.
//!
//! TSSAO uses the lower-level pieces ([`ao_history`], [`add_reprojection`]) and writes the
//! history itself from its sampling pass, because its blend (Eq. 5 with k new samples) and its
//! neighbourhood test (Eq. 8) happen where the samples are taken.
//!
//! # The history (AO buffer) layout, Rgba32Float, one texel per output pixel
//!
//! | channel | meaning |
//! |---|---|
//! | x | accessibility accumulated so far (1 = unoccluded) |
//! | y | n_t: how many samples (TSSAO) or frames ([`TemporalMode::Average`]) it holds, <= n_max |
//! | z | TSSAO: the pixel's position in its low-discrepancy sequence (its Halton index); [`TemporalMode::Average`]: the running mean of A^2 (the second moment, so the variance is z - x^2: [`mod@super::history_denoise`] reads it); 0 otherwise |
//! | w | linear depth of the pixel when written; **negative** where the surface was moving (its motion differed from the camera-only reprojection by more than [`MOVING_PIXELS`] pixels); 0 = sky / nothing |
//!
//! The graph clears an invalid history to zero (first frame, resize, camera cut), which reads
//! as "sky, nothing accumulated": every pixel then starts afresh, and the shaders also check the
//! view block's `frame.y` (history valid), so nothing from before a cut or resize survives.
//! It is 32-bit RGBA as in the paper (§4: "Both the ambient occlusion buffer and the SSAO
//! texture are 32-bit RGBA render targets"); it is the one texture of `blocks` that is not
//! R32Float ([`BLOCK_FORMAT`](super::BLOCK_FORMAT)), and its shaders write it as an rgba32float
//! storage texture, which core wgpu guarantees.
//!
//! # The reprojected texture, Rgba32Float (output of [`add_reprojection`])
//!
//! | channel | meaning |
//! |---|---|
//! | x | previous accessibility at the reprojected position: bilinear over the 2x2 history texels that pass Eq. 7, renormalised (the paper: "requires bilinear filtering for reconstruction") |
//! | y | n_t of the reprojected texel (nearest passing texel), 0 where the history is invalid here |
//! | z | history.z of the passing texel with the largest bilinear weight (the sequence index, or the second moment; kept from the nearest texel on disocclusion; 0 off screen or without history) |
//! | w | flags: 1 = history valid here, 2 = this pixel is moving (see history.w) |
//!
//! # Decisions the papers leave open (written down here)
//!
//! - Depth of the current point in the previous frame (d_new of Eq. 7): where the g-buffer has
//!   motion, its 3D motion's previous depth (the surface's own previous transform through the
//!   previous camera), so an object approaching the camera keeps its history however fast;
//!   elsewhere (static scenes) the camera-only reprojection of the current view-space point
//!   (`view_to_prev_clip`), exact for static geometry. A pixel counts as moving when its
//!   motion differs from the camera-only one by more than [`MOVING_PIXELS`] across the screen
//!   or a quarter of epsilon along the view axis. The previous camera is assumed to have the same
//!   projection as the current one (the renderer changes only the camera's pose).
//! - Eq. 7 per bilinear tap against the tangent plane: each of the 2x2 texels around prev_uv
//!   is tested with d_new taken where its pixel ray meets the current point's tangent plane
//!   (in the previous view), not at prev_uv itself. At the reprojected position this is
//!   exactly Eq. 7; at the taps it removes the half-pixel depth slope that otherwise fails
//!   Eq. 7 on every grazing surface as soon as the camera moves. Where the plane is edge-on
//!   (or the correction exceeds 50%) the plain d_new is used.
//! - The pixel is valid if any tap passes; n_t and the index come from the passing tap with
//!   the largest bilinear weight (nearest, as §3.3.1 requires for the index; the spec's \[I\]
//!   reading for n_t), the value bilinearly from the passing taps only, so no value leaks
//!   across a depth edge.
//! - Off-screen in the previous frame (prev_uv outside [0, 1]^2), behind the previous camera,
//!   sky now or sky then: invalid (TSSAO §3.4.1, §3.6.3; MSSAO Table 5).
//! - [`TemporalMode::FixedBlend`]'s k is the weight of the *previous* value, as in MSSAO Eq. 14
//!   (AO_curr = k AO_prev + (1 - k) AO); k = 0 where the history is invalid. MSSAO stores the
//!   blended value as next frame's AO_prev (an exponential moving average; spec §7 \[IMPL\]).
//! - [`TemporalMode::Average`] is TSSAO Eqs. 5-6 with one "sample" per frame: a running mean
//!   over up to n_max frames, then exponential decay with weight 1 / (n_max + 1).

use aograph_frame::ReadsView;
use aograph_frame::{GBufferChannel, GBufferChannels, GBufferTextures};
use aograph_graph::{
    BufferHandle, GraphBuilder, HistoryTexture, SizeClass, TextureDesc, TextureHandle,
};
use bytemuck::{Pod, Zeroable};

use crate::error::{AoError, AoResult, check_param};
use crate::technique::ACCESSIBILITY_FORMAT;

/// Format of the history (AO buffer) and of the reprojected texture.
pub const HISTORY_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

/// A pixel whose motion differs from the camera-only reprojection by more than this many
/// pixels per frame counts as moving (history.w < 0).
pub const MOVING_PIXELS: f32 = 0.05;

/// Largest n_max accepted (n_t and the sequence index stay exact in f32 far beyond this).
pub const MAX_N_MAX: u32 = 65536;

/// How this frame's value is combined with the reprojected previous one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TemporalMode {
    /// TSSAO Eqs. 5-6 with one sample per frame: A = (n_t A_prev + A) / (n_t + 1),
    /// n_t+1 = min(n_t + 1, n_max). An exact running mean until n_max frames, then decay.
    Average,
    /// MSSAO Eq. 14: A = k A_prev + (1 - k) A where the history is valid, A elsewhere. k is
    /// the weight of the previous value, in [0, 1); the paper uses 0.5.
    FixedBlend(f32),
}

/// Parameters of [`add_temporal`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TemporalAccumulation {
    /// Relative depth tolerance of the disocclusion test |1 - d_new/d_old| < epsilon (TSSAO
    /// Eq. 7, MSSAO Eq. 13). Neither paper gives a value; both specs suggest 0.01-0.05.
    pub epsilon: f32,
    /// Cap of the per-pixel count n_t (TSSAO Eq. 6; ignored by `FixedBlend`).
    pub n_max: u32,
    /// How this frame's value is blended with the reprojected history.
    pub mode: TemporalMode,
}

impl Default for TemporalAccumulation {
    /// A running mean over up to 32 frames with epsilon = 0.03.
    fn default() -> Self {
        Self {
            epsilon: DEFAULT_EPSILON,
            n_max: 32,
            mode: TemporalMode::Average,
        }
    }
}

/// Default epsilon of Eq. 7 (the papers give none; the middle of the specs' 0.01-0.05).
pub const DEFAULT_EPSILON: f32 = 0.03;

impl TemporalAccumulation {
    /// MSSAO's temporal filter (Eqs. 12-14, Table 5): a fixed blend with k = 0.5.
    pub fn mssao() -> Self {
        Self {
            epsilon: DEFAULT_EPSILON,
            n_max: 1,
            mode: TemporalMode::FixedBlend(0.5),
        }
    }
    /// Range checks; errors are reported under `owner` (the technique or block prefix).
    pub fn validate(&self, owner: &str) -> AoResult<()> {
        check_epsilon(owner, "temporal_epsilon", self.epsilon)?;
        check_param(owner, "n_max", self.n_max, 1, MAX_N_MAX)?;
        if let TemporalMode::FixedBlend(k) = self.mode {
            if !(k.is_finite() && (0.0..1.0).contains(&k)) {
                return Err(AoError::InvalidParameter {
                    technique: owner.into(),
                    name: "temporal_k".into(),
                    value: k.to_string(),
                    allowed: "0 to 1 (excluding 1: the current frame must contribute)".into(),
                });
            }
        }
        Ok(())
    }
}

/// Checks an Eq. 7 epsilon: finite, in (0, 1].
pub fn check_epsilon(owner: &str, name: &str, epsilon: f32) -> AoResult<()> {
    if epsilon.is_finite() && epsilon > 0.0 && epsilon <= 1.0 {
        Ok(())
    } else {
        Err(AoError::InvalidParameter {
            technique: owner.into(),
            name: name.into(),
            value: epsilon.to_string(),
            allowed: "greater than 0 and at most 1 (relative depth)".into(),
        })
    }
}

/// The g-buffer channels the block reads; add them to the technique's `channels()`. Motion is
/// requested too: the g-buffer drops it for scenes where nothing moves, and the block then
/// reprojects through the camera alone.
pub fn temporal_channels() -> GBufferChannels {
    GBufferChannels::of(&[
        GBufferChannel::LinearDepth,
        GBufferChannel::Normals,
        GBufferChannel::Motion,
    ])
}

/// What [`add_temporal`] wrote.
#[derive(Clone, Copy, Debug)]
pub struct TemporalOutputs {
    /// The accumulated accessibility (R32Float, full size, 1 on sky): the technique's output.
    pub accumulated: TextureHandle,
    /// The history (AO buffer), for debugging views; `current` is this frame's version.
    pub history: HistoryTexture,
    /// This frame's reprojected history (see the module docs' layout).
    pub reprojected: TextureHandle,
}

/// What [`add_reprojection`] wrote, and the motion texture to bind alongside it.
#[derive(Clone, Copy, Debug)]
pub struct Reprojection {
    /// Rgba32Float, full size (layout in the module docs).
    pub reprojected: TextureHandle,
    /// The g-buffer's motion, or a 1x1 stand-in when the g-buffer has none.
    pub motion: TextureHandle,
    /// Whether `motion` holds real motion vectors (shaders must not read it otherwise).
    pub has_motion: bool,
}

/// The `params` uniform of shaders/blocks/temporal_reproject.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct ReprojectUniform {
    epsilon: f32,
    has_motion: u32,
    moving_pixels: f32,
    _pad: f32,
}

aograph_graph::uniform_layout!(ReprojectUniform {
    epsilon,
    has_motion,
    moving_pixels,
    _pad
});

/// The `params` uniform of shaders/blocks/temporal_accumulate.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct AccumulateUniform {
    /// 0 = Average, 1 = FixedBlend.
    mode: u32,
    n_max: f32,
    k: f32,
    /// Cap of n_t where the pixel changed ([`ChangeMask`]); 0 = no mask.
    changed_n_max: f32,
}

aograph_graph::uniform_layout!(AccumulateUniform {
    mode,
    n_max,
    k,
    changed_n_max
});

/// Where this frame's value may differ from the history for reasons reprojection cannot see
/// (the technique knows: rtao's rays hit moving geometry), for [`add_temporal_with_changes`]:
/// a full-size texture whose `.r > 0.5` marks such pixels, and the cap of n_t there (and at
/// pixels whose own surface moves). The ray-traced counterpart of TSSAO's Eq. 8: a shadow
/// cast by a moving object is averaged over `n_max` frames at most, so it neither lags nor
/// trails for long (after the mark clears n_t grows by one a frame again).
#[derive(Clone, Copy, Debug)]
pub struct ChangeMask {
    /// Full-size texture whose `.r > 0.5` marks pixels whose value changed in ways
    /// reprojection cannot see.
    pub mask: TextureHandle,
    /// Cap of n_t at marked pixels and at pixels whose own surface moves (1 to
    /// [`MAX_N_MAX`]).
    pub n_max: u32,
}

/// Declares the history (AO buffer) `<prefix>.history`: Rgba32Float, full size.
pub fn ao_history(builder: &mut GraphBuilder, prefix: &str) -> HistoryTexture {
    builder.history_texture(
        &format!("{prefix}.history"),
        TextureDesc::new(HISTORY_FORMAT, SizeClass::FULL),
    )
}

fn channel(gbuffer: &GBufferTextures, prefix: &str, c: GBufferChannel) -> AoResult<TextureHandle> {
    gbuffer.get(c).ok_or_else(|| AoError::MissingChannel {
        technique: prefix.into(),
        channel: c.name().into(),
    })
}

/// The motion texture to bind: the g-buffer's, or a 1x1 stand-in written by
/// `<prefix>.zero_motion` (so shaders can always declare the binding).
fn motion_or_stand_in(
    builder: &mut GraphBuilder,
    prefix: &str,
    gbuffer: &GBufferTextures,
) -> (TextureHandle, bool) {
    if let Some(m) = gbuffer.motion {
        return (m, true);
    }
    let name = format!("{prefix}.zero_motion");
    let t = builder.create_texture(
        &name,
        TextureDesc::new(GBufferChannel::Motion.format(), SizeClass::fixed(1, 1)),
    );
    let mut p = builder.compute_pass(&name, "blocks/temporal_zero.wgsl", "main");
    let t = p.write_storage("dst", t);
    p.dispatch_over(t);
    (t, false)
}

/// Pass `<prefix>.reproject`: reprojects `history_previous` (an [`ao_history`]'s `previous`)
/// into this frame and applies the disocclusion test with `epsilon`. Reads linear depth,
/// normals and, when present, motion.
pub fn add_reprojection(
    builder: &mut GraphBuilder,
    prefix: &str,
    history_previous: TextureHandle,
    gbuffer: &GBufferTextures,
    view: BufferHandle,
    epsilon: f32,
) -> AoResult<Reprojection> {
    check_epsilon(prefix, "temporal_epsilon", epsilon)?;
    let depth = channel(gbuffer, prefix, GBufferChannel::LinearDepth)?;
    let normals = channel(gbuffer, prefix, GBufferChannel::Normals)?;
    let (motion, has_motion) = motion_or_stand_in(builder, prefix, gbuffer);
    let name = format!("{prefix}.reproject");
    let out = builder.create_texture(
        &format!("{prefix}.reprojected"),
        TextureDesc::new(HISTORY_FORMAT, SizeClass::FULL),
    );
    let mut p = builder.compute_pass(&name, "blocks/temporal_reproject.wgsl", "main");
    p.sample("history", history_previous)
        .sample("linear_depth", depth)
        .sample("normals", normals)
        .sample("motion", motion);
    p.read_view(view);
    p.uniform_struct(
        "params",
        &ReprojectUniform {
            epsilon,
            has_motion: has_motion as u32,
            moving_pixels: MOVING_PIXELS,
            _pad: 0.0,
        },
    );
    let reprojected = p.write_storage("reprojected", out);
    p.dispatch_over(reprojected);
    Ok(Reprojection {
        reprojected,
        motion,
        has_motion,
    })
}

/// Adds temporal accumulation on top of `current` (this frame's full-size accessibility,
/// R32Float or R16Float): reprojection, disocclusion test, blend. Pass and resource names
/// start with `prefix` (e.g. `mssao.temporal`). Needs the g-buffer's linear depth and normals
/// ([`temporal_channels`]); the technique using it is temporal (`is_temporal` = true).
pub fn add_temporal(
    builder: &mut GraphBuilder,
    prefix: &str,
    current: TextureHandle,
    gbuffer: &GBufferTextures,
    view: BufferHandle,
    params: &TemporalAccumulation,
) -> AoResult<TemporalOutputs> {
    add_temporal_with_changes(builder, prefix, current, None, gbuffer, view, params)
}

/// [`add_temporal`] with a [`ChangeMask`]: n_t capped at `changes.n_max` where the mask is
/// set or the pixel's own surface moves (Average mode; FixedBlend ignores it).
pub fn add_temporal_with_changes(
    builder: &mut GraphBuilder,
    prefix: &str,
    current: TextureHandle,
    changes: Option<ChangeMask>,
    gbuffer: &GBufferTextures,
    view: BufferHandle,
    params: &TemporalAccumulation,
) -> AoResult<TemporalOutputs> {
    params.validate(prefix)?;
    if let Some(c) = changes {
        check_param(prefix, "changed_n_max", c.n_max, 1, MAX_N_MAX)?;
    }
    let depth = channel(gbuffer, prefix, GBufferChannel::LinearDepth)?;
    let history = ao_history(builder, prefix);
    let r = add_reprojection(
        builder,
        prefix,
        history.previous,
        gbuffer,
        view,
        params.epsilon,
    )?;
    let (mode, k) = match params.mode {
        TemporalMode::Average => (0, 0.0),
        TemporalMode::FixedBlend(k) => (1, k),
    };
    let uniform = AccumulateUniform {
        mode,
        n_max: params.n_max as f32,
        k,
        changed_n_max: changes.map_or(0.0, |c| c.n_max as f32),
    };
    let name = format!("{prefix}.accumulate");
    let out = builder.create_texture(
        &format!("{prefix}.accumulated"),
        TextureDesc::new(ACCESSIBILITY_FORMAT, SizeClass::FULL),
    );
    let mut p = builder.compute_pass(&name, "blocks/temporal_accumulate.wgsl", "main");
    p.sample("current", current)
        .sample("reprojected", r.reprojected)
        .sample("linear_depth", depth)
        // Without a mask the shader never reads `changed` (changed_n_max = 0).
        .sample("changed", changes.map_or(current, |c| c.mask));
    p.uniform_struct("params", &uniform);
    let written = p.write_storage("history", history.current);
    let accumulated = p.write_storage("accumulated", out);
    p.dispatch_over(accumulated);
    Ok(TemporalOutputs {
        accumulated,
        history: HistoryTexture {
            previous: history.previous,
            current: written,
        },
        reprojected: r.reprojected,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use aograph_frame::ViewUniforms;
    use aograph_graph::{BufferDesc, CompileOptions, compile};

    fn plan(with_motion: bool, params: &TemporalAccumulation) -> Vec<String> {
        let mut b = GraphBuilder::new();
        let view = b.import_buffer(
            aograph_frame::VIEW_BUFFER,
            BufferDesc {
                size: std::mem::size_of::<ViewUniforms>() as u64,
            },
        );
        let mut g = GBufferTextures::default();
        for c in temporal_channels()
            .iter()
            .filter(|c| with_motion || *c != GBufferChannel::Motion)
        {
            g.set(
                c,
                b.import_texture(c.name(), TextureDesc::new(c.format(), SizeClass::FULL)),
            );
        }
        let current = b.import_texture(
            "ao",
            TextureDesc::new(ACCESSIBILITY_FORMAT, SizeClass::FULL),
        );
        let out = add_temporal(&mut b, "t", current, &g, view, params).unwrap();
        b.export(out.accumulated);
        let shaders = crate::shader_library().unwrap();
        let plan = compile(b.build(), &shaders, CompileOptions::default()).unwrap();
        plan.pass_names().into_iter().map(String::from).collect()
    }

    #[test]
    fn plan_is_reproject_then_accumulate() {
        assert_eq!(
            plan(true, &TemporalAccumulation::default()),
            ["t.reproject", "t.accumulate"]
        );
        assert_eq!(
            plan(true, &TemporalAccumulation::mssao()),
            ["t.reproject", "t.accumulate"]
        );
        assert_eq!(
            plan(false, &TemporalAccumulation::default()),
            ["t.zero_motion", "t.reproject", "t.accumulate"]
        );
    }

    #[test]
    fn parameters_are_range_checked() {
        let ok = TemporalAccumulation::default();
        assert!(ok.validate("t").is_ok() && TemporalAccumulation::mssao().validate("t").is_ok());
        for (bad, name) in [
            (
                TemporalAccumulation { epsilon: 0.0, ..ok },
                "temporal_epsilon",
            ),
            (
                TemporalAccumulation {
                    epsilon: f32::NAN,
                    ..ok
                },
                "temporal_epsilon",
            ),
            (TemporalAccumulation { n_max: 0, ..ok }, "n_max"),
            (
                TemporalAccumulation {
                    mode: TemporalMode::FixedBlend(1.0),
                    ..ok
                },
                "temporal_k",
            ),
            (
                TemporalAccumulation {
                    mode: TemporalMode::FixedBlend(-0.1),
                    ..ok
                },
                "temporal_k",
            ),
        ] {
            let e = bad.validate("t").unwrap_err().to_string();
            assert!(e.contains(name), "{e}");
        }
    }

    #[test]
    fn missing_normals_is_an_error_naming_the_channel() {
        let mut b = GraphBuilder::new();
        let view = b.import_buffer(aograph_frame::VIEW_BUFFER, BufferDesc { size: 16 });
        let mut g = GBufferTextures::default();
        g.set(
            GBufferChannel::LinearDepth,
            b.import_texture(
                "d",
                TextureDesc::new(wgpu::TextureFormat::R32Float, SizeClass::FULL),
            ),
        );
        let current = b.import_texture(
            "ao",
            TextureDesc::new(ACCESSIBILITY_FORMAT, SizeClass::FULL),
        );
        let e = add_temporal(
            &mut b,
            "t",
            current,
            &g,
            view,
            &TemporalAccumulation::default(),
        )
        .unwrap_err();
        assert!(
            matches!(&e, AoError::MissingChannel { channel, .. } if channel == "normals"),
            "{e}"
        );
    }
}
