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
use std::collections::hash_map::Entry;

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
use crate::error::AographBevyError;
use crate::frame_inputs::ao_inputs;
use crate::status::AographAoStatus;

/// An aograph camera with MSAA off that bevy made no SSAO resources for (inactive cameras have
/// none): its entity, and whether it has a view this frame.
type CameraWithoutSsao = (&'static MainEntity, Has<ExtractedView>);
type WithoutSsaoFilter = (
    With<AographAo>,
    Without<ScreenSpaceAmbientOcclusionResources>,
    Without<MsaaRefused>,
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
/// an application (or a test) may copy it out, and it is written 1 when made. bevy still makes its SSAO bind groups for
/// the view (its system for them cannot be ordered against), binding this texture as its
/// denoiser's storage output, so it has that usage too; bevy's format for it (R16Float where
/// the device writes it as storage, else R32Float) is storage-capable by construction.
const AO_TEXTURE_USAGE: wgpu::TextureUsages = wgpu::TextureUsages::RENDER_ATTACHMENT
    .union(wgpu::TextureUsages::TEXTURE_BINDING)
    .union(wgpu::TextureUsages::STORAGE_BINDING)
    .union(wgpu::TextureUsages::COPY_DST)
    .union(wgpu::TextureUsages::COPY_SRC);

/// Marks, for this frame, a camera whose MSAA is on: aograph leaves it alone.
#[derive(Component)]
pub(crate) struct MsaaRefused;

/// Runs before the frame's AO systems. A camera with MSAA on gets no AO from aograph (bevy
/// reads no prepass AO can come from), and an error saying why.
pub(crate) fn refuse_msaa(
    mut commands: Commands,
    status: Res<AographAoStatus>,
    cameras: Query<(Entity, &MainEntity, &Msaa, Has<MsaaRefused>), With<AographAo>>,
) {
    for (entity, camera, msaa, marked) in &cameras {
        let mut entity = commands.entity(entity);
        if *msaa == Msaa::Off {
            if marked {
                entity.remove::<MsaaRefused>();
            }
            continue;
        }
        record_error(
            &status,
            camera.id(),
            &AographBevyError::MsaaOn(format!("{msaa:?}")),
        );
        if !marked {
            entity.insert(MsaaRefused);
        }
    }
}

#[allow(clippy::too_many_arguments)]
pub(crate) fn hand_over_ao_texture(
    mut commands: Commands,
    mut cameras: ResMut<AographCameras>,
    status: Res<AographAoStatus>,
    adapter: Res<RenderAdapter>,
    device: Res<RenderDevice>,
    queue: Res<RenderQueue>,
    mut views: Query<
        (
            Entity,
            &MainEntity,
            &AographAo,
            &ExtractedView,
            &mut ScreenSpaceAmbientOcclusionResources,
        ),
        Without<MsaaRefused>,
    >,
    without_ssao: Query<CameraWithoutSsao, WithoutSsaoFilter>,
    with_aograph: Query<&MainEntity, With<AographAo>>,
) {
    for (camera, active) in &without_ssao {
        // An inactive camera has no view this frame: nothing to say.
        if active {
            record_error(&status, camera.id(), &AographBevyError::NoSsaoResources);
        }
    }
    // A camera keeps its state (plans, pipelines, history) while it has an AographAo, even on
    // frames without a view (inactive, minimised); it is dropped, with its status, when the
    // component goes.
    let wanted: Vec<Entity> = with_aograph.iter().map(|m| m.id()).collect();
    cameras.0.retain(|camera, _| wanted.contains(camera));
    status.retain(&wanted);

    for (entity, camera, settings, view, mut resources) in &mut views {
        let camera = camera.id();
        let bevy_format = resources
            .screen_space_ambient_occlusion_texture
            .texture
            .format();
        let Some(output) = AoOutputFormat::of(bevy_format) else {
            record_error(
                &status,
                camera,
                &AographBevyError::AoTextureFormat(bevy_format),
            );
            continue;
        };
        let state = match cameras.0.entry(camera) {
            Entry::Occupied(o) => o.into_mut(),
            Entry::Vacant(v) => match new_camera_ao(&adapter, &device, &queue, settings) {
                Ok(ao) => v.insert(ao),
                Err(error) => {
                    // bevy's own SSAO stays in place for this camera meanwhile.
                    record_error(&status, camera, &error);
                    continue;
                }
            },
        };
        match state.follow(settings.settings(), output) {
            Switch::Current => status.update(camera, |s| s.preparing = false),
            Switch::Preparing => status.update(camera, |s| s.preparing = true),
            Switch::Refused(error) => {
                status.update(camera, |s| s.preparing = false);
                record_error(&status, camera, &error);
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
            state.output = Some(unoccluded_texture(&device, &queue, width, height, output));
        }
        let Some((texture, view)) = &state.output else {
            continue;
        };
        resources.screen_space_ambient_occlusion_texture = CachedTexture {
            texture: texture.clone().into(),
            default_view: view.clone().into(),
        };
        // bevy's own SSAO system runs only for views with a pipeline id: none for this one,
        // now that binding 17 is aograph's.
        commands.entity(entity).remove::<SsaoPipelineId>();
    }
}

/// A new AO texture of the viewport's size in bevy's format, reading 1 (nothing occluded)
/// until aograph's first frame writes it: a frame that writes no AO (settings being prepared,
/// an error) never darkens indirect light.
fn unoccluded_texture(
    device: &RenderDevice,
    queue: &RenderQueue,
    width: u32,
    height: u32,
    output: AoOutputFormat,
) -> (wgpu::Texture, wgpu::TextureView) {
    let texture = aograph_graph::plain_texture(
        device.wgpu_device(),
        "aograph_ao_texture",
        (width, height),
        output.wgpu(),
        AO_TEXTURE_USAGE,
    );
    let one: &[u8] = match output {
        AoOutputFormat::R8Unorm => &[255],
        // 1.0 as IEEE half and single precision, little-endian.
        AoOutputFormat::R16Float => &[0x00, 0x3c],
        AoOutputFormat::R32Float => &[0x00, 0x00, 0x80, 0x3f],
    };
    let row = one.repeat(width as usize);
    queue.write_texture(
        texture.as_image_copy(),
        &row.repeat(height as usize),
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(row.len() as u32),
            rows_per_image: Some(height),
        },
        texture.size(),
    );
    let view = texture.create_view(&Default::default());
    (texture, view)
}

fn new_camera_ao(
    adapter: &RenderAdapter,
    device: &RenderDevice,
    queue: &RenderQueue,
    settings: &AographAo,
) -> Result<CameraAo, AographBevyError> {
    let mut ao = AmbientOcclusion::new(adapter, device.wgpu_device(), queue, settings.config())?;
    if device.features().contains(wgpu::Features::TIMESTAMP_QUERY) {
        ao.set_timing(aograph_graph::TimingMode::GpuTimestamps)?;
    }
    Ok(CameraAo::new(ao, settings.settings().clone()))
}

pub(crate) fn encode_ao(
    view: ViewQuery<AoView, (With<AographAo>, Without<MsaaRefused>)>,
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
        record_error(&status, camera, &AographBevyError::NoDepthPrepass);
        return;
    };
    let layout = match InputLayout::of(&inputs) {
        Ok(layout) => layout,
        Err(e) => {
            record_error(&status, camera, &e.into());
            return;
        }
    };
    // Settings are being prepared: this frame keeps the previous AO.
    let Some(mut ao) = state.try_ao() else {
        return;
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
            let refusing = state.refusing();
            status.update(camera, |s| {
                s.frames += 1;
                s.pipelines_created = pipelines;
                if gpu_ms.is_some() {
                    s.gpu_ms = gpu_ms;
                }
                // A frame ran with the settings wanted: an earlier error no longer holds.
                if !refusing {
                    s.error = None;
                }
            });
        }
        Err(e) => record_error(&status, camera, &e.into()),
    }
}

/// Logs an error the first time it is seen for a camera and keeps it in the status.
fn record_error(status: &AographAoStatus, camera: Entity, error: &AographBevyError) {
    let message = error.to_string();
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
