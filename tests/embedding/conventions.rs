//! Every depth convention and format, and an orthographic projection, give the g-buffer's AO.

use crate::common::user_frame::{depth_buffer, upload};
use aograph_embed::{AoInputs, DepthInput, NormalEncoding, NormalSpace, NormalsInput};
use aograph_graph::test_gpu;
use aograph_scene::{Camera, Projection};

use super::*;

#[test]
fn every_depth_convention_and_format_gives_the_g_buffers_ao() {
    let Some(gpu) = test_gpu() else { return };
    let scene = aograph_scene::procedural_scene("columns").unwrap();
    let radius = aograph_scene::suggested_radius(&scene).radius;
    let mut failures = Vec::new();
    for (technique, params) in [("gtao", ""), ("mssao", "levels = 3")] {
        let config = common::ao_config(technique, radius, params);
        let own = own_frame(&scene, &config, None).unwrap();
        let normals = given_normals(&gpu, &own);
        let (zmin, zmax) = depth_range(&own);
        let near = own.camera.near();
        let far = 2.0 * zmax;
        let d32 = wgpu::TextureFormat::Depth32Float;
        // Depth stored with 24 significant bits spaced evenly in d (standard Z in a float,
        // whose d crowds towards 1, or any 24-bit unorm): a depth rounds by lin * 2^-25 / near
        // relative, up to 5e-5 at the back of this view, where reversed Z in a float keeps
        // 2^-24 relative everywhere. MSSAO's coarse levels compare depths and normals against
        // thresholds, and 2% of its pixels then move by more than 1e-3 (at most 0.0084,
        // 8.6e-5 on average): the application's depth precision, not the adapter's.
        let lossy_24 = 0.01;
        // (what, projection, reversed, format, bound and why)
        let cases = [
            (
                "standard Z, finite far, Depth32Float",
                perspective(&own.camera, near, Some(far), false),
                false,
                d32,
                lossy_24,
            ),
            (
                "standard Z, infinite far, Depth32Float",
                perspective(&own.camera, near, None, false),
                false,
                d32,
                lossy_24,
            ),
            (
                "reversed Z, infinite far, Depth32Float",
                perspective(&own.camera, near, None, true),
                true,
                d32,
                SAME_INPUTS,
            ),
            (
                "reversed Z, finite far, Depth32Float",
                perspective(&own.camera, near, Some(far), true),
                true,
                d32,
                SAME_INPUTS,
            ),
            (
                "reversed Z, infinite far, Depth24Plus",
                perspective(&own.camera, near, None, true),
                true,
                wgpu::TextureFormat::Depth24Plus,
                lossy_24,
            ),
            // 16 bits over the frame's own depth range: a depth rounds by up to 2^-17 in d,
            // which is lin * 2^-17 / near relative (~5e-5 here): a plane becomes terraces of
            // that height, and a tap at a grazing angle sees a terrace's edge as a small
            // horizon. Bounded per pixel by 0.05 and on average by 0.005 (measured: 0.030 and
            // 1.9e-4).
            (
                "standard Z, tight range, Depth16Unorm",
                perspective(&own.camera, 0.5 * zmin, Some(1.01 * zmax), false),
                false,
                wgpu::TextureFormat::Depth16Unorm,
                0.05,
            ),
        ];
        let mut ao = embedding(&gpu, &config);
        for (what, proj, reversed, format, bound) in cases {
            let depth = depth_buffer(
                &gpu.device,
                &gpu.queue,
                &own.linear_depth,
                (SIZE.width, SIZE.height),
                proj,
                reversed,
                format,
            );
            let mut inputs = AoInputs::new(DepthInput::Hardware(&depth), proj, own.view);
            inputs.normals = Some(NormalsInput {
                texture: &normals,
                space: NormalSpace::View,
                encoding: NormalEncoding::Xyz,
            });
            let got = embed_frame(&gpu, &mut ao, &inputs).unwrap();
            failures.extend(compare(&format!("{technique}, {what}"), &got, &own, bound));
        }
        // Linear depth handed over as such: read in place, no adapter pass.
        let lin = upload(
            &gpu.device,
            &gpu.queue,
            wgpu::TextureFormat::R32Float,
            (SIZE.width, SIZE.height),
            bytemuck::cast_slice(&own.linear_depth),
        );
        let mut inputs = AoInputs::new(DepthInput::Linear(&lin), own.proj, own.view);
        inputs.normals = Some(NormalsInput {
            texture: &normals,
            space: NormalSpace::View,
            encoding: NormalEncoding::Xyz,
        });
        let got = embed_frame(&gpu, &mut ao, &inputs).unwrap();
        failures.extend(compare(
            &format!("{technique}, linear depth"),
            &got,
            &own,
            SAME_INPUTS,
        ));
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn an_orthographic_projection_gives_the_g_buffers_ao() {
    let Some(gpu) = test_gpu() else { return };
    let scene = aograph_scene::procedural_scene("corner").unwrap();
    let radius = aograph_scene::suggested_radius(&scene).radius;
    let base = scene.camera_at(0.0);
    let camera = Camera {
        projection: Projection::Orthographic {
            height: 6.0 * radius,
            near: 0.1,
            far: 100.0 * radius,
        },
        ..base
    };
    let config = common::ao_config("gtao", radius, "");
    let own = own_frame(&scene, &config, Some(camera)).unwrap();
    let normals = given_normals(&gpu, &own);
    let mut ao = embedding(&gpu, &config);
    let depth = depth_buffer(
        &gpu.device,
        &gpu.queue,
        &own.linear_depth,
        (SIZE.width, SIZE.height),
        own.proj,
        false,
        wgpu::TextureFormat::Depth32Float,
    );
    let mut inputs = AoInputs::new(DepthInput::Hardware(&depth), own.proj, own.view);
    inputs.normals = Some(NormalsInput {
        texture: &normals,
        space: NormalSpace::View,
        encoding: NormalEncoding::Xyz,
    });
    let got = embed_frame(&gpu, &mut ao, &inputs).unwrap();
    if let Some(f) = compare("gtao, orthographic", &got, &own, SAME_INPUTS) {
        panic!("{f}");
    }
}
