//! G-buffer channels: the small type the g-buffer node (aograph-scene) and the techniques
//! (aograph-ao-passes) share without depending on each other. A technique states which channels it
//! reads; the g-buffer node writes only those. The set also carries the hardware depth format
//! ([`DepthFormat`], Depth32Float unless the application asks for Depth24Plus): techniques read
//! linear depth, never the depth buffer's encoding, so they work with either.

use aograph_graph::TextureHandle;

/// One g-buffer channel and its format.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum GBufferChannel {
    /// Hardware depth, as rasterised (Depth32Float by default; see [`DepthFormat`]).
    Depth,
    /// Linear view depth (R32Float), positive, in scene units; 0 marks sky.
    LinearDepth,
    /// View-space unit normals (Rgba16Float, xyz; w = 1 on geometry, 0 on sky).
    Normals,
    /// View-space positions (Rgba32Float, xyz; w = 1 on geometry, 0 on sky).
    Positions,
    /// Base colour (Rgba8Unorm).
    Albedo,
    /// Directly lit radiance: albedo * light * max(0, n.l), unshadowed (Rgba16Float).
    DirectLight,
    /// Motion to the previous frame, in 3D (Rgba32Float): xy = screen-space motion in UV units
    /// (prev_uv = uv + m.xy), z = the surface's linear depth in the previous frame (its own
    /// previous transform through the previous camera: an object approaching the camera keeps
    /// its history), w unused; 0 on sky.
    Motion,
    /// View-space unit normals, compact: octahedral, two snorm16 in one u32 (R32Uint,
    /// shaders/common/normal_oct.wgsl). 4 bytes against `Normals`' 8 and finer (error below
    /// 1e-4 rad); sky is where linear depth is 0 (a cleared texel decodes to +z).
    NormalsOct,
    /// The second depth layer (R32Float): the linear depth of the nearest surface at least
    /// the set's [`GBufferChannels::second_layer_separation`] behind the first layer's
    /// (Mara, McGuire, Nowrouzezahrai, Luebke 2016, "Deep G-Buffers", §2: the minimum
    /// separation Δ); 0 where no surface lies that far behind (and on sky). Written by a
    /// second raster pass only when a technique asks for it.
    SecondLayerDepth,
}

impl GBufferChannel {
    /// Every channel, in the order [`GBufferChannels::iter`] yields them.
    pub const ALL: [GBufferChannel; 9] = [
        Self::Depth,
        Self::LinearDepth,
        Self::Normals,
        Self::Positions,
        Self::Albedo,
        Self::DirectLight,
        Self::Motion,
        Self::NormalsOct,
        Self::SecondLayerDepth,
    ];
    /// The channel's default format (`Depth`: [`DepthFormat::default`]; a set may choose
    /// another depth format, see [`GBufferChannels::depth_format`]).
    pub fn format(self) -> wgpu::TextureFormat {
        use wgpu::TextureFormat as F;
        match self {
            Self::Depth => F::Depth32Float,
            Self::LinearDepth => F::R32Float,
            Self::Normals => F::Rgba16Float,
            Self::Positions => F::Rgba32Float,
            Self::Albedo => F::Rgba8Unorm,
            Self::DirectLight => F::Rgba16Float,
            Self::Motion => F::Rgba32Float,
            Self::NormalsOct => F::R32Uint,
            Self::SecondLayerDepth => F::R32Float,
        }
    }
    /// The channel's name (`"linear_depth"`, `"normals_oct"`, ...): the g-buffer names its
    /// texture `gbuffer.<name>`, and aograph-ao-passes's errors name a missing channel by it.
    pub fn name(self) -> &'static str {
        match self {
            Self::Depth => "depth",
            Self::LinearDepth => "linear_depth",
            Self::Normals => "normals",
            Self::Positions => "positions",
            Self::Albedo => "albedo",
            Self::DirectLight => "direct_light",
            Self::Motion => "motion",
            Self::NormalsOct => "normals_oct",
            Self::SecondLayerDepth => "second_layer_depth",
        }
    }
    fn bit(self) -> u16 {
        1 << (self as u8)
    }
}

