//! One page's frame, target-independent: a procedural scene or a glTF file's drawn by [`PageRenderer`], its
//! depth and normals handed to `aograph_embed::AmbientOcclusion`, the AO shaded into a target.
//! The browser glue (`page.rs`) and the native example run exactly this.
//!
//! Invariant: the page's settings are the `[ao]` TOML a user would write (technique, radius,
//! `[technique]` table); on a device without r16float storage textures (core WebGPU), the page
//! asks for r32float intermediates unless the text names a format, so every technique that
//! fits WebGPU's defaults runs at them.

use aograph_embed::{
    AmbientOcclusion, AoInputs, AoOutputView, DepthInput, NormalEncoding, NormalSpace, NormalsInput,
};
use aograph_graph::GpuContext;
use glam::Mat4;

use crate::page_renderer::PageRenderer;
use crate::scene_mesh::SceneMesh;

/// Why the page cannot do what was asked: the embedding's or the scene's error, as text a
/// user can act on.
#[derive(Debug, thiserror::Error)]
pub enum PageError {
    /// aograph-embed refused (an unknown technique, a parameter out of range, a limit).
    #[error(transparent)]
    Embed(#[from] aograph_embed::EmbedError),
    /// The scene is not one of aograph's procedural scenes, or its glTF is malformed.
    #[error(transparent)]
    Scene(#[from] aograph_scene::SceneError),
    /// A scene without a triangle to draw.
    #[error("the scene has no triangles to draw")]
    Empty,
    /// A zero-sized output.
    #[error("the page's size is {width}x{height}; it must be at least 1x1")]
    Size {
        /// Width asked for.
        width: u32,
        /// Height asked for.
        height: u32,
    },
}

/// The scene, the page's renderer, aograph's AO and the camera.
pub struct AoPage {
    renderer: PageRenderer,
    ao: AmbientOcclusion,
    view: Mat4,
    projection: Mat4,
    light_dir: glam::Vec3,
    radius: f32,
    r16float_storage: bool,
    ao_only: bool,
    time: f32,
    output: Option<AoOutputView>,
}

impl AoPage {
    /// The procedural scene `scene` from its own camera at `width` x `height`, shaded into
    /// `target_format`, with gtao at the scene's suggested radius.
    pub fn new(
        adapter: &wgpu::Adapter,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        scene: &str,
        size: (u32, u32),
        target_format: wgpu::TextureFormat,
    ) -> Result<Self, PageError> {
        let scene = aograph_scene::procedural_scene(scene)?;
        Self::with_scene(adapter, device, queue, &scene, size, target_format)
    }

    /// A glTF file's scene from its bytes (a `.glb`, or a `.gltf` with its buffers embedded),
    /// named `name` in messages, from its default camera (the file's first, or aograph's
    /// automatic view).
    pub fn from_gltf(
        adapter: &wgpu::Adapter,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        (name, bytes): (&str, &[u8]),
        size: (u32, u32),
        target_format: wgpu::TextureFormat,
    ) -> Result<Self, PageError> {
        let scene = aograph_scene::import_gltf_bytes(std::path::Path::new(name), bytes)?.scene;
        Self::with_scene(adapter, device, queue, &scene, size, target_format)
    }

    /// `scene` from its own camera at `size`, shaded into `target_format`, with gtao at the
    /// scene's suggested radius.
    pub fn with_scene(
        adapter: &wgpu::Adapter,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        scene: &aograph_scene::Scene,
        (width, height): (u32, u32),
        target_format: wgpu::TextureFormat,
    ) -> Result<Self, PageError> {
        if width == 0 || height == 0 {
            return Err(PageError::Size { width, height });
        }
        if scene.triangle_count() == 0 {
            return Err(PageError::Empty);
        }
        let aspect = width as f32 / height as f32;
        // The page's own depth convention: reversed Z with an infinite far plane for a
        // perspective camera (as most engines draw); an orthographic camera's own projection,
        // with standard Z. aograph-embed reads the convention off the projection.
        let (projection, reversed_z) = match scene.camera.fov_y() {
            Some(fov_y) => (
                Mat4::perspective_infinite_reverse_rh(fov_y, aspect, scene.camera.near()),
                true,
            ),
            None => (scene.camera.projection(aspect), false),
        };
        let mesh = SceneMesh::of(scene, 0.0);
        let renderer = PageRenderer::new(
            device,
            queue,
            &mesh,
            (width, height),
            target_format,
            reversed_z,
        );
        let radius = aograph_scene::suggested_radius(scene).radius;
        let gpu = GpuContext::from_device(adapter.clone(), device.clone(), queue.clone());
        let r16float_storage = gpu.supports(
            wgpu::TextureFormat::R16Float,
            wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::TEXTURE_BINDING,
        );
        let settings = Self::settings_text("technique = \"gtao\"", radius, r16float_storage)
            .map_err(aograph_embed::EmbedError::from)?;
        let mut ao = AmbientOcclusion::from_toml(adapter, device, queue, &settings)?;
        // Per-pass GPU times where the device has timestamp queries (a browser's
        // `timestamp-query`: written at each pass's boundaries).
        let timestamps = device.features().contains(wgpu::Features::TIMESTAMP_QUERY);
        if timestamps {
            ao.set_timing(aograph_graph::TimingMode::GpuTimestamps)?;
        }
        Ok(Self {
            renderer,
            ao,
            view: scene.camera.view(),
            projection,
            light_dir: scene.light.direction,
            radius,
            r16float_storage,
            ao_only: false,
            time: 0.0,
            output: None,
        })
    }

    /// `text` with the scene's radius and, on a device without r16float storage, r32float
    /// intermediates, where the text does not set them itself: parsed as TOML, the keys added
    /// at the top level, written back.
    fn settings_text(
        text: &str,
        radius: f32,
        r16float_storage: bool,
    ) -> Result<String, aograph_ao_passes::AoError> {
        let mut table: toml::Table = text.parse().map_err(|e: toml::de::Error| {
            aograph_ao_passes::AoError::Config(format!("not valid TOML: {}", e.message()))
        })?;
        if !table.contains_key("radius") {
            table.insert("radius".into(), toml::Value::Float(f64::from(radius)));
        }
        if !r16float_storage && !table.contains_key("intermediate_format") {
            table.insert(
                "intermediate_format".into(),
                toml::Value::String("r32float".into()),
            );
        }
        toml::to_string(&table)
            .map_err(|e| aograph_ao_passes::AoError::Config(format!("cannot write TOML: {e}")))
    }

    /// Switches to the `[ao]` settings in `text` (TOML); the previous settings stay on an
    /// error. Returns the settings as applied (radius and format filled in).
    pub fn set_settings(&mut self, text: &str) -> Result<String, PageError> {
        let full = Self::settings_text(text, self.radius, self.r16float_storage)
            .map_err(aograph_embed::EmbedError::from)?;
        self.ao.set_config_toml(&full)?;
        Ok(full)
    }

    /// The technique running now.
    pub fn technique(&self) -> &str {
        &self.ao.config().technique
    }

    /// The scene's suggested AO radius R (what the settings get when they name none).
    pub fn radius(&self) -> f32 {
        self.radius
    }

    /// The pixel (x right, y down) that world point `p` projects to, if it is in the view.
    pub fn pixel_of(&self, p: glam::Vec3) -> Option<(u32, u32)> {
        let clip = self.projection * self.view * p.extend(1.0);
        if clip.w <= 0.0 {
            return None;
        }
        let ndc = clip.truncate() / clip.w;
        let (w, h) = (self.renderer.width as f32, self.renderer.height as f32);
        let x = (0.5 * ndc.x + 0.5) * w;
        let y = (0.5 - 0.5 * ndc.y) * h;
        ((0.0..w).contains(&x) && (0.0..h).contains(&y)).then_some((x as u32, y as u32))
    }

    /// The newest per-pass GPU milliseconds that have arrived (a few frames late), with the
    /// frame they measured; `None` on a device without timestamp queries.
    pub fn pass_timings(&mut self) -> Result<Option<aograph_graph::PassTimings>, PageError> {
        if self.ao.executor().timing() != aograph_graph::TimingMode::GpuTimestamps {
            return Ok(None);
        }
        Ok(Some(self.ao.latest_timings()?.clone()))
    }

    /// Show the AO alone (grey) instead of the shaded scene.
    pub fn set_ao_only(&mut self, ao_only: bool) {
        self.ao_only = ao_only;
    }

    /// Records one frame into `encoder`: the pre-pass, aograph's AO, shading into `target`.
    pub fn record(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        target: &wgpu::TextureView,
    ) -> Result<(), PageError> {
        self.renderer
            .set_camera(self.projection * self.view, self.light_dir, self.ao_only);
        self.renderer.prepass(encoder);
        let mut inputs = AoInputs::new(
            DepthInput::Hardware(&self.renderer.depth),
            self.projection,
            self.view,
        );
        inputs.normals = Some(NormalsInput {
            texture: &self.renderer.normals,
            space: NormalSpace::World,
            encoding: NormalEncoding::Xyz,
        });
        inputs.time = self.time;
        self.time += 1.0 / 60.0;
        let out = self.ao.encode(encoder, &inputs)?;
        self.renderer.shade(encoder, &out.view, target);
        self.output = Some(out);
        Ok(())
    }

    /// The texture the last frame's AO was written to (R8Unorm).
    pub fn ao_texture(&self) -> Option<&wgpu::Texture> {
        self.output.as_ref().map(|o| &o.texture)
    }
}

/// Accessibility in [0, 1] per pixel of R8Unorm rows read back as `bytes`.
pub fn ao_values(bytes: &[u8]) -> Vec<f32> {
    bytes.iter().map(|&b| f32::from(b) / 255.0).collect()
}

/// The mean of [`ao_values`].
pub fn ao_mean(bytes: &[u8]) -> f64 {
    if bytes.is_empty() {
        return 0.0;
    }
    bytes.iter().map(|&b| f64::from(b) / 255.0).sum::<f64>() / bytes.len() as f64
}
