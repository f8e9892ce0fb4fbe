//! Pyramid HBAO's march reaches s0 xi S (K^L - 1) / (K - 1) pixels with L levels (Eq. 8: the
//! step multiplied by K = 3 per level), measured on the GPU: a flat floor facing an
//! orthographic camera meets a raised step at a known column, and the farthest pixel of a row
//! whose AO sees the step is the march's longest reach over that row's directions.
//!
//! With S = 4 reads per level, s0 = 1 px and L = 3, the reach is 52 xi px for the start-step
//! multiplier xi in [0.5, 1.5) of each direction (§2.5): the farthest pixel that sees the step
//! is at least 52 px away (some of a row's many forward directions has xi cos(theta) >= 1)
//! and at most 78 px, plus one level-2 texel (9 px) of the 3x3-mean pyramid, whose texel
//! straddling the edge is already raised. A march whose step grew x2 per level reaches at
//! most 1.5 x 4 x 7 = 42 px (+ 9); x4, 126 px: both fail.

mod common;

use aograph_embed::{AmbientOcclusion, AoInputs, DepthInput};
use aograph_graph::test_gpu;
use glam::Mat4;

/// Odd and not square.
const W: u32 = 181;
const H: u32 = 61;
/// The step's first column.
const WALL: u32 = 150;
/// World units per pixel, the floor's and the step's linear depth.
const PIXEL: f32 = 0.01;
const FLOOR: f32 = 10.0;
const STEP: f32 = 9.5;

#[test]
fn the_march_reaches_s0_xi_s_k_to_the_l_minus_1_over_k_minus_1_pixels() {
    let Some(gpu) = test_gpu() else { return };
    let depth: Vec<f32> = (0..H)
        .flat_map(|_| (0..W).map(|x| if x >= WALL { STEP } else { FLOOR }))
        .collect();
    let bytes: Vec<u8> = depth.iter().flat_map(|d| d.to_le_bytes()).collect();
    let texture = common::user_frame::upload(
        &gpu.device,
        &gpu.queue,
        wgpu::TextureFormat::R32Float,
        (W, H),
        &bytes,
    );
    let (hw, hh) = (W as f32 * PIXEL / 2.0, H as f32 * PIXEL / 2.0);
    let projection = Mat4::orthographic_rh(-hw, hw, -hh, hh, 0.1, 100.0);
    // R far beyond the row (W(r) ~ 1, and the march never ends on R); no blur, so a pixel's
    // AO is its own directions' only.
    let config = common::ao_config(
        "pyramid-hbao",
        10.0,
        "levels = 3\ndirections = 32\nstep_count = 4\ninitial_step = 1.0\nblur = false",
    );
    let mut ao = AmbientOcclusion::new(&gpu.adapter, &gpu.device, &gpu.queue, &config).unwrap();
    ao.set_output_format(aograph_embed::AoOutputFormat::R32Float);
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    let out = ao
        .encode(
            &mut encoder,
            &AoInputs::new(DepthInput::Linear(&texture), projection, Mat4::IDENTITY),
        )
        .unwrap();
    gpu.queue.submit([encoder.finish()]);
    let values = aograph_graph::read_texture(&gpu.device, &gpu.queue, &out.texture, 0)
        .unwrap()
        .channel(0)
        .unwrap();
    // The farthest floor pixel, over the middle rows, whose AO the step lowers.
    let mut farthest = 0.0f32;
    for y in H / 3..2 * H / 3 {
        for x in 0..WALL {
            let a = values[(y * W + x) as usize];
            // One direction of 32 seeing the step at W sin(alpha) >= 0.3 lowers AO by 0.009.
            if a < 0.999 {
                farthest = farthest.max(WALL as f32 - (x as f32 + 0.5));
            }
        }
    }
    let s = 4.0 * (27.0 - 1.0) / (3.0 - 1.0); // s0 S (K^L - 1) / (K - 1) = 52 px
    println!(
        "the farthest pixel that sees the step is {farthest} px away; s0 S (K^L-1)/(K-1) = {s}"
    );
    assert!(
        (s..=1.5 * s + 9.0).contains(&farthest),
        "the march reaches {farthest} px; with K = 3 per level it reaches {s} xi px, xi in [0.5, 1.5) \
         (allowed {s} to {})",
        1.5 * s + 9.0
    );
    // Far from the step, the flat floor is unoccluded.
    assert!(values[(H / 2 * W + 5) as usize] > 0.9999);
}
