//! What an engine's render world needs of the embedding: plans prepared ahead of the frame
//! that switches to them, and matrices from any maths library.

use std::time::Instant;

use aograph_embed::{AoInputs, AoOutputFormat, DepthInput, InputLayout};
use aograph_graph::test_gpu;

use super::*;

/// One frame of `inputs` into `ao`'s own output, recorded and submitted; the CPU time of
/// `encode` (what the render loop waits for) in milliseconds.
fn timed_frame(
    gpu: &aograph_graph::GpuContext,
    ao: &mut aograph_embed::AmbientOcclusion,
    inputs: &AoInputs<'_>,
) -> f64 {
    let mut enc = gpu.device.create_command_encoder(&Default::default());
    let started = Instant::now();
    ao.encode(&mut enc, inputs).unwrap();
    let ms = started.elapsed().as_secs_f64() * 1e3;
    gpu.queue.submit([enc.finish()]);
    ms
}

#[test]
pub(crate) fn a_prepared_plan_makes_the_switch_frame_create_no_pipeline() {
    let Some(gpu) = test_gpu() else { return };
    let (depth, proj, view, config) = plane_frame(&gpu);
    let inputs = AoInputs::new(DepthInput::Hardware(&depth), proj, view);
    let layout = InputLayout::of(&inputs).unwrap();
    // mssao and pyramid-hbao share no pass with gtao (the first frame's technique).
    let mssao = common::ao_config("mssao", 0.5, "levels = 3");
    let pyramid = common::ao_config("pyramid-hbao", 0.5, "levels = 3");

    let mut ao = embedding(&gpu, &config);
    timed_frame(&gpu, &mut ao, &inputs);
    // Unprepared: the switch frame builds the plan and its pipelines.
    let before = ao.pipelines_created();
    ao.set_config(&pyramid).unwrap();
    let unprepared_ms = timed_frame(&gpu, &mut ao, &inputs);
    let created_unprepared = ao.pipelines_created() - before;
    assert!(
        created_unprepared > 0,
        "an unseen technique creates its pipelines"
    );

    // Prepared from another thread while the frame loop is elsewhere: the switch frame
    // creates none. `AmbientOcclusion` is Send + Sync; the worker borrows it mutably.
    let layout_format = AoOutputFormat::default();
    assert!(!ao.is_prepared(&mssao, layout, layout_format));
    assert!(
        ao.is_prepared(&pyramid, layout, layout_format),
        "the frame ran it"
    );
    std::thread::scope(|s| {
        s.spawn(|| ao.prepare(&mssao, layout, layout_format).unwrap())
            .join()
            .unwrap()
    });
    assert!(ao.is_prepared(&mssao, layout, layout_format));
    assert!(
        !ao.is_prepared(&mssao, layout, AoOutputFormat::R32Float),
        "another output"
    );
    let before = ao.pipelines_created();
    let plans = ao.plan_count();
    ao.set_config(&mssao).unwrap();
    let prepared_ms = timed_frame(&gpu, &mut ao, &inputs);
    assert_eq!(
        ao.pipelines_created() - before,
        0,
        "the prepared plan's switch frame created pipelines"
    );
    assert_eq!(ao.plan_count(), plans, "the switch frame built a plan");
    println!(
        "switch frame's encode on the CPU: {unprepared_ms:.2} ms unprepared ({created_unprepared} \
         pipelines created), {prepared_ms:.2} ms prepared (0 created), {}x{}",
        SIZE.width, SIZE.height
    );
    assert!(gpu.take_errors().is_empty());
}

#[test]
pub(crate) fn matrices_as_column_arrays_give_the_glam_frame() {
    let Some(gpu) = test_gpu() else { return };
    let (depth, proj, view, config) = plane_frame(&gpu);
    let glam_inputs = AoInputs::new(DepthInput::Hardware(&depth), proj, view);
    let arrays = AoInputs::from_column_arrays(
        DepthInput::Hardware(&depth),
        proj.to_cols_array_2d(),
        view.to_cols_array_2d(),
    );
    assert_eq!((arrays.projection, arrays.view), (proj, view));
    // Rows for columns would be another matrix (the projection is not symmetric).
    let transposed = AoInputs::from_column_arrays(
        DepthInput::Hardware(&depth),
        proj.transpose().to_cols_array_2d(),
        view.to_cols_array_2d(),
    );
    assert_ne!(transposed.projection, proj);
    let mut ao = embedding(&gpu, &config);
    let a = embed_frame(&gpu, &mut ao, &glam_inputs).unwrap();
    ao.cut();
    let b = embed_frame(&gpu, &mut ao, &arrays).unwrap();
    assert_eq!(a, b);
}

/// `inner` (w x h values of `texel` bytes each) placed at (x, y) in a (pw x ph) image whose
/// other texels are `fill`: the application's larger render target around a view.
fn padded<T: Copy>(
    inner: &[T],
    (w, h): (u32, u32),
    (pw, ph): (u32, u32),
    (x, y): (u32, u32),
    fill: impl Fn(u32, u32) -> T,
) -> Vec<T> {
    let mut out = Vec::with_capacity((pw * ph) as usize);
    for py in 0..ph {
        for px in 0..pw {
            let inside = (x..x + w).contains(&px) && (y..y + h).contains(&py);
            out.push(if inside {
                inner[((py - y) * w + (px - x)) as usize]
            } else {
                fill(px, py)
            });
        }
    }
    out
}

