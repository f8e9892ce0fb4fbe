//! A headless bevy app pumped by hand, after bevy's `externally_driven_headless_renderer`
//! example: no window, pipelines compiled synchronously, the camera rendering into an image,
//! and a probe in the camera's Core3d schedule (after the main pass) that reads back the AO
//! texture bevy's PBR pass read (binding 17) and, on the same prepass, a fresh
//! `aograph_embed::AmbientOcclusion`'s AO.

#![allow(dead_code)]

use std::sync::{Arc, Mutex};

use aograph_bevy::{AographAo, AographAoPlugin, AographAoStatus, ao_inputs};
use aograph_embed::{AmbientOcclusion, AoOutputFormat};
use bevy::app::SubApps;
use bevy::asset::RenderAssetUsages;
use bevy::camera::RenderTarget;
use bevy::core_pipeline::prepass::ViewPrepassTextures;
use bevy::core_pipeline::schedule::{Core3d, Core3dSystems};
use bevy::pbr::ScreenSpaceAmbientOcclusionResources;
use bevy::prelude::*;
use bevy::render::camera::TemporalJitter;
use bevy::render::diagnostic::RenderDiagnosticsPlugin;
use bevy::render::error_handler::{RenderErrorHandler, RenderErrorPolicy};
use bevy::render::pipelined_rendering::PipelinedRenderingPlugin;
use bevy::render::render_resource::TextureFormat;
use bevy::render::renderer::{RenderAdapter, RenderContext, RenderDevice, RenderQueue, ViewQuery};
use bevy::render::view::ExtractedView;
use bevy::render::{RenderApp, RenderPlugin};
use bevy::window::ExitCondition;

/// What the probe read on the newest frame.
#[derive(Default)]
pub struct Probe {
    /// Read-backs recorded this frame, mapped after it: (binding 17's AO, fresh AO), size.
    pending: Option<(wgpu::Buffer, Option<wgpu::Buffer>, u32, u32)>,
    /// Read binding 17 on the next frame.
    armed: bool,
    /// Settings for the fresh AmbientOcclusion (the camera's, when the test asks).
    pub reference_toml: Option<String>,
    reference: Option<AmbientOcclusion>,
    pipeline: Option<(wgpu::ComputePipeline, wgpu::BindGroupLayout)>,
}

#[derive(Resource, Clone, Default)]
pub struct SharedProbe(pub Arc<Mutex<Probe>>);

/// Render errors bevy reported (its RenderErrorHandler), kept in the main world.
#[derive(Resource, Default)]
pub struct RenderErrors(pub Vec<String>);

/// The AO of one frame, as bevy's PBR pass read it and as a fresh aograph-embed made it.
pub struct AoFrame {
    pub width: u32,
    pub height: u32,
    pub bound: Vec<f32>,
    pub fresh: Vec<f32>,
}

impl AoFrame {
    pub fn at(&self, values: &[f32], x: u32, y: u32) -> f32 {
        values[(y * self.width + x) as usize]
    }
}

pub struct Harness {
    apps: SubApps,
    pub camera: Entity,
    pub probe: SharedProbe,
}

impl Harness {
    /// A scene of a 2 m cube on a 20 m floor, lit, seen by a camera rendering into a
    /// `width` x `height` image with `ao` on it.
    pub fn new(width: u32, height: u32, ao: AographAo) -> Self {
        Self::with_camera(width, height, ao, |_| {})
    }

    /// The headless app: bevy's default plugins without a window, pipelines compiled
    /// synchronously, each update rendering its own frame, aograph's plugin, bevy's render
    /// errors kept, and the probe in Core3d. `asset_root`: where bevy's asset server reads.
    fn apps(asset_root: Option<String>) -> (SubApps, SharedProbe) {
        let mut app = App::new();
        app.add_plugins(
            DefaultPlugins
                .set(AssetPlugin {
                    file_path: asset_root.unwrap_or_else(|| "assets".into()),
                    ..default()
                })
                .set(WindowPlugin {
                    primary_window: None,
                    exit_condition: ExitCondition::DontExit,
                    ..default()
                })
                .set(RenderPlugin {
                    synchronous_pipeline_compilation: true,
                    ..default()
                })
                // Each update renders its own frame (not the previous one on another thread),
                // so a frame's read-back is ready when `update` returns.
                .disable::<PipelinedRenderingPlugin>(),
        )
        .add_plugins((AographAoPlugin, RenderDiagnosticsPlugin))
        .init_resource::<RenderErrors>()
        .insert_resource(RenderErrorHandler(|error, main_world, _render_world| {
            if let Some(mut errors) = main_world.get_resource_mut::<RenderErrors>() {
                errors
                    .0
                    .push(format!("{:?}: {}", error.ty, error.description));
            }
            RenderErrorPolicy::StopRendering
        }));
        let probe = SharedProbe::default();
        app.sub_app_mut(RenderApp)
            .insert_resource(probe.clone())
            .add_systems(Core3d, probe_ao.after(Core3dSystems::MainPass));
        app.finish();
        app.cleanup();
        (std::mem::take(app.sub_apps_mut()), probe)
    }

