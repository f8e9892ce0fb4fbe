//! Every normal encoding decodes to the g-buffer's normals; normals rebuilt from depth match
//! the faces away from depth edges.

use std::sync::Arc;

use crate::common::user_frame::{oct_encode, pack_rgb10a2, upload};
use aograph_ao_passes::{AoConfig, TechniqueRegistry};
use aograph_embed::{AoInputs, DepthInput, NormalEncoding, NormalSpace, NormalsInput};
use aograph_frame::GBufferChannel;
use aograph_graph::{GpuContext, test_gpu};
use aograph_renderer::FrameOutputs;
use aograph_renderer::Renderer;
use aograph_scene::{ReferenceNormals, Scene};
use glam::{Mat4, Vec3};

use super::*;

#[test]
pub(crate) fn every_normal_encoding_decodes_to_the_g_buffers_normals() {
    let Some(gpu) = test_gpu() else { return };
    let scene = aograph_scene::procedural_scene("stairs").unwrap();
    let radius = aograph_scene::suggested_radius(&scene).radius;
    let config = common::ao_config("gtao", radius, "");
    let own = own_frame(&scene, &config, None).unwrap();
    let (depth, proj) = reversed_z_depth(&gpu, &own);
    let size = (SIZE.width, SIZE.height);
    let world = own.view.inverse();
    let world_normals: Vec<Vec3> = own
        .normals
        .iter()
        .map(|n| world.transform_vector3(*n))
        .collect();
    let f32s = |v: Vec<f32>| bytemuck::cast_slice::<f32, u8>(&v).to_vec();
    let texture = |format, bytes: Vec<u8>| upload(&gpu.device, &gpu.queue, format, size, &bytes);
    use wgpu::TextureFormat as F;
    // (what, texture, space, encoding, bound and why)
    let cases = [
        (
            "world space, xyz, Rgba32Float",
            texture(
                F::Rgba32Float,
                f32s(
                    world_normals
                        .iter()
                        .flat_map(|n| [n.x, n.y, n.z, 0.0])
                        .collect(),
                ),
            ),
            NormalSpace::World,
            NormalEncoding::Xyz,
            // The view rotation applied and rounded to f16 again: within an f16 ulp.
            SAME_INPUTS,
        ),
        (
            "world space, packed, Rgb10a2Unorm",
            texture(
                F::Rgb10a2Unorm,
                world_normals
                    .iter()
                    .flat_map(|n| pack_rgb10a2(*n * 0.5 + 0.5).to_le_bytes())
                    .collect(),
            ),
            NormalSpace::World,
            NormalEncoding::PackedXyz,
            // 10 bits per axis: a normal turns by up to ~1.7e-3 rad. GTAO projects it into each
            // slice's plane, where a slice nearly perpendicular to it turns the projection by
            // far more: up to 0.022 on 17 of 5917 pixels, 8e-4 on average (measured).
            0.03,
        ),
        (
            "view space, octahedral, Rg32Float",
            texture(
                F::Rg32Float,
                f32s(
                    own.normals
                        .iter()
                        .flat_map(|n| oct_encode(*n).to_array())
                        .collect(),
                ),
            ),
            NormalSpace::View,
            NormalEncoding::Octahedral,
            SAME_INPUTS,
        ),
        (
            "view space, octahedral packed, Rg8Unorm",
            texture(
                F::Rg8Unorm,
                own.normals
                    .iter()
                    .flat_map(|n| {
                        let e = oct_encode(*n) * 0.5 + 0.5;
                        [e.x, e.y].map(|x| (x.clamp(0.0, 1.0) * 255.0).round() as u8)
                    })
                    .collect(),
            ),
            NormalSpace::View,
            NormalEncoding::PackedOctahedral,
            // 8 bits per coordinate: a normal turns by up to ~0.01 rad, ten times the 10-bit
            // case above.
            0.1,
        ),
    ];
    let mut ao = embedding(&gpu, &config);
    let mut failures = Vec::new();
    for (what, normals, space, encoding, bound) in &cases {
        let mut inputs = AoInputs::new(DepthInput::Hardware(&depth), proj, own.view);
        inputs.normals = Some(NormalsInput {
            texture: normals,
            space: *space,
            encoding: *encoding,
        });
        let got = embed_frame(&gpu, &mut ao, &inputs).unwrap();
        failures.extend(compare(what, &got, &own, *bound));
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Normals rebuilt from a hardware depth buffer by the adapter alone.
pub(crate) fn rebuilt_normals(
    gpu: &Arc<GpuContext>,
    depth: &wgpu::Texture,
    proj: Mat4,
    view: Mat4,
) -> Vec<Vec3> {
    let inputs = AoInputs::new(DepthInput::Hardware(depth), proj, view);
    let n = adapter_channel(gpu, &inputs, GBufferChannel::Normals, proj * view)
        .to_f32()
        .unwrap();
    n.chunks(4).map(|c| Vec3::new(c[0], c[1], c[2])).collect()
}

/// The angle between two (not quite unit: f16) vectors, accurate near 0, where acos of the
/// dot product is not.
pub(crate) fn angle_degrees(a: Vec3, b: Vec3) -> f32 {
    let (a, b) = (a.normalize_or_zero(), b.normalize_or_zero());
    a.cross(b).length().atan2(a.dot(b)).to_degrees()
}

/// The view-space point at pixel `i` with linear depth `z` (common/view.wgsl view_position).
pub(crate) fn view_point(own: &OwnFrame, i: usize, z: f32) -> Vec3 {
    let (w, h) = (SIZE.width as usize, SIZE.height as usize);
    let uv = glam::Vec2::new(
        ((i % w) as f32 + 0.5) / w as f32,
        ((i / w) as f32 + 0.5) / h as f32,
    );
    let ndc = glam::Vec2::new(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0);
    let scale = glam::Vec2::new(own.proj.x_axis.x, own.proj.y_axis.y);
    let shear = glam::Vec2::new(own.proj.z_axis.x, own.proj.z_axis.y);
    let xy = z * (ndc + shear) / scale;
    Vec3::new(xy.x, xy.y, -z)
}

/// Pixels where, along each image axis, the two texels on at least one side lie on the
/// centre's face (geometry with the centre's geometric normal within 0.06 degrees, f16
/// rounding, and on its plane within 1e-4 of the depth), and how many of them have another
/// surface or sky on the other side (next to an edge or crease). There a rebuilt normal has
/// one right answer, which an edge-unaware rule (central differences) misses next to edges.
pub(crate) fn one_face_each_axis(own: &OwnFrame) -> (Vec<usize>, usize) {
    let (w, h) = (SIZE.width as i32, SIZE.height as i32);
    let mut pixels = Vec::new();
    let mut next_to_edge = 0;
    for y in 2..h - 2 {
        for x in 2..w - 2 {
            let i = (y * w + x) as usize;
            let (z, n) = (own.linear_depth[i], own.normals[i]);
            if z <= 0.0 {
                continue;
            }
            let p = view_point(own, i, z);
            let on_face = |dx: i32, dy: i32| {
                let j = ((y + dy) * w + x + dx) as usize;
                let zj = own.linear_depth[j];
                zj > 0.0
                    && angle_degrees(own.normals[j], n) < 0.06
                    && (view_point(own, j, zj) - p).dot(n.normalize()).abs() < 1e-4 * z
            };
            let side = |sx: i32, sy: i32| on_face(sx, sy) && on_face(2 * sx, 2 * sy);
            // A side on another face whose plane passes through the centre too (the centre
            // is on a crease: a symmetric view puts one down the middle column): both faces
            // are right there, and the rasteriser's tie-break picked one.
            let crease = |sx: i32, sy: i32| {
                let j = ((y + sy) * w + x + sx) as usize;
                let zj = own.linear_depth[j];
                zj > 0.0
                    && angle_degrees(own.normals[j], n) >= 0.06
                    && (view_point(own, j, zj) - p)
                        .dot(own.normals[j].normalize())
                        .abs()
                        < 1e-4 * z
            };
            if crease(-1, 0) || crease(1, 0) || crease(0, -1) || crease(0, 1) {
                continue;
            }
            let (l, r, u, d) = (side(-1, 0), side(1, 0), side(0, -1), side(0, 1));
            if (l || r) && (u || d) {
                pixels.push(i);
                if !(l && r && u && d) {
                    next_to_edge += 1;
                }
            }
        }
    }
    (pixels, next_to_edge)
}

/// The worst angle (degrees) between normals rebuilt from depth and the g-buffer's face
/// normals where each axis has one side on the centre's face (`one_face_each_axis`), on
/// every procedural scene. On a face 1/z is affine in screen space and the rebuild exact but
/// for rounding: positions carry f32 rounding, and differences of neighbours ~1/100 of the
/// depth apart lose two digits of it; measured at most 0.0069 degrees (wall, stairs). A
/// rule blind to edges (one fixed side, or central differences) is off by up to 90 degrees
/// next to every edge and crease.
pub(crate) const REBUILT_NORMAL_DEGREES: f32 = 0.05;

#[test]
pub(crate) fn reconstructed_normals_match_the_faces_away_from_depth_edges() {
    let Some(gpu) = test_gpu() else { return };
    let mut failures = Vec::new();
    for name in aograph_scene::PROCEDURAL_SCENE_NAMES {
        let scene = aograph_scene::procedural_scene(name).unwrap();
        let radius = aograph_scene::suggested_radius(&scene).radius;
        // rtao's g-buffer: geometric (face) normals.
        let config = common::ao_config("none", radius, "");
        let Some(own) = own_frame_with_face_normals(&scene, &config) else {
            return;
        };
        let (depth, proj) = reversed_z_depth(&gpu, &own);
        let rebuilt = rebuilt_normals(&gpu, &depth, proj, own.view);
        let (pixels, next_to_edge) = one_face_each_axis(&own);
        let (worst, at) = pixels
            .iter()
            .map(|&i| (angle_degrees(rebuilt[i], own.normals[i]), i))
            .fold((0.0f32, 0), |m, (a, i)| if a > m.0 { (a, i) } else { m });
        // Everywhere on geometry, edges included: how far the rebuild strays at silhouettes.
        let mean_all = {
            let geo: Vec<usize> = (0..rebuilt.len())
                .filter(|&i| own.linear_depth[i] > 0.0)
                .collect();
            geo.iter()
                .map(|&i| angle_degrees(rebuilt[i], own.normals[i]))
                .sum::<f32>()
                / geo.len().max(1) as f32
        };
        println!(
            "{name}: worst angle {worst:.4} degrees at pixel {at} over {} pixels with one face along \
             each axis ({next_to_edge} of them next to an edge); mean over all geometry \
             {mean_all:.3} degrees",
            pixels.len()
        );
        if worst > REBUILT_NORMAL_DEGREES {
            failures.push(format!(
                "{name}: rebuilt normal {worst} degrees off at pixel {at}"
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// aograph's own frame with geometric normals in the g-buffer (as rtao and mssao read them).
pub(crate) fn own_frame_with_face_normals(scene: &Scene, config: &AoConfig) -> Option<OwnFrame> {
    let gpu = test_gpu()?;
    let outputs = FrameOutputs {
        linear_depth: true,
        surfaces: true,
        surface_normals: ReferenceNormals::Geometric,
        ..Default::default()
    };
    let mut r = Renderer::new(
        gpu,
        aograph::shader_library(),
        &TechniqueRegistry::with_builtins(),
        Arc::new(scene.clone()),
        config,
        outputs,
        SIZE,
    )
    .ok()?;
    let camera = scene.camera_at(0.0);
    r.render_with_camera(0.0, camera).ok()?;
    let n = r.read_gbuffer(GBufferChannel::Normals).ok()?;
    Some(OwnFrame {
        ao: r.read_ao().ok()?,
        linear_depth: r.read_linear_depth().ok()?,
        normals_bytes: n.bytes.clone(),
        normals: n
            .to_f32()
            .ok()?
            .chunks(4)
            .map(|c| Vec3::new(c[0], c[1], c[2]))
            .collect(),
        camera,
        view: camera.view(),
        proj: camera.projection(aspect()),
        renderer: r,
    })
}

/// Directions spread over the whole sphere (a Fibonacci lattice), `n` of them: every octant,
/// both hemispheres of z, and the poles' neighbourhoods.
fn sphere_directions(n: usize) -> Vec<Vec3> {
    let golden = std::f32::consts::PI * (3.0 - 5f32.sqrt());
    (0..n)
        .map(|i| {
            let z = 1.0 - 2.0 * (i as f32 + 0.5) / n as f32;
            let r = (1.0 - z * z).max(0.0).sqrt();
            let phi = golden * i as f32;
            Vec3::new(r * phi.cos(), r * phi.sin(), z)
        })
        .collect()
}

#[test]
pub(crate) fn world_space_octahedral_normals_decode_in_every_octant() {
    // The adapter's normals channel against the source normals directly: world-space unit
    // vectors in all eight octants, encoded octahedrally (exact in Rg32Float), decoded and
    // turned into view space by the adapter; expected: the view matrix applied on the CPU.
    let Some(gpu) = test_gpu() else { return };
    let (depth, proj, view, _) = plane_frame(&gpu);
    let n = (SIZE.width * SIZE.height) as usize;
    let world = sphere_directions(n);
    let mut octants = [0usize; 8];
    for d in &world {
        octants
            [(d.x < 0.0) as usize | ((d.y < 0.0) as usize) << 1 | ((d.z < 0.0) as usize) << 2] += 1;
    }
    assert!(octants.iter().all(|c| *c > n / 10), "{octants:?}");
    let bytes: Vec<u8> = world
        .iter()
        .flat_map(|d| oct_encode(*d).to_array())
        .flat_map(f32::to_le_bytes)
        .collect();
    let normals = upload(
        &gpu.device,
        &gpu.queue,
        wgpu::TextureFormat::Rg32Float,
        (SIZE.width, SIZE.height),
        &bytes,
    );
    let mut inputs = AoInputs::new(DepthInput::Hardware(&depth), proj, view);
    inputs.normals = Some(NormalsInput {
        texture: &normals,
        space: NormalSpace::World,
        encoding: NormalEncoding::Octahedral,
    });
    let got = adapter_channel(&gpu, &inputs, GBufferChannel::Normals, proj * view)
        .to_f32()
        .unwrap();
    // The channel is Rgba16Float: each component of a unit vector rounds by at most 2^-11
    // (4.9e-4); the decode and the rotation in f32 add ~1e-6.
    let bound = 1e-3;
    let mut worst = (0.0f32, 0usize);
    for (i, d) in world.iter().enumerate() {
        let expected = view.transform_vector3(*d);
        let c = &got[i * 4..i * 4 + 4];
        let e = (Vec3::new(c[0], c[1], c[2]) - expected).abs().max_element();
        assert_eq!(c[3], 1.0, "pixel {i} is geometry");
        if e > worst.0 {
            worst = (e, i);
        }
    }
    let (e, i) = worst;
    println!(
        "octahedral world normals: largest component error {e:e} at {i} ({})",
        world[i]
    );
    assert!(
        e <= bound,
        "pixel {i}: source {} decodes {e} away from its view-space normal",
        world[i]
    );
}
