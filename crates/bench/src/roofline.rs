//! The roofline of a bench run: the device's own peaks, measured in the same run, and every
//! pass's achieved share of them.
//!
//! - Load peak: a compute kernel whose every thread loads the 7x7 neighbourhood of its pixel
//!   (shaders/bench/load_peak.wgsl) over a 1024x1024 R32Float texture: texel loads per second.
//! - Byte peak: a texture-to-texture copy of a 1024x1024 Rgba32Float (16 MiB read, 16 MiB
//!   written): bytes per second.
//!
//! Each pass's loads come from what it declares (`PassBuilder::loads_per_invocation`, per its
//! parameters) times its invocations, its bytes from the textures it reads and writes
//! (`aograph_graph::pass_costs`); divided by its median time they give its rates, and the
//! rates over the peaks its fractions. A pass far under both peaks is slow, not costly.
//!
//! Invariant: peaks and passes are timed the same way in the same run (`renderer::timing_mode`:
//! GPU timestamps on a GPU, CPU wall time per pass on a software device), so the fractions are
//! ratios of like quantities, meaningful on lavapipe too.

use std::sync::Arc;

use aograph_graph::{
    CompileOptions, Executor, Extent, GpuContext, GraphBuilder, PassCost, SizeClass, TextureDesc,
    compile,
};
use serde::{Deserialize, Serialize};

use crate::stats::PassTime;
use aograph_app_config::error::AppResult;

/// Loads each thread of the peak kernel makes.
pub const PEAK_LOADS_PER_THREAD: f32 = 49.0;
/// Side of the peak kernel's and the copy's textures.
pub const PEAK_SIDE: u32 = 1024;

/// The device's peaks, measured in the run.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct DevicePeaks {
    /// Texel loads per second (the load-bound kernel).
    pub loads_per_s: f64,
    /// Bytes per second (read + written, the copy).
    pub bytes_per_s: f64,
}

/// One pass's place under the peaks.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PassRoofline {
    /// The pass's name in the render graph.
    pub pass: String,
    /// Its median time over the measured frames, in ms.
    pub ms: f64,
    /// Invocations per frame: threads of a compute pass, fragments of a full-screen pass (0 for
    /// copies and custom passes).
    pub invocations: u64,
    /// Declared loads per invocation.
    pub loads_per_invocation: Option<f32>,
    /// Bytes of the textures the pass reads and writes per frame, each counted once (a lower
    /// bound of its memory traffic).
    pub bytes: u64,
    /// Achieved texel loads per second: declared loads x invocations over the median time;
    /// `None` when the pass declares no loads.
    pub loads_per_s: Option<f64>,
    /// `loads_per_s` over the device's load peak (1 = at the peak); `None` when the pass
    /// declares no loads.
    pub load_fraction: Option<f64>,
    /// Achieved bytes per second: `bytes` over the median time.
    pub bytes_per_s: f64,
    /// `bytes_per_s` over the device's byte peak (1 = at the peak).
    pub byte_fraction: f64,
}

impl PassRoofline {
    /// The larger of the two fractions: how close the pass is to the limit that binds it.
    pub fn bound_fraction(&self) -> f64 {
        self.load_fraction.unwrap_or(0.0).max(self.byte_fraction)
    }
}

