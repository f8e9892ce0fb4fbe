//! Virtual resources: descriptors, size classes, access kinds and typed, versioned handles.
//!
//! A handle names one *version* of a resource. Writing a handle yields the next version, so a
//! read always names the version some earlier pass (or an import) produced: the types make
//! read-before-write and accidental cycles hard to express. Sizes are classes relative to the
//! output, resolved only at execution time, so compile stays independent of the output size.

use std::hash::{Hash, Hasher};
use std::marker::PhantomData;

/// A concrete 2D size in pixels.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Extent {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
}

impl Extent {
    /// A `width` x `height` pixel size.
    pub const fn new(width: u32, height: u32) -> Self {
        Self { width, height }
    }
    /// Size of mip `level`, rounded up, never below 1x1.
    pub fn mip(self, level: u32) -> Self {
        Self {
            width: self.width.div_ceil(1 << level.min(31)).max(1),
            height: self.height.div_ceil(1 << level.min(31)).max(1),
        }
    }
    /// Number of pixels, `width * height`, without overflow.
    pub fn pixels(self) -> u64 {
        self.width as u64 * self.height as u64
    }
}

impl std::fmt::Display for Extent {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}x{}", self.width, self.height)
    }
}

/// A texture's size relative to the graph's output size.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SizeClass {
    /// Output size divided by `divisor`, rounded up (1 = full resolution). Nested divisions
    /// compose exactly: ceil(ceil(w/a)/b) = ceil(w/(a*b)), so pyramid level k of a factor-K
    /// pyramid is `Relative { divisor: K^k }`.
    Relative {
        /// The factor the output size is divided by on each axis (0 reads as 1).
        divisor: u32,
    },
    /// A fixed size, independent of the output.
    Fixed(Extent),
    /// Level `level` of a *centred* factor-`factor` pyramid over the output divided by
    /// `base_divisor` (rounded up): each level is ceil(n / factor) per axis, plus one where
    /// `factor * m - n` is odd, so the block grid overhangs both edges by the same
    /// `(factor * m - n) / 2` texels and the pyramid is its own mirror image ([`centred_step`];
    /// for an odd factor). Pyramid HBAO's 3x3 pyramid.
    Centred {
        /// The output is divided by this first, rounded up (1 = full output).
        base_divisor: u32,
        /// Per-level reduction factor of the pyramid (odd, e.g. 3, for the mirror symmetry).
        factor: u32,
        /// Pyramid level; level 0 is the base itself.
        level: u32,
    },
}

/// One level of a centred pyramid: `n` texels become ceil(n / factor), or one more where the
/// overhang `factor * m - n` would be odd (it is then even, for an odd factor).
pub fn centred_step(n: u32, factor: u32) -> u32 {
    let k = factor.max(1);
    let m = n.max(1).div_ceil(k);
    if (k * m - n.max(1)) % 2 == 1 {
        m + 1
    } else {
        m
    }
}

impl SizeClass {
    /// Full output resolution.
    pub const FULL: SizeClass = SizeClass::Relative { divisor: 1 };
    /// 1/2^k of the output, rounded up.
    pub fn half_pow(k: u32) -> Self {
        SizeClass::Relative {
            divisor: 1 << k.min(30),
        }
    }
    /// Level `level` of a pyramid that divides by `factor` per level, rounded up.
    pub fn pyramid_level(factor: u32, level: u32) -> Self {
        SizeClass::Relative {
            divisor: factor.max(1).saturating_pow(level),
        }
    }
    /// A fixed `width` x `height` size, whatever the output size.
    pub fn fixed(width: u32, height: u32) -> Self {
        SizeClass::Fixed(Extent::new(width, height))
    }
    /// Level `level` of a centred factor-`factor` pyramid over the full output.
    pub fn centred_pyramid_level(factor: u32, level: u32) -> Self {
        SizeClass::Centred {
            base_divisor: 1,
            factor,
            level,
        }
    }
    /// This size class over an output `divisor` times smaller (rounded up, as every relative
    /// class is): relative and centred classes compose exactly (ceil(ceil(w/a)/b) =
    /// ceil(w/(ab))); a fixed size stays fixed. What `GraphBuilder::set_size_divisor` applies.
    pub fn divided(self, divisor: u32) -> Self {
        let d = divisor.max(1);
        match self {
            SizeClass::Relative { divisor } => SizeClass::Relative {
                divisor: divisor.max(1).saturating_mul(d),
            },
            SizeClass::Fixed(e) => SizeClass::Fixed(e),
            SizeClass::Centred {
                base_divisor,
                factor,
                level,
            } => SizeClass::Centred {
                base_divisor: base_divisor.max(1).saturating_mul(d),
                factor,
                level,
            },
        }
    }
    /// The inverse of [`SizeClass::divided`]: this size class as named inside a scope whose
    /// output is `divisor` times smaller (a relative or centred class whose divisor `divisor`
    /// divides; anything else is returned as it is).
    pub fn within(self, divisor: u32) -> Self {
        let k = divisor.max(1);
        match self {
            SizeClass::Relative { divisor: d } if d % k == 0 => {
                SizeClass::Relative { divisor: d / k }
            }
            SizeClass::Centred {
                base_divisor,
                factor,
                level,
            } if base_divisor % k == 0 => SizeClass::Centred {
                base_divisor: base_divisor / k,
                factor,
                level,
            },
            other => other,
        }
    }
    /// The concrete size for an output of size `output`; never below 1x1.
    pub fn resolve(self, output: Extent) -> Extent {
        match self {
            SizeClass::Relative { divisor } => {
                let d = divisor.max(1);
                Extent::new(
                    output.width.div_ceil(d).max(1),
                    output.height.div_ceil(d).max(1),
                )
            }
            SizeClass::Fixed(e) => Extent::new(e.width.max(1), e.height.max(1)),
            SizeClass::Centred {
                base_divisor,
                factor,
                level,
            } => {
                let base = SizeClass::Relative {
                    divisor: base_divisor,
                }
                .resolve(output);
                let level_of = |n: u32| (0..level.min(64)).fold(n, |n, _| centred_step(n, factor));
                Extent::new(level_of(base.width), level_of(base.height))
            }
        }
    }
}

