//! The GPU g-buffer against the CPU's primary rays (`aograph_scene::CpuGBuffer`), on every
//! procedural scene, every test scene found (`aograph_scene::TEST_SCENES`: tests/scenes, else
//! ../shared/scenes; those in neither are skipped, saying so) and `node-transforms` (a node scaled
//! [1, 8, 1], a mirrored node and a sheared nested pair). The reference starts its rays from the
//! GPU g-buffer, so this is what makes it trustworthy on real assets.
//!
//! Animated scenes are compared a third time, mid-animation (CesiumMan mid-stride: the GPU's
//! skinning against the CPU's, `Scene::world_triangles`).
//!
//! Checks, per scene at 128x96:
//! - coverage (geometry or sky) agrees on at least 99.5% of pixels;
//! - away from silhouettes (every 3x3 neighbour sees geometry in both buffers and lies within
//!   1% of the view distance of the pixel's plane), positions agree within 1e-3 of the view
//!   distance, and geometric and shading normals both have dot > 0.999.
//!
//! Tolerances, with reasons: the rasteriser snaps vertices to 1/256 pixel, so a pixel centre
//! that close to an edge can be covered by the triangle on either side. Such pixels are found
//! by tracing four extra rays 1/256 pixel off the centre; a GPU point and normals there must
//! match those of one of the triangles those rays hit (a pixel whose centre grazes a
//! silhouette sees the near or the far surface). Elsewhere the probes hit the pixel's own
//! triangle and move its point by ~1e-5 of the view distance: 1e-3 is ~30x the worst snapping
//! shift at grazing angles.
//! Normals are stored as Rgba16Float (about 5e-4 rad of error, dot 1 - 1e-7).

mod common;

use std::path::PathBuf;
use std::sync::Arc;

use aograph_graph::{Extent, test_gpu};
use aograph_renderer::frame_reference::{FrameView, reference_surfaces};
use aograph_scene::{
    Camera, CpuGBuffer, PROCEDURAL_SCENE_NAMES, ReferenceNormals, Scene, SurfaceBuffer,
    TriangleBvh, load_scene, procedural_scene,
};
use glam::{Vec2, Vec3};

const SIZE: Extent = Extent {
    width: 128,
    height: 96,
};
/// The rasteriser's sub-pixel precision (Vulkan's minimum is 4 bits; lavapipe and desktop
/// GPUs use 8), as the offset of the ambiguity probes.
const SNAP: f32 = 1.0 / 256.0;

/// Every test scene that can be found (`aograph_scene::test_scene` says which it skips).
fn shared_scenes() -> Vec<PathBuf> {
    aograph_scene::TEST_SCENES
        .iter()
        .filter_map(|file| {
            aograph_scene::test_scene("gpu_gbuffer_matches_cpu_primary_rays_on_every_scene", file)
        })
        .collect()
}

/// What one scene's comparison found.
#[derive(Debug, Default)]
struct Agreement {
    coverage: f64,
    compared: usize,
    ambiguous: usize,
    worst_position: (f32, usize),
    worst_geometric: (f32, usize),
    worst_shading: (f32, usize),
}

/// A second view of each scene, from another side, with the bounding sphere filling the
/// frame: the scene's own camera sees the shared glTF files small (they carry no camera).
fn close_view(scene: &Scene) -> Camera {
    let b = scene.bounds();
    let (centre, radius) = (b.centre(), 0.5 * b.diagonal());
    let fov = 45f32.to_radians();
    let direction = Vec3::new(-0.6, 0.5, 1.0).normalize();
    let distance = radius / (0.5 * fov).sin();
    Camera::perspective(
        centre + direction * distance * 0.75,
        centre,
        fov,
        0.01 * radius,
        10.0 * radius,
    )
}

