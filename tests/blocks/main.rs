//! The shared AO blocks on the GPU: each runs on a known image (imported R32Float textures)
//! and is compared with a CPU computation of the same arithmetic: the 3x3-average pyramid
//! exactly on integer data, min/max exactly, blurs of constants and impulses, edge-stopping of
//! the bilateral filters, XeGTAO's depth prefilter and edge-aware denoiser against CPU mirrors.
//! Skips (saying so) only without an adapter and AOGRAPH_REQUIRE_GPU.
//!
//! Files: the rig (imported textures, one block's graph, CPU helpers) is here; `pyramids.rs`
//! (the 3x3-average and min/max pyramids, XeGTAO's depth prefilter), `blurs.rs` (Gaussian,
//! bilateral, upsample), `denoise.rs` (XeGTAO's edge-aware denoiser).

#[path = "../common/mod.rs"]
mod common;

mod blurs;
mod denoise;
mod pyramids;

use std::sync::Arc;

use aograph_ao_passes::blocks::*;
use aograph_graph::{
    CompileOptions, Executor, Extent, GraphBuilder, SizeClass, TextureDesc, TextureHandle, compile,
    test_gpu,
};
use wgpu::TextureFormat::R32Float;

/// An imported texture: name, size, format (R32Float or Rgba32Float) and texels.
struct Input {
    name: &'static str,
    size: Extent,
    format: wgpu::TextureFormat,
    data: Vec<f32>,
}

fn r32(name: &'static str, w: u32, h: u32, data: Vec<f32>) -> Input {
    assert_eq!(data.len(), (w * h) as usize);
    Input {
        name,
        size: Extent::new(w, h),
        format: R32Float,
        data,
    }
}

/// Declares `inputs` (with the given size classes), lets `declare` add the block, runs one frame
/// at `output` and reads back every returned handle.
fn run(
    output: Extent,
    inputs: &[(&Input, SizeClass)],
    declare: impl FnOnce(&mut GraphBuilder, &[TextureHandle]) -> Vec<TextureHandle>,
) -> Option<Vec<Vec<f32>>> {
    let gpu = test_gpu()?;
    let mut b = GraphBuilder::new();
    let handles: Vec<TextureHandle> = inputs
        .iter()
        .map(|(i, s)| b.import_texture(i.name, TextureDesc::new(i.format, *s)))
        .collect();
    let outs = declare(&mut b, &handles);
    outs.iter().for_each(|h| b.export(*h));
    let plan = Arc::new(
        compile(
            b.build(),
            &aograph::shader_library(),
            CompileOptions::default(),
        )
        .expect("block graph compiles"),
    );
    let mut exec = Executor::with_shaders(gpu.clone(), aograph::shader_library());
    for (i, _) in inputs {
        let tex = gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some(i.name),
            size: wgpu::Extent3d {
                width: i.size.width,
                height: i.size.height,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: i.format,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        });
        let bytes: Vec<u8> = if i.format == wgpu::TextureFormat::Rgba8Unorm {
            i.data.iter().map(|f| (f * 255.0).round() as u8).collect()
        } else {
            i.data.iter().flat_map(|f| f.to_le_bytes()).collect()
        };
        let row = i.size.width * i.format.block_copy_size(None).unwrap();
        gpu.queue.write_texture(
            tex.as_image_copy(),
            &bytes,
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(row),
                rows_per_image: None,
            },
            tex.size(),
        );
        exec.import_texture(i.name, tex);
    }
    exec.execute(&plan, output).expect("block graph runs");
    Some(
        outs.iter()
            .map(|h| exec.read_texture(&plan, *h).unwrap().channel(0).unwrap())
            .collect(),
    )
}

/// Deterministic pseudo-random values in [0, 1).
fn noise(n: usize, seed: u32) -> Vec<f32> {
    (0..n as u32)
        .map(|i| {
            ((i.wrapping_mul(2654435761) ^ seed.wrapping_mul(40503)).wrapping_mul(2246822519) >> 8)
                as f32
                / 16777216.0
        })
        .collect()
}

fn assert_close(got: &[f32], want: &[f32], tol: f32, what: &str) {
    assert_eq!(got.len(), want.len(), "{what}: length");
    for (i, (g, w)) in got.iter().zip(want).enumerate() {
        assert!(
            g.is_finite() && (g - w).abs() <= tol * w.abs().max(1.0),
            "{what}: texel {i}: got {g}, want {w}"
        );
    }
}

/// Level `l` of a `r` pyramid over `base`: centred for the 3x3 average, ceil-sized otherwise.
fn level_size(r: DepthReduction, base: Extent, l: u32) -> Extent {
    match r {
        DepthReduction::Average3x3 => centred_level_extent(base, 3, l),
        _ => level_extent(base, r.factor(), l),
    }
}