/// Format of the g-buffer's hardware depth buffer.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum DepthFormat {
    /// 32-bit float depth (the default).
    #[default]
    Depth32Float,
    /// At least 24 bits of depth, as many engines use (may be a 24-bit unorm format).
    Depth24Plus,
}

impl DepthFormat {
    /// The wgpu texture format the depth buffer is created with.
    pub fn format(self) -> wgpu::TextureFormat {
        match self {
            Self::Depth32Float => wgpu::TextureFormat::Depth32Float,
            Self::Depth24Plus => wgpu::TextureFormat::Depth24Plus,
        }
    }
}

/// A set of channels, plus whether normals are flat (face) normals and the depth format.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct GBufferChannels {
    bits: u16,
    /// Normals are per-face (MSSAO needs them) rather than interpolated.
    pub face_normals: bool,
    /// Format of the hardware depth buffer the g-buffer rasterises into.
    pub depth_format: DepthFormat,
    /// Δ of [`GBufferChannel::SecondLayerDepth`] as `f32` bits (0: none asked): in units of R
    /// as a technique states it, in view units after [`Self::with_radius`].
    second_layer_separation: u32,
}

impl GBufferChannels {
    /// The empty set: no channel, interpolated normals, the default depth format.
    pub fn none() -> Self {
        Self::default()
    }
    /// The set of exactly `channels` (interpolated normals, the default depth format).
    pub fn of(channels: &[GBufferChannel]) -> Self {
        channels.iter().fold(Self::default(), |s, c| s.with(*c))
    }
    /// The same set with `c` added.
    pub fn with(mut self, c: GBufferChannel) -> Self {
        self.bits |= c.bit();
        self
    }
    /// The same set with `c` removed (face normals and depth format unchanged).
    pub fn without(mut self, c: GBufferChannel) -> Self {
        self.bits &= !c.bit();
        self
    }
    /// The same set with [`GBufferChannel::Normals`], written per face (flat) rather than
    /// interpolated, as MSSAO needs.
    pub fn with_face_normals(mut self) -> Self {
        self.face_normals = true;
        self.with(GBufferChannel::Normals)
    }
    /// Face normals in the compact encoding ([`GBufferChannel::NormalsOct`]).
    pub fn with_compact_face_normals(mut self) -> Self {
        self.face_normals = true;
        self.with(GBufferChannel::NormalsOct)
    }
    /// Whether the set has normals in either encoding.
    pub fn has_normals(&self) -> bool {
        self.contains(GBufferChannel::Normals) || self.contains(GBufferChannel::NormalsOct)
    }
    /// The same set, rasterising into a `depth_format` depth buffer.
    pub fn with_depth_format(mut self, depth_format: DepthFormat) -> Self {
        self.depth_format = depth_format;
        self
    }
    /// The same set with [`GBufferChannel::SecondLayerDepth`] (and the first layer's
    /// [`GBufferChannel::LinearDepth`], which the second pass reads), its surfaces at least
    /// Δ = `separation` x R behind the first layer's. A technique states Δ in units of the AO
    /// radius R, as it states every length (a scene in centimetres keeps its Δ); whoever
    /// declares the g-buffer and knows R turns it into view units with
    /// [`Self::with_radius`]. A non-finite or negative separation is taken as 0 (the next
    /// surface strictly behind).
    pub fn with_second_layer(mut self, separation: f32) -> Self {
        let separation = if separation.is_finite() {
            separation.max(0.0)
        } else {
            0.0
        };
        self.second_layer_separation = separation.to_bits();
        self.with(GBufferChannel::LinearDepth)
            .with(GBufferChannel::SecondLayerDepth)
    }
    /// The same set with the second layer's Δ, stated in units of R, multiplied by `radius`
    /// (view units): what the g-buffer's second pass compares against.
    pub fn with_radius(mut self, radius: f32) -> Self {
        let separation = self.second_layer_separation() * radius;
        self.second_layer_separation = if separation.is_finite() {
            separation.max(0.0).to_bits()
        } else {
            0
        };
        self
    }
    /// Δ of the second layer: in units of R as a technique states it, in view units after
    /// [`Self::with_radius`] (0 when the set has none).
    pub fn second_layer_separation(&self) -> f32 {
        f32::from_bits(self.second_layer_separation)
    }
    /// Whether `c` is in the set.
    pub fn contains(&self, c: GBufferChannel) -> bool {
        self.bits & c.bit() != 0
    }
    /// Channels of both; face normals if either asks; a non-default depth format wins.
    pub fn union(self, o: Self) -> Self {
        let depth_format = if self.depth_format != DepthFormat::default() {
            self.depth_format
        } else {
            o.depth_format
        };
        Self {
            bits: self.bits | o.bits,
            face_normals: self.face_normals || o.face_normals,
            depth_format,
            // Two techniques asking for different separations get the larger: the nearer
            // one's surfaces are then found by neither (both read the same channel).
            second_layer_separation: self
                .second_layer_separation()
                .max(o.second_layer_separation())
                .to_bits(),
        }
    }
    /// The channels in the set, in [`GBufferChannel::ALL`] order.
    pub fn iter(&self) -> impl Iterator<Item = GBufferChannel> + '_ {
        GBufferChannel::ALL
            .into_iter()
            .filter(|c| self.contains(*c))
    }
}

