//! `aograph scene info FILE|NAME`: what a scene holds and how aograph will see it: bounds,
//! node, mesh and triangle counts, cameras, materials, transforms that need the normal matrix
//! (non-uniform scale, shear, mirroring), the views it offers and the automatic radius with its
//! derivation.

use std::fmt::Write as _;

use aograph_ao_passes::RadiusSetting;
use aograph_scene::views::scene_views;
use aograph_scene::{Projection, Scene, import_gltf, procedural_scene, suggested_radius};
use glam::{Mat3, Vec3};

use aograph_app_config::config::SceneSource;
use aograph_app_config::error::AppResult;
use aograph_app_config::prepared_scene::short;

/// How an instance's linear part transforms: (non-uniform scale or shear, mirrored).
fn transform_kind(m: Mat3) -> (bool, bool) {
    let lengths = [m.x_axis.length(), m.y_axis.length(), m.z_axis.length()];
    let (lo, hi) = lengths.iter().fold((f32::INFINITY, 0.0f32), |(lo, hi), l| {
        (lo.min(*l), hi.max(*l))
    });
    let axes = [m.x_axis, m.y_axis, m.z_axis].map(|a| a.normalize_or_zero());
    let skew = [(0, 1), (1, 2), (0, 2)]
        .iter()
        .any(|&(i, j)| axes[i].dot(axes[j]).abs() > 1e-4);
    (hi - lo > 1e-4 * hi || skew, m.determinant() < 0.0)
}

fn vec(v: Vec3) -> String {
    format!("({}, {}, {})", short(v.x), short(v.y), short(v.z))
}

fn camera_line(c: &aograph_scene::Camera) -> String {
    let projection = match c.projection {
        Projection::Perspective {
            fov_y,
            near,
            far,
            reversed_z_infinite,
        } => format!(
            "perspective, vertical fov {:.1} degrees, near {}, far {}",
            fov_y.to_degrees(),
            short(near),
            if reversed_z_infinite {
                "infinite (reversed Z)".to_string()
            } else {
                short(far)
            }
        ),
        Projection::Orthographic { height, near, far } => format!(
            "orthographic, height {}, near {}, far {}",
            short(height),
            short(near),
            short(far)
        ),
    };
    format!(
        "at {} looking at {}, {projection}",
        vec(c.position),
        vec(c.target)
    )
}

/// The report `aograph scene info` prints.
pub fn scene_info_text(source: &SceneSource) -> AppResult<String> {
    let (scene, gltf): (Scene, Option<aograph_scene::GltfInfo>) = match source {
        SceneSource::Procedural(name) => (procedural_scene(name)?, None),
        SceneSource::File(path) => {
            let import = import_gltf(path)?;
            for w in &import.warnings {
                eprintln!("warning: {}: {w}", path.display());
            }
            (import.scene, Some(import.info))
        }
    };
    let mut s = String::new();
    let b = scene.bounds();
    let _ = writeln!(s, "scene: {}", source.label());
    let _ = writeln!(
        s,
        "bounds: {} to {}, size {}, diagonal {}",
        vec(b.min),
        vec(b.max),
        vec(b.size()),
        short(b.diagonal())
    );
    let backdrops = scene.instances.iter().filter(|i| i.backdrop).count();
    if backdrops > 0 {
        let c = scene.content_bounds();
        let _ = writeln!(
            s,
            "content bounds ({backdrops} backdrop instance(s) left out): {} to {}, diagonal {}",
            vec(c.min),
            vec(c.max),
            short(c.diagonal())
        );
    }
    let unique: usize = scene.meshes.iter().map(|m| m.triangle_count()).sum();
    match &gltf {
        Some(info) => {
            let _ = writeln!(
                s,
                "nodes: {}, glTF meshes: {} ({} primitives), mesh instances: {}",
                info.nodes,
                info.meshes,
                scene.meshes.len(),
                scene.instances.len()
            );
        }
        None => {
            let _ = writeln!(
                s,
                "meshes: {}, instances: {} (procedural)",
                scene.meshes.len(),
                scene.instances.len()
            );
        }
    }
    let _ = writeln!(
        s,
        "triangles: {} placed, {unique} in the meshes",
        scene.triangle_count()
    );
    if let Some(info) = gltf.as_ref().filter(|i| !i.skins.is_empty()) {
        let skinned = (scene.instances.iter())
            .filter(|i| {
                scene
                    .meshes
                    .get(i.mesh)
                    .is_some_and(|m| i.skin_for(m).is_some())
            })
            .count();
        let skins: Vec<String> = (info.skins.iter())
            .map(|(name, joints)| format!("{name} ({joints} joints)"))
            .collect();
        let _ = writeln!(
            s,
            "skins: {}; {skinned} mesh instance(s) deformed on the GPU",
            skins.join(", ")
        );
    }
    let (mut stretched, mut mirrored) = (0, 0);
    for i in &scene.instances {
        let (ns, mi) = transform_kind(Mat3::from_mat4(i.transform));
        stretched += ns as usize;
        mirrored += mi as usize;
    }
    let _ = writeln!(
        s,
        "transforms: {stretched} instance(s) with non-uniform scale or shear, {mirrored} mirrored (negative determinant); normals use the inverse transpose either way"
    );
    if scene.cameras.is_empty() {
        let _ = writeln!(s, "cameras: none in the file");
    } else {
        let _ = writeln!(s, "cameras: {}", scene.cameras.len());
        for (i, c) in scene.cameras.iter().enumerate() {
            let _ = writeln!(
                s,
                "  {i}: {} {}{}",
                c.name,
                camera_line(&c.camera),
                if c.motion.is_some() { ", animated" } else { "" }
            );
        }
    }
    let _ = writeln!(
        s,
        "enclosed: {}",
        if aograph_scene::views::is_enclosed(&scene) {
            "yes (interior views added)"
        } else {
            "no"
        }
    );
    let _ = writeln!(s, "views (for --camera and bench --views):");
    for v in scene_views(&scene) {
        let _ = writeln!(s, "  {}: {}", v.name, camera_line(&v.camera));
        // The R `radius = "auto"` gives this view (the view rule where it is an interior).
        let viewed = aograph_app_config::camera_spec::apply_view(&scene, &v);
        let (r, note) =
            aograph_app_config::prepared_scene::resolve_radius(&viewed, RadiusSetting::Auto);
        let _ = writeln!(s, "    R = {} ({note})", short(r.get()));
    }
    match &gltf {
        Some(info) if !info.materials.is_empty() => {
            let _ = writeln!(s, "materials: {}", info.materials.len());
            for m in &info.materials {
                let _ = writeln!(
                    s,
                    "  {}: {}, alpha mode {}",
                    m.name,
                    if m.double_sided {
                        "double-sided"
                    } else {
                        "single-sided"
                    },
                    m.alpha_mode
                );
            }
            let _ = writeln!(s, "  (aograph draws every surface two-sided and opaque)");
        }
        _ => {
            let _ = writeln!(s, "materials: {}", scene.materials.len());
        }
    }
    if let Some(info) = &gltf {
        write_extensions(&mut s, &info.extensions);
    }
    let r = suggested_radius(&scene);
    let _ = writeln!(
        s,
        "suggested R: {} ({}; interior views use what they see, as listed above)",
        short(r.radius),
        r.derivation
    );
    Ok(s)
}