    /// As [`Harness::new`], with `camera` adding to or changing the camera entity (a
    /// projection, a viewport).
    pub fn with_camera(
        width: u32,
        height: u32,
        ao: AographAo,
        camera: impl FnOnce(&mut EntityWorldMut),
    ) -> Self {
        let setup = camera;
        let (mut apps, probe) = Self::apps(None);
        let world = apps.main.world_mut();
        let image = target_and_light(world, width, height);
        let floor = world
            .resource_mut::<Assets<Mesh>>()
            .add(Plane3d::default().mesh().size(20.0, 20.0));
        let cube = world
            .resource_mut::<Assets<Mesh>>()
            .add(Cuboid::new(2.0, 2.0, 2.0));
        let white = world
            .resource_mut::<Assets<StandardMaterial>>()
            .add(Color::WHITE);
        world.spawn((Mesh3d(floor), MeshMaterial3d(white.clone())));
        world.spawn((
            Mesh3d(cube),
            MeshMaterial3d(white),
            Transform::from_xyz(0.0, 1.0, 0.0),
        ));
        let camera = world
            .spawn((
                Camera3d::default(),
                RenderTarget::from(image),
                Msaa::Off,
                Transform::from_xyz(3.0, 3.5, 6.0).looking_at(Vec3::new(-0.5, 0.5, 0.0), Vec3::Y),
                ao,
            ))
            .id();
        setup(&mut world.entity_mut(camera));
        Self {
            apps,
            camera,
            probe,
        }
    }

    /// A glTF file loaded by bevy's own loader, lit, seen by a camera with depth, normal and
    /// motion prepasses and no AO yet, rendering into a `width` x `height` image; frames are
    /// pumped until the scene's meshes are drawn.
    pub fn gltf(
        width: u32,
        height: u32,
        file: &std::path::Path,
        transform: Transform,
        projection: Projection,
    ) -> Self {
        use bevy::core_pipeline::prepass::{DepthPrepass, MotionVectorPrepass, NormalPrepass};
        let folder = file.parent().expect("a file in a folder");
        let name = file.file_name().expect("a file name").to_string_lossy();
        let (mut apps, probe) = Self::apps(Some(folder.to_string_lossy().into_owned()));
        let world = apps.main.world_mut();
        let image = target_and_light(world, width, height);
        let scene: Handle<bevy::world_serialization::WorldAsset> = world
            .resource::<AssetServer>()
            .load(GltfAssetLabel::Scene(0).from_asset(name.into_owned()));
        world.spawn(bevy::world_serialization::WorldAssetRoot(scene.clone()));
        let camera = world
            .spawn((
                Camera3d::default(),
                RenderTarget::from(image),
                Msaa::Off,
                transform,
                projection,
                DepthPrepass,
                NormalPrepass,
                MotionVectorPrepass,
            ))
            .id();
        let mut harness = Self {
            apps,
            camera,
            probe,
        };
        let drawn = (0..600).any(|_| {
            harness.update();
            let world = harness.world();
            let loaded = world
                .resource::<AssetServer>()
                .is_loaded_with_dependencies(&scene);
            loaded && world.query::<&Mesh3d>().iter(world).count() > 0
        });
        assert!(drawn, "bevy did not load {} in 600 frames", file.display());
        // A few frames more: the meshes' GPU data and pipelines.
        for _ in 0..3 {
            harness.update();
        }
        harness
    }

    /// bevy's own SSAO on the camera at `quality` (aograph's removed).
    pub fn set_bevy_ssao(&mut self, quality: bevy::pbr::ScreenSpaceAmbientOcclusionQualityLevel) {
        let camera = self.camera;
        let mut entity = self.world().entity_mut(camera);
        entity.remove::<AographAo>();
        entity.insert(bevy::pbr::ScreenSpaceAmbientOcclusion {
            quality_level: quality,
            ..default()
        });
    }

