//! The viewer's state apart from its window: the renderer (one executor, every technique's
//! plan kept), the settings a user changes, the camera, the display textures and the
//! reference worker. Every change is checked before it applies: a rejected one leaves the
//! session as it was and returns an error naming what is allowed.
//!
//! Invariant: `settings.ao` is what the renderer renders, and `config_text()` writes exactly the
//! settings `aograph render --config` needs to render the same picture (for techniques without
//! history; a temporal technique's render converges over the frames the config asks for).

use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

use aograph_ao_passes::{AoConfig, DynAoTechnique, IntermediateFormat, TechniqueRegistry};
use aograph_graph::{Extent, GpuContext};
use aograph_scene::{Camera, Scene};

use super::camera_control::CameraController;
use super::display::{
    DISPLAY_PASS, DISPLAY_UNIFORM, DisplayMode, DisplayTextures, REFERENCE_TEXTURE, VIEW_TEXTURE,
    display_extension, display_uniform,
};
use super::reference_worker::{GpuReferenceDevice, ReferenceJob, ReferenceWorker};
use crate::shader_library;
use aograph_app_config::camera_spec::CameraSpec;
use aograph_app_config::config::{AppConfig, RadiusSetting, SceneSource};
use aograph_app_config::error::{AppError, AppResult};
use aograph_app_config::prepared_scene::resolve_radius;
use aograph_renderer::frame_graph::FrameOutputs;
use aograph_renderer::renderer::Renderer;

/// What the user chose.
#[derive(Clone, Debug)]
pub struct ViewerSettings {
    pub scene: SceneSource,
    /// Technique, its parameters (every technique's table is kept), intermediate format, and R
    /// pinned to the number in effect for this scene.
    pub ao: AoConfig,
    /// How R was chosen (`auto` or a number), re-resolved when the scene changes.
    pub radius: RadiusSetting,
    pub display: DisplayMode,
    /// Where the split falls, 0..1 of the width.
    pub split: f32,
    /// The signed error that shows full colour in the heat map.
    pub error_scale: f32,
    /// Scene time runs (animated scenes move) or stands at 0.
    pub animate: bool,
}

/// Moving averages of the frame and its passes.
#[derive(Default)]
pub struct FrameStats {
    /// Milliseconds per pass of the newest timed frame, and their moving averages.
    pub passes: Vec<(String, f64, f64)>,
    /// Whether the pass times are CPU times (a software device).
    pub cpu_times: bool,
    /// Wall-clock milliseconds between frames (moving average).
    pub frame_ms: f64,
    /// Every frame's wall-clock milliseconds since the last settings change.
    pub recent: Vec<f64>,
}

impl FrameStats {
    fn record(&mut self, passes: &aograph_graph::PassTimings) {
        const A: f64 = 0.1;
        let same = self.passes.len() == passes.passes.len()
            && self
                .passes
                .iter()
                .zip(&passes.passes)
                .all(|(a, b)| a.0 == b.0);
        if !same {
            self.passes = passes
                .passes
                .iter()
                .map(|(n, ms)| (n.clone(), *ms, *ms))
                .collect();
            return;
        }
        for (slot, (_, ms)) in self.passes.iter_mut().zip(&passes.passes) {
            slot.1 = *ms;
            slot.2 += A * (*ms - slot.2);
        }
    }
}

/// The viewer's state (see the module docs).
pub struct Session {
    pub gpu: Arc<GpuContext>,
    pub registry: TechniqueRegistry,
    pub renderer: Renderer,
    pub settings: ViewerSettings,
    pub camera: CameraController,
    /// The scene as loaded (its own camera, no view applied).
    pub scene: Arc<Scene>,
    /// Named views of the scene: the config's, the glTF cameras, the automatic ones.
    pub views: Vec<(String, Camera)>,
    pub textures: DisplayTextures,
    pub reference: ReferenceWorker,
    pub stats: FrameStats,
    /// Where R came from, for the panel.
    pub radius_note: String,
    /// Scene time of the next frame.
    pub time: f32,
    pub frames: u64,
    last_frame: Option<Instant>,
    /// A screenshot of the whole window (panel included) asked for, taken after the next frame
    /// is drawn.
    pub window_shot: Option<std::path::PathBuf>,
    /// Rays per pixel of the reference now shown (0: none yet).
    pub reference_rays: u32,
    pub reference_progress: f32,
    /// The bench's two ceilings for this view, once the worker has traced them.
    pub reference_ceilings: Option<super::reference_worker::CeilingSummary>,
    /// The reference worker's last failure, for the panel.
    pub reference_error: Option<String>,
}

