//! The one error type of aograph-bevy: what a user's settings or camera got wrong. Settings are
//! refused where the user sets them (a camera component); what only the render world can see
//! (the camera's MSAA, the device's refusal) is logged once and kept in `AographAoStatus`,
//! never a panic in bevy's render world.

/// Why aograph's AO was refused for a camera, or could not run on it.
#[derive(Debug, thiserror::Error)]
pub enum AographBevyError {
    /// The `[ao]` settings are not ones aograph can run on a bevy camera's prepass: an unknown
    /// technique or parameter, a value out of range, an automatic radius, or a technique that
    /// needs more than depth, normals and motion (rtao traces the scene's triangles). Also the
    /// device's refusal of settings (r16float intermediates where it cannot store them).
    #[error("aograph settings refused: {0}")]
    Settings(#[from] aograph_embed::EmbedError),
    /// bevy makes no prepass AO can be read from with MSAA on.
    #[error(
        "the camera has Msaa::{0}: aograph reads bevy's prepass, which needs Msaa::Off (as \
         bevy's own SSAO does)"
    )]
    MsaaOn(String),
    /// bevy's SSAO plugin made no AO resources for an active camera with MSAA off: bevy does
    /// not load it where the device has fewer than 5 storage textures per shader stage.
    #[error(
        "bevy made no SSAO resources for the camera, so its PBR pass reads no AO: bevy's \
         ScreenSpaceAmbientOcclusionPlugin needs a device with at least 5 storage textures per \
         shader stage, and PbrPlugin must be added"
    )]
    NoSsaoResources,
    /// bevy's AO texture has a format aograph cannot write.
    #[error(
        "bevy's AO texture is {0:?}; aograph writes R8Unorm, R16Float or R32Float (bevy 0.20.1 \
         makes R16Float, or R32Float where the device cannot store R16Float)"
    )]
    AoTextureFormat(wgpu::TextureFormat),
    /// The camera's depth prepass is gone.
    #[error("the camera has no depth prepass (AographAo brings DepthPrepass: was it removed?)")]
    NoDepthPrepass,
    /// Preparing settings on bevy's async compute pool panicked (a bug in aograph: please
    /// report it); the camera's AO starts again from its component's settings.
    #[error("preparing the settings panicked: {0}")]
    PreparePanicked(String),
}