/// Handles of the channels a g-buffer node wrote (None for channels not requested).
#[derive(Clone, Copy, Debug, Default)]
pub struct GBufferTextures {
    /// Hardware depth, in the set's [`DepthFormat`] ([`GBufferChannel::Depth`]).
    pub depth: Option<TextureHandle>,
    /// Linear view depth, R32Float, 0 on sky ([`GBufferChannel::LinearDepth`]).
    pub linear_depth: Option<TextureHandle>,
    /// View-space unit normals, Rgba16Float ([`GBufferChannel::Normals`]).
    pub normals: Option<TextureHandle>,
    /// View-space positions, Rgba32Float ([`GBufferChannel::Positions`]).
    pub positions: Option<TextureHandle>,
    /// Base colour, Rgba8Unorm ([`GBufferChannel::Albedo`]).
    pub albedo: Option<TextureHandle>,
    /// Unshadowed directly lit radiance, Rgba16Float ([`GBufferChannel::DirectLight`]).
    pub direct_light: Option<TextureHandle>,
    /// 3D motion to the previous frame, Rgba32Float ([`GBufferChannel::Motion`]); also `None`
    /// on a scene where nothing moves, whose g-buffer drops the channel.
    pub motion: Option<TextureHandle>,
    /// Octahedral view-space normals, R32Uint ([`GBufferChannel::NormalsOct`]).
    pub normals_oct: Option<TextureHandle>,
    /// The second depth layer's linear depth, R32Float ([`GBufferChannel::SecondLayerDepth`]).
    pub second_layer_depth: Option<TextureHandle>,
}

impl GBufferTextures {
    /// The handle of channel `c`, or `None` when the g-buffer did not write it.
    pub fn get(&self, c: GBufferChannel) -> Option<TextureHandle> {
        match c {
            GBufferChannel::Depth => self.depth,
            GBufferChannel::LinearDepth => self.linear_depth,
            GBufferChannel::Normals => self.normals,
            GBufferChannel::Positions => self.positions,
            GBufferChannel::Albedo => self.albedo,
            GBufferChannel::DirectLight => self.direct_light,
            GBufferChannel::Motion => self.motion,
            GBufferChannel::NormalsOct => self.normals_oct,
            GBufferChannel::SecondLayerDepth => self.second_layer_depth,
        }
    }
    /// Records `h` as the handle of channel `c`, replacing any previous one.
    pub fn set(&mut self, c: GBufferChannel, h: TextureHandle) {
        let slot = match c {
            GBufferChannel::Depth => &mut self.depth,
            GBufferChannel::LinearDepth => &mut self.linear_depth,
            GBufferChannel::Normals => &mut self.normals,
            GBufferChannel::Positions => &mut self.positions,
            GBufferChannel::Albedo => &mut self.albedo,
            GBufferChannel::DirectLight => &mut self.direct_light,
            GBufferChannel::Motion => &mut self.motion,
            GBufferChannel::NormalsOct => &mut self.normals_oct,
            GBufferChannel::SecondLayerDepth => &mut self.second_layer_depth,
        };
        *slot = Some(h);
    }
}