impl Session {
    /// A session for `config` (scene, technique, parameters, R, camera) rendering at `size`.
    pub fn new(gpu: Arc<GpuContext>, config: &AppConfig, size: Extent) -> AppResult<Self> {
        let registry = TechniqueRegistry::with_builtins();
        let scene = Arc::new(aograph_app_config::load_scene(&config.scene)?);
        let (radius, radius_note) = resolve_radius(&scene, config.ao.radius);
        let ao = AoConfig {
            radius: RadiusSetting::Units(radius),
            ..config.ao.clone()
        };
        let start = match &config.camera {
            Some(spec) => spec.resolve(&scene, &config.views)?.camera,
            None => scene.camera,
        };
        let mut renderer = Renderer::new(
            gpu.clone(),
            shader_library(),
            &registry,
            scene.clone(),
            &ao,
            FrameOutputs {
                shaded: true,
                ..Default::default()
            },
            size,
        )?;
        renderer.exec.set_timing(if gpu.has_timestamps() {
            aograph_graph::TimingMode::GpuTimestamps
        } else {
            aograph_graph::TimingMode::Off
        })?;
        renderer.set_extension(display_extension())?;
        let textures = DisplayTextures::new(&gpu, size);
        renderer
            .exec
            .import_texture(VIEW_TEXTURE, textures.view.clone());
        renderer
            .exec
            .import_texture(REFERENCE_TEXTURE, textures.reference.clone());
        let views = scene_views(&scene, config);
        // The progressive reference on the GPU where `[reference] tracer` says so (auto: a
        // hardware device), on the CPU's other cores otherwise.
        let tracer = (config.reference_tracer).resolve(gpu.is_software(), gpu.has_ray_queries());
        let reference_device =
            (tracer != aograph_scene::ReferenceTracer::Cpu).then(|| GpuReferenceDevice {
                gpu: gpu.clone(),
                shaders: renderer.shaders.clone(),
                hardware: tracer == aograph_scene::ReferenceTracer::Hardware,
            });
        let stats = FrameStats {
            cpu_times: gpu.is_software(),
            ..Default::default()
        };
        Ok(Self {
            camera: CameraController::from_camera(start, scene.bounds().diagonal()),
            settings: ViewerSettings {
                scene: config.scene.clone(),
                ao,
                radius: config.ao.radius,
                display: DisplayMode::Ao,
                split: 0.5,
                error_scale: 0.25,
                animate: false,
            },
            gpu,
            registry,
            renderer,
            scene,
            views,
            textures,
            reference: ReferenceWorker::start(reference_device),
            stats,
            radius_note,
            time: 0.0,
            frames: 0,
            last_frame: None,
            window_shot: None,
            reference_rays: 0,
            reference_progress: 0.0,
            reference_ceilings: None,
            reference_error: None,
        })
    }

    /// Pipelines created so far: the executor's (every technique pass) and the g-buffer
    /// rasteriser's (its own pipelines, made when a g-buffer node first draws).
    pub fn pipelines_created(&self) -> u64 {
        self.renderer.exec.pipeline_created_count()
            + aograph_renderer::gbuffer::raster_pipelines_created()
    }

    /// The render size.
    pub fn size(&self) -> Extent {
        self.textures.size
    }

    /// The technique now shown.
    pub fn technique(&self) -> AppResult<&Arc<dyn DynAoTechnique>> {
        Ok(self.registry.get(&self.settings.ao.technique)?)
    }

    fn apply_ao(&mut self, ao: AoConfig) -> AppResult<()> {
        self.renderer.set_ao(&ao)?;
        self.settings.ao = ao;
        self.stats.recent.clear();
        Ok(())
    }

