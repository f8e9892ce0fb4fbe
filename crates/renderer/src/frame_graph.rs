//! The frame graph aograph renders: the imported `View` block, the g-buffer (only the channels
//! the technique and the requested outputs need), the chosen AO technique, and optionally the
//! shading pass. Which channels exist is decided here, from the technique's declaration, the
//! outputs asked for and the scene's traits.

use aograph_frame::ReadsView;
use std::sync::Arc;

use crate::gbuffer::{GBufferClock, GBufferStates, add_gbuffer_shared, required_channels};
use aograph_ao_passes::{
    AoBuildContext, AoConfig, ConfiguredTechnique, ExtraOutput, RadianceOutput, RadiusSetting,
    TechniqueRegistry, TracingSupport,
};
use aograph_frame::{
    DeclaredInputs, DepthFormat, GBufferChannel, GBufferChannels, GBufferTextures, ViewBlock,
};
use aograph_graph::{Extent, GraphBuilder, GraphDecl, SizeClass, TextureDesc, TextureHandle};
use aograph_scene::{ReferenceNormals, Scene};

use crate::error::{RenderError, RenderResult};
use crate::pass_owner::{PassOwner, PassOwners};

/// Which outputs besides accessibility a run wants.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FrameOutputs {
    /// shaded.png: albedo * ambient * AO + direct light.
    pub shaded: bool,
    /// The g-buffer's view-space positions and normals, read back for the reference.
    pub surfaces: bool,
    /// Which normals `surfaces` writes: geometric (face) or shading (interpolated). A
    /// technique that reads the other kind cannot share the g-buffer: build the reference's
    /// surfaces with their own renderer (`frame_reference`).
    pub surface_normals: ReferenceNormals,
    /// Linear depth, read back (depth image, edge bands); with it the second depth layer,
    /// where the technique reads one (`layers = 2`).
    pub linear_depth: bool,
    /// The g-buffer's motion vectors (previous uv - current uv), read back, where the scene
    /// moves (a static scene has none: `read_gbuffer(Motion)` is then an error).
    pub motion: bool,
    /// The g-buffer's albedo, read back (the radiance reference's receivers).
    pub albedo: bool,
    /// The g-buffer's unshadowed directional light, read back (a CPU recomputation of what a
    /// technique does with it, such as SSDO's golden test).
    pub direct_light: bool,
    /// Format of the g-buffer's hardware depth buffer (Depth32Float by default).
    pub depth_format: DepthFormat,
}

/// A declared frame graph and the handles a caller reads.
pub struct FrameGraph {
    /// The declaration (compile it with `aograph_graph::GraphCompiler`).
    pub decl: GraphDecl,
    /// The technique's accessibility output (R32Float, 1 = unoccluded); `None` in a
    /// g-buffer-only frame ([`build_gbuffer_graph`]).
    pub ao: Option<TextureHandle>,
    /// shaded.png's texture, when `FrameOutputs::shaded` asked for it.
    pub shaded: Option<TextureHandle>,
    /// The g-buffer channels written (None for those not needed).
    pub gbuffer: GBufferTextures,
    /// Which channels the g-buffer writes, with its depth format.
    pub channels: GBufferChannels,
    /// The technique's extra outputs, each under its key (e.g. `aograph_ao_passes::PER_FRAME_OUTPUT`).
    pub extra: Vec<(ExtraOutput, TextureHandle)>,
    /// The technique's radiance outputs, where it computes radiance.
    pub radiance: Option<RadianceOutput>,
    /// Which part of the frame declared each pass (timings total by owner).
    pub owners: PassOwners,
    /// The g-buffer's per-frame time and depth convention, set by the renderer each frame.
    pub clock: GBufferClock,
    /// The technique carries history between frames.
    pub temporal: bool,
    /// Frame inputs the frame declared: the View block, and what the technique asked for
    /// (the scene's lighting, its BVH for ray-traced AO, ...): the renderer
    /// builds and binds exactly these.
    pub declared: DeclaredInputs,
}

impl FrameGraph {
    /// The technique's accessibility output, or an error saying this frame runs none (a
    /// g-buffer-only frame).
    pub fn accessibility(&self) -> RenderResult<TextureHandle> {
        self.ao.ok_or_else(|| RenderError::InvalidArgument {
            name: "accessibility".into(),
            value: "a g-buffer-only frame".into(),
            allowed: "a frame of a technique (Renderer::new, or Renderer::set_ao)".into(),
        })
    }
    /// The technique's extra output under `key`, if it wrote one.
    pub fn extra(&self, key: ExtraOutput) -> Option<TextureHandle> {
        self.extra.iter().find(|(k, _)| *k == key).map(|(_, h)| *h)
    }
}

