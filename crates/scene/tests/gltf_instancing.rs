//! EXT_mesh_gpu_instancing: a node whose mesh is placed by per-instance TRANSLATION / ROTATION
//! (normalized SHORT) / SCALE accessors gives exactly the triangles of the same scene written as
//! one node per instance under the instanced node's transform, and the same reference AO.

mod common;

use aograph_scene::reference::{
    CpuGBuffer, ProgressMode, ReferenceMode, ReferenceNormals, ReferenceParams, TriangleBvh,
    trace_reference,
};
use aograph_scene::{Scene, import_gltf};
use glam::{Quat, Vec3};
use serde_json::{Value, json};

/// A unit cube (8 vertices, 36 u16 indices) and a 10 x 10 floor quad, as bytes and views.
fn geometry() -> (Vec<u8>, Value, Value) {
    let mut positions = Vec::new();
    for i in 0..8u32 {
        positions.extend([
            (i & 1) as f32 - 0.5,
            (i >> 1 & 1) as f32,
            (i >> 2 & 1) as f32 - 0.5,
        ]);
    }
    positions.extend([
        -5.0, 0.0, -5.0, 5.0, 0.0, -5.0, 5.0, 0.0, 5.0, -5.0, 0.0, 5.0,
    ]);
    let cube: [u16; 36] = [
        0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4, 2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6,
        1, 3, 5, 3, 7, 5,
    ];
    let floor: [u16; 6] = [8, 10, 9, 8, 11, 10];
    let mut bytes = common::f32_bytes(&positions); // 144 bytes
    bytes.extend(cube.iter().chain(&floor).flat_map(|i| i.to_le_bytes())); // 84 bytes at 144
    let views = json!([
        {"buffer": 0, "byteOffset": 0, "byteLength": 144},
        {"buffer": 0, "byteOffset": 144, "byteLength": 72},
        {"buffer": 0, "byteOffset": 216, "byteLength": 12},
    ]);
    let accessors = json!([
        {"bufferView": 0, "componentType": 5126, "count": 12, "type": "VEC3",
         "min": [-5, 0, -5], "max": [5, 1, 5]},
        {"bufferView": 1, "componentType": 5123, "count": 36, "type": "SCALAR"},
        {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"},
    ]);
    (bytes, views, accessors)
}

/// Instance i: at (1.7 i, 0, 0), turned by 30 i degrees about y, scaled by 1 + 0.25 i.
fn instance(i: usize) -> (Vec3, [i16; 4], Vec3) {
    let q = Quat::from_rotation_y((30.0 * i as f32).to_radians());
    let short = q.to_array().map(|c| (c * 32767.0).round() as i16);
    (
        Vec3::new(1.7 * i as f32, 0.0, 0.0),
        short,
        Vec3::splat(1.0 + 0.25 * i as f32),
    )
}

const INSTANCES: usize = 4;

/// The same placement two ways: one node with the extension, or one child node per instance.
fn scene(instanced: bool, test: &str) -> Scene {
    let (mut bytes, mut views, mut accessors) = geometry();
    let meshes = json!([
        {"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]},
        {"primitives": [{"attributes": {"POSITION": 0}, "indices": 2}]},
    ]);
    // The instanced node's own transform: instances are placed before it (T_node * T_instance).
    let parent = json!({"translation": [-2.5, 0.0, 0.5], "rotation": [0.0, 0.0, 0.0, 1.0],
                        "scale": [0.8, 0.8, 0.8]});
    let mut nodes = vec![json!({"mesh": 1})];
    let mut extensions_used = vec![];
    if instanced {
        let start = bytes.len();
        let (mut t, mut r, mut s) = (Vec::new(), Vec::new(), Vec::new());
        for i in 0..INSTANCES {
            let (ti, ri, si) = instance(i);
            t.extend(ti.to_array());
            r.extend(ri);
            s.extend(si.to_array());
        }
        bytes.extend(common::f32_bytes(&t));
        bytes.extend(r.iter().flat_map(|c| c.to_le_bytes()));
        bytes.extend(common::f32_bytes(&s));
        let (lt, lr) = (12 * INSTANCES, 8 * INSTANCES);
        let views = views.as_array_mut().unwrap();
        views.push(json!({"buffer": 0, "byteOffset": start, "byteLength": lt}));
        views.push(json!({"buffer": 0, "byteOffset": start + lt, "byteLength": lr}));
        views.push(json!({"buffer": 0, "byteOffset": start + lt + lr, "byteLength": lt}));
        let accessors = accessors.as_array_mut().unwrap();
        accessors.push(
            json!({"bufferView": 3, "componentType": 5126, "count": INSTANCES, "type": "VEC3"}),
        );
        accessors.push(
            json!({"bufferView": 4, "componentType": 5122, "normalized": true,
                              "count": INSTANCES, "type": "VEC4"}),
        );
        accessors.push(
            json!({"bufferView": 5, "componentType": 5126, "count": INSTANCES, "type": "VEC3"}),
        );
        let mut node = parent.clone();
        node["mesh"] = json!(0);
        node["extensions"] = json!({"EXT_mesh_gpu_instancing": {
            "attributes": {"TRANSLATION": 3, "ROTATION": 4, "SCALE": 5, "_ID": 3}}});
        nodes.push(node);
        extensions_used.push("EXT_mesh_gpu_instancing");
    } else {
        let mut node = parent.clone();
        node["children"] = json!((2..2 + INSTANCES).collect::<Vec<_>>());
        nodes.push(node);
        for i in 0..INSTANCES {
            let (t, r, s) = instance(i);
            // The dequantized quaternion the extension's reader sees (glTF 2.0 §3.11).
            let r = glam::Vec4::from_array(r.map(|c| (c as f32 / 32767.0).max(-1.0))).normalize();
            nodes.push(
                json!({"mesh": 0, "translation": t.to_array(), "rotation": r.to_array(),
                              "scale": s.to_array()}),
            );
        }
    }
    let gltf = json!({
        "extensionsUsed": extensions_used,
        "extensionsRequired": extensions_used,
        "bufferViews": views, "accessors": accessors, "meshes": meshes, "nodes": nodes,
        "scenes": [{"nodes": [0, 1]}],
    });
    let name = format!("{test}-{}", if instanced { "instanced" } else { "nodes" });
    let import =
        import_gltf(common::write_gltf(&name, gltf, &bytes)).unwrap_or_else(|e| panic!("{e}"));
    import.scene
}

#[test]
fn instances_are_the_triangles_of_one_node_per_instance() {
    let (instanced, nodes) = (scene(true, "triangles"), scene(false, "triangles"));
    assert_eq!(instanced.instances.len(), 1 + INSTANCES);
    let (a, b) = (instanced.world_triangles(0.0), nodes.world_triangles(0.0));
    assert_eq!(a.len(), b.len());
    assert_eq!(a.len(), 2 + 12 * INSTANCES);
    // Both list the floor, then the copies in instance order: vertex by vertex, the same
    // placement up to float rounding of the two matrix products (1e-5 of a 6-unit scene).
    for (ta, tb) in a.iter().zip(&b) {
        for (p, q) in ta.iter().zip(tb) {
            assert!(p.distance(*q) < 1e-5, "{p} vs {q}");
        }
    }
    // Instance 2, vertex (0.5, 1, 0.5) of the cube: parent (0.8 scale, moved) * instance.
    let (t, _, s) = instance(2);
    let r = Quat::from_rotation_y(60f32.to_radians());
    let expected = Vec3::new(-2.5, 0.0, 0.5) + 0.8 * (t + r * (s * Vec3::new(0.5, 1.0, 0.5)));
    let corner = a[2 + 12 * 2..2 + 12 * 3]
        .iter()
        .flatten()
        .map(|p| p.distance(expected))
        .fold(f32::MAX, f32::min);
    assert!(
        corner < 1e-3,
        "instance 2's corner is {corner} from {expected}"
    );
}

#[test]
fn instanced_and_node_per_instance_scenes_have_the_same_reference_ao() {
    let (instanced, nodes) = (scene(true, "reference"), scene(false, "reference"));
    // Close above the row of cubes, so most pixels see a cube or the floor beside one.
    let camera = aograph_scene::Camera {
        position: Vec3::new(0.0, 3.0, 3.5),
        target: Vec3::new(0.0, 0.3, 0.0),
        up: Vec3::Y,
        projection: aograph_scene::Projection::Perspective {
            fov_y: 60f32.to_radians(),
            near: 0.05,
            far: 100.0,
            reversed_z_infinite: false,
        },
    };
    let params = ReferenceParams {
        radius: 1.0,
        rays_per_pixel: 32,
        mode: ReferenceMode::Binary,
        progress: ProgressMode::Never,
    };
    let trace = |scene: &Scene| {
        let surfaces =
            CpuGBuffer::trace(scene, &camera, 47, 29, 0.0).surfaces(ReferenceNormals::Geometric);
        trace_reference(
            &TriangleBvh::new(&scene.world_triangles(0.0)),
            &surfaces,
            &params,
        )
        .unwrap()
    };
    let (a, b) = (trace(&instanced), trace(&nodes));
    let n = a.accessibility.len() as f32;
    let diff = (a.accessibility.iter().zip(&b.accessibility))
        .map(|(x, y)| x - y)
        .sum::<f32>()
        / n;
    let se = (a.std_error.iter().zip(&b.std_error))
        .map(|(x, y)| x * x + y * y)
        .sum::<f32>()
        .sqrt()
        / n;
    let mean = a.accessibility.iter().sum::<f32>() / n;
    eprintln!(
        "instanced vs nodes: mean accessibility {mean:.4}, difference {diff:.2e}, SE {se:.2e}"
    );
    assert!(
        mean < 0.95,
        "the view must see occlusion to compare ({mean})"
    );
    assert!(
        diff.abs() <= 3.0 * se,
        "difference {diff} over 3 SE {}",
        3.0 * se
    );
}
