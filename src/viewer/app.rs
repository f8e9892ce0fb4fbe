//! The viewer's window: winit events, egui on the device the graph uses, and the frame loop
//! (script step, camera, session frame, panel, present). The picture is the session's view
//! texture, shown by egui in the central panel; the render size follows that panel unless a
//! size was fixed (`--width`/`--height`, a script's `size`).
//!
//! Invariant: the viewer exits with an error (never a panic) when the window, the device or a
//! script action fails, and when wgpu reported a validation error during the run.

use std::sync::Arc;
use std::time::Instant;

use aograph_graph::{Extent, GpuContext};
use winit::application::ApplicationHandler;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::ActiveEventLoop;
use winit::keyboard::{KeyCode, PhysicalKey};
use winit::window::{Window, WindowId};

use super::camera_control::{CameraMode, MoveKeys};
use super::panel::{PanelState, side_panel};
use super::script::{Script, Step, stats_line};
use super::session::Session;
use aograph_app_config::config::{AppConfig, SceneSource};
use aograph_app_config::error::{AppError, AppResult};

/// What the viewer was started with.
pub struct ViewerOptions {
    pub config: AppConfig,
    /// A fixed render size (else the central panel's).
    pub size: Option<Extent>,
    pub script: Option<Script>,
}

/// Everything that exists once the window does.
struct Running {
    window: Arc<Window>,
    surface: wgpu::Surface<'static>,
    surface_config: wgpu::SurfaceConfiguration,
    gpu: Arc<GpuContext>,
    session: Session,
    egui_ctx: egui::Context,
    egui_state: egui_winit::State,
    egui_renderer: egui_wgpu::Renderer,
    view_id: egui::TextureId,
    view_size: Extent,
    panel: PanelState,
    keys: MoveKeys,
    dragging: bool,
    cursor: Option<(f64, f64)>,
    last: Instant,
}

/// The winit application.
pub struct ViewerApp {
    options: ViewerOptions,
    running: Option<Running>,
    /// How the run ended.
    pub result: AppResult<()>,
}

impl ViewerApp {
    pub fn new(options: ViewerOptions) -> Self {
        Self {
            options,
            running: None,
            result: Ok(()),
        }
    }

    fn fail(&mut self, el: &ActiveEventLoop, e: AppError) {
        if self.result.is_ok() {
            self.result = Err(e);
        }
        el.exit();
    }

    fn start(&mut self, el: &ActiveEventLoop) -> AppResult<Running> {
        let attrs = Window::default_attributes()
            .with_title("aograph view")
            .with_inner_size(winit::dpi::PhysicalSize::new(1280u32, 720u32));
        let window = Arc::new(
            el.create_window(attrs)
                .map_err(|e| AppError::InvalidArgument {
                    name: "window".into(),
                    value: e.to_string(),
                    allowed: super::NO_DISPLAY_FIX.into(),
                })?,
        );
        let (gpu, surface) = GpuContext::with_surface(window.clone())?;
        let gpu = Arc::new(gpu);
        let caps = surface.get_capabilities(&gpu.adapter);
        let format = caps
            .formats
            .iter()
            .copied()
            .find(|f| f.is_srgb())
            .or_else(|| caps.formats.first().copied())
            .ok_or_else(|| AppError::InvalidArgument {
                name: "window surface".into(),
                value: "no format".into(),
                allowed: "a surface the device can present to".into(),
            })?;
        let inner = window.inner_size();
        // Copies out of the window's texture make window screenshots, where the surface allows.
        let usage =
            wgpu::TextureUsages::RENDER_ATTACHMENT | (caps.usages & wgpu::TextureUsages::COPY_SRC);
        let surface_config = wgpu::SurfaceConfiguration {
            usage,
            format,
            color_space: wgpu::SurfaceColorSpace::Auto,
            width: inner.width.max(1),
            height: inner.height.max(1),
            present_mode: wgpu::PresentMode::AutoNoVsync,
            desired_maximum_frame_latency: 2,
            alpha_mode: caps.alpha_modes[0],
            view_formats: vec![],
        };
        surface.configure(&gpu.device, &surface_config);
        let size = self
            .options
            .size
            .unwrap_or(Extent::new(inner.width * 3 / 4, inner.height));
        let session = Session::new(gpu.clone(), &self.options.config, size)?;
        let egui_ctx = egui::Context::default();
        let egui_state = egui_winit::State::new(
            egui_ctx.clone(),
            egui::ViewportId::ROOT,
            &window,
            Some(window.scale_factor() as f32),
            None,
            Some(gpu.device.limits().max_texture_dimension_2d as usize),
        );
        let mut egui_renderer =
            egui_wgpu::Renderer::new(&gpu.device, format, egui_wgpu::RendererOptions::default());
        let view = session.textures.view.create_view(&Default::default());
        let view_id =
            egui_renderer.register_native_texture(&gpu.device, &view, wgpu::FilterMode::Linear);
        Ok(Running {
            window,
            surface,
            surface_config,
            view_size: session.size(),
            gpu,
            session,
            egui_ctx,
            egui_state,
            egui_renderer,
            view_id,
            panel: PanelState::new(),
            keys: MoveKeys::default(),
            dragging: false,
            cursor: None,
            last: Instant::now(),
        })
    }

