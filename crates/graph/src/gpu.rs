//! The wgpu device the graph executes on, and how to get one.
//!
//! Only the Vulkan backend is compiled in (a real GPU or Mesa's lavapipe). Optional features
//! (timestamps, filterable 32-bit floats, adapter-specific storage formats, ray queries) are
//! requested when the adapter has them. Ray queries (`EXPERIMENTAL_RAY_QUERY`: acceleration
//! structures and WGSL's `ray_query`) are one of wgpu's experimental features, which a device
//! must opt into; aograph opts in only when the adapter offers them, and uses them only in the
//! hardware ray tracer (`aograph_tracing::gpu::hardware`). Validation errors raised outside an error scope are collected, so a
//! test can assert that a whole run produced none.

use std::sync::{Arc, Mutex};

use crate::error::{GraphError, GraphResult};

/// Device, queue and what they can do.
pub struct GpuContext {
    /// The adapter the device was made on (format support is asked of it).
    pub adapter: wgpu::Adapter,
    /// The device every plan records on.
    pub device: wgpu::Device,
    /// The device's queue, which frames are submitted to.
    pub queue: wgpu::Queue,
    /// The adapter's name, backend, device type and driver.
    pub info: wgpu::AdapterInfo,
    /// Features enabled on the device: the optional ones the adapter had, or the
    /// application's own with [`GpuContext::from_device`].
    pub features: wgpu::Features,
    errors: Arc<Mutex<Vec<String>>>,
    debug_groups: bool,
}

impl GpuContext {
    /// The first Vulkan adapter, or [`GraphError::NoAdapter`] with the fix.
    pub fn new() -> GraphResult<Self> {
        let instance = Self::instance();
        pollster::block_on(Self::new_async(&instance, None))
    }

    /// A device on an adapter that can present to `target` (a window), and the surface.
    pub fn with_surface(
        target: impl Into<wgpu::SurfaceTarget<'static>>,
    ) -> GraphResult<(Self, wgpu::Surface<'static>)> {
        let instance = Self::instance();
        let surface = instance
            .create_surface(target)
            .map_err(|e| GraphError::NoAdapter {
                detail: format!("cannot create a surface for the window: {e}"),
            })?;
        let gpu = pollster::block_on(Self::new_async(&instance, Some(&surface)))?;
        Ok((gpu, surface))
    }

    fn instance() -> wgpu::Instance {
        let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
        desc.backends = wgpu::Backends::VULKAN;
        desc.flags = wgpu::InstanceFlags::from_env_or_default();
        wgpu::Instance::new(desc)
    }

