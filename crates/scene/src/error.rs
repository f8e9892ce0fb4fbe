//! The crate's one error type, [`SceneError`].
//!
//! Invariant: every variant that comes from a file names that file, and every message says what
//! is wrong in words a user can act on (which file, which mesh or vertex, which parameter and the
//! allowed range). Nothing in this crate panics on user input; it returns one of these instead.

use std::path::PathBuf;

/// Everything that can go wrong when loading, building, exporting or ray tracing a scene.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The scene file does not exist.
    #[error("scene file {path} does not exist (check the path and the working directory)")]
    MissingFile { path: PathBuf },

    /// Reading or writing a file failed for a reason other than its absence.
    #[error("could not {action} {path}: {source}")]
    Io {
        action: &'static str,
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },

    /// The glTF JSON could not be parsed.
    #[error("{path} is not valid glTF JSON: {message}")]
    MalformedJson { path: PathBuf, message: String },

    /// A glTF 1.0 file (`asset.version` 1.x, or a version-1 .glb).
    #[error(
        "{path} is a glTF 1.0 file, which aograph does not read; convert it to glTF 2.0 \
         (for example with gltf-pipeline: `gltf-pipeline -i in.gltf -o out.gltf`)"
    )]
    Gltf1 { path: PathBuf },

    /// The file requires an extension aograph does not read (`extensionsRequired`).
    #[error(
        "{path} requires the glTF extension {extension}, which aograph does not read; to load it, \
         {conversion}. Required extensions aograph accepts: {}",
        supported.join(", ")
    )]
    UnsupportedExtension {
        path: PathBuf,
        extension: String,
        supported: Vec<String>,
        conversion: String,
    },

    /// The file parsed but breaks the glTF 2.0 rules (bad .glb header, dangling index, ...).
    #[error("{path} is not a valid glTF 2.0 file: {message}")]
    InvalidGltf { path: PathBuf, message: String },

    /// An external buffer (.bin) the glTF refers to could not be found.
    #[error(
        "{path} refers to buffer file \"{uri}\", which does not exist at {resolved} \
         (put the file there, or fix the buffer's \"uri\" in the glTF)"
    )]
    MissingBuffer {
        path: PathBuf,
        uri: String,
        resolved: PathBuf,
    },

    /// A vertex position is NaN or infinite.
    #[error(
        "{path}: mesh \"{mesh}\" has a non-finite (NaN or infinite) position at vertex {vertex}"
    )]
    NonFiniteVertex {
        path: PathBuf,
        mesh: String,
        vertex: usize,
    },

    /// The file holds no triangle at all, so there is nothing to render.
    #[error(
        "{path} contains no triangles (its scene has no triangle meshes; points and lines are \
         skipped)"
    )]
    EmptyScene { path: PathBuf },

    /// The scene cannot be written as glTF (non-finite position, index out of range, ...).
    #[error("cannot export the scene to {path}: {message}")]
    Export { path: PathBuf, message: String },

    /// A procedural scene name that is not in the registry.
    #[error(
        "unknown procedural scene \"{name}\"{}; known scenes: {known}",
        aograph_graph::did_you_mean(name, known.split(", "))
    )]
    UnknownScene { name: String, known: String },

    /// A GPU operation (a pipeline, a dispatch, a readback) failed.
    #[error("GPU error while {what}: {message}")]
    Gpu { what: &'static str, message: String },

    /// The scene's BVH does not fit one of the device's storage-buffer limits.
    #[error(
        "the scene's BVH does not fit this device: its {buffer} buffer is {size} bytes (the whole \
         BVH {total} bytes), over the device's limit of {limit} bytes ({limit_name}); trace fewer \
         or decimated meshes, or use a device with larger limits"
    )]
    BvhTooLarge {
        buffer: &'static str,
        size: u64,
        total: u64,
        limit: u64,
        limit_name: &'static str,
    },

    /// A GPU tracer's input or output buffer over the device's storage-buffer limit.
    #[error(
        "the GPU tracer's {what} need {size} bytes, over this device's storage-buffer limit of \
         {limit} bytes: trace a smaller image or batch, or use the CPU tracer \
         ([reference] tracer = \"cpu\")"
    )]
    OverDeviceLimit {
        what: &'static str,
        size: u64,
        limit: u64,
    },

    /// A BVH level deeper than the GPU traversal's fixed stack.
    #[error(
        "the scene's {level}-level BVH is {depth} nodes deep, over the GPU traversal stack of \
         {limit}: the geometry is too degenerate to trace (split the mesh or remove stacked \
         duplicate triangles)"
    )]
    BvhTooDeep {
        level: &'static str,
        depth: u32,
        limit: u32,
    },

    /// A numeric parameter outside its allowed range.
    #[error("invalid parameter {name} = {value}: must be {allowed}")]
    InvalidParameter {
        name: &'static str,
        value: String,
        allowed: &'static str,
    },

    /// Per-pixel input buffers whose lengths do not match the image size.
    #[error("{what} has {actual} entries but the image is {width}x{height} ({expected} pixels)")]
    InputSizeMismatch {
        what: &'static str,
        width: u32,
        height: u32,
        expected: usize,
        actual: usize,
    },

    /// A raw reference image file that is truncated or not in the AOREF32 format.
    #[error("{path} is not a valid AOREF32 reference image: {reason}")]
    BadReferenceFile { path: PathBuf, reason: String },

    /// PNG encoding failed.
    #[error("could not write PNG {path}: {message}")]
    Png { path: PathBuf, message: String },
}

impl SceneError {
    /// An [`SceneError::Io`] for `path`, with `action` such as "read" or "write".
    pub(crate) fn io(
        action: &'static str,
        path: impl Into<PathBuf>,
        source: std::io::Error,
    ) -> Self {
        SceneError::Io {
            action,
            path: path.into(),
            source,
        }
    }
}
