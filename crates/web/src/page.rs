//! The browser glue (wasm32 only): a canvas's WebGPU device, surface and frame loop around
//! [`AoPage`], exported to the page's script with wasm-bindgen (www/page.js).
//!
//! Invariant: nothing here blocks. GPU completion and read-backs are awaited through the
//! browser's promises (`on_submitted_work_done`, `map_async`), since a page's thread may not
//! wait. Per-pass times are GPU timestamps where the browser has `timestamp-query`; the frame's
//! wall time (`performance.now()`) is always given too, each said for what it is.

use std::sync::{Arc, Mutex};

use wasm_bindgen::prelude::*;

use crate::ao_page::AoPage;

/// A JavaScript function moved into a wgpu callback, which wgpu (built with
/// `fragile-send-sync-non-atomic-wasm`) requires to be `Send`.
struct MainThread(js_sys::Function);
// SAFETY: wasm32-unknown-unknown without the `atomics` target feature has one thread: the
// function never leaves the thread that made it, the only one there is. With atomics (wasm
// threads) this would not hold, so the impl does not exist there.
#[cfg(not(target_feature = "atomics"))]
unsafe impl Send for MainThread {}

/// A promise resolved by `register` calling the function it is given, awaited.
async fn callback_promise(register: impl FnOnce(Box<dyn FnOnce() + Send>)) -> Result<(), JsValue> {
    let mut resolve_fn = None;
    let promise = js_sys::Promise::new(&mut |resolve, _reject| resolve_fn = Some(resolve));
    let resolve = MainThread(resolve_fn.ok_or("the promise gave no resolve function")?);
    register(Box::new(move || {
        let resolve = resolve;
        let _ = resolve.0.call0(&JsValue::NULL);
    }));
    wasm_bindgen_futures::JsFuture::from(promise)
        .await
        .map(|_| ())
}

fn now_ms() -> f64 {
    web_sys::window()
        .and_then(|w| w.performance())
        .map_or(0.0, |p| p.now())
}

fn js_error(e: impl std::fmt::Display) -> JsValue {
    JsValue::from_str(&e.to_string())
}

/// aograph's AO on a canvas: the page's script makes one with [`WebPage::start`].
#[wasm_bindgen]
pub struct WebPage {
    page: AoPage,
    device: wgpu::Device,
    queue: wgpu::Queue,
    /// The canvas's WebGPU context, or `None` when frames are copied out instead.
    surface: Option<wgpu::Surface<'static>>,
    /// Where frames are drawn when they are copied out (Rgba8Unorm).
    offscreen: Option<wgpu::Texture>,
    adapter: String,
    errors: Arc<Mutex<Vec<String>>>,
    size: (u32, u32),
}

#[wasm_bindgen]
impl WebPage {
    /// The procedural scene `scene` on `canvas` (its size is the output's), on a device with
    /// WebGPU's default limits and no optional features. With `copy_out`, frames are drawn
    /// into a texture that [`WebPage::read_color`] returns for a 2D canvas, instead of into
    /// the canvas's WebGPU context (headless Chromium's software adapter cannot present one).
    pub async fn start(
        canvas: web_sys::HtmlCanvasElement,
        scene: String,
        copy_out: bool,
    ) -> Result<WebPage, JsValue> {
        Self::open(canvas, Source::Procedural(scene), copy_out).await
    }

    /// As [`WebPage::start`], with the scene of a glTF file the page fetched: `bytes` of a
    /// `.glb` (or a `.gltf` with embedded buffers), `name` its URL for messages.
    pub async fn start_gltf(
        canvas: web_sys::HtmlCanvasElement,
        name: String,
        bytes: Vec<u8>,
        copy_out: bool,
    ) -> Result<WebPage, JsValue> {
        Self::open(canvas, Source::Gltf { name, bytes }, copy_out).await
    }

    /// The techniques the page can run, with their parameters' descriptions (JSON).
    pub fn catalogue(&self) -> String {
        let registry = aograph_ao_passes::TechniqueRegistry::with_builtins();
        crate::catalogue::technique_catalogue(&registry).to_string()
    }

    /// The adapter, as the browser names it.
    pub fn adapter(&self) -> String {
        self.adapter.clone()
    }

