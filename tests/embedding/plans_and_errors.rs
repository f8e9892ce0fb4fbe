//! Wrong inputs are named errors; switching techniques and sizes reuses what was built; motion
//! vectors in pixels become the motion channel.

use crate::common::user_frame::{depth_buffer, upload};
use aograph_embed::{
    AmbientOcclusion, AoInputs, DepthInput, EmbedError, NormalEncoding, NormalSpace, NormalsInput,
};
use aograph_frame::GBufferChannel;
use aograph_graph::test_gpu;
use glam::{Mat4, Vec3};

use super::*;

#[test]
pub(crate) fn wrong_inputs_and_settings_are_named_errors() {
    let Some(gpu) = test_gpu() else { return };
    let (depth, proj, view, config) = plane_frame(&gpu);
    let mut ao = embedding(&gpu, &config);
    let size = (SIZE.width, SIZE.height);
    let rgba8 = upload(
        &gpu.device,
        &gpu.queue,
        wgpu::TextureFormat::Rgba8Unorm,
        size,
        &vec![0; (size.0 * size.1 * 4) as usize],
    );
    let small = upload(
        &gpu.device,
        &gpu.queue,
        wgpu::TextureFormat::Rgba16Float,
        (size.0 - 1, size.1),
        &vec![0; ((size.0 - 1) * size.1 * 8) as usize],
    );
    let r32 = upload(
        &gpu.device,
        &gpu.queue,
        wgpu::TextureFormat::R32Float,
        size,
        &vec![0; (size.0 * size.1 * 4) as usize],
    );
    let err = |r: Result<Vec<f32>, EmbedError>| r.expect_err("must be refused").to_string();

    let m = err(embed_frame(
        &gpu,
        &mut ao,
        &AoInputs::new(DepthInput::Hardware(&rgba8), proj, view),
    ));
    assert!(
        m.contains("Rgba8Unorm") && m.contains("Depth32Float, Depth24Plus or Depth16Unorm"),
        "{m}"
    );

    let m = err(embed_frame(
        &gpu,
        &mut ao,
        &AoInputs::new(DepthInput::Linear(&depth), proj, view),
    ));
    assert!(m.contains("linear depth") && m.contains("R32Float"), "{m}");

    let mut inputs = AoInputs::new(DepthInput::Hardware(&depth), proj, view);
    inputs.normals = Some(NormalsInput {
        texture: &small,
        space: NormalSpace::View,
        encoding: NormalEncoding::Xyz,
    });
    let m = err(embed_frame(&gpu, &mut ao, &inputs));
    assert!(m.contains("96x61") && m.contains("97x61"), "{m}");

    inputs.normals = Some(NormalsInput {
        texture: &r32,
        space: NormalSpace::View,
        encoding: NormalEncoding::Xyz,
    });
    let m = err(embed_frame(&gpu, &mut ao, &inputs));
    assert!(m.contains("normals") && m.contains("three channels"), "{m}");

    let lh = Mat4::perspective_lh(1.0, aspect(), 0.1, 100.0);
    let m = err(embed_frame(
        &gpu,
        &mut ao,
        &AoInputs::new(DepthInput::Hardware(&depth), lh, view),
    ));
    assert!(m.contains("left-handed"), "{m}");

    // The output: a format the pass cannot write, and a texture without RENDER_ATTACHMENT.
    let mut enc = gpu.device.create_command_encoder(&Default::default());
    let inputs = AoInputs::new(DepthInput::Hardware(&depth), proj, view);
    let m = ao
        .encode_into(&mut enc, &inputs, &rgba8)
        .unwrap_err()
        .to_string();
    assert!(
        m.contains("output") && m.contains("R8Unorm, R16Float or R32Float"),
        "{m}"
    );
    let m = ao
        .encode_into(&mut enc, &inputs, &r32)
        .unwrap_err()
        .to_string();
    assert!(m.contains("RENDER_ATTACHMENT"), "{m}");
    drop(enc);

    // Settings: "auto" radius, a technique that needs what an application's frame lacks, and
    // an unknown technique; each leaves the current settings in place.
    let mut auto = config.clone();
    auto.radius = aograph_ao_passes::RadiusSetting::Auto;
    let m = ao.set_config(&auto).unwrap_err().to_string();
    assert!(
        m.contains("radius") && m.contains("view matrix's units"),
        "{m}"
    );
    // Refused when chosen (`set_config`), not at the first frame.
    for (technique, needs) in [("rtao", "BVH"), ("ssdo", "albedo")] {
        let m = ao
            .set_config(&common::ao_config(technique, 0.5, ""))
            .unwrap_err()
            .to_string();
        assert!(
            m.contains(technique) && m.contains(needs),
            "{technique}: {m}"
        );
        // The techniques offered instead are those whose defaults read only what the
        // adapters make and trace no scene, asked of the registry.
        assert!(
            m.contains("(gtao, hbao, mssao, pyramid-hbao, ssao, tssao, vbao)"),
            "{technique}: {m}"
        );
    }
    let m = ao
        .set_config(&common::ao_config("gtao", 0.5, "multibounce = true"))
        .unwrap_err()
        .to_string();
    assert!(m.contains("multibounce = false"), "{m}");
    // A second depth layer is aograph's own g-buffer's; an application's depth holds one.
    for technique in ["gtao", "vbao"] {
        let m = ao
            .set_config(&common::ao_config(technique, 0.5, "layers = 2"))
            .unwrap_err()
            .to_string();
        assert!(
            m.contains("second_layer_depth") && m.contains("layers = 1"),
            "{technique}: {m}"
        );
    }
    let m = ao
        .set_config_toml("technique = \"gtoa\"\nradius = 0.5")
        .unwrap_err()
        .to_string();
    assert!(m.contains("gtao"), "the nearest name is suggested: {m}");
    // After all of that, a right frame still renders.
    ao.set_config(&config).unwrap();
    embed_frame(
        &gpu,
        &mut ao,
        &AoInputs::new(DepthInput::Hardware(&depth), proj, view),
    )
    .unwrap();
    assert!(gpu.take_errors().is_empty());
}