/// The `extensions:` lines: each extension the file uses, and what aograph does with it.
fn write_extensions(s: &mut String, extensions: &[aograph_scene::ExtensionUse]) {
    use aograph_scene::ExtensionHandling;
    if extensions.is_empty() {
        let _ = writeln!(s, "extensions: none");
        return;
    }
    let _ = writeln!(s, "extensions: {}", extensions.len());
    for e in extensions {
        let handling = match e.handling {
            ExtensionHandling::Read => "read",
            ExtensionHandling::Ignored => "not read (cannot change AO)",
            ExtensionHandling::Unknown => "not read (unknown to aograph)",
        };
        let required = if e.required { ", required" } else { "" };
        let _ = writeln!(s, "  {}{required}: {handling}", e.name);
    }
}

/// `aograph scene info`.
pub fn scene_info(scene: &str) -> AppResult<()> {
    let source = SceneSource::parse(scene);
    if let SceneSource::File(path) = &source
        && !path.exists()
    {
        return Err(aograph_scene::SceneError::MissingFile { path: path.clone() }.into());
    }
    print!("{}", scene_info_text(&source)?);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn node_transforms_reports_its_stretched_and_mirrored_nodes() {
        let text = scene_info_text(&SceneSource::Procedural("node-transforms".into())).unwrap();
        assert!(
            text.contains("4 instance(s) with non-uniform scale or shear, 2 mirrored"),
            "{text}"
        );
        assert!(text.contains("suggested R: 0.9038"), "{text}");
        assert!(text.contains("backdrop instance(s) left out"), "{text}");
    }

    #[test]
    fn the_transform_kinds_are_told_apart() {
        assert_eq!(transform_kind(Mat3::IDENTITY * 3.0), (false, false));
        assert_eq!(
            transform_kind(Mat3::from_diagonal(Vec3::new(1.0, 8.0, 1.0))),
            (true, false)
        );
        assert_eq!(
            transform_kind(Mat3::from_diagonal(Vec3::new(-2.0, 2.0, 2.0))),
            (false, true)
        );
        let shear = Mat3::from_diagonal(Vec3::new(1.0, 2.5, 1.0))
            * Mat3::from_rotation_z(std::f32::consts::FRAC_PI_4);
        assert_eq!(transform_kind(shear), (true, false));
    }

    #[test]
    fn the_extensions_a_file_uses_are_listed_with_what_aograph_does() {
        let dir = std::env::temp_dir().join(format!("aograph-info-ext-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("extensions.gltf");
        // One triangle: positions (0,0,0), (1,0,0), (0,1,0) as a base64 data URI.
        let gltf = serde_json::json!({
            "asset": {"version": "2.0"},
            "extensionsUsed": ["KHR_mesh_quantization", "KHR_texture_basisu", "VENDOR_made_up"],
            "extensionsRequired": ["KHR_mesh_quantization"],
            "buffers": [{"byteLength": 36, "uri": "data:application/octet-stream;base64,\
                AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}],
            "bufferViews": [{"buffer": 0, "byteLength": 36}],
            "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                           "min": [0, 0, 0], "max": [1, 1, 0]}],
            "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
            "nodes": [{"mesh": 0}],
        });
        std::fs::write(&path, serde_json::to_vec(&gltf).unwrap()).unwrap();
        let text = scene_info_text(&SceneSource::File(path)).unwrap();
        assert!(
            text.contains(
                "extensions: 3\n  KHR_mesh_quantization, required: read\n  \
                 KHR_texture_basisu: not read (cannot change AO)\n  \
                 VENDOR_made_up: not read (unknown to aograph)\n"
            ),
            "{text}"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}