    /// No AO on the camera (its prepasses stay).
    pub fn clear_ao(&mut self) {
        let camera = self.camera;
        let mut entity = self.world().entity_mut(camera);
        entity.remove::<(AographAo, bevy::pbr::ScreenSpaceAmbientOcclusion)>();
    }

    /// Wall milliseconds of `frames` whole frames, each waited for (on a software device
    /// such as lavapipe this is CPU time, the GPU's work included).
    pub fn time_frames(&mut self, frames: u32) -> Vec<f64> {
        (0..frames)
            .map(|_| {
                let start = std::time::Instant::now();
                self.update();
                start.elapsed().as_secs_f64() * 1e3
            })
            .collect()
    }

    /// GPU milliseconds of bevy's render-diagnostics span `span` (`ssao` for bevy's SSAO,
    /// `aograph_ao` for aograph's passes) over `frames` frames, from timestamp queries; `None`
    /// where the device has none (bevy then records CPU time only).
    pub fn span_gpu_ms(&mut self, span: &str, frames: u32) -> Option<Vec<f64>> {
        use bevy::diagnostic::{DiagnosticPath, DiagnosticsStore};
        let path = DiagnosticPath::from_components(["render", span, "elapsed_gpu"]);
        if let Some(d) = self
            .world()
            .resource_mut::<DiagnosticsStore>()
            .get_mut(&path)
        {
            d.clear_history();
        }
        // Timestamps reach the main world a few frames after their frame.
        for _ in 0..frames + 4 {
            self.update();
        }
        let store = self.world().resource::<DiagnosticsStore>();
        let values: Vec<f64> = store.get(&path)?.values().copied().collect();
        let n = values.len().min(frames as usize);
        (n > 0).then(|| values[values.len() - n..].to_vec())
    }

    pub fn world(&mut self) -> &mut World {
        self.apps.main.world_mut()
    }

    /// One frame, waited for.
    pub fn update(&mut self) {
        self.apps.update();
        self.device()
            .poll(wgpu::PollType::Wait {
                submission_index: None,
                timeout: None,
            })
            .expect("the frame finishes");
    }

    fn device(&self) -> wgpu::Device {
        self.apps
            .main
            .world()
            .resource::<RenderDevice>()
            .wgpu_device()
            .clone()
    }

    pub fn status(&self) -> AographAoStatus {
        self.apps.main.world().resource::<AographAoStatus>().clone()
    }

    pub fn render_errors(&self) -> Vec<String> {
        self.apps.main.world().resource::<RenderErrors>().0.clone()
    }

    /// Puts new settings on the camera.
    pub fn set_ao(&mut self, ao: AographAo) {
        let camera = self.camera;
        self.world().entity_mut(camera).insert(ao);
    }

    /// Renders frames until the camera runs `technique` (a switch to new settings is prepared
    /// off the render thread first), at most `frames`.
    pub fn run_until_technique(&mut self, technique: &str, frames: u32) {
        for _ in 0..frames {
            self.update();
            if self
                .status()
                .camera(self.camera)
                .is_some_and(|s| s.technique == technique && !s.preparing)
            {
                return;
            }
        }
        panic!(
            "the camera did not switch to {technique} in {frames} frames: {:?}",
            self.status().camera(self.camera)
        );
    }

    /// Renders one frame with the probe on: binding 17's AO and a fresh aograph-embed's AO of
    /// the same prepass with `reference_toml`.
    pub fn probe_frame(&mut self, reference_toml: &str) -> AoFrame {
        self.probe_with(Some(reference_toml))
    }

    /// Renders one frame and reads binding 17 only (`fresh` is empty).
    pub fn probe_bound(&mut self) -> AoFrame {
        self.probe_with(None)
    }

    fn probe_with(&mut self, reference_toml: Option<&str>) -> AoFrame {
        {
            let mut probe = self.probe.0.lock().unwrap();
            probe.armed = true;
            probe.reference_toml = reference_toml.map(str::to_owned);
            probe.reference = None;
        }
        self.update();
        let (bound, fresh, width, height) = {
            let mut probe = self.probe.0.lock().unwrap();
            probe.armed = false;
            probe.pending.take().unwrap_or_else(|| {
                panic!(
                    "the probe did not run this frame: {:?}, render errors {:?}",
                    self.status().camera(self.camera),
                    self.render_errors()
                )
            })
        };
        let device = self.device();
        let read = |buffer: &wgpu::Buffer| -> Vec<f32> {
            buffer
                .slice(..)
                .map_async(wgpu::MapMode::Read, |r| r.expect("maps"));
            device
                .poll(wgpu::PollType::Wait {
                    submission_index: None,
                    timeout: None,
                })
                .expect("maps");
            let values = le_f32s(&buffer.slice(..).get_mapped_range().expect("mapped"));
            buffer.unmap();
            values
        };
        AoFrame {
            width,
            height,
            bound: read(&bound),
            fresh: fresh.as_ref().map(read).unwrap_or_default(),
        }
    }