/// The CPU g-buffer at time `time` at the pixel centres and at four probes `SNAP` pixels off
/// them.
fn cpu_gbuffers(scene: &Scene, camera: &Camera, time: f32) -> Vec<CpuGBuffer> {
    let triangles = scene.world_triangles(time);
    let normals = scene.world_vertex_normals(time);
    let bvh = TriangleBvh::new(&triangles);
    [
        Vec2::ZERO,
        Vec2::new(SNAP, SNAP),
        Vec2::new(-SNAP, SNAP),
        Vec2::new(SNAP, -SNAP),
        Vec2::new(-SNAP, -SNAP),
    ]
    .into_iter()
    .map(|offset| {
        CpuGBuffer::trace_with_bvh(
            &bvh,
            &triangles,
            &normals,
            camera,
            SIZE.width,
            SIZE.height,
            offset,
        )
    })
    .collect()
}

/// True when pixel `i` is away from silhouettes in both buffers (see the module docs).
fn interior(i: usize, cpu: &CpuGBuffer, gpu: &SurfaceBuffer) -> bool {
    let (w, h) = (SIZE.width as i64, SIZE.height as i64);
    let (x, y) = (i as i64 % w, i as i64 / w);
    let (p, n) = (cpu.points[i], cpu.geometric_normals[i]);
    let reach = 0.01 * cpu.distances[i];
    for dy in -1..=1 {
        for dx in -1..=1 {
            let (qx, qy) = (x + dx, y + dy);
            if qx < 0 || qy < 0 || qx >= w || qy >= h {
                return false;
            }
            let q = (qy * w + qx) as usize;
            if !cpu.valid[q] || !gpu.valid[q] || n.dot(cpu.points[q] - p).abs() > reach {
                return false;
            }
        }
    }
    true
}

/// The closest point to `p` on triangle `[a, b, c]` (Ericson, Real-Time Collision Detection
/// 5.1.5).
fn closest_point_on_triangle(p: Vec3, [a, b, c]: [Vec3; 3]) -> Vec3 {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = 1.0 / (va + vb + vc);
    a + ab * (vb * denom) + ac * (vc * denom)
}

/// The world-space triangles of a scene and their vertex normals, for point queries.
struct Geometry {
    triangles: Vec<[Vec3; 3]>,
    normals: Vec<[Vec3; 3]>,
}

/// The (geometric, shading) normals of every triangle passing within `reach` of `point`, as
/// seen from `eye`: at a pixel whose centre grazes an edge the GPU may show any of them.
fn normals_touching(g: &Geometry, point: Vec3, reach: f32, eye: Vec3) -> Vec<(Vec3, Vec3)> {
    let view = (point - eye).normalize_or_zero();
    g.triangles
        .iter()
        .zip(&g.normals)
        .filter(|(t, _)| {
            let lo = t[0].min(t[1]).min(t[2]) - Vec3::splat(reach);
            let hi = t[0].max(t[1]).max(t[2]) + Vec3::splat(reach);
            point.cmpge(lo).all() && point.cmple(hi).all()
        })
        .filter(|(t, _)| closest_point_on_triangle(point, **t).distance(point) <= reach)
        .filter_map(|(t, n)| aograph_scene::reference::surface_normals(*t, *n, point, view))
        .collect()
}

