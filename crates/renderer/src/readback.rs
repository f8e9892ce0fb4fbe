//! What a renderer's last frame reads back to the CPU: accessibility, the technique's extra
//! and radiance outputs, the shaded image and g-buffer channels, and the world-space surfaces
//! a reference traces from.
//!
//! Invariant: every read-back is of the last frame rendered, and asking for something the
//! frame does not output is an error naming it and how to request it, never a panic.

use aograph_ao_passes::ExtraOutput;
use aograph_frame::GBufferChannel;
use aograph_graph::TextureHandle;
use aograph_scene::SurfaceBuffer;
use glam::{Mat4, Vec3};

use crate::error::{RenderError, RenderResult};
use crate::renderer::Renderer;

impl Renderer {
    pub(crate) fn read_channel(
        &self,
        h: Option<TextureHandle>,
        what: &str,
    ) -> RenderResult<aograph_graph::TextureReadback> {
        let h = h.ok_or_else(|| RenderError::InvalidArgument {
            name: what.into(),
            value: "not requested".into(),
            allowed: "request it in FrameOutputs".into(),
        })?;
        Ok(self.exec.read_texture(&self.plan, h)?)
    }

    /// Accessibility of the last frame, row-major, top row first.
    pub fn read_ao(&self) -> RenderResult<Vec<f32>> {
        let ao = self.graph.accessibility()?;
        Ok(self.exec.read_texture(&self.plan, ao)?.channel(0)?)
    }

    /// An extra output of the technique (e.g. SSDO's radiance, `ssdo::DIRECT_OUTPUT`) as RGBA
    /// floats.
    pub fn read_extra(&self, key: ExtraOutput) -> RenderResult<Vec<f32>> {
        Ok(self.read_extra_readback(key)?.to_f32()?)
    }

    /// An extra output of the technique as read back: its own size (a technique at
    /// `resolution = "half"` leaves its extras at half size) and format.
    pub fn read_extra_readback(
        &self,
        key: ExtraOutput,
    ) -> RenderResult<aograph_graph::TextureReadback> {
        self.read_channel(self.graph.extra(key), key.name())
    }

    /// The technique's radiance outputs (direct, indirect) as RGBA floats, or an error when
    /// the technique computes no radiance.
    pub fn read_radiance(&self) -> RenderResult<(Vec<f32>, Vec<f32>)> {
        let r = self.graph.radiance;
        Ok((
            self.read_channel(r.map(|r| r.direct), "radiance (direct)")?
                .to_f32()?,
            self.read_channel(r.map(|r| r.indirect), "radiance (indirect)")?
                .to_f32()?,
        ))
    }

    /// shaded.png's pixels (RGBA8, sRGB-encoded).
    pub fn read_shaded(&self) -> RenderResult<Vec<u8>> {
        Ok(self.read_channel(self.graph.shaded, "shaded")?.bytes)
    }

    /// A g-buffer channel of the last frame as stored, for the channels [`FrameOutputs`](crate::FrameOutputs)
    /// keeps readable: with `surfaces`, positions and the normals in whichever encodings the
    /// frame wrote (`normals`, `normals_oct`); with `linear_depth`, linear depth.
    pub fn read_gbuffer(&self, c: GBufferChannel) -> RenderResult<aograph_graph::TextureReadback> {
        self.read_channel(self.graph.gbuffer.get(c), c.name())
    }

    /// Linear depth of the last frame (0 = sky).
    pub fn read_linear_depth(&self) -> RenderResult<Vec<f32>> {
        Ok(self
            .read_channel(self.graph.gbuffer.linear_depth, "linear_depth")?
            .channel(0)?)
    }

    /// World-space points and normals of the last frame from the g-buffer, for the reference.
    pub fn surfaces(&self) -> RenderResult<SurfaceBuffer> {
        let pos = self
            .read_channel(self.graph.gbuffer.positions, "positions")?
            .to_f32()?;
        let nrm = self
            .read_channel(self.graph.gbuffer.normals, "normals")?
            .to_f32()?;
        let inv_view: Mat4 = self.camera().view().inverse();
        let n = (self.output.width * self.output.height) as usize;
        let mut s = SurfaceBuffer {
            width: self.output.width,
            height: self.output.height,
            points: Vec::with_capacity(n),
            normals: Vec::with_capacity(n),
            valid: Vec::with_capacity(n),
        };
        for i in 0..n {
            let p = &pos[i * 4..i * 4 + 4];
            let q = &nrm[i * 4..i * 4 + 4];
            let valid = p[3] > 0.5;
            s.points
                .push(inv_view.transform_point3(Vec3::new(p[0], p[1], p[2])));
            s.normals.push(
                inv_view
                    .transform_vector3(Vec3::new(q[0], q[1], q[2]))
                    .normalize_or_zero(),
            );
            s.valid.push(valid);
        }
        Ok(s)
    }
}