    /// One frame: the script's step, the camera, the session's frame, the panel, the present.
    fn redraw(&mut self, el: &ActiveEventLoop) -> AppResult<()> {
        let Some(r) = self.running.as_mut() else {
            return Ok(());
        };
        if let Some(script) = self.options.script.as_mut() {
            if script.step(&mut r.session)? == Step::Quit {
                println!("at exit: {}", stats_line(&r.session));
                el.exit();
                return Ok(());
            }
        }
        let dt = r.last.elapsed().as_secs_f32().min(0.25);
        r.last = Instant::now();
        r.session.camera.fly(r.keys, dt);
        r.session.frame()?;
        if r.view_size != r.session.size() {
            let view = r.session.textures.view.create_view(&Default::default());
            r.egui_renderer.update_egui_texture_from_wgpu_texture(
                &r.gpu.device,
                &view,
                wgpu::FilterMode::Linear,
                r.view_id,
            );
            r.view_size = r.session.size();
        }

        let input = r.egui_state.take_egui_input(&r.window);
        let mut wanted = None;
        let (session, panel, view_id) = (&mut r.session, &mut r.panel, r.view_id);
        let mut output = r.egui_ctx.run_ui(input, |root| {
            side_panel(root, session, panel);
            egui::CentralPanel::no_frame().show(root, |ui| {
                let avail = ui.available_size();
                let ppp = ui.ctx().pixels_per_point();
                wanted = Some(Extent::new(
                    ((avail.x * ppp) as u32).max(16),
                    ((avail.y * ppp) as u32).max(16),
                ));
                let size = session.size();
                let aspect = size.width as f32 / size.height.max(1) as f32;
                let fit = if avail.x / avail.y.max(1.0) > aspect {
                    egui::vec2(avail.y * aspect, avail.y)
                } else {
                    egui::vec2(avail.x, avail.x / aspect)
                };
                ui.centered_and_justified(|ui| {
                    ui.image((view_id, fit));
                });
            });
        });
        r.egui_state
            .handle_platform_output(&r.window, output.platform_output);
        let fixed = self.options.size.is_some()
            || self.options.script.as_ref().is_some_and(|s| s.fixed_size());
        if let (false, Some(size)) = (fixed, wanted) {
            if let Err(e) = r.session.resize(size) {
                r.panel.report(Err(e));
            }
        }
        let jobs = r
            .egui_ctx
            .tessellate(output.shapes, output.pixels_per_point);
        let mut textures = std::mem::take(&mut output.textures_delta);
        for (id, deltas) in textures.set.drain() {
            for delta in &deltas {
                r.egui_renderer
                    .update_texture(&r.gpu.device, &r.gpu.queue, id, delta);
            }
        }
        let unused: Vec<egui::TextureId> = textures.free.drain().collect();
        let frame = match r.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(f)
            | wgpu::CurrentSurfaceTexture::Suboptimal(f) => f,
            wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                r.surface.configure(&r.gpu.device, &r.surface_config);
                free(&mut r.egui_renderer, &unused);
                return Ok(());
            }
            _ => return Ok(()),
        };
        let screen = egui_wgpu::ScreenDescriptor {
            size_in_pixels: [r.surface_config.width, r.surface_config.height],
            pixels_per_point: output.pixels_per_point,
        };
        let mut encoder = r
            .gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("aograph view ui"),
            });
        let mut buffers = r.egui_renderer.update_buffers(
            &r.gpu.device,
            &r.gpu.queue,
            &mut encoder,
            &jobs,
            &screen,
        );
        let target = frame.texture.create_view(&Default::default());
        {
            let pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("aograph view ui"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &target,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color {
                            r: 0.05,
                            g: 0.05,
                            b: 0.06,
                            a: 1.0,
                        }),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            let mut pass = pass.forget_lifetime();
            r.egui_renderer.render(&mut pass, &jobs, &screen);
        }
        buffers.push(encoder.finish());
        r.gpu.queue.submit(buffers);
        if let Some(path) = r.session.window_shot.take() {
            window_screenshot(&r.gpu, &frame.texture, &path)?;
            println!("window screenshot {}", path.display());
        }
        r.gpu.queue.present(frame);
        free(&mut r.egui_renderer, &unused);
        let errors = r.gpu.take_errors();
        if !errors.is_empty() {
            return Err(aograph_graph::GraphError::Device {
                during: "drawing the viewer's frame",
                message: errors.join("; "),
            }
            .into());
        }
        Ok(())
    }

    fn input(r: &mut Running, event: &WindowEvent, consumed: bool) {
        match event {
            WindowEvent::KeyboardInput { event, .. } if !consumed => {
                let down = event.state == ElementState::Pressed;
                let PhysicalKey::Code(code) = event.physical_key else {
                    return;
                };
                let k = &mut r.keys;
                match code {
                    KeyCode::KeyW => k.forward = down,
                    KeyCode::KeyS => k.back = down,
                    KeyCode::KeyA => k.left = down,
                    KeyCode::KeyD => k.right = down,
                    KeyCode::KeyE => k.up = down,
                    KeyCode::KeyQ => k.down = down,
                    KeyCode::KeyR if down => r.session.camera.reset(),
                    KeyCode::KeyF if down => {
                        r.session.camera.mode = match r.session.camera.mode {
                            CameraMode::Orbit => CameraMode::Fly,
                            CameraMode::Fly => CameraMode::Orbit,
                        }
                    }
                    _ => {}
                }
            }
            WindowEvent::MouseInput {
                state,
                button: MouseButton::Left | MouseButton::Right,
                ..
            } => r.dragging = *state == ElementState::Pressed && !consumed,
            WindowEvent::CursorMoved { position, .. } => {
                if let (true, Some((x, y))) = (r.dragging, r.cursor) {
                    r.session
                        .camera
                        .drag((position.x - x) as f32, (position.y - y) as f32);
                }
                r.cursor = Some((position.x, position.y));
            }
            WindowEvent::MouseWheel { delta, .. } if !consumed => {
                let steps = match delta {
                    MouseScrollDelta::LineDelta(_, y) => *y,
                    MouseScrollDelta::PixelDelta(p) => p.y as f32 / 40.0,
                };
                r.session.camera.scroll(steps);
            }
            WindowEvent::DroppedFile(path) => {
                let label = path.display().to_string();
                let result = r.session.load_scene(SceneSource::File(path.clone()));
                r.panel.scene_path = label.clone();
                r.panel.report(result.map(|_| format!("opened {label}")));
            }
            _ => {}
        }
    }
}