fn compare(scene: &Arc<Scene>, camera: Camera, time: f32) -> Option<Agreement> {
    let gpu = test_gpu()?;
    let view = FrameView {
        camera,
        scene: scene.clone(),
        time,
        extent: SIZE,
    };
    let shaders = aograph::shader_library();
    let (geometric, _) = reference_surfaces(
        gpu.clone(),
        shaders.clone(),
        &view,
        ReferenceNormals::Geometric,
    )
    .expect("geometric g-buffer");
    let (shading, _) = reference_surfaces(gpu, shaders, &view, ReferenceNormals::Shading)
        .expect("shading g-buffer");
    assert_eq!(
        geometric.valid, shading.valid,
        "the two g-buffers cover alike"
    );
    assert_eq!(
        geometric.points, shading.points,
        "the two g-buffers place points alike"
    );
    let cpu = cpu_gbuffers(scene, &camera, time);
    let c = &cpu[0];
    let n = c.valid.len();
    let agree = (0..n).filter(|&i| c.valid[i] == geometric.valid[i]).count();
    let mut a = Agreement {
        coverage: agree as f64 / n as f64,
        worst_position: (0.0, 0),
        worst_geometric: (1.0, 0),
        worst_shading: (1.0, 0),
        ..Default::default()
    };
    let g = Geometry {
        triangles: scene.world_triangles(time),
        normals: scene.world_vertex_normals(time),
    };
    for i in (0..n).filter(|&i| c.valid[i] && geometric.valid[i] && interior(i, c, &geometric)) {
        a.compared += 1;
        // The normals the GPU may show here: the centre ray's, or at an ambiguous pixel any
        // probe's and any triangle's through the GPU's point.
        let mut candidates = vec![(c.geometric_normals[i], c.shading_normals[i])];
        if cpu.iter().any(|b| b.triangles[i] != c.triangles[i]) {
            a.ambiguous += 1;
            candidates.extend(
                cpu.iter()
                    .filter(|b| b.valid[i])
                    .map(|b| (b.geometric_normals[i], b.shading_normals[i])),
            );
            let reach = 1e-5 * c.distances[i];
            candidates.extend(normals_touching(
                &g,
                geometric.points[i],
                reach,
                camera.position,
            ));
        }
        let position = cpu
            .iter()
            .filter(|b| b.valid[i])
            .map(|b| (geometric.points[i] - b.points[i]).length() / c.distances[i])
            .fold(f32::INFINITY, f32::min);
        if position > a.worst_position.0 {
            a.worst_position = (position, i);
        }
        let best = |normal: Vec3, pick: fn(&(Vec3, Vec3)) -> Vec3| {
            candidates
                .iter()
                .map(|c| normal.dot(pick(c)))
                .fold(-1.0, f32::max)
        };
        let dot = best(geometric.normals[i], |c| c.0);
        if dot < a.worst_geometric.0 {
            a.worst_geometric = (dot, i);
        }
        let dot = best(shading.normals[i], |c| c.1);
        if dot < a.worst_shading.0 {
            a.worst_shading = (dot, i);
        }
    }
    Some(a)
}

fn pixel(i: usize) -> String {
    format!("({}, {})", i as u32 % SIZE.width, i as u32 / SIZE.width)
}

