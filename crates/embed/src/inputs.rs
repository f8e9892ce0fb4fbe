//! What an application hands over each frame ([`AoInputs`]): its depth buffer and the
//! projection it was rendered with, optionally its normals and motion vectors, and the frame's
//! view matrix, time and cut flag. Each optional input states its own encoding, so aograph's
//! adapters (`adapters.rs`) turn it into the channels the techniques read.
//!
//! Invariant: an input's format is checked here, against the encodings listed, before any GPU
//! work; the per-frame description ([`InputLayout`]) is a small `Copy` value, so choosing the
//! plan for a frame allocates nothing.

use glam::Mat4;

use crate::error::{EmbedError, EmbedResult};

/// The depth the application rendered.
#[derive(Clone, Copy, Debug)]
pub enum DepthInput<'a> {
    /// A hardware depth buffer (Depth32Float, Depth24Plus or Depth16Unorm) with
    /// `TEXTURE_BINDING` usage, in the convention of [`AoInputs::projection`].
    Hardware(&'a wgpu::Texture),
    /// Linear view depth already (R32Float, `TEXTURE_BINDING`): positive distance along the
    /// view direction (-z in view space) in the view matrix's units, 0 where nothing was drawn.
    Linear(&'a wgpu::Texture),
}

impl<'a> DepthInput<'a> {
    /// The texture either way.
    pub fn texture(&self) -> &'a wgpu::Texture {
        match self {
            Self::Hardware(t) | Self::Linear(t) => t,
        }
    }
}

/// Which space an application's normals are in.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum NormalSpace {
    /// View space (right-handed, camera looking down -Z), as aograph's g-buffer stores them.
    #[default]
    View,
    /// World space; turned into view space with [`AoInputs::view`].
    World,
}

/// How an application's normal texture stores a unit vector.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum NormalEncoding {
    /// xyz as signed values (Rgba16Float, Rgba32Float, Rgba8Snorm, Rgba16Snorm).
    #[default]
    Xyz,
    /// xyz packed to [0, 1] as `n * 0.5 + 0.5` (Rgb10a2Unorm, Rgba8Unorm, Rgba16Unorm).
    PackedXyz,
    /// Octahedral, xy in [-1, 1] (Rg16Float, Rg32Float, Rg16Snorm, Rg8Snorm).
    Octahedral,
    /// Octahedral packed to [0, 1] (Rg16Unorm, Rg8Unorm, Rgba8Unorm's xy).
    PackedOctahedral,
}

impl NormalEncoding {
    /// The `ENCODING` constant of shaders/embed/normals_decode.wgsl.
    pub(crate) fn shader_constant(self) -> f64 {
        match self {
            Self::Xyz => 0.0,
            Self::PackedXyz => 1.0,
            Self::Octahedral => 2.0,
            Self::PackedOctahedral => 3.0,
        }
    }
}

/// An application's normal buffer.
#[derive(Clone, Copy, Debug)]
pub struct NormalsInput<'a> {
    /// A float-readable texture (`TEXTURE_BINDING`) of the depth's size.
    pub texture: &'a wgpu::Texture,
    /// View or world space.
    pub space: NormalSpace,
    /// How the texture stores a normal.
    pub encoding: NormalEncoding,
}

/// An application's motion vectors.
#[derive(Clone, Copy, Debug)]
pub struct MotionInput<'a> {
    /// A float-readable texture (`TEXTURE_BINDING`) of the depth's size, motion in xy.
    pub texture: &'a wgpu::Texture,
    /// The convention, as a scale: previous uv = uv + `uv_scale` * m (uv in 0..1, y down).
    /// `[1, 1]`: aograph's own (previous - current, uv); `[-1, -1]`: current - previous, uv;
    /// `[1/width, 1/height]`: previous - current in pixels; `[0.5, -0.5]`: previous - current
    /// in NDC (y up).
    pub uv_scale: [f32; 2],
}