#[test]
pub(crate) fn switching_techniques_back_creates_no_pipeline() {
    let Some(gpu) = test_gpu() else { return };
    let (depth, proj, view, config) = plane_frame(&gpu);
    let mut ao = embedding(&gpu, &config);
    let inputs = AoInputs::new(DepthInput::Hardware(&depth), proj, view);
    let settings = [
        common::ao_config("gtao", 0.5, ""),
        common::ao_config("mssao", 0.5, "levels = 3"),
        common::ao_config("hbao", 0.5, "temporal = true"),
    ];
    let mut out = None;
    for s in &settings {
        ao.set_config(s).unwrap();
        let mut enc = gpu.device.create_command_encoder(&Default::default());
        out = Some(ao.encode(&mut enc, &inputs).unwrap());
        gpu.queue.submit([enc.finish()]);
    }
    let (pipelines, plans) = (ao.pipelines_created(), ao.plan_count());
    assert_eq!(plans, 3);
    for _ in 0..2 {
        for s in &settings {
            ao.set_config(s).unwrap();
            let mut enc = gpu.device.create_command_encoder(&Default::default());
            let o = ao.encode(&mut enc, &inputs).unwrap();
            gpu.queue.submit([enc.finish()]);
            // aograph's own output texture is the same one while the size and format stay.
            assert_eq!(Some(&o.texture), out.as_ref().map(|o| &o.texture));
        }
    }
    assert_eq!(
        ao.pipelines_created(),
        pipelines,
        "a switch back created pipelines"
    );
    assert_eq!(ao.plan_count(), plans);
    // A new output format is a new plan (and texture); going back to the old one is not.
    ao.set_output_format(aograph_embed::AoOutputFormat::R16Float);
    let mut enc = gpu.device.create_command_encoder(&Default::default());
    let o = ao.encode(&mut enc, &inputs).unwrap();
    gpu.queue.submit([enc.finish()]);
    assert_eq!(o.texture.format(), wgpu::TextureFormat::R16Float);
    assert_eq!(ao.plan_count(), plans + 1);
    assert!(gpu.take_errors().is_empty());
}

#[test]
pub(crate) fn motion_vectors_in_pixels_become_the_motion_channel() {
    let Some(gpu) = test_gpu() else { return };
    let scene = aograph_scene::procedural_scene("stairs").unwrap();
    let radius = aograph_scene::suggested_radius(&scene).radius;
    let own = own_frame(&scene, &common::ao_config("none", radius, ""), None).unwrap();
    let (depth, proj) = reversed_z_depth(&gpu, &own);
    let size = (SIZE.width, SIZE.height);
    // The camera moved 0.5 units forward since the previous frame: each point was 0.5 deeper.
    let prev_view = Mat4::from_translation(Vec3::new(0.0, 0.0, -0.5)) * own.view;
    let prev_view_proj = proj * prev_view;
    // Motion in pixels, current - previous (x, y) = (i mod 7 - 3, i mod 5 - 2): uv_scale
    // (-1/w, -1/h) turns it into aograph's previous - current in uv.
    let n = (size.0 * size.1) as usize;
    let m: Vec<[f32; 2]> = (0..n)
        .map(|i| [(i % 7) as f32 - 3.0, (i % 5) as f32 - 2.0])
        .collect();
    let motion = upload(
        &gpu.device,
        &gpu.queue,
        wgpu::TextureFormat::Rg32Float,
        size,
        bytemuck::cast_slice(&m),
    );
    let scale = [-1.0 / size.0 as f32, -1.0 / size.1 as f32];
    let mut inputs = AoInputs::new(DepthInput::Hardware(&depth), proj, own.view);
    inputs.motion = Some(aograph_embed::MotionInput {
        texture: &motion,
        uv_scale: scale,
    });
    let got = adapter_channel(&gpu, &inputs, GBufferChannel::Motion, prev_view_proj)
        .to_f32()
        .unwrap();
    let mut worst: f32 = 0.0;
    for i in 0..n {
        let (g, z) = (&got[i * 4..i * 4 + 4], own.linear_depth[i]);
        if z <= 0.0 {
            assert_eq!(g, [0.0; 4], "sky at pixel {i}");
            continue;
        }
        assert_eq!(
            [g[0], g[1]],
            [m[i][0] * scale[0], m[i][1] * scale[1]],
            "pixel {i}"
        );
        worst = worst.max((g[2] - (z + 0.5)).abs() / z);
    }
    // The previous depth through view_to_prev_clip: f32 products of a few matrices.
    println!("previous depth: largest relative error {worst:.2e}");
    assert!(worst < 1e-5, "previous depth off by {worst} relative");
}

