//! The plugin's two render-world systems, in frame order:
//! 1. [`hand_over_ao_texture`] (PrepareBindGroups, before bevy makes the mesh view bind
//!    group): follows each camera's settings, puts aograph's AO texture where bevy's PBR pass
//!    reads AO (`ScreenSpaceAmbientOcclusionResources`, group 0 binding 17), and takes away the
//!    pipeline id bevy's SSAO system needs, so bevy's three SSAO passes do not run;
//! 2. [`encode_ao`] (the camera's Core3d schedule, after the prepass, before the main pass):
//!    records the camera's AO into that texture from its prepass.
//!
//! Invariant: nothing here panics on user input; every failure is logged once and recorded in
//! [`AographAoStatus`], and the frame keeps the previous AO.

use std::collections::HashMap;
use std::sync::TryLockError;

use aograph_embed::{AmbientOcclusion, AoOutputFormat, InputLayout};
use bevy::core_pipeline::prepass::ViewPrepassTextures;
use bevy::pbr::{ScreenSpaceAmbientOcclusionResources, SsaoPipelineId};
use bevy::prelude::*;
use bevy::render::camera::TemporalJitter;
use bevy::render::diagnostic::RecordDiagnostics;
use bevy::render::renderer::{RenderAdapter, RenderContext, RenderDevice, RenderQueue, ViewQuery};
use bevy::render::sync_world::MainEntity;
use bevy::render::texture::CachedTexture;
use bevy::render::view::{ExtractedView, Msaa};

use crate::camera_ao::{CameraAo, Switch};
use crate::component::AographAo;
use crate::frame_inputs::ao_inputs;
use crate::status::AographAoStatus;

/// An aograph camera bevy made no SSAO resources for (bevy's SSAO extraction skips cameras
/// with MSAA on): its entity and MSAA.
type CameraWithoutSsao = (&'static MainEntity, Option<&'static Msaa>);
type WithoutSsaoFilter = (
    With<AographAo>,
    Without<ScreenSpaceAmbientOcclusionResources>,
);
/// What encoding one view's AO reads: its camera, matrices, prepass, AO texture, TAA jitter.
type AoView = (
    &'static MainEntity,
    &'static ExtractedView,
    &'static ViewPrepassTextures,
    &'static ScreenSpaceAmbientOcclusionResources,
    Option<&'static TemporalJitter>,
);

/// Each aograph camera's state, keyed by its main-world entity.
#[derive(Resource, Default)]
pub(crate) struct AographCameras(HashMap<Entity, CameraAo>);

/// Usages of the AO texture: aograph writes it in a render pass, bevy's PBR pass samples it,
/// and an application (or a test) may copy it out. bevy still makes its SSAO bind groups for
/// the view (its system for them cannot be ordered against), binding this texture as its
/// denoiser's storage output, so it has that usage too; bevy's format for it (R16Float where
/// the device writes it as storage, else R32Float) is storage-capable by construction.
const AO_TEXTURE_USAGE: wgpu::TextureUsages = wgpu::TextureUsages::RENDER_ATTACHMENT
    .union(wgpu::TextureUsages::TEXTURE_BINDING)
    .union(wgpu::TextureUsages::STORAGE_BINDING)
    .union(wgpu::TextureUsages::COPY_SRC);

#[allow(clippy::too_many_arguments)]
pub(crate) fn hand_over_ao_texture(
    mut commands: Commands,
    mut cameras: ResMut<AographCameras>,
    status: Res<AographAoStatus>,
    adapter: Res<RenderAdapter>,
    device: Res<RenderDevice>,
    queue: Res<RenderQueue>,
    mut views: Query<(
        Entity,
        &MainEntity,
        &AographAo,
        &ExtractedView,
        &mut ScreenSpaceAmbientOcclusionResources,
    )>,
    without_ssao: Query<CameraWithoutSsao, WithoutSsaoFilter>,
) {
    for (camera, msaa) in &without_ssao {
        if msaa.is_some_and(|m| *m != Msaa::Off) {
            let message = format!(
                "the camera has Msaa::{:?}: aograph reads its prepass, which needs Msaa::Off (as \
                 bevy's own SSAO does)",
                msaa.copied().unwrap_or_default()
            );
            record_error(&status, camera.id(), message);
        }
    }
    let mut seen = Vec::new();
    for (entity, camera, settings, view, mut resources) in &mut views {
        let camera = camera.id();
        seen.push(camera);
        // bevy's own SSAO system runs only for views with a pipeline id: none for this one.
        commands.entity(entity).remove::<SsaoPipelineId>();
        let bevy_texture = &resources.screen_space_ambient_occlusion_texture.texture;
        let Some(output) = AoOutputFormat::of(bevy_texture.format()) else {
            record_error(
                &status,
                camera,
                format!("bevy's AO texture has format {:?}", bevy_texture.format()),
            );
            continue;
        };
        let state = match cameras.0.entry(camera) {
            std::collections::hash_map::Entry::Occupied(o) => o.into_mut(),
            std::collections::hash_map::Entry::Vacant(v) => {
                match new_camera_ao(&adapter, &device, &queue, settings) {
                    Ok(ao) => v.insert(ao),
                    Err(message) => {
                        record_error(&status, camera, message);
                        continue;
                    }
                }
            }
        };
        match state.follow(settings.settings(), output) {
            Switch::Current => status.update(camera, |s| s.preparing = false),
            Switch::Preparing => status.update(camera, |s| s.preparing = true),
            Switch::Refused(message) => {
                status.update(camera, |s| s.preparing = false);
                record_error(&status, camera, message);
            }
            Switch::StillRefused => {}
        }
        let technique = state.technique().to_owned();
        status.update(camera, |s| s.technique = technique);

        let (width, height) = (view.viewport.z.max(1), view.viewport.w.max(1));
        let fits = state.output.as_ref().is_some_and(|(t, _)| {
            (t.width(), t.height(), t.format()) == (width, height, output.wgpu())
        });
        if !fits {
            let texture = device
                .wgpu_device()
                .create_texture(&wgpu::TextureDescriptor {
                    label: Some("aograph_ao_texture"),
                    size: wgpu::Extent3d {
                        width,
                        height,
                        depth_or_array_layers: 1,
                    },
                    mip_level_count: 1,
                    sample_count: 1,
                    dimension: wgpu::TextureDimension::D2,
                    format: output.wgpu(),
                    usage: AO_TEXTURE_USAGE,
                    view_formats: &[],
                });
            let view = texture.create_view(&Default::default());
            state.output = Some((texture, view));
        }
        if let Some((texture, view)) = &state.output {
            resources.screen_space_ambient_occlusion_texture = CachedTexture {
                texture: texture.clone().into(),
                default_view: view.clone().into(),
            };
        }
    }
    cameras.0.retain(|camera, _| seen.contains(camera));
}