    /// Where a world point lands in the camera's AO texture, in pixels (the viewport's
    /// rectangle: bevy's `world_to_viewport` answers in the render target's pixels).
    pub fn pixel_of(&mut self, point: Vec3) -> (u32, u32) {
        let camera = self.camera;
        let mut query = self.world().query::<(&Camera, &GlobalTransform)>();
        let (cam, transform) = query.get(self.world(), camera).expect("the camera");
        let p = cam
            .world_to_viewport(transform, point)
            .expect("the point is in view");
        let corner = cam
            .viewport
            .as_ref()
            .map_or(UVec2::ZERO, |v| v.physical_position);
        (p.x as u32 - corner.x, p.y as u32 - corner.y)
    }
}

/// The image a camera renders into, `width` x `height`, and a directional light over the
/// origin: what every harness scene has.
fn target_and_light(world: &mut World, width: u32, height: u32) -> Handle<Image> {
    let mut image = Image::new_target_texture(width, height, TextureFormat::Rgba8UnormSrgb, None);
    image.asset_usage = RenderAssetUsages::RENDER_WORLD;
    world.spawn((
        DirectionalLight::default(),
        Transform::from_xyz(2.0, 5.0, 3.0).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    world.resource_mut::<Assets<Image>>().add(image)
}

fn le_f32s(bytes: &[u8]) -> Vec<f32> {
    let (words, _) = bytes.as_chunks::<4>();
    words.iter().map(|w| f32::from_le_bytes(*w)).collect()
}

#[allow(clippy::too_many_arguments)]
fn probe_ao(
    view: ViewQuery<(
        &ExtractedView,
        &ViewPrepassTextures,
        &ScreenSpaceAmbientOcclusionResources,
        Option<&TemporalJitter>,
    )>,
    probe: Res<SharedProbe>,
    adapter: Res<RenderAdapter>,
    device: Res<RenderDevice>,
    queue: Res<RenderQueue>,
    time: Res<Time>,
    mut ctx: RenderContext,
) {
    let (extracted, prepass, resources, jitter) = view.into_inner();
    let mut probe = probe.0.lock().unwrap();
    if !probe.armed {
        return;
    }
    let device = device.wgpu_device().clone();
    let encoder = ctx.command_encoder();
    let fresh = probe.reference_toml.clone().map(|toml| {
        let inputs =
            ao_inputs(prepass, extracted, jitter, time.elapsed_secs()).expect("a depth prepass");
        if probe.reference.is_none() {
            let mut ao = AmbientOcclusion::from_toml(&adapter, &device, &queue, &toml)
                .expect("the reference settings");
            ao.set_output_format(AoOutputFormat::R32Float);
            probe.reference = Some(ao);
        }
        let ao = probe.reference.as_mut().expect("made above");
        ao.encode(encoder, &inputs).expect("the fresh AO encodes")
    });
    if probe.pipeline.is_none() {
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("read_r"),
            source: wgpu::ShaderSource::Wgsl(include_str!("read_r.wgsl").into()),
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("read_r"),
            layout: None,
            module: &module,
            entry_point: Some("main"),
            compilation_options: Default::default(),
            cache: None,
        });
        let layout = pipeline.get_bind_group_layout(0);
        probe.pipeline = Some((pipeline, layout));
    }
    let (pipeline, layout) = probe.pipeline.clone().expect("made above");
    let bound_texture: &wgpu::Texture = &resources.screen_space_ambient_occlusion_texture.texture;
    let (width, height) = (bound_texture.width(), bound_texture.height());
    let mut read = |texture: &wgpu::Texture| -> wgpu::Buffer {
        let size = u64::from(width * height) * 4;
        let storage = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("probe values"),
            size,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let readback = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("probe readback"),
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let view = texture.create_view(&Default::default());
        let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("read_r"),
            layout: &layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(&view),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: storage.as_entire_binding(),
                },
            ],
        });
        {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &bind, &[]);
            pass.dispatch_workgroups(width.div_ceil(8), height.div_ceil(8), 1);
        }
        encoder.copy_buffer_to_buffer(&storage, 0, &readback, 0, size);
        readback
    };
    let bound = read(bound_texture);
    let fresh = fresh.map(|f| read(&f.texture));
    probe.pending = Some((bound, fresh, width, height));
}