#[test]
pub(crate) fn a_resize_builds_a_plan_for_the_new_size_and_going_back_builds_nothing() {
    let Some(gpu) = test_gpu() else { return };
    let (depth, proj, view, config) = plane_frame(&gpu);
    let scene = aograph_scene::procedural_scene("plane").unwrap();
    let camera = scene.camera_at(0.0);
    // The same view at 64x48 (another aspect: its own projection).
    let small_proj =
        Mat4::perspective_infinite_reverse_rh(camera.fov_y().unwrap(), 64.0 / 48.0, camera.near());
    let small = depth_buffer(
        &gpu.device,
        &gpu.queue,
        &vec![5.0f32; 64 * 48],
        (64, 48),
        small_proj,
        true,
        wgpu::TextureFormat::Depth32Float,
    );
    let mut ao = embedding(&gpu, &config);
    let frame = |ao: &mut AmbientOcclusion, depth: &wgpu::Texture, proj: Mat4| {
        let mut enc = gpu.device.create_command_encoder(&Default::default());
        let out = ao
            .encode(
                &mut enc,
                &AoInputs::new(DepthInput::Hardware(depth), proj, view),
            )
            .unwrap();
        gpu.queue.submit([enc.finish()]);
        let ao_values = aograph_graph::read_texture(&gpu.device, &gpu.queue, &out.texture, 0)
            .unwrap()
            .bytes;
        (out.texture.width(), out.texture.height(), ao_values)
    };
    let (w, h, full) = frame(&mut ao, &depth, proj);
    assert_eq!((w, h), (SIZE.width, SIZE.height));
    let (w, h, resized) = frame(&mut ao, &small, small_proj);
    assert_eq!((w, h, resized.len()), (64, 48, 64 * 48));
    let (_, _, again) = frame(&mut ao, &depth, proj);
    // A plane facing the camera at one depth is unoccluded at any size.
    assert!(full.iter().chain(&resized).chain(&again).all(|&a| a == 255));
    assert_eq!(ao.plan_count(), 2, "one plan per size, kept");
    let pipelines = ao.pipelines_created();
    frame(&mut ao, &small, small_proj);
    frame(&mut ao, &depth, proj);
    assert_eq!(ao.pipelines_created(), pipelines);
    assert!(gpu.take_errors().is_empty());
}

#[test]
pub(crate) fn settings_are_checked_without_a_device_as_from_toml_would_check_them() {
    let gtao = aograph_embed::check_settings_toml(
        "technique = \"gtao\"\nradius = 0.5\n[gtao]\nslices = 3",
    )
    .unwrap();
    assert_eq!(
        (
            gtao.technique.as_str(),
            gtao.params["gtao"]["slices"].as_integer()
        ),
        ("gtao", Some(3))
    );
    for (text, named) in [
        ("technique = \"gtoa\"\nradius = 0.5", "gtoa"),
        ("technique = \"gtao\"\nradius = -1", "radius"),
        ("technique = \"gtao\"\nradius = \"auto\"", "radius"),
        (
            "technique = \"gtao\"\nradius = 0.5\n[gtao]\nslices = 0",
            "slices",
        ),
        // rtao traces the scene's triangles, which an application's frame does not carry.
        ("technique = \"rtao\"\nradius = 0.5", "rtao"),
        ("technique = \"gtao\"\nradius = [", "TOML"),
    ] {
        let error = aograph_embed::check_settings_toml(text)
            .unwrap_err()
            .to_string();
        assert!(error.contains(named), "{text:?}: {error}");
    }
}
