//! The scene's lighting as a frame input: a small uniform block (its directional light, ambient
//! and built-in sky) that a pass needing light beyond the g-buffer binds as
//! `var<uniform> lighting: Lighting`, imported into the graph under [`LIGHTING_BUFFER`] by the
//! technique that reads it and filled by whoever owns the frame (the app's `Renderer` writes it
//! from the scene). Generic frame data like the `View` block, so the renderer knows no technique
//! and techniques stay independent of the scene crate; one source of truth: the g-buffer's
//! `DirectLight` channel and SSDO's sun visibility use the same light, and SSDO's environment is
//! the same ambient `shaded.png` uses.
//!
//! WGSL mirror: `Lighting` in shaders/ao/ssdo/common.wgsl.

use bytemuck::{Pod, Zeroable};

use crate::frame_input::{BufferBlock, BufferInput};

/// Name under which the lighting block is imported (`Executor::import_buffer`).
pub const LIGHTING_BUFFER: &str = "lighting";

/// The lighting block. Each `[f32; 3]` and the scalar after it fill one 16-byte row (a WGSL
/// `vec3<f32>` is 16-byte aligned with a 12-byte size), so the Rust and WGSL layouts agree.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct LightingUniforms {
    /// World-space unit direction the directional light travels.
    pub light_direction: [f32; 3],
    /// Unused; pads the row to 16 bytes.
    pub pad0: f32,
    /// Linear RGB colour times intensity.
    pub light_color: [f32; 3],
    /// Unused; pads the row to 16 bytes.
    pub pad1: f32,
    /// Linear RGB ambient (the constant environment radiance).
    pub ambient: [f32; 3],
    /// Unused; pads the row to 16 bytes.
    pub pad2: f32,
    /// The sky environment (`environment = "sky"`; `aograph_scene::SkyEnvironment`, mirrored
    /// by `sky_radiance` in common.wgsl): zenith radiance (linear RGB),
    pub sky_zenith: [f32; 3],
    /// Unused; pads the row to 16 bytes.
    pub pad3: f32,
    /// horizon radiance (linear RGB),
    pub sky_horizon: [f32; 3],
    /// Unused; pads the row to 16 bytes.
    pub pad4: f32,
    /// ground radiance (linear RGB),
    pub sky_ground: [f32; 3],
    /// Unused; pads the row to 16 bytes.
    pub pad5: f32,
    /// the world-space unit direction towards the sun,
    pub sun_direction: [f32; 3],
    /// the sun lobe's exponent k (>= 1),
    pub sun_exponent: f32,
    /// and the irradiance the sun lobe puts on a surface facing it (linear RGB).
    pub sun_irradiance: [f32; 3],
    /// Unused; pads the row to 16 bytes.
    pub pad6: f32,
}

aograph_graph::uniform_layout!(LightingUniforms {
    light_direction,
    pad0,
    light_color,
    pad1,
    ambient,
    pad2,
    sky_zenith,
    pad3,
    sky_horizon,
    pad4,
    sky_ground,
    pad5,
    sun_direction,
    sun_exponent,
    sun_irradiance,
    pad6
});

/// The sky of [`LightingUniforms::with_sky`]: world space, +Y up, linear RGB.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SkyColours {
    /// Radiance straight up; above the horizon the sky blends from `horizon` to this.
    pub zenith: [f32; 3],
    /// Radiance at the horizon.
    pub horizon: [f32; 3],
    /// Radiance from below the horizon: blended in from `horizon`, full where a direction's
    /// y is -0.25 or lower.
    pub ground: [f32; 3],
    /// World-space direction towards the sun (normalised by [`LightingUniforms::with_sky`]).
    pub sun_direction: [f32; 3],
    /// Irradiance the sun lobe puts on a surface facing the sun.
    pub sun_irradiance: [f32; 3],
    /// Exponent k of the sun lobe: radiance `sun_irradiance` (k + 1) / 2π max(0, ω·s)^k
    /// towards direction ω, s the sun's direction (>= 1; the larger k, the smaller the sun).
    pub sun_exponent: f32,
}

impl LightingUniforms {
    /// A block from a light direction (normalised; straight down if degenerate), the light's
    /// colour times intensity and the ambient; non-finite or negative colours become 0.
    pub fn new(direction: [f32; 3], color: [f32; 3], ambient: [f32; 3]) -> Self {
        let d = glam::Vec3::from(direction);
        let d = if d.is_finite() {
            d.try_normalize().unwrap_or(glam::Vec3::NEG_Y)
        } else {
            glam::Vec3::NEG_Y
        };
        let clean = |c: [f32; 3]| c.map(|v| if v.is_finite() { v.max(0.0) } else { 0.0 });
        let [r, g, b] = clean(color);
        let [ar, ag, ab] = clean(ambient);
        Self {
            light_direction: [d.x, d.y, d.z],
            light_color: [r, g, b],
            ambient: [ar, ag, ab],
            ..Self::zeroed()
        }
    }

    /// This block with `sky` as its sky environment (non-finite or negative colours become 0,
    /// a degenerate sun direction points up, a non-finite exponent is 1).
    pub fn with_sky(self, sky: SkyColours) -> Self {
        let clean = |c: [f32; 3]| c.map(|v| if v.is_finite() { v.max(0.0) } else { 0.0 });
        let d = glam::Vec3::from(sky.sun_direction);
        let d = if d.is_finite() {
            d.try_normalize().unwrap_or(glam::Vec3::Y)
        } else {
            glam::Vec3::Y
        };
        let k = if sky.sun_exponent.is_finite() {
            sky.sun_exponent.max(1.0)
        } else {
            1.0
        };
        Self {
            sky_zenith: clean(sky.zenith),
            sky_horizon: clean(sky.horizon),
            sky_ground: clean(sky.ground),
            sun_direction: [d.x, d.y, d.z],
            sun_exponent: k,
            sun_irradiance: clean(sky.sun_irradiance),
            ..self
        }
    }
    /// The block's 128 bytes, in the WGSL `Lighting` layout, for the buffer imported as
    /// [`LIGHTING_BUFFER`].
    pub fn bytes(&self) -> &[u8] {
        bytemuck::bytes_of(self)
    }
}

impl BufferBlock for LightingUniforms {
    const NAME: &'static str = "the scene's lighting";
    const IMPORT: &'static str = LIGHTING_BUFFER;
}

/// The scene's lighting block as a frame input: declared by a technique that shades
/// (`AoBuildContext::scene_lighting`), bound to the buffer its owner fills with
/// [`LightingUniforms`].
pub type SceneLighting = BufferInput<LightingUniforms>;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn new_normalises_and_cleans() {
        let l = LightingUniforms::new([0.0, -2.0, 0.0], [1.0, f32::NAN, -1.0], [0.25, 0.27, 0.3]);
        assert_eq!(l.light_direction, [0.0, -1.0, 0.0]);
        assert_eq!(l.light_color, [1.0, 0.0, 0.0]);
        assert_eq!(
            LightingUniforms::new([0.0; 3], [0.0; 3], [0.0; 3]).light_direction,
            [0.0, -1.0, 0.0]
        );
        assert_eq!(std::mem::size_of::<LightingUniforms>(), 128);
    }
}