/// Declares the whole frame for `scene` (seen from its camera at t = 0) at `size` with the
/// `[ao]` config, for no device in particular (a ray tracer set to `auto` takes the compute
/// backend; [`build_frame_graph_with`] names the device's ray tracing).
pub fn build_frame_graph(
    registry: &TechniqueRegistry,
    scene: Arc<Scene>,
    ao: &AoConfig,
    outputs: FrameOutputs,
    size: Extent,
) -> RenderResult<FrameGraph> {
    build_frame_graph_with(
        registry,
        scene,
        ao,
        outputs,
        size,
        &GBufferStates::default(),
        &TracingSupport::default(),
    )
}

/// [`build_frame_graph`] whose g-buffer shares its GPU state (mesh upload, pipelines) with
/// every graph built with the same `gbuffer` (see `crate::gbuffer::add_gbuffer_shared`),
/// for a device offering `tracing` (a technique's `tracer = "auto"` resolves against it).
pub fn build_frame_graph_with(
    registry: &TechniqueRegistry,
    scene: Arc<Scene>,
    ao: &AoConfig,
    outputs: FrameOutputs,
    size: Extent,
    gbuffer: &GBufferStates,
    tracing: &TracingSupport,
) -> RenderResult<FrameGraph> {
    // Parsed and validated once; everything below asks the configured technique.
    let technique = ao.resolve(registry)?;
    declare_frame(
        scene,
        Some((&*technique, ao)),
        outputs,
        size,
        gbuffer,
        tracing,
    )
}

/// The g-buffer alone for `scene` at `size` with the read-backs `outputs` asks for: no AO
/// technique runs (what every reference starts its rays from). `outputs.shaded` is refused:
/// shading needs an accessibility.
pub fn build_gbuffer_graph(
    scene: Arc<Scene>,
    outputs: FrameOutputs,
    size: Extent,
    gbuffer: &GBufferStates,
) -> RenderResult<FrameGraph> {
    declare_frame(
        scene,
        None,
        outputs,
        size,
        gbuffer,
        &TracingSupport::default(),
    )
}

/// The frame: the g-buffer, then `technique` (configured from `ao`) when there is one, then
/// the shading and exports `outputs` asks for.
fn declare_frame(
    scene: Arc<Scene>,
    technique: Option<(&dyn ConfiguredTechnique, &AoConfig)>,
    outputs: FrameOutputs,
    size: Extent,
    gbuffer: &GBufferStates,
    tracing: &TracingSupport,
) -> RenderResult<FrameGraph> {
    let radius_setting = technique.map_or(RadiusSetting::Auto, |(_, ao)| ao.radius);
    let radius = crate::scene_radius::resolve_radius(&scene, radius_setting)
        .0
        .get();
    let mut requested = technique.map_or_else(GBufferChannels::default, |(t, _)| t.channels());
    if outputs.shaded {
        requested = requested
            .with(GBufferChannel::Albedo)
            .with(GBufferChannel::DirectLight);
    }
    if outputs.surfaces {
        let face = outputs.surface_normals == ReferenceNormals::Geometric;
        if requested.has_normals() && requested.face_normals != face {
            return Err(RenderError::InvalidArgument {
                name: "surface normals".into(),
                value: outputs.surface_normals.name().into(),
                allowed: format!(
                    "the kind technique `{}` reads ({}); trace the reference from a g-buffer of \
                     its own (frame_reference)",
                    technique.map_or("", |(t, _)| t.name()),
                    if requested.face_normals {
                        "geometric"
                    } else {
                        "shading"
                    }
                ),
            });
        }
        requested = requested
            .with(GBufferChannel::Positions)
            .with(GBufferChannel::Normals);
        requested.face_normals = face;
    }
    if outputs.linear_depth {
        requested = requested.with(GBufferChannel::LinearDepth);
    }
    if outputs.motion {
        requested = requested.with(GBufferChannel::Motion);
    }
    if outputs.albedo {
        requested = requested.with(GBufferChannel::Albedo);
    }
    if outputs.direct_light {
        requested = requested.with(GBufferChannel::DirectLight);
    }
    // The second layer's Δ, stated in units of R, in view units for the g-buffer.
    let channels = required_channels(requested, &scene)
        .with_depth_format(outputs.depth_format)
        .with_radius(radius);
    let mut b = GraphBuilder::new();
    let mut declared = DeclaredInputs::default();
    let view = declared.declare::<ViewBlock>(&mut b);
    let clock = GBufferClock::default();
    let mut owners = PassOwners::default();
    let gbuffer = owners.record(&mut b, PassOwner::GBuffer, |b| {
        add_gbuffer_shared(b, scene.clone(), channels, view, clock.clone(), gbuffer)
    });
    // What an automatic level count must reach: R at the view's closest geometry, at most the
    // image's diagonal (`ProjectedRadius::reach_needed_px`).
    let Some((technique, ao)) = technique else {
        if outputs.shaded {
            return Err(aograph_ao_passes::AoError::MissingChannel {
                technique: "shading".into(),
                channel: "accessibility (a g-buffer-only frame runs no technique)".into(),
            }
            .into());
        }
        export_gbuffer(&mut b, &gbuffer, &outputs);
        return Ok(FrameGraph {
            decl: b.build(),
            ao: None,
            shaded: None,
            gbuffer,
            channels,
            extra: Vec::new(),
            radiance: None,
            owners,
            clock,
            temporal: false,
            declared,
        });
    };
    let radius_pixels = if technique.needs_radius_pixels() {
        aograph_scene::projected_radius(
            &scene,
            &scene.camera_at(0.0),
            size.width,
            size.height,
            radius,
        )
        .map(|p| p.reach_needed_px())
    } else {
        None
    };
    let (out, declared) = owners.record(&mut b, PassOwner::Technique, |b| {
        let mut ctx = AoBuildContext {
            builder: b,
            gbuffer,
            view,
            radius,
            intermediate_format: ao.intermediate_format.wgpu(),
            technique: technique.name(),
            radius_pixels,
            declared,
            tracing: tracing.clone(),
        };
        let out = technique.build(&mut ctx)?;
        Ok::<_, aograph_ao_passes::AoError>((out, ctx.declared))
    })?;
    let temporal = technique.is_temporal();
    b.export(out.accessibility);
    for (_, h) in &out.extra {
        b.export(*h);
    }
    if let Some(r) = out.radiance {
        b.export(r.direct);
        b.export(r.indirect);
    }
    let shaded = if outputs.shaded {
        Some(owners.record(&mut b, PassOwner::Shading, |b| {
            add_shading(b, &gbuffer, out.accessibility, &scene, view)
        })?)
    } else {
        None
    };
    export_gbuffer(&mut b, &gbuffer, &outputs);
    Ok(FrameGraph {
        decl: b.build(),
        ao: Some(out.accessibility),
        shaded,
        gbuffer,
        channels,
        extra: out.extra,
        radiance: out.radiance,
        owners,
        clock,
        temporal,
        declared,
    })
}

