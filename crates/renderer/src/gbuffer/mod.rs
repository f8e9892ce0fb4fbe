//! The g-buffer node: a graph plugin that rasterises the scene and writes only the channels
//! downstream passes requested (see `GBufferChannel`). Hardware depth is always rasterised
//! (into a transient texture unless `Depth` is requested); every other channel exists only
//! when asked for, so a depth-only technique's plan has no normal, colour or motion attachment.
//! Motion vectors are requested only for scenes that move. The depth buffer's format is the
//! channel set's `depth_format` (Depth32Float by default, or Depth24Plus).
//!
//! The second depth layer (`GBufferChannel::SecondLayerDepth`, Mara et al. 2016's deep
//! g-buffer) is a second raster pass, `gbuffer.second_layer`, declared only when asked: it
//! draws the scene again into its own depth buffer and keeps, per pixel, the nearest fragment
//! at least Δ behind the first layer's linear depth (their "two-pass" construction, with this
//! frame's first layer rather than the previous frame's, so it is exact under motion).

mod raster;

use aograph_frame::ReadsView;
use std::sync::{Arc, Mutex};

use aograph_frame::{GBufferChannel, GBufferChannels, GBufferTextures};
use aograph_graph::{BufferHandle, GraphBuilder, SizeClass, TextureDesc};

use aograph_scene::model::Scene;
use raster::RasterSource;
pub use raster::{GBufferRaster, GBufferStates, SecondLayerRaster, raster_pipelines_created};

/// Per-frame inputs of the g-buffer: scene time now and at the previous frame, and whether
/// this frame's camera uses reversed Z (`None`: as the scene's camera does).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct GBufferFrame {
    /// Scene time of this frame, in seconds: where animated instances and skins are drawn.
    pub time: f32,
    /// Scene time of the previous frame, in seconds: the other end of the motion vectors
    /// (equal to `time` for no motion).
    pub prev_time: f32,
    /// `Some(true)` to rasterise with reversed depth (clear 0, test Greater), `Some(false)`
    /// for standard depth; `None` follows the scene camera's `reversed_z_infinite`.
    pub reversed_z: Option<bool>,
}

/// Shared handle to set the g-buffer's frame time from the render loop.
#[derive(Clone, Default)]
pub struct GBufferClock(Arc<Mutex<GBufferFrame>>);

impl GBufferClock {
    /// Sets the frame the next execution of the g-buffer pass draws (every clone sees it).
    pub fn set(&self, frame: GBufferFrame) {
        if let Ok(mut f) = self.0.lock() {
            *f = frame;
        }
    }

    /// The frame last set (the default, time 0, if none was or the lock is poisoned).
    pub fn get(&self) -> GBufferFrame {
        self.0.lock().map(|f| *f).unwrap_or_default()
    }
}

/// Which channels to write: what the consumers asked for, pruned by what the scene needs
/// (a static scene gets no motion vectors: every motion would be zero).
pub fn required_channels(requested: GBufferChannels, scene: &Scene) -> GBufferChannels {
    if scene.is_static() {
        requested.without(GBufferChannel::Motion)
    } else {
        requested
    }
}

/// Declares the g-buffer pass. `view` is the imported `View` uniform buffer. Returns the
/// handles of the channels written (others are `None`).
pub fn add_gbuffer(
    builder: &mut GraphBuilder,
    scene: Arc<Scene>,
    channels: GBufferChannels,
    view: BufferHandle,
    clock: GBufferClock,
) -> GBufferTextures {
    add_gbuffer_shared(
        builder,
        scene,
        channels,
        view,
        clock,
        &GBufferStates::default(),
    )
}

/// [`add_gbuffer`], with the GPU state (uploaded meshes, pipelines) shared with every other
/// g-buffer node declared with the same `states`, scene and channels: a renderer that
/// rebuilds its graph (another technique, another parameter) keeps one upload and one set of
/// pipelines. One `states` serves one device.
pub fn add_gbuffer_shared(
    builder: &mut GraphBuilder,
    scene: Arc<Scene>,
    channels: GBufferChannels,
    view: BufferHandle,
    clock: GBufferClock,
    states: &GBufferStates,
) -> GBufferTextures {
    let mut out = GBufferTextures::default();
    let depth_desc = TextureDesc::new(channels.depth_format.format(), SizeClass::FULL);
    let depth = builder.create_texture(
        if channels.contains(GBufferChannel::Depth) {
            "gbuffer.depth"
        } else {
            "gbuffer.zbuffer"
        },
        depth_desc,
    );
    let mut targets = Vec::new();
    let second_layer = channels.contains(GBufferChannel::SecondLayerDepth);
    // The second layer reads the first layer's linear depth, so asking for it writes that too.
    let channels = if second_layer {
        channels.with(GBufferChannel::LinearDepth)
    } else {
        channels
    };
    for c in channels
        .iter()
        .filter(|c| *c != GBufferChannel::Depth && *c != GBufferChannel::SecondLayerDepth)
    {
        let h = builder.create_texture(
            &format!("gbuffer.{}", c.name()),
            TextureDesc::new(c.format(), SizeClass::FULL),
        );
        targets.push((c, h));
    }
    let state = states.state(&scene, channels);
    let source = RasterSource {
        scene,
        channels,
        view,
        clock,
        state,
    };
    let raster = GBufferRaster::new(source.clone(), targets.clone(), depth);
    let mut pass = builder.custom_pass("gbuffer", raster);
    pass.read_view(view);
    let depth = pass.depth_attachment(depth);
    for (c, h) in targets {
        out.set(c, pass.color_attachment(h));
    }
    if channels.contains(GBufferChannel::Depth) {
        out.depth = Some(depth);
    }
    if let (true, Some(first)) = (second_layer, out.linear_depth) {
        let layer_depth = builder.create_texture("gbuffer.second_layer_zbuffer", depth_desc);
        let target = builder.create_texture(
            "gbuffer.second_layer_depth",
            TextureDesc::new(GBufferChannel::SecondLayerDepth.format(), SizeClass::FULL),
        );
        let raster = SecondLayerRaster::new(source, first, target, layer_depth);
        let mut pass = builder.custom_pass("gbuffer.second_layer", raster);
        pass.read_view(view);
        pass.read_texture(aograph_graph::TextureAccess::Sampled, first);
        pass.depth_attachment(layer_depth);
        out.second_layer_depth = Some(pass.color_attachment(target));
    }
    out
}