impl std::fmt::Display for SizeClass {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SizeClass::Relative { divisor: 1 } => write!(f, "full"),
            SizeClass::Relative { divisor } => write!(f, "1/{divisor}"),
            SizeClass::Fixed(e) => write!(f, "fixed {e}"),
            SizeClass::Centred {
                base_divisor,
                factor,
                level,
            } => write!(
                f,
                "centred level {level} of 1/{factor} over 1/{base_divisor}"
            ),
        }
    }
}

/// What a texture is: format, size class and mip count. Two resources with equal descriptors
/// and disjoint lifetimes may share one physical texture.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct TextureDesc {
    /// The texel format.
    pub format: wgpu::TextureFormat,
    /// Size of mip 0, relative to the output.
    pub size: SizeClass,
    /// Number of mip levels (at least 1); each is half the previous, rounded up.
    pub mip_levels: u32,
}

impl TextureDesc {
    /// A texture of `format` and size class `size` with a single mip level.
    pub fn new(format: wgpu::TextureFormat, size: SizeClass) -> Self {
        Self {
            format,
            size,
            mip_levels: 1,
        }
    }
    /// This descriptor with `mip_levels` mip levels (at least 1).
    pub fn with_mips(mut self, mip_levels: u32) -> Self {
        self.mip_levels = mip_levels.max(1);
        self
    }
    /// Bytes of all mip levels at output size `output`.
    pub fn bytes(&self, output: Extent) -> u64 {
        let base = self.size.resolve(output);
        let texel = texel_bytes(self.format);
        (0..self.mip_levels)
            .map(|m| base.mip(m).pixels() * texel)
            .sum()
    }
}

/// Bytes per texel of a format (depth formats count their depth aspect; 24-bit depth as 4).
pub fn texel_bytes(format: wgpu::TextureFormat) -> u64 {
    format
        .block_copy_size(None)
        .or_else(|| format.block_copy_size(Some(wgpu::TextureAspect::DepthOnly)))
        .unwrap_or(4) as u64
}

/// A GPU buffer's descriptor.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct BufferDesc {
    /// Size in bytes.
    pub size: u64,
}

/// Marker type for texture handles.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Texture {}
/// Marker type for buffer handles.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Buffer {}
/// Marker type for acceleration-structure handles (a top-level acceleration structure the
/// caller provides, read by ray queries).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum AccelerationStructure {}

/// A typed, versioned handle to one version of a virtual resource of one graph.
pub struct Handle<K> {
    pub(crate) id: u32,
    pub(crate) version: u32,
    _kind: PhantomData<fn() -> K>,
}

impl<K> Handle<K> {
    pub(crate) fn new(id: u32, version: u32) -> Self {
        Self {
            id,
            version,
            _kind: PhantomData,
        }
    }
    /// The resource's index in its graph.
    pub fn resource_index(&self) -> usize {
        self.id as usize
    }
    /// The version this handle names (0 = as created or imported).
    pub fn version(&self) -> u32 {
        self.version
    }
}

impl<K> Clone for Handle<K> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<K> Copy for Handle<K> {}
impl<K> PartialEq for Handle<K> {
    fn eq(&self, o: &Self) -> bool {
        self.id == o.id && self.version == o.version
    }
}
impl<K> Eq for Handle<K> {}
impl<K> Hash for Handle<K> {
    fn hash<H: Hasher>(&self, h: &mut H) {
        self.id.hash(h);
        self.version.hash(h);
    }
}
impl<K> std::fmt::Debug for Handle<K> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "#{}v{}", self.id, self.version)
    }
}