/// Exports the g-buffer channels `outputs` reads back.
fn export_gbuffer(b: &mut GraphBuilder, gbuffer: &GBufferTextures, outputs: &FrameOutputs) {
    if outputs.surfaces {
        gbuffer
            .positions
            .into_iter()
            .chain(gbuffer.normals)
            .chain(gbuffer.normals_oct)
            .for_each(|h| b.export(h));
    }
    if outputs.linear_depth {
        (gbuffer.linear_depth.into_iter())
            .chain(gbuffer.second_layer_depth)
            .for_each(|h| b.export(h));
    }
    if outputs.motion {
        gbuffer.motion.into_iter().for_each(|h| b.export(h));
    }
    if outputs.albedo {
        gbuffer.albedo.into_iter().for_each(|h| b.export(h));
    }
    if outputs.direct_light {
        gbuffer.direct_light.into_iter().for_each(|h| b.export(h));
    }
}

/// shaded = albedo * ambient * accessibility + direct light, in sRGB-encoded 8-bit.
fn add_shading(
    b: &mut GraphBuilder,
    g: &GBufferTextures,
    ao: TextureHandle,
    scene: &Scene,
    view: aograph_graph::BufferHandle,
) -> RenderResult<TextureHandle> {
    let (Some(albedo), Some(direct)) = (g.albedo, g.direct_light) else {
        return Err(aograph_ao_passes::AoError::MissingChannel {
            technique: "shading".into(),
            channel: "albedo/direct_light".into(),
        }
        .into());
    };
    let out = b.create_texture(
        "shaded",
        TextureDesc::new(wgpu::TextureFormat::Rgba8Unorm, SizeClass::FULL),
    );
    let mut p = b.compute_pass("shade", "render/shade.wgsl", "main");
    p.sample("albedo", albedo)
        .sample("direct_light", direct)
        .sample("ao", ao);
    p.read_view(view);
    let a = scene.ambient;
    let bytes: Vec<u8> = [a[0], a[1], a[2], 0.0]
        .iter()
        .flat_map(|f| f.to_le_bytes())
        .collect();
    p.uniform("ambient", &bytes);
    let out = p.write_storage("shaded", out);
    p.dispatch_over(out);
    b.export(out);
    Ok(out)
}
