//! The viewer's picture as a pass of the frame graph: it reads the technique's accessibility,
//! the shaded image and the ray-traced reference (an imported texture the reference worker
//! fills), and draws into the imported view texture that the window shows and screenshots read.
//! Both imports are the viewer's own textures, so the graph composes with the viewer the way
//! it would with any user's renderer.
//!
//! Invariant: the view texture holds display values (sRGB bytes): in AO mode a pixel's byte is
//! what `aograph render` writes into ao.png for the same accessibility.

use std::sync::Arc;

use aograph_ao_passes::PER_FRAME_OUTPUT;
use aograph_graph::{ColorTarget, Extent, GpuContext, GraphBuilder, SizeClass, TextureDesc};

use aograph_app_config::error::{AppError, AppResult};
use aograph_renderer::frame_graph::FrameGraph;
use aograph_renderer::renderer::GraphExtension;

/// Name of the imported texture the picture is drawn into.
pub const VIEW_TEXTURE: &str = "viewer.view";
/// Name of the imported texture holding the reference (-1 where not traced yet).
pub const REFERENCE_TEXTURE: &str = "viewer.reference";
/// The display pass and its uniform block.
pub const DISPLAY_PASS: &str = "viewer.display";
pub const DISPLAY_UNIFORM: &str = "display";
/// Format of the view texture: sRGB, so egui samples it as the colour it shows.
pub const VIEW_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;

/// What the picture shows.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DisplayMode {
    #[default]
    Ao,
    Shaded,
    /// The technique left of the split, the reference right of it.
    Split,
    /// Technique minus reference, signed.
    Error,
    /// With `temporal = true`: the accumulated image left of the split, the technique's own
    /// image of this frame (what it shows with `temporal = false`, noise of this frame) right
    /// of it. Without accumulation both sides are the same image.
    Temporal,
}

impl DisplayMode {
    pub const ALL: [DisplayMode; 5] = [
        Self::Ao,
        Self::Shaded,
        Self::Split,
        Self::Error,
        Self::Temporal,
    ];
    pub fn name(self) -> &'static str {
        match self {
            Self::Ao => "ao",
            Self::Shaded => "shaded",
            Self::Split => "split",
            Self::Error => "error",
            Self::Temporal => "temporal",
        }
    }
    pub fn parse(s: &str) -> AppResult<Self> {
        Self::ALL
            .into_iter()
            .find(|m| m.name() == s)
            .ok_or_else(|| AppError::InvalidArgument {
                name: "display mode".into(),
                value: s.into(),
                allowed: "ao, shaded, split, error or temporal".into(),
            })
    }
    /// True when the picture needs the reference.
    pub fn uses_reference(self) -> bool {
        matches!(self, Self::Split | Self::Error)
    }
}

/// The display uniform block's bytes: mode, split position (0..1 of the width), error scale.
pub fn display_uniform(mode: DisplayMode, split: f32, error_scale: f32) -> Vec<u8> {
    let mode = mode as u32;
    [
        mode.to_le_bytes(),
        split.to_le_bytes(),
        error_scale.to_le_bytes(),
        0f32.to_le_bytes(),
    ]
    .concat()
}

/// The display pass as a frame-graph extension (see the module docs).
pub fn display_extension() -> GraphExtension {
    Arc::new(|b: &mut GraphBuilder, fg: &FrameGraph| {
        let ao = fg.accessibility()?;
        let shaded = fg
            .shaded
            .ok_or_else(|| aograph_renderer::RenderError::InvalidArgument {
                name: "viewer frame graph".into(),
                value: "no shaded output".into(),
                allowed: "a frame graph built with FrameOutputs { shaded: true }".into(),
            })?;
        let target = b.import_texture(VIEW_TEXTURE, TextureDesc::new(VIEW_FORMAT, SizeClass::FULL));
        let reference = b.import_texture(
            REFERENCE_TEXTURE,
            TextureDesc::new(wgpu::TextureFormat::R32Float, SizeClass::FULL),
        );
        // The technique's own image of this frame where it accumulates (else its output).
        let per_frame = fg.extra(PER_FRAME_OUTPUT).unwrap_or(ao);
        let mut p = b.fullscreen_pass(DISPLAY_PASS, "viewer/display.wgsl", "vs", "fs");
        p.sample("ao", ao)
            .sample("shaded", shaded)
            .sample("reference", reference)
            .sample("per_frame", per_frame);
        p.uniform(
            DISPLAY_UNIFORM,
            &display_uniform(DisplayMode::Ao, 0.5, 0.25),
        );
        let out = p.color_target(target, ColorTarget::clear([0.0, 0.0, 0.0, 1.0]));
        b.export(out);
        Ok(())
    })
}

/// The viewer's two imported textures at one size.
pub struct DisplayTextures {
    pub size: Extent,
    pub view: wgpu::Texture,
    pub reference: wgpu::Texture,
}

impl DisplayTextures {
    pub fn new(gpu: &GpuContext, size: Extent) -> Self {
        let texture = |label, format, usage| {
            aograph_graph::plain_texture(
                &gpu.device,
                label,
                (size.width, size.height),
                format,
                usage,
            )
        };
        use wgpu::TextureUsages as U;
        let view = texture(
            VIEW_TEXTURE,
            VIEW_FORMAT,
            U::RENDER_ATTACHMENT | U::TEXTURE_BINDING | U::COPY_SRC,
        );
        let reference = texture(
            REFERENCE_TEXTURE,
            wgpu::TextureFormat::R32Float,
            U::TEXTURE_BINDING | U::COPY_DST,
        );
        let t = Self {
            size,
            view,
            reference,
        };
        t.clear_reference(gpu);
        t
    }

    /// Marks the whole reference as not traced yet.
    pub fn clear_reference(&self, gpu: &GpuContext) {
        let n = (self.size.width * self.size.height) as usize;
        self.write_reference(gpu, &vec![-1.0; n]);
    }

    /// Uploads a reference image (row-major, top row first, one value per pixel).
    pub fn write_reference(&self, gpu: &GpuContext, values: &[f32]) {
        gpu.queue.write_texture(
            self.reference.as_image_copy(),
            bytemuck::cast_slice(values),
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(self.size.width * 4),
                rows_per_image: Some(self.size.height),
            },
            self.reference.size(),
        );
    }
}