    /// Shows technique `name` from the next frame on (its parameters as last set).
    pub fn set_technique(&mut self, name: &str) -> AppResult<()> {
        self.registry.get(name)?;
        let ao = AoConfig {
            technique: name.to_string(),
            ..self.settings.ao.clone()
        };
        self.apply_ao(ao)
    }

    /// Sets parameter `name` of the current technique; a value the technique rejects (wrong
    /// type, out of range) is an error and changes nothing.
    pub fn set_param(&mut self, name: &str, value: toml::Value) -> AppResult<()> {
        let technique = self.settings.ao.technique.clone();
        let mut ao = self.settings.ao.clone();
        ao.params
            .entry(technique.clone())
            .or_default()
            .insert(name.to_string(), value);
        self.registry
            .get(&technique)?
            .check(&ao.params_for(&technique))?;
        self.apply_ao(ao)
    }

    /// Goes back to the technique's default for parameter `name`.
    pub fn reset_param(&mut self, name: &str) -> AppResult<()> {
        let technique = self.settings.ao.technique.clone();
        let mut ao = self.settings.ao.clone();
        if let Some(t) = ao.params.get_mut(&technique) {
            t.remove(name);
        }
        self.apply_ao(ao)
    }

    /// The shared radius R in effect, in scene units (the setting resolved for this scene).
    pub fn radius(&self) -> f32 {
        resolve_radius(&self.scene, self.settings.ao.radius).0.get()
    }

    /// Sets the shared radius R (`auto` or scene units).
    pub fn set_radius(&mut self, setting: RadiusSetting) -> AppResult<()> {
        let (radius, note) = resolve_radius(&self.scene, setting);
        let ao = AoConfig {
            radius: RadiusSetting::Units(radius),
            ..self.settings.ao.clone()
        };
        self.apply_ao(ao)?;
        self.settings.radius = setting;
        self.radius_note = note;
        Ok(())
    }

    /// Sets the intermediate precision.
    pub fn set_intermediate(&mut self, format: IntermediateFormat) -> AppResult<()> {
        let ao = AoConfig {
            intermediate_format: format,
            ..self.settings.ao.clone()
        };
        self.apply_ao(ao)
    }

    /// Opens another scene; on an error (a missing or malformed file) the session keeps the
    /// scene it had.
    pub fn load_scene(&mut self, source: SceneSource) -> AppResult<()> {
        let scene = Arc::new(aograph_app_config::load_scene(&source)?);
        let (radius, note) = resolve_radius(&scene, self.settings.radius);
        let ao = AoConfig {
            radius: RadiusSetting::Units(radius),
            ..self.settings.ao.clone()
        };
        self.renderer.set_scene(scene.clone(), &ao)?;
        self.settings.ao = ao;
        self.settings.scene = source;
        self.radius_note = note;
        self.camera = CameraController::from_camera(scene.camera, scene.bounds().diagonal());
        self.views = scene_views(&scene, &AppConfig::default());
        self.scene = scene;
        self.time = 0.0;
        self.stats.recent.clear();
        Ok(())
    }

    /// Renders at `size` from the next frame on.
    pub fn resize(&mut self, size: Extent) -> AppResult<()> {
        if size == self.textures.size {
            return Ok(());
        }
        aograph_app_config::config::check_size("width", size.width)?;
        aograph_app_config::config::check_size("height", size.height)?;
        self.renderer.resize(size)?;
        self.textures = DisplayTextures::new(&self.gpu, size);
        self.renderer
            .exec
            .import_texture(VIEW_TEXTURE, self.textures.view.clone());
        self.renderer
            .exec
            .import_texture(REFERENCE_TEXTURE, self.textures.reference.clone());
        self.stats.recent.clear();
        Ok(())
    }

