//! The one error type of the render graph.
//!
//! Every variant names what is at fault (the pass, the resource, the shader file and line) and,
//! where there is one, the fix, so a message can be acted on without reading the source.
//! User input (configs, declarations, shaders) never panics; it ends up here.

use thiserror::Error;

/// Everything that can go wrong while declaring, compiling or executing a graph.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum GraphError {
    /// The passes' reads and writes form a cycle, so no execution order exists.
    #[error("cycle in the graph: pass `{pass}` depends (through its reads) on its own output")]
    Cycle {
        /// A pass on the cycle.
        pass: String,
    },

    #[error(
        "pass `{pass}` reads `{resource}`, which no pass writes and which is not imported; write it in an earlier pass or import it"
    )]
    /// A pass reads version 0 of a transient resource (or a history's `current` half), which
    /// holds nothing yet.
    ReadOfUnwritten {
        /// The pass that reads.
        pass: String,
        /// The resource it reads.
        resource: String,
    },

    #[error(
        "conflicting writes to `{resource}`: pass `{second}` writes a version that pass `{first}` already overwrote; write the handle `{first}` returned"
    )]
    /// Two passes write the same version of a resource: the second wrote a stale handle
    /// instead of the one the first write returned.
    ConflictingWrites {
        /// The resource written twice.
        resource: String,
        /// The pass that produced the next version first.
        first: String,
        /// The pass that wrote the stale version afterwards.
        second: String,
    },

    #[error(
        "size mismatch in pass `{pass}`: `{resource}` is {found} but the pass needs {expected}"
    )]
    /// A texture's size does not fit its use: attachments of one render pass of different
    /// size classes, a copy between different sizes, or an imported texture of the wrong size.
    SizeMismatch {
        /// The pass at fault (`import` for an imported texture bound at execution).
        pass: String,
        /// The texture whose size is wrong.
        resource: String,
        /// The size the use needs, and where that comes from.
        expected: String,
        /// The texture's size (a size class at compile, pixels at execution).
        found: String,
    },

    #[error(
        "format mismatch in pass `{pass}`: `{resource}` is {found:?} but the pass needs {expected}"
    )]
    /// A texture's format does not fit its use (a colour format as a depth attachment, a
    /// depth format as storage, a copy between different formats).
    FormatMismatch {
        /// The pass using the texture.
        pass: String,
        /// The texture whose format is wrong.
        resource: String,
        /// What the use needs, in words (e.g. "a depth format").
        expected: String,
        /// The texture's declared format.
        found: wgpu::TextureFormat,
    },

    #[error(
        "history resource `{resource}` is read but never written this frame; add a pass that writes it"
    )]
    /// A pass reads a history's `previous` half, but no pass writes its `current` half, so
    /// the next frame would have nothing to read.
    HistoryNeverWritten {
        /// The history's name.
        resource: String,
    },

    #[error(
        "two {kind}s are named `{name}`: {kind}s are bound by name, so they would silently share one resource; give each its own name"
    )]
    /// Two imports, or two histories, share a name; both are looked up by name, so they
    /// would silently alias one resource.
    DuplicateName {
        /// `import` or `history`.
        kind: String,
        /// The shared name.
        name: String,
    },

    #[error(
        "imported texture `{resource}` was created without usage {missing}, which the plan needs (it has {has}); add it to the texture's usage"
    )]
    /// An imported texture lacks a usage flag its uses in the plan need.
    ImportUsage {
        /// The imported resource.
        resource: String,
        /// The missing [`wgpu::TextureUsages`] flags, debug-formatted.
        missing: String,
        /// The usages the texture was created with, debug-formatted.
        has: String,
    },

    #[error("pass `{pass}`: {message}")]
    /// A pass is declared or used wrongly in a way no more specific variant covers (a handle
    /// of another graph, a mip out of range, a shader binding without a matching use, ...).
    InvalidPass {
        /// The pass at fault (`#index` for a `PassId` of another graph).
        pass: String,
        /// What is wrong and, where there is one, the fix.
        message: String,
    },

    #[error("pass `{pass}`, sampler `{binding}`: {message}")]
    /// A pass's samplers do not match its shader's `sampler` globals: one the shader binds is
    /// undeclared, one declared is not in the shader, or the pass kind binds no samplers.
    Sampler {
        /// The pass at fault.
        pass: String,
        /// Name of the `sampler` global.
        binding: String,
        /// What is wrong.
        message: String,
    },

    #[error("invalid parameter `{name}` = {value} for `{owner}`: allowed {allowed}")]
    /// A value outside what its owner accepts (an output size, a timing mode, a uniform's
    /// byte length, or a parameter of a crate above the graph).
    InvalidParameter {
        /// What the parameter belongs to (a pass, the executor, a technique, ...).
        owner: String,
        /// The parameter's name.
        name: String,
        /// The value given, formatted.
        value: String,
        /// The values allowed, in words.
        allowed: String,
    },

    #[error("shader `{file}` line {line}: {message}")]
    /// A WGSL shader failed to parse or validate, or uses something the graph cannot bind.
    Shader {
        /// The file the error is in (an included file where it comes from one).
        file: String,
        /// 1-based line in that file; 0 when the error has no single line.
        line: u32,
        /// naga's message, or the graph's.
        message: String,
    },

    #[error("cannot read shader `{file}`: {message}")]
    /// A shader source could not be read: no such file under the root, or no inline source of
    /// that name.
    ShaderFile {
        /// The name or path looked up.
        file: String,
        /// Why it could not be read.
        message: String,
    },

    #[error(
        "no GPU adapter found ({detail}). aograph needs a Vulkan device; without a GPU install Mesa's software driver: on Debian/Ubuntu `apt-get install mesa-vulkan-drivers`"
    )]
    /// No usable Vulkan adapter or device.
    NoAdapter {
        /// wgpu's reason.
        detail: String,
    },

    /// The device reported errors (wgpu validation, out of memory) while `during` ran; the
    /// messages are wgpu's.
    #[error("the GPU device reported an error while {during}: {message}")]
    Device {
        /// What aograph was doing: "executing a frame", "creating a plan's textures", ...
        during: &'static str,
        /// wgpu's messages, `; `-separated.
        message: String,
    },

    /// Waiting for the device or mapping its results failed (a lost device, an aborted map).
    #[error("reading results back from the GPU failed while {during}: {message}")]
    ReadbackFailed {
        /// What was being read: "reading a texture back", "reading timestamp queries", ...
        during: &'static str,
        /// wgpu's message.
        message: String,
    },

    /// A texture read back in a form its format cannot be converted to.
    #[error("a {format:?} texture cannot be read back as {wanted}; {allowed}")]
    ReadbackFormat {
        /// The texture's format.
        format: wgpu::TextureFormat,
        /// The form asked for ("floats", "32-bit unsigned integers").
        wanted: &'static str,
        /// The formats that form supports, or what to call instead.
        allowed: &'static str,
    },

    /// An invariant of aograph itself broke: a bug to report, not something the caller did.
    #[error("internal error in aograph ({0}); please report it with the steps that led here")]
    Internal(&'static str),

    #[error(
        "texture `{resource}` is {format:?}, which this device ({device}) cannot use as {usage}; declare it in a format the device supports for that use"
    )]
    /// The device cannot use a texture's format with the usages the plan needs (e.g. R16Float
    /// storage without adapter-specific format features).
    UnsupportedFormat {
        /// The texture, or the textures sharing one physical texture, by name.
        resource: String,
        /// The declared format.
        format: wgpu::TextureFormat,
        /// The [`wgpu::TextureUsages`] the plan needs, debug-formatted.
        usage: String,
        /// The device, as [`GpuContext::describe`](crate::GpuContext::describe) gives it.
        device: String,
    },

    #[error(
        "pass `{pass}` needs {needs} {what}, and {device} allows {allows} (wgpu's `{limit}`): \
         ask the device for a higher `{limit}` where the adapter has one, or choose settings or a \
         technique that needs fewer"
    )]
    /// A pass of a plan needs more of something a device limits than the device allows
    /// (`device_fit.rs`): storage textures per stage, workgroup storage, bind groups ...
    OverDeviceLimit {
        /// The pass, by name (its technique's prefix names the technique).
        pass: String,
        /// What it needs, in words ("storage textures in its compute stage").
        what: String,
        /// The limit, by its field name in `wgpu::Limits`.
        limit: String,
        /// How many the pass needs.
        needs: u64,
        /// How many the device allows.
        allows: u64,
        /// The device, or "a WebGPU device with default limits".
        device: String,
    },

    #[error(
        "pass `{pass}` needs {what}, which {device} does not offer: choose settings or a \
         technique without it, or a device that has it"
    )]
    /// A pass needs a feature or storage format the device lacks (`device_fit.rs`).
    DeviceLacks {
        /// The pass, by name.
        pass: String,
        /// The feature or format, in words.
        what: String,
        /// The device, or "a WebGPU device with default limits".
        device: String,
    },

    #[error("resource `{resource}` is not available: {message}")]
    /// A resource asked for at execution is not there: an import never provided, a texture a
    /// custom pass did not declare, a read-back of a texture the last frame did not keep.
    MissingResource {
        /// The resource, by name or handle.
        resource: String,
        /// Why it is unavailable.
        message: String,
    },
}

/// Result with [`GraphError`].
pub type GraphResult<T> = Result<T, GraphError>;