fn new_camera_ao(
    adapter: &RenderAdapter,
    device: &RenderDevice,
    queue: &RenderQueue,
    settings: &AographAo,
) -> Result<CameraAo, String> {
    let mut ao = AmbientOcclusion::new(adapter, device.wgpu_device(), queue, settings.config())
        .map_err(|e| e.to_string())?;
    if device.features().contains(wgpu::Features::TIMESTAMP_QUERY) {
        ao.set_timing(aograph_graph::TimingMode::GpuTimestamps)
            .map_err(|e| e.to_string())?;
    }
    Ok(CameraAo::new(ao, settings.settings().clone()))
}

pub(crate) fn encode_ao(
    view: ViewQuery<AoView, With<AographAo>>,
    mut cameras: ResMut<AographCameras>,
    status: Res<AographAoStatus>,
    time: Res<Time>,
    mut ctx: RenderContext,
) {
    let (camera, extracted, prepass, resources, jitter) = view.into_inner();
    let camera = camera.id();
    let Some(state) = cameras.0.get_mut(&camera) else {
        return;
    };
    let Some(inputs) = ao_inputs(prepass, extracted, jitter, time.elapsed_secs()) else {
        record_error(
            &status,
            camera,
            "the camera has no depth prepass (AographAo brings DepthPrepass: was it removed?)"
                .into(),
        );
        return;
    };
    let layout = match InputLayout::of(&inputs) {
        Ok(layout) => layout,
        Err(e) => {
            record_error(&status, camera, e.to_string());
            return;
        }
    };
    let ao_lock = state.ao.clone();
    let mut ao = match ao_lock.try_lock() {
        Ok(ao) => ao,
        // Settings are being prepared: this frame keeps the previous AO.
        Err(TryLockError::WouldBlock) => return,
        Err(TryLockError::Poisoned(p)) => p.into_inner(),
    };
    let target = &resources.screen_space_ambient_occlusion_texture.texture;
    // bevy's render diagnostics (RenderDiagnosticsPlugin) time aograph's passes as one span,
    // `render/aograph_ao/elapsed_gpu`, beside bevy's own `render/ssao/...`.
    let diagnostics = ctx.diagnostic_recorder();
    let diagnostics = diagnostics.as_deref();
    let span = diagnostics.time_span(ctx.command_encoder(), "aograph_ao");
    let encoded = ao.encode_into(ctx.command_encoder(), &inputs, target);
    span.end(ctx.command_encoder());
    match encoded {
        Ok(()) => {
            let gpu_ms = ao
                .latest_timings()
                .ok()
                .and_then(|t| t.frame.map(|_| t.total_ms()));
            let pipelines = ao.pipelines_created();
            drop(ao);
            state.ran(layout);
            status.update(camera, |s| {
                s.frames += 1;
                s.pipelines_created = pipelines;
                if gpu_ms.is_some() {
                    s.gpu_ms = gpu_ms;
                }
            });
        }
        Err(e) => record_error(&status, camera, e.to_string()),
    }
}

/// Logs an error the first time it is seen for a camera and keeps it in the status.
fn record_error(status: &AographAoStatus, camera: Entity, message: String) {
    let mut new = false;
    status.update(camera, |s| {
        if s.error.as_deref() != Some(message.as_str()) {
            new = true;
            s.error = Some(message.clone());
        }
    });
    if new {
        tracing::error!("aograph AO on camera {camera}: {message}");
    }
}