/// Measures the peaks: median of 7 timed frames after 2 warm-up frames.
pub fn measure_peaks(gpu: &Arc<GpuContext>) -> AppResult<DevicePeaks> {
    let shaders = aograph_renderer::shader_library();
    shaders.mount(crate::shader_mount())?;
    let side = Extent::new(PEAK_SIDE, PEAK_SIDE);
    let mut b = GraphBuilder::new();
    let src = b.import_texture(
        "peak.src",
        TextureDesc::new(wgpu::TextureFormat::R32Float, SizeClass::FULL),
    );
    let out = b.create_texture(
        "peak.out",
        TextureDesc::new(wgpu::TextureFormat::R32Float, SizeClass::FULL),
    );
    let mut p = b.compute_pass("peak.loads", "bench/load_peak.wgsl", "main");
    p.sample("src", src)
        .loads_per_invocation(PEAK_LOADS_PER_THREAD);
    let out = p.write_storage("dst", out);
    p.dispatch_over(out);
    b.export(out);
    let wide = TextureDesc::new(wgpu::TextureFormat::Rgba32Float, SizeClass::FULL);
    let copy_src = b.import_texture("peak.copy_src", wide);
    let copy_dst = b.create_texture("peak.copy_dst", wide);
    let copied = b.copy_pass("peak.copy", copy_src, copy_dst);
    b.export(copied);
    let plan = Arc::new(compile(b.build(), &shaders, CompileOptions::default())?);
    let mut exec = Executor::with_shaders(gpu.clone(), shaders);
    exec.set_timing(aograph_renderer::renderer::timing_mode(gpu)?)?;
    let texture = |format, usage| {
        aograph_graph::plain_texture(
            &gpu.device,
            "peak input",
            (PEAK_SIDE, PEAK_SIDE),
            format,
            usage,
        )
    };
    use wgpu::TextureUsages as U;
    let src_texture = texture(
        wgpu::TextureFormat::R32Float,
        U::TEXTURE_BINDING | U::COPY_DST,
    );
    let ones: Vec<f32> = vec![1.0; (PEAK_SIDE * PEAK_SIDE) as usize];
    gpu.queue.write_texture(
        src_texture.as_image_copy(),
        bytemuck::cast_slice(&ones),
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(PEAK_SIDE * 4),
            rows_per_image: None,
        },
        src_texture.size(),
    );
    exec.import_texture("peak.src", src_texture);
    exec.import_texture(
        "peak.copy_src",
        texture(wgpu::TextureFormat::Rgba32Float, U::COPY_SRC),
    );
    let (mut loads_ms, mut copy_ms) = (Vec::new(), Vec::new());
    for frame in 0..9 {
        exec.execute(&plan, side)?;
        let t = exec.wait_timings()?;
        if frame >= 2 {
            loads_ms.extend(t.get("peak.loads"));
            copy_ms.extend(t.get("peak.copy"));
        }
    }
    let median = |mut v: Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v.get(v.len() / 2).copied().unwrap_or(f64::NAN)
    };
    let pixels = side.pixels() as f64;
    Ok(DevicePeaks {
        loads_per_s: PEAK_LOADS_PER_THREAD as f64 * pixels / (median(loads_ms) / 1000.0),
        bytes_per_s: 2.0 * 16.0 * pixels / (median(copy_ms) / 1000.0),
    })
}

/// Every pass of a run under the peaks: its median time from `times`, its cost from `costs`.
pub fn passes_under(
    peaks: &DevicePeaks,
    costs: &[PassCost],
    times: &[PassTime],
) -> Vec<PassRoofline> {
    costs
        .iter()
        .filter_map(|c| {
            let ms = times.iter().find(|t| t.name == c.pass)?.ms.median;
            let seconds = (ms / 1000.0).max(1e-12);
            let loads_per_s = c.loads().map(|l| l / seconds);
            let bytes_per_s = c.bytes() as f64 / seconds;
            Some(PassRoofline {
                pass: c.pass.clone(),
                ms,
                invocations: c.invocations,
                loads_per_invocation: c.loads_per_invocation,
                bytes: c.bytes(),
                loads_per_s,
                load_fraction: loads_per_s.map(|l| l / peaks.loads_per_s),
                bytes_per_s,
                byte_fraction: bytes_per_s / peaks.bytes_per_s,
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stats::Spread;

    #[test]
    fn fractions_are_rates_over_peaks() {
        let peaks = DevicePeaks {
            loads_per_s: 1e9,
            bytes_per_s: 4e9,
        };
        let cost = PassCost {
            pass: "blur".into(),
            invocations: 1000,
            loads_per_invocation: Some(5.0),
            bytes_read: 4000,
            bytes_written: 4000,
        };
        let time = PassTime {
            name: "blur".into(),
            ms: Spread::of(&[0.01]),
        };
        let r = &passes_under(&peaks, &[cost], &[time])[0];
        // 5,000 loads in 10 us: 5e8 loads/s, half the peak; 8,000 bytes: 8e8 B/s, a fifth.
        assert!((r.loads_per_s.unwrap() - 5e8).abs() < 1.0);
        assert!((r.load_fraction.unwrap() - 0.5).abs() < 1e-9);
        assert!((r.byte_fraction - 0.2).abs() < 1e-9);
        assert!((r.bound_fraction() - 0.5).abs() < 1e-9);
    }
}