#[test]
pub(crate) fn a_viewport_gives_the_ao_of_its_cropped_inputs() {
    let Some(gpu) = test_gpu() else { return };
    let scene = aograph_scene::procedural_scene("columns").unwrap();
    let radius = aograph_scene::suggested_radius(&scene).radius;
    // An odd corner in an odd, larger target; the rest of the target holds another picture
    // (near depth, sideways normals), which a dropped offset would read.
    let (pw, ph) = (SIZE.width + 13, SIZE.height + 8);
    let corner = (9, 5);
    let size = (SIZE.width, SIZE.height);
    let viewport = aograph_embed::Viewport {
        x: corner.0,
        y: corner.1,
        width: SIZE.width,
        height: SIZE.height,
    };
    let mut failures = Vec::new();
    // gtao from hardware depth and given normals; mssao from linear depth given as such (the
    // crop pass) with normals rebuilt from depth.
    for (technique, params, linear) in [("gtao", "", false), ("mssao", "levels = 3", true)] {
        let config = common::ao_config(technique, radius, params);
        let own = own_frame(&scene, &config, None).unwrap();
        let lin = padded(&own.linear_depth, size, (pw, ph), corner, |x, y| {
            0.5 + 0.01 * ((x * 7 + y * 3) % 11) as f32
        });
        let proj = perspective(&own.camera, own.camera.near(), None, true);
        let (cropped_depth, padded_depth) = if linear {
            let up = |v: &[f32], s| {
                let bytes: Vec<u8> = v.iter().flat_map(|f| f.to_le_bytes()).collect();
                crate::common::user_frame::upload(
                    &gpu.device,
                    &gpu.queue,
                    wgpu::TextureFormat::R32Float,
                    s,
                    &bytes,
                )
            };
            (up(&own.linear_depth, size), up(&lin, (pw, ph)))
        } else {
            let depth = |v: &[f32], s| {
                crate::common::user_frame::depth_buffer(
                    &gpu.device,
                    &gpu.queue,
                    v,
                    s,
                    proj,
                    true,
                    wgpu::TextureFormat::Depth32Float,
                )
            };
            (depth(&own.linear_depth, size), depth(&lin, (pw, ph)))
        };
        let wrap = |t| {
            if linear {
                DepthInput::Linear(t)
            } else {
                DepthInput::Hardware(t)
            }
        };
        // Normals: Rgba16Float texels (8 bytes), sideways outside the view.
        let texels: Vec<[u8; 8]> = own
            .normals_bytes
            .chunks(8)
            .map(|c| c.try_into().unwrap())
            .collect();
        let sideways = [0x00, 0x3c, 0, 0, 0, 0, 0x00, 0x3c]; // (1, 0, 0, 1) in f16
        let normal_bytes: Vec<u8> =
            padded(&texels, size, (pw, ph), corner, |_, _| sideways).concat();
        let cropped_normals = given_normals(&gpu, &own);
        let padded_normals = crate::common::user_frame::upload(
            &gpu.device,
            &gpu.queue,
            wgpu::TextureFormat::Rgba16Float,
            (pw, ph),
            &normal_bytes,
        );
        let normals = |t| aograph_embed::NormalsInput {
            texture: t,
            space: aograph_embed::NormalSpace::View,
            encoding: aograph_embed::NormalEncoding::Xyz,
        };

        let mut ao = embedding(&gpu, &config);
        let mut inputs = AoInputs::new(wrap(&cropped_depth), proj, own.view);
        inputs.normals = (!linear).then(|| normals(&cropped_normals));
        let expected = embed_frame(&gpu, &mut ao, &inputs).unwrap();

        let mut ao = embedding(&gpu, &config);
        let mut inputs = AoInputs::new(wrap(&padded_depth), proj, own.view);
        inputs.normals = (!linear).then(|| normals(&padded_normals));
        inputs.viewport = Some(viewport);
        let got = embed_frame(&gpu, &mut ao, &inputs).unwrap();
        let (d, at) = max_diff(&got, &expected);
        println!("{technique}: viewport against cropped inputs, largest difference {d:e} at {at}");
        // The same texels reach the technique either way; 1e-4 leaves room for nothing but
        // a driver's reordering of the same sums.
        if d > 1e-4 {
            failures.push(format!(
                "{technique}: the viewport's AO differs from the cropped inputs' by {d} at \
                 pixel {at} ({} vs {})",
                got[at], expected[at]
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert!(gpu.take_errors().is_empty());
}

#[test]
pub(crate) fn a_viewport_outside_the_inputs_is_a_named_error() {
    let Some(gpu) = test_gpu() else { return };
    let (depth, proj, view, config) = plane_frame(&gpu);
    let mut ao = embedding(&gpu, &config);
    for (x, y, width, height) in [(1, 0, SIZE.width, 4), (0, 0, 0, 4), (0, SIZE.height, 4, 1)] {
        let mut inputs = AoInputs::new(DepthInput::Hardware(&depth), proj, view);
        inputs.viewport = Some(aograph_embed::Viewport {
            x,
            y,
            width,
            height,
        });
        let e = embed_frame(&gpu, &mut ao, &inputs)
            .expect_err("outside the inputs")
            .to_string();
        assert!(
            e.contains("viewport") && e.contains(&format!("{}x{}", SIZE.width, SIZE.height)),
            "{e}"
        );
    }
}