    /// Renders one frame: the reference follows the view, the display block follows the
    /// settings, and timings that arrived are averaged in.
    pub fn frame(&mut self) -> AppResult<()> {
        let now = Instant::now();
        if let Some(last) = self.last_frame {
            let ms = now.duration_since(last).as_secs_f64() * 1000.0;
            self.stats.frame_ms = if self.stats.frame_ms == 0.0 {
                ms
            } else {
                self.stats.frame_ms + 0.1 * (ms - self.stats.frame_ms)
            };
            self.stats.recent.push(ms);
            if self.settings.animate {
                self.time += (ms / 1000.0) as f32;
            }
        }
        self.last_frame = Some(now);
        let camera = self.camera.camera();
        self.update_reference(camera);
        let plan = self.renderer.plan.clone();
        if let Some(h) = plan.decl.uniform(DISPLAY_PASS, DISPLAY_UNIFORM) {
            let s = &self.settings;
            self.renderer.exec.write_uniform(
                &plan,
                h,
                &display_uniform(s.display, s.split, s.error_scale),
            )?;
        }
        self.renderer.render_with_camera(self.time, camera)?;
        self.frames += 1;
        let timings = self.renderer.exec.latest_timings()?.clone();
        if timings.frame.is_some() {
            self.stats.record(&timings);
        }
        Ok(())
    }

    /// Starts a new trace when the view changed (while the picture shows the reference: in the
    /// other modes the worker rests, leaving the CPU to the frame); uploads what the worker
    /// traced since.
    fn update_reference(&mut self, camera: Camera) {
        let size = self.textures.size;
        let wanted = self.settings.display.uses_reference();
        let started = wanted
            && self.reference.request(ReferenceJob {
                scene: self.scene.clone(),
                camera,
                time: self.time,
                width: size.width,
                height: size.height,
                radius: self.radius(),
            });
        if started {
            self.textures.clear_reference(&self.gpu);
        }
        let textures = &self.textures;
        let gpu = &self.gpu;
        let taken = self.reference.with_state(|st| {
            if st.dirty && st.width == size.width && st.height == size.height {
                textures.write_reference(gpu, &st.values);
                st.dirty = false;
            }
            (st.rays_complete, st.progress, st.error.take(), st.ceilings)
        });
        if let Some((rays, progress, error, ceilings)) = taken {
            self.reference_rays = rays;
            self.reference_progress = progress;
            self.reference_ceilings = ceilings;
            if error.is_some() {
                self.reference_error = error;
            }
        }
    }

    /// Writes the picture last rendered (what the window shows) to `path` as a PNG.
    pub fn screenshot(&self, path: &Path) -> AppResult<()> {
        let t = &self.textures;
        let rb = aograph_graph::read_texture(&self.gpu.device, &self.gpu.queue, &t.view, 0)?;
        aograph_bench::images::write_rgba_png(path, t.size.width, t.size.height, &rb.bytes)
    }

    /// Moves the camera to view `name` of the scene.
    pub fn set_view(&mut self, name: &str) -> AppResult<()> {
        let camera = self
            .views
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, c)| *c)
            .ok_or_else(|| AppError::InvalidArgument {
                name: "view".into(),
                value: name.into(),
                allowed: self
                    .views
                    .iter()
                    .map(|(n, _)| n.as_str())
                    .collect::<Vec<_>>()
                    .join(", "),
            })?;
        self.camera.set(camera);
        Ok(())
    }

    /// Moves the camera to a camera written out (`pos=x,y,z target=x,y,z fov=60`).
    pub fn set_camera_text(&mut self, text: &str) -> AppResult<()> {
        let spec = CameraSpec::parse(text)?;
        let view = spec.resolve(&self.scene, &[])?;
        self.camera.set(view.camera);
        Ok(())
    }
}

/// The scene's named views: `[[views]]` of the config, then the scene's own (glTF cameras and
/// the automatic ones).
fn scene_views(scene: &Scene, config: &AppConfig) -> Vec<(String, Camera)> {
    let mut views: Vec<(String, Camera)> = config
        .views
        .iter()
        .map(|v| (v.name.clone(), v.params.camera(scene)))
        .collect();
    for name in aograph_scene::views::view_names(scene) {
        if let Some(v) = aograph_scene::views::find_view(scene, &name) {
            views.push((name, v.camera));
        }
    }
    views
}
