//! The crate's one error type, [`SceneError`].
//!
//! Invariant: every variant that comes from a file names that file, and every message says what
//! is wrong in words a user can act on (which file, which mesh or vertex, which parameter and the
//! allowed range). Nothing in this crate panics on user input; it returns one of these instead.

use std::path::PathBuf;

/// Everything that can go wrong when loading, building or exporting a scene, or tracing it on
/// the CPU (the GPU tracers' errors are `aograph_tracing::TracingError`).
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The scene file does not exist.
    #[error("scene file {path} does not exist (check the path and the working directory)")]
    MissingFile {
        /// The path as given (relative paths resolve against the working directory).
        path: PathBuf,
    },

    /// Reading or writing a file failed for a reason other than its absence.
    #[error("could not {action} {path}: {source}")]
    Io {
        /// What was being attempted, as a verb phrase: "read", "write", "create cache directory".
        action: &'static str,
        /// The file or directory the operation was on.
        path: PathBuf,
        /// The underlying OS error.
        #[source]
        source: std::io::Error,
    },

    /// The glTF JSON could not be parsed.
    #[error("{path} is not valid glTF JSON: {message}")]
    MalformedJson {
        /// The .gltf or .glb file.
        path: PathBuf,
        /// The JSON parser's description of the error, with its line and column where known.
        message: String,
    },

    /// A glTF 1.0 file (`asset.version` 1.x, or a version-1 .glb).
    #[error(
        "{path} is a glTF 1.0 file, which aograph does not read; convert it to glTF 2.0 \
         (for example with gltf-pipeline: `gltf-pipeline -i in.gltf -o out.gltf`)"
    )]
    Gltf1 {
        /// The glTF 1.0 file.
        path: PathBuf,
    },

    /// The file requires an extension aograph does not read (`extensionsRequired`).
    #[error(
        "{path} requires the glTF extension {extension}, which aograph does not read; to load it, \
         {conversion}. Required extensions aograph accepts: {}",
        supported.join(", ")
    )]
    UnsupportedExtension {
        /// The .gltf or .glb file.
        path: PathBuf,
        /// The first unsupported name in `extensionsRequired`, e.g. `KHR_draco_mesh_compression`.
        extension: String,
        /// Every required extension aograph accepts (those it reads and those it may ignore).
        supported: Vec<String>,
        /// Advice on converting the file, as a clause that follows "to load it, ".
        conversion: String,
    },

    /// The file parsed but breaks the glTF 2.0 rules (bad .glb header, dangling index, ...).
    #[error("{path} is not a valid glTF 2.0 file: {message}")]
    InvalidGltf {
        /// The .gltf or .glb file.
        path: PathBuf,
        /// Which rule is broken and where (accessor, buffer view, mesh, byte offset, ...).
        message: String,
    },

    /// An external buffer (.bin) the glTF refers to could not be found.
    #[error(
        "{path} refers to buffer file \"{uri}\", which does not exist at {resolved} \
         (put the file there, or fix the buffer's \"uri\" in the glTF)"
    )]
    MissingBuffer {
        /// The .gltf file that refers to the buffer.
        path: PathBuf,
        /// The buffer's `uri` exactly as written in the glTF.
        uri: String,
        /// The file path the URI resolved to (percent-decoded; a relative URI against the glTF's
        /// directory).
        resolved: PathBuf,
    },

    /// A vertex position is NaN or infinite.
    #[error(
        "{path}: mesh \"{mesh}\" has a non-finite (NaN or infinite) position at vertex {vertex}"
    )]
    NonFiniteVertex {
        /// The .gltf or .glb file.
        path: PathBuf,
        /// The glTF mesh's name, or "mesh N" (its index) when it has none.
        mesh: String,
        /// The vertex's index within its primitive's POSITION accessor.
        vertex: usize,
    },

    /// The file holds no triangle at all, so there is nothing to render.
    #[error(
        "{path} contains no triangles (its scene has no triangle meshes; points and lines are \
         skipped)"
    )]
    EmptyScene {
        /// The .gltf or .glb file.
        path: PathBuf,
    },

    /// The scene cannot be written as glTF (non-finite position, index out of range, ...).
    #[error("cannot export the scene to {path}: {message}")]
    Export {
        /// The .glb file that was to be written (it is left untouched).
        path: PathBuf,
        /// What in the scene cannot be written, naming the mesh or value.
        message: String,
    },

    /// A procedural scene name that is not in the registry.
    #[error(
        "unknown procedural scene \"{name}\"{}; known scenes: {known}",
        aograph_graph::did_you_mean(name, known.split(", "))
    )]
    UnknownScene {
        /// The name that was asked for.
        name: String,
        /// The registered names, joined with ", " (see [`crate::PROCEDURAL_SCENE_NAMES`]).
        known: String,
    },

    /// A numeric parameter outside its allowed range.
    #[error("invalid parameter {name} = {value}: must be {allowed}")]
    InvalidParameter {
        /// The parameter's name, as in the config or the Rust field.
        name: &'static str,
        /// The rejected value, formatted.
        value: String,
        /// The allowed range in words, completing "must be ...", e.g. "at least 1".
        allowed: &'static str,
    },

    /// Per-pixel input buffers whose lengths do not match the image size.
    #[error("{what} has {actual} entries but the image is {width}x{height} ({expected} pixels)")]
    InputSizeMismatch {
        /// Which input has the wrong length, e.g. "normals".
        what: &'static str,
        /// Image width in pixels.
        width: u32,
        /// Image height in pixels.
        height: u32,
        /// The length it should have: `width * height` for per-pixel inputs.
        expected: usize,
        /// The length it has.
        actual: usize,
    },

    /// A raw reference image file that is truncated or not in the AOREF32 format.
    #[error("{path} is not a valid AOREF32 reference image: {reason}")]
    BadReferenceFile {
        /// The reference image (or cache entry) file.
        path: PathBuf,
        /// What is wrong: bad magic, truncated, size mismatch, ...
        reason: String,
    },

    /// PNG encoding failed.
    #[error("could not write PNG {path}: {message}")]
    Png {
        /// The PNG that was being written.
        path: PathBuf,
        /// The encoder's error text.
        message: String,
    },
}

impl SceneError {
    /// An [`SceneError::Io`] for `path`, with `action` such as "read" or "write".
    pub fn io(action: &'static str, path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        SceneError::Io {
            action,
            path: path.into(),
            source,
        }
    }
}