    async fn new_async(
        instance: &wgpu::Instance,
        surface: Option<&wgpu::Surface<'static>>,
    ) -> GraphResult<Self> {
        let adapter = instance
            .request_adapter(&wgpu::RequestAdapterOptions {
                power_preference: wgpu::PowerPreference::HighPerformance,
                force_fallback_adapter: false,
                compatible_surface: surface,
                ..Default::default()
            })
            .await
            .map_err(|e| GraphError::NoAdapter {
                detail: e.to_string(),
            })?;
        let wanted = wgpu::Features::TIMESTAMP_QUERY
            | wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS
            | wgpu::Features::FLOAT32_FILTERABLE
            | wgpu::Features::TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES
            | wgpu::Features::CLEAR_TEXTURE
            | wgpu::Features::EXPERIMENTAL_RAY_QUERY;
        let features = adapter.features() & wanted;
        let experimental_features = if features.contains(wgpu::Features::EXPERIMENTAL_RAY_QUERY) {
            // SAFETY: wgpu asks a device to opt into features it marks experimental. The only
            // experimental feature requested is ray queries, which only the hardware tracer
            // uses (acceleration structures built from validated scene geometry, read by ray
            // queries in compute shaders); nothing else changes with the opt-in.
            unsafe { wgpu::ExperimentalFeatures::enabled() }
        } else {
            wgpu::ExperimentalFeatures::disabled()
        };
        let mut limits = wgpu::Limits::default().using_resolution(adapter.limits());
        // A full g-buffer (positions, normals, albedo, direct light, linear depth, motion: 52
        // bytes per sample by WebGPU's cost table) exceeds the default limit of 32; use what
        // the adapter supports.
        limits.max_color_attachment_bytes_per_sample = limits
            .max_color_attachment_bytes_per_sample
            .max(adapter.limits().max_color_attachment_bytes_per_sample);
        if features.contains(wgpu::Features::EXPERIMENTAL_RAY_QUERY) {
            // Acceleration structures' limits are 0 unless asked for: the adapter's own.
            limits = limits.using_acceleration_structure_values(adapter.limits());
        }
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("aograph"),
                required_features: features,
                required_limits: limits,
                experimental_features,
                ..Default::default()
            })
            .await
            .map_err(|e| GraphError::NoAdapter {
                detail: format!("the adapter refused a device: {e}"),
            })?;
        let errors: Arc<Mutex<Vec<String>>> = Arc::default();
        let sink = errors.clone();
        device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
            if let Ok(mut v) = sink.lock() {
                v.push(e.to_string());
            }
        }));
        let info = adapter.get_info();
        let debug_groups = debug_groups_on(&info);
        Ok(Self {
            adapter,
            device,
            queue,
            info,
            features,
            errors,
            debug_groups,
        })
    }

    /// A context over an application's own adapter, device and queue (the embedding API): the
    /// device keeps the features and limits the application requested, and its uncaptured
    /// errors keep going to the application's handler (`take_errors` then reports none;
    /// aograph installs no handler on a device it did not create).
    pub fn from_device(adapter: wgpu::Adapter, device: wgpu::Device, queue: wgpu::Queue) -> Self {
        let info = adapter.get_info();
        let features = device.features();
        let debug_groups = debug_groups_on(&info);
        Self {
            adapter,
            device,
            queue,
            info,
            features,
            errors: Arc::default(),
            debug_groups,
        }
    }

    /// True when the device can build acceleration structures and run ray queries (wgpu's
    /// `EXPERIMENTAL_RAY_QUERY`: hardware ray tracing, or lavapipe from Mesa 24.1).
    pub fn has_ray_queries(&self) -> bool {
        self.features
            .contains(wgpu::Features::EXPERIMENTAL_RAY_QUERY)
    }

    /// True when textures of `format` can have `usage` on this device: the adapter's own
    /// format features where the device enabled `TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES`,
    /// WebGPU's guaranteed ones otherwise. Storage usage also needs write-only storage access
    /// (R16Float storage, for instance, is not core WebGPU: most Vulkan devices have it).
    pub fn supports(&self, format: wgpu::TextureFormat, usage: wgpu::TextureUsages) -> bool {
        let f = self.format_features(format);
        let storage_ok = !usage.contains(wgpu::TextureUsages::STORAGE_BINDING)
            || f.flags
                .contains(wgpu::TextureFormatFeatureFlags::STORAGE_WRITE_ONLY);
        f.allowed_usages.contains(usage) && storage_ok
    }

    /// What textures of `format` can do on this device: the adapter's own format features
    /// where the device enabled `TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES`, WebGPU's
    /// guaranteed ones otherwise.
    pub fn format_features(&self, format: wgpu::TextureFormat) -> wgpu::TextureFormatFeatures {
        if self
            .features
            .contains(wgpu::Features::TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES)
        {
            self.adapter.get_texture_format_features(format)
        } else {
            format.guaranteed_format_features(self.features)
        }
    }

    /// True when passes can be timed with GPU timestamps: written between commands where the
    /// device also has `TIMESTAMP_QUERY_INSIDE_ENCODERS`, at each compute or full-screen
    /// pass's own boundaries otherwise (WebGPU's `timestamp-query`, where copies and custom
    /// passes read 0).
    pub fn has_timestamps(&self) -> bool {
        self.features.contains(wgpu::Features::TIMESTAMP_QUERY)
    }

    /// Whether passes are wrapped in debug groups. Mesa's lavapipe (llvmpipe driver, as in
    /// Debian 12's Mesa 22.3) crashes in `vkCmdBeginDebugUtilsLabelEXT` once a render pass has
    /// been recorded, so there passes are labelled only through their own descriptors.
    /// `AOGRAPH_DEBUG_GROUPS=1` forces them on. Decided once, when the context is made.
    pub fn debug_groups(&self) -> bool {
        self.debug_groups
    }

    /// True on a CPU (software) device such as lavapipe: its times are CPU times.
    pub fn is_software(&self) -> bool {
        self.info.device_type == wgpu::DeviceType::Cpu
    }

    /// "name (backend, device type)".
    pub fn describe(&self) -> String {
        format!(
            "{} ({:?}, {:?})",
            self.info.name, self.info.backend, self.info.device_type
        )
    }

    /// Validation errors collected since the last call.
    pub fn take_errors(&self) -> Vec<String> {
        self.errors
            .lock()
            .map(|mut v| std::mem::take(&mut *v))
            .unwrap_or_default()
    }

    /// Blocks until the GPU has finished all submitted work.
    pub fn wait_idle(&self) -> GraphResult<()> {
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map(|_| ())
            .map_err(|e| GraphError::ReadbackFailed {
                during: "waiting for submitted work",
                message: e.to_string(),
            })
    }
}

/// Whether a device of `info` gets debug groups (see [`GpuContext::debug_groups`]).
fn debug_groups_on(info: &wgpu::AdapterInfo) -> bool {
    std::env::var_os("AOGRAPH_DEBUG_GROUPS").is_some_and(|v| v == "1")
        || !info.driver.to_ascii_lowercase().contains("llvmpipe")
}

/// For tests: a device, `None` (with a printed reason) when there is none and
/// `AOGRAPH_REQUIRE_GPU` is unset; an error when it is set, so CI cannot skip GPU tests.
pub fn test_gpu() -> Option<Arc<GpuContext>> {
    static GPU: std::sync::OnceLock<Result<Arc<GpuContext>, GraphError>> =
        std::sync::OnceLock::new();
    match GPU.get_or_init(|| GpuContext::new().map(Arc::new)) {
        Ok(g) => Some(g.clone()),
        Err(e) => {
            if std::env::var_os("AOGRAPH_REQUIRE_GPU").is_some_and(|v| v != "0") {
                panic!("AOGRAPH_REQUIRE_GPU is set but no GPU device is available: {e}");
            }
            eprintln!(
                "SKIPPED: GPU test skipped, no adapter ({e}); set AOGRAPH_REQUIRE_GPU=1 to make this an error"
            );
            None
        }
    }
}