/// One frame of an application's inputs.
#[derive(Clone, Copy, Debug)]
pub struct AoInputs<'a> {
    /// The depth buffer; its size is the output's size.
    pub depth: DepthInput<'a>,
    /// The projection the depth was rendered with (wgpu's 0..1 clip depth, right-handed):
    /// it decides standard or reversed Z, finite or infinite far plane, perspective or
    /// orthographic.
    pub projection: Mat4,
    /// World to view space (right-handed, looking down -Z). Temporal techniques reproject
    /// through it; world-space normals are turned into view space with it.
    pub view: Mat4,
    /// Normals; `None`: rebuilt from depth (edge-aware).
    pub normals: Option<NormalsInput<'a>>,
    /// Motion vectors; `None`: only the camera moves (reprojection through the view matrices).
    pub motion: Option<MotionInput<'a>>,
    /// Time in seconds.
    pub time: f32,
    /// The camera jumped: temporal techniques drop their history this frame.
    pub camera_cut: bool,
    /// The rectangle of the input textures this view covers (split screen, an editor pane);
    /// `None`: all of them. AO is computed for that rectangle only and the output is its size;
    /// the projection is the view's own (its aspect the rectangle's).
    pub viewport: Option<Viewport>,
}

/// A rectangle of the input textures, in texels from their top-left corner.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Viewport {
    /// Left edge.
    pub x: u32,
    /// Top edge.
    pub y: u32,
    /// Width (at least 1).
    pub width: u32,
    /// Height (at least 1).
    pub height: u32,
}

impl<'a> AoInputs<'a> {
    /// A frame with depth, projection and view only (normals rebuilt, camera motion only).
    pub fn new(depth: DepthInput<'a>, projection: Mat4, view: Mat4) -> Self {
        Self {
            depth,
            projection,
            view,
            normals: None,
            motion: None,
            time: 0.0,
            camera_cut: false,
            viewport: None,
        }
    }

    /// As [`AoInputs::new`], with the matrices as plain column-major arrays (`m[column][row]`,
    /// the layout of glam's `to_cols_array_2d`, cgmath, nalgebra's and mint's column-major
    /// matrices): for an application on another maths library or another glam version.
    pub fn from_column_arrays(
        depth: DepthInput<'a>,
        projection: [[f32; 4]; 4],
        view: [[f32; 4]; 4],
    ) -> Self {
        Self::new(
            depth,
            Mat4::from_cols_array_2d(&projection),
            Mat4::from_cols_array_2d(&view),
        )
    }
}

/// The shape of a frame's inputs, which decides the adapter passes: one plan per layout. (A
/// viewport's size is part of it; where the viewport sits is not: it moves without a new plan.)
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct InputLayout {
    /// The depth texture's format (R32Float: linear depth given).
    pub depth_format: wgpu::TextureFormat,
    /// The normals' format, space and encoding, when given.
    pub normals: Option<(wgpu::TextureFormat, NormalSpace, NormalEncoding)>,
    /// The motion texture's format and the scale's bits, when given.
    pub motion: Option<(wgpu::TextureFormat, [u32; 2])>,
    /// The output's width in pixels: the viewport's, else the depth's.
    pub width: u32,
    /// The output's height in pixels.
    pub height: u32,
    /// The input textures' size when a viewport covers part of them (`None`: the output's).
    pub inputs_size: Option<(u32, u32)>,
}

/// Depth formats a hardware depth input may have.
pub const HARDWARE_DEPTH_FORMATS: &str = "Depth32Float, Depth24Plus or Depth16Unorm (or \
     DepthInput::Linear with an R32Float linear depth)";