/// A handle to one version of a virtual texture.
pub type TextureHandle = Handle<Texture>;
/// A handle to one version of a virtual buffer.
pub type BufferHandle = Handle<Buffer>;
/// A handle to an imported top-level acceleration structure (`GraphBuilder::
/// import_acceleration_structure`); passes only read it, so it has one version.
pub type AccelerationStructureHandle = Handle<AccelerationStructure>;

/// How a pass uses a texture. Usage flags of the physical texture are inferred from these.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum TextureAccess {
    /// Read through a `texture_2d` binding.
    Sampled,
    /// Read through a read-only storage binding.
    StorageRead,
    /// Written through a write-only storage binding (the pass produces a new version).
    StorageWrite,
    /// Read and written through a read-write storage binding (in-place update).
    StorageReadWrite,
    /// Written as a colour attachment of a render pass.
    ColorAttachment,
    /// Written (depth test and write) as the depth attachment of a render pass.
    DepthAttachment,
    /// Read as the depth attachment of a render pass (test only, no write).
    DepthRead,
    /// Source of a copy.
    CopySrc,
    /// Destination of a copy (produces a new version).
    CopyDst,
    /// Read by ray queries through a WGSL `acceleration_structure` binding (the resource is a
    /// top-level acceleration structure, not a buffer: `PassBuilder::read_acceleration_structure`).
    AccelerationStructure,
}

impl TextureAccess {
    /// True when the access itself reads the texture. A colour or depth attachment that loads
    /// also reads its previous version; that follows from its load
    /// ([`AttachmentOps::loads`](crate::AttachmentOps::loads)), not from this.
    pub fn reads(self) -> bool {
        matches!(
            self,
            Self::Sampled
                | Self::StorageRead
                | Self::StorageReadWrite
                | Self::DepthRead
                | Self::CopySrc
        )
    }
    /// True when the access writes the texture, producing a new version of it.
    pub fn writes(self) -> bool {
        matches!(
            self,
            Self::StorageWrite
                | Self::StorageReadWrite
                | Self::ColorAttachment
                | Self::DepthAttachment
                | Self::CopyDst
        )
    }
    /// The wgpu usage this access needs.
    pub fn usage(self) -> wgpu::TextureUsages {
        use wgpu::TextureUsages as U;
        match self {
            Self::Sampled => U::TEXTURE_BINDING,
            Self::StorageRead | Self::StorageWrite | Self::StorageReadWrite => U::STORAGE_BINDING,
            Self::ColorAttachment | Self::DepthAttachment | Self::DepthRead => U::RENDER_ATTACHMENT,
            Self::CopySrc => U::COPY_SRC,
            Self::CopyDst => U::COPY_DST,
            // The caller creates the structure; the graph creates no buffer for it.
            Self::AccelerationStructure => U::empty(),
        }
    }
}

/// How a pass uses a buffer.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BufferAccess {
    /// Read through a `var<uniform>` binding.
    Uniform,
    /// Read through a `var<storage, read>` binding.
    StorageRead,
    /// Written through a `var<storage, read_write>` binding whose old contents the pass does
    /// not need (produces a new version).
    StorageWrite,
    /// Read and written through a `var<storage, read_write>` binding (in-place update).
    StorageReadWrite,
    /// Source of a copy.
    CopySrc,
    /// Destination of a copy (produces a new version).
    CopyDst,
    /// Read by ray queries through a WGSL `acceleration_structure` binding (the resource is a
    /// top-level acceleration structure, not a buffer: `PassBuilder::read_acceleration_structure`).
    AccelerationStructure,
}

impl BufferAccess {
    /// True when the access reads the buffer's previous contents.
    pub fn reads(self) -> bool {
        matches!(
            self,
            Self::Uniform
                | Self::StorageRead
                | Self::StorageReadWrite
                | Self::CopySrc
                | Self::AccelerationStructure
        )
    }
    /// True when the access writes the buffer, producing a new version of it.
    pub fn writes(self) -> bool {
        matches!(
            self,
            Self::StorageWrite | Self::StorageReadWrite | Self::CopyDst
        )
    }
    /// The wgpu usage this access needs.
    pub fn usage(self) -> wgpu::BufferUsages {
        use wgpu::BufferUsages as U;
        match self {
            Self::Uniform => U::UNIFORM,
            Self::StorageRead | Self::StorageWrite | Self::StorageReadWrite => U::STORAGE,
            Self::CopySrc => U::COPY_SRC,
            Self::CopyDst => U::COPY_DST,
            // The caller creates the structure; the graph creates no buffer for it.
            Self::AccelerationStructure => U::empty(),
        }
    }
}