    /// The technique running now.
    pub fn technique(&self) -> String {
        self.page.technique().to_string()
    }

    /// The scene's suggested radius R.
    pub fn radius(&self) -> f32 {
        self.page.radius()
    }

    /// Applies `[ao]` settings (TOML); an error leaves the previous ones running and says why.
    pub fn set_settings(&mut self, toml: &str) -> Result<String, JsValue> {
        self.page.set_settings(toml).map_err(js_error)
    }

    /// Shows the AO alone instead of the shaded scene.
    pub fn set_ao_only(&mut self, ao_only: bool) {
        self.page.set_ao_only(ao_only);
    }

    /// Draws one frame into the canvas and waits (without blocking) for the GPU to finish it:
    /// the wall time from recording to completion, in milliseconds.
    pub async fn frame(&mut self) -> Result<f64, JsValue> {
        let started = now_ms();
        let mut encoder = self.device.create_command_encoder(&Default::default());
        match (&self.surface, &self.offscreen) {
            (Some(surface), _) => {
                let frame = match surface.get_current_texture() {
                    wgpu::CurrentSurfaceTexture::Success(f)
                    | wgpu::CurrentSurfaceTexture::Suboptimal(f) => f,
                    other => {
                        return Err(js_error(format!("the canvas gave no texture: {other:?}")));
                    }
                };
                let view = frame.texture.create_view(&Default::default());
                self.page.record(&mut encoder, &view).map_err(js_error)?;
                self.queue.submit([encoder.finish()]);
                self.queue.present(frame);
            }
            (None, Some(texture)) => {
                let view = texture.create_view(&Default::default());
                self.page.record(&mut encoder, &view).map_err(js_error)?;
                self.queue.submit([encoder.finish()]);
            }
            (None, None) => return Err(js_error("the page has no target")),
        }
        let queue = self.queue.clone();
        callback_promise(move |done| queue.on_submitted_work_done(done)).await?;
        Ok(now_ms() - started)
    }

    /// The last frame as RGBA8 rows, top to bottom, when frames are copied out (`copy_out`).
    pub async fn read_color(&self) -> Result<Vec<u8>, JsValue> {
        let texture = self
            .offscreen
            .as_ref()
            .ok_or("frames go to the canvas's WebGPU context; there is nothing to copy out")?;
        self.read_texture(texture, 4).await
    }

    /// The last frame's AO, one byte per pixel (R8Unorm), rows top to bottom.
    pub async fn read_ao(&self) -> Result<Vec<u8>, JsValue> {
        let texture = self
            .page
            .ao_texture()
            .ok_or("no frame has been drawn yet")?;
        self.read_texture(texture, 1).await
    }

    /// The newest per-pass GPU times that have arrived, as JSON: `{"frame": n, "passes":
    /// [[name, ms], ...]}`, or `null` when the device has no timestamp queries.
    pub fn pass_timings(&mut self) -> Result<String, JsValue> {
        let timings = self.page.pass_timings().map_err(js_error)?;
        Ok(match timings {
            None => "null".into(),
            Some(t) => serde_json::json!({
                "frame": t.frame.map(|f| f.0),
                "passes": t.passes,
            })
            .to_string(),
        })
    }

    /// WebGPU validation errors the device reported since the last call.
    pub fn take_errors(&self) -> Vec<String> {
        self.errors
            .lock()
            .map(|mut v| std::mem::take(&mut *v))
            .unwrap_or_default()
    }
}

