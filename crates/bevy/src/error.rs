//! The one error type of aograph-bevy: what a user's settings got wrong, said where the user
//! sets them (a camera component), never as a panic in bevy's render world.

/// Why a camera's AO settings were refused.
#[derive(Debug, thiserror::Error)]
pub enum AographBevyError {
    /// The `[ao]` settings are not ones aograph can run on a bevy camera's prepass: an unknown
    /// technique or parameter, a value out of range, an automatic radius, or a technique that
    /// needs more than depth, normals and motion (rtao traces the scene's triangles).
    #[error("aograph settings refused: {0}")]
    Settings(#[from] aograph_embed::EmbedError),
}