/// Writes the window's texture to `path` as a PNG (BGRA surfaces swapped to RGBA).
fn window_screenshot(
    gpu: &GpuContext,
    texture: &wgpu::Texture,
    path: &std::path::Path,
) -> AppResult<()> {
    if !texture.usage().contains(wgpu::TextureUsages::COPY_SRC) {
        return Err(AppError::InvalidArgument {
            name: "window-screenshot".into(),
            value: "the window's surface cannot be copied on this device".into(),
            allowed: "`screenshot`, which saves the picture without the panel".into(),
        });
    }
    let mut bytes = aograph_graph::read_texture(&gpu.device, &gpu.queue, texture, 0)?.bytes;
    if matches!(
        texture.format(),
        wgpu::TextureFormat::Bgra8Unorm | wgpu::TextureFormat::Bgra8UnormSrgb
    ) {
        for px in bytes.chunks_exact_mut(4) {
            px.swap(0, 2);
        }
    }
    for px in bytes.chunks_exact_mut(4) {
        px[3] = 255;
    }
    aograph_bench::images::write_rgba_png(path, texture.width(), texture.height(), &bytes)
}

/// Frees the egui textures a frame no longer needs.
fn free(renderer: &mut egui_wgpu::Renderer, ids: &[egui::TextureId]) {
    for id in ids {
        renderer.free_texture(id);
    }
}

impl ApplicationHandler for ViewerApp {
    fn resumed(&mut self, el: &ActiveEventLoop) {
        if self.running.is_some() {
            return;
        }
        match self.start(el) {
            Ok(r) => {
                r.window.request_redraw();
                self.running = Some(r);
            }
            Err(e) => self.fail(el, e),
        }
    }

    fn window_event(&mut self, el: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let Some(r) = self.running.as_mut() else {
            return;
        };
        let response = r.egui_state.on_window_event(&r.window, &event);
        match &event {
            WindowEvent::CloseRequested => el.exit(),
            WindowEvent::Resized(size) => {
                r.surface_config.width = size.width.max(1);
                r.surface_config.height = size.height.max(1);
                r.surface.configure(&r.gpu.device, &r.surface_config);
            }
            WindowEvent::RedrawRequested => {
                if let Err(e) = self.redraw(el) {
                    self.fail(el, e);
                }
            }
            _ => Self::input(r, &event, response.consumed),
        }
    }

    fn about_to_wait(&mut self, _el: &ActiveEventLoop) {
        if let Some(r) = &self.running {
            r.window.request_redraw();
        }
    }
}