impl WebPage {
    /// `texture` (the page's size, `texel_bytes` per texel) read back: tight rows, top to
    /// bottom. Awaits the map without blocking.
    async fn read_texture(
        &self,
        texture: &wgpu::Texture,
        texel_bytes: u32,
    ) -> Result<Vec<u8>, JsValue> {
        let (w, h) = self.size;
        let row = w * texel_bytes;
        let stride = row.next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
        let buffer = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("page AO read-back"),
            size: u64::from(stride * h),
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        let mut encoder = self.device.create_command_encoder(&Default::default());
        encoder.copy_texture_to_buffer(
            texture.as_image_copy(),
            wgpu::TexelCopyBufferInfo {
                buffer: &buffer,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(stride),
                    rows_per_image: Some(h),
                },
            },
            texture.size(),
        );
        self.queue.submit([encoder.finish()]);
        let slice = buffer.slice(..);
        let mapped: Arc<Mutex<Option<Result<(), wgpu::BufferAsyncError>>>> = Arc::default();
        let sink = mapped.clone();
        callback_promise(move |done| {
            slice.map_async(wgpu::MapMode::Read, move |r| {
                if let Ok(mut m) = sink.lock() {
                    *m = Some(r);
                }
                done();
            });
        })
        .await?;
        let status = mapped.lock().ok().and_then(|mut m| m.take());
        match status {
            Some(Ok(())) => {}
            Some(Err(e)) => return Err(js_error(format!("mapping the read-back failed: {e}"))),
            None => return Err(js_error("the read-back was never mapped")),
        }
        let mapped = buffer.slice(..).get_mapped_range().map_err(js_error)?;
        let mut out = Vec::with_capacity((row * h) as usize);
        for chunk in mapped.chunks(stride as usize) {
            out.extend_from_slice(&chunk[..row as usize]);
        }
        drop(mapped);
        buffer.unmap();
        Ok(out)
    }
}

/// Which scene a page draws.
enum Source {
    /// One of aograph's procedural scenes, by name.
    Procedural(String),
    /// A glTF file's bytes, with the name (URL) messages give it.
    Gltf { name: String, bytes: Vec<u8> },
}

impl WebPage {
    async fn open(
        canvas: web_sys::HtmlCanvasElement,
        source: Source,
        copy_out: bool,
    ) -> Result<WebPage, JsValue> {
        let size = (canvas.width(), canvas.height());
        let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle());
        let surface = if copy_out {
            None
        } else {
            Some(
                instance
                    .create_surface(wgpu::SurfaceTarget::Canvas(canvas))
                    .map_err(js_error)?,
            )
        };
        let adapter = instance
            .request_adapter(&wgpu::RequestAdapterOptions {
                compatible_surface: surface.as_ref(),
                ..Default::default()
            })
            .await
            .map_err(|e| js_error(format!("no WebGPU adapter: {e}")))?;
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("aograph web page"),
                // Timestamps, where the browser offers them, for per-pass GPU times; no other
                // feature and no limit above WebGPU's defaults.
                required_features: adapter.features() & wgpu::Features::TIMESTAMP_QUERY,
                ..Default::default()
            })
            .await
            .map_err(|e| js_error(format!("the adapter refused a device: {e}")))?;
        let errors: Arc<Mutex<Vec<String>>> = Arc::default();
        let sink = errors.clone();
        device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
            if let Ok(mut v) = sink.lock() {
                v.push(e.to_string());
            }
        }));
        let (format, offscreen) = match &surface {
            Some(surface) => {
                let caps = surface.get_capabilities(&adapter);
                let format = caps
                    .formats
                    .first()
                    .copied()
                    .ok_or("the canvas offers no format")?;
                surface.configure(
                    &device,
                    &wgpu::SurfaceConfiguration {
                        usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
                        format,
                        width: size.0,
                        height: size.1,
                        present_mode: wgpu::PresentMode::Fifo,
                        desired_maximum_frame_latency: 2,
                        alpha_mode: caps
                            .alpha_modes
                            .first()
                            .copied()
                            .unwrap_or(wgpu::CompositeAlphaMode::Auto),
                        view_formats: vec![],
                        color_space: Default::default(),
                    },
                );
                (format, None)
            }
            None => {
                let format = crate::OFFSCREEN_FORMAT;
                let texture = crate::offscreen_target(&device, size);
                (format, Some(texture))
            }
        };
        let page = match &source {
            Source::Procedural(scene) => {
                AoPage::new(&adapter, &device, &queue, scene, size, format)
            }
            Source::Gltf { name, bytes } => {
                AoPage::from_gltf(&adapter, &device, &queue, (name, bytes), size, format)
            }
        }
        .map_err(js_error)?;
        let info = adapter.get_info();
        Ok(WebPage {
            page,
            device,
            queue,
            surface,
            offscreen,
            adapter: format!("{} ({:?})", info.name, info.backend),
            errors,
            size,
        })
    }
}