impl InputLayout {
    /// The layout of `inputs`, with every texture's format and size checked.
    pub fn of(inputs: &AoInputs<'_>) -> EmbedResult<Self> {
        use wgpu::TextureFormat as F;
        let depth = inputs.depth.texture();
        let depth_format = depth.format();
        match (inputs.depth, depth_format) {
            (DepthInput::Hardware(_), F::Depth32Float | F::Depth24Plus | F::Depth16Unorm) => {}
            (DepthInput::Linear(_), F::R32Float) => {}
            (DepthInput::Hardware(_), found) => {
                return Err(EmbedError::InputFormat {
                    input: "the depth texture",
                    found,
                    allowed: HARDWARE_DEPTH_FORMATS,
                });
            }
            (DepthInput::Linear(_), found) => {
                return Err(EmbedError::InputFormat {
                    input: "the linear depth texture",
                    found,
                    allowed: "R32Float",
                });
            }
        }
        let (width, height) = (depth.width(), depth.height());
        let same_size = |input: &'static str, t: &wgpu::Texture| {
            if (t.width(), t.height()) == (width, height) {
                Ok(())
            } else {
                Err(EmbedError::InputSize {
                    input,
                    found: format!("{}x{}", t.width(), t.height()),
                    expected: format!("{width}x{height}"),
                })
            }
        };
        let normals = match inputs.normals {
            Some(n) => {
                same_size("the normals texture", n.texture)?;
                check_normals_format(n.texture.format(), n.encoding)?;
                Some((n.texture.format(), n.space, n.encoding))
            }
            None => None,
        };
        let motion = match inputs.motion {
            Some(m) => {
                same_size("the motion texture", m.texture)?;
                check_float_readable("the motion texture", m.texture.format(), 2)?;
                if !m.uv_scale.iter().all(|s| s.is_finite()) {
                    return Err(EmbedError::InvalidSetting {
                        name: "motion uv_scale".into(),
                        value: format!("{:?}", m.uv_scale),
                        allowed: "finite numbers".into(),
                    });
                }
                Some((m.texture.format(), m.uv_scale.map(f32::to_bits)))
            }
            None => None,
        };
        let (width, height, inputs_size) = match inputs.viewport {
            None => (width, height, None),
            Some(v) => {
                let fits = v.width > 0
                    && v.height > 0
                    && u64::from(v.x) + u64::from(v.width) <= u64::from(width)
                    && u64::from(v.y) + u64::from(v.height) <= u64::from(height);
                if !fits {
                    return Err(EmbedError::InvalidSetting {
                        name: "viewport".into(),
                        value: format!("{}x{} at ({}, {})", v.width, v.height, v.x, v.y),
                        allowed: format!(
                            "a rectangle of at least 1x1 inside the {width}x{height} input textures"
                        ),
                    });
                }
                (v.width, v.height, Some((width, height)))
            }
        };
        Ok(Self {
            depth_format,
            normals,
            motion,
            width,
            height,
            inputs_size,
        })
    }

    /// The depth was given as linear depth.
    pub fn linear_depth_given(&self) -> bool {
        self.depth_format == wgpu::TextureFormat::R32Float
    }
}

/// A texture a shader reads as `texture_2d<f32>` with at least `channels` channels.
fn check_float_readable(
    input: &'static str,
    found: wgpu::TextureFormat,
    channels: u32,
) -> EmbedResult<()> {
    let float = matches!(
        found.sample_type(None, None),
        Some(wgpu::TextureSampleType::Float { .. })
    );
    if float && found.components() >= channels as u8 && !found.is_compressed() {
        return Ok(());
    }
    Err(EmbedError::InputFormat {
        input,
        found,
        allowed: if channels >= 3 {
            "a float, unorm or snorm colour format with at least three channels"
        } else {
            "a float, unorm or snorm colour format with at least two channels"
        },
    })
}

fn check_normals_format(found: wgpu::TextureFormat, encoding: NormalEncoding) -> EmbedResult<()> {
    let channels = match encoding {
        NormalEncoding::Xyz | NormalEncoding::PackedXyz => 3,
        NormalEncoding::Octahedral | NormalEncoding::PackedOctahedral => 2,
    };
    check_float_readable("the normals texture", found, channels)
}