#[test]
fn gpu_gbuffer_matches_cpu_primary_rays_on_every_scene() {
    let mut scenes: Vec<(String, Scene)> = PROCEDURAL_SCENE_NAMES
        .iter()
        .map(|n| {
            (
                n.to_string(),
                procedural_scene(n).expect("procedural scene"),
            )
        })
        .collect();
    assert!(scenes.iter().any(|(n, _)| n == "node-transforms"));
    for path in shared_scenes() {
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        scenes.push((name, load_scene(&path).expect("shared scene loads")));
    }
    let mut failures = Vec::new();
    eprintln!(
        "{:<32} {:>9} {:>8} {:>6} {:>20} {:>20} {:>20}",
        "scene (view)",
        "coverage",
        "compared",
        "ambig",
        "worst position",
        "worst 1 - dot geo",
        "worst 1 - dot shade"
    );
    let mut worst = (1.0f64, 0.0f32, 1.0f32, 1.0f32);
    for (name, scene) in scenes {
        let scene = Arc::new(scene);
        let mut views = vec![
            ("own".to_string(), scene.camera_at(0.0), 0.0),
            ("close".to_string(), close_view(&scene), 0.0),
        ];
        if scene.is_animated() {
            let t = 0.37 * scene.duration();
            views.push((format!("close, t = {t:.2}"), close_view(&scene), t));
        }
        for (view, camera, time) in views {
            let Some(a) = compare(&scene, camera, time) else {
                return;
            };
            let name = format!("{name} ({view})");
            eprintln!(
                "{:<32} {:>8.3}% {:>8} {:>6} {:>9.2e} {:>10} {:>9.2e} {:>10} {:>9.2e} {:>10}",
                name,
                a.coverage * 100.0,
                a.compared,
                a.ambiguous,
                a.worst_position.0,
                pixel(a.worst_position.1),
                1.0 - a.worst_geometric.0,
                pixel(a.worst_geometric.1),
                1.0 - a.worst_shading.0,
                pixel(a.worst_shading.1),
            );
            worst = (
                worst.0.min(a.coverage),
                worst.1.max(a.worst_position.0),
                worst.2.min(a.worst_geometric.0),
                worst.3.min(a.worst_shading.0),
            );
            if a.coverage < 0.995 {
                failures.push(format!(
                    "{name}: coverage agrees on {:.3}%",
                    a.coverage * 100.0
                ));
            }
            if a.compared < 300 {
                failures.push(format!("{name}: only {} pixels compared", a.compared));
            }
            if a.worst_position.0 > 1e-3 {
                failures.push(format!(
                    "{name}: position off by {:.2e} of the view distance at {}",
                    a.worst_position.0,
                    pixel(a.worst_position.1)
                ));
            }
            for (what, (dot, i)) in [
                ("geometric", a.worst_geometric),
                ("shading", a.worst_shading),
            ] {
                if dot <= 0.999 {
                    failures.push(format!(
                        "{name}: {what} normal dot {dot:.6} at {}",
                        pixel(i)
                    ));
                }
            }
        }
    }
    eprintln!(
        "worst over every scene and view: coverage {:.3}%, position {:.2e}, geometric dot {:.6}, shading dot {:.6}",
        worst.0 * 100.0,
        worst.1,
        worst.2,
        worst.3
    );
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn compact_normals_decode_to_the_wide_normals_on_every_procedural_scene() {
    // MSSAO asks for face normals in the compact encoding (normals_oct, R32Uint); the
    // reference's surfaces add the Rgba16Float normals of the same (geometric) kind, so one
    // g-buffer writes both. Decoded, they agree within both encodings' rounding: f16 moves a
    // component by up to 2^-11 of 1 (5e-4 rad), the octahedral code by under 1e-4 rad. Sky
    // (depth 0) carries code 0.
    use aograph::shader_library;
    use aograph_ao_passes::{AoConfig, TechniqueRegistry};
    use aograph_frame::{GBufferChannel, normal_oct};
    use aograph_renderer::FrameOutputs;
    use aograph_renderer::Renderer;
    let Some(gpu) = test_gpu() else { return };
    let registry = TechniqueRegistry::with_builtins();
    let ao = AoConfig {
        technique: "mssao".into(),
        ..AoConfig::default()
    };
    let outputs = FrameOutputs {
        surfaces: true,
        surface_normals: ReferenceNormals::Geometric,
        linear_depth: true,
        ..Default::default()
    };
    let mut worst = 0.0f32;
    for name in PROCEDURAL_SCENE_NAMES {
        let scene = Arc::new(procedural_scene(name).expect("procedural scene"));
        let mut r = Renderer::new(
            gpu.clone(),
            shader_library(),
            &registry,
            scene,
            &ao,
            outputs,
            SIZE,
        )
        .expect("renderer");
        r.render(0.0).expect("frame");
        let wide = r
            .read_gbuffer(GBufferChannel::Normals)
            .unwrap()
            .to_f32()
            .unwrap();
        let codes = r
            .read_gbuffer(GBufferChannel::NormalsOct)
            .unwrap()
            .to_u32()
            .unwrap();
        let depth = r.read_linear_depth().unwrap();
        let mut geometry = 0;
        for (i, &code) in codes.iter().enumerate() {
            if depth[i].is_nan() || depth[i] <= 0.0 {
                assert_eq!(code, 0, "{name}: sky pixel {} has a normal code", pixel(i));
                continue;
            }
            geometry += 1;
            let w = Vec3::from_slice(&wide[i * 4..i * 4 + 3]).normalize();
            let c = Vec3::from_array(normal_oct::decode(code));
            let angle = w.cross(c).length().atan2(w.dot(c));
            worst = worst.max(angle);
            assert!(
                angle < 1e-3,
                "{name}: pixel {}: wide {w}, compact {c}, {angle:e} rad apart",
                pixel(i)
            );
        }
        assert!(geometry > 100, "{name}: {geometry} geometry pixels");
    }
    eprintln!("compact against wide normals: worst {worst:e} rad");
}
