//! Helpers shared by the scene crate's test files: a deterministic generator, a per-test
//! temporary folder, the base64 of a .gltf's embedded buffer, gltfpack, and hand-written files
//! (sparse accessors, a plain triangle).
#![allow(dead_code)] // each test file uses some of them

use glam::Vec3;
use serde_json::{Value, json};
use std::path::{Path, PathBuf};
use std::process::Command;

/// A fresh folder for `test` under the system's temporary directory (per process).
pub fn temp_dir(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("aograph-scene-{test}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Standard base64 (RFC 4648, with padding), for `data:` URIs.
pub fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for chunk in bytes.chunks(3) {
        let b = [
            chunk[0],
            *chunk.get(1).unwrap_or(&0),
            *chunk.get(2).unwrap_or(&0),
        ];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for k in 0..4 {
            if k <= chunk.len() {
                out.push(ALPHABET[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

/// Runs gltfpack with `args` on `input`, writing `output`; `None` (the test skips) when
/// gltfpack is not installed, unless AOGRAPH_REQUIRE_GLTFPACK=1.
pub fn gltfpack(input: &Path, output: &Path, args: &[&str]) -> Option<()> {
    let run = Command::new("gltfpack")
        .args(args)
        .arg("-i")
        .arg(input)
        .arg("-o")
        .arg(output)
        .output();
    match run {
        Ok(out) => {
            assert!(
                out.status.success(),
                "gltfpack {args:?} failed: {}",
                String::from_utf8_lossy(&out.stderr)
            );
            Some(())
        }
        Err(e) => {
            assert!(
                std::env::var("AOGRAPH_REQUIRE_GLTFPACK").as_deref() != Ok("1"),
                "gltfpack is required (AOGRAPH_REQUIRE_GLTFPACK=1) but could not run: {e}; \
                 install it with scripts/ensure-gltfpack.sh"
            );
            eprintln!(
                "skipping: gltfpack is not installed ({e}); scripts/ensure-gltfpack.sh installs it"
            );
            None
        }
    }
}

/// Writes `gltf` as `{test}.gltf` in the test's folder, buffer 0 being `bytes` as a data URI.
pub fn write_gltf(test: &str, mut gltf: Value, bytes: &[u8]) -> PathBuf {
    gltf["asset"] = json!({"version": "2.0"});
    gltf["buffers"] = json!([{
        "byteLength": bytes.len(),
        "uri": format!("data:application/octet-stream;base64,{}", base64(bytes)),
    }]);
    let path = temp_dir(test).join(format!("{test}.gltf"));
    std::fs::write(&path, serde_json::to_vec_pretty(&gltf).unwrap()).unwrap();
    path
}

/// Little-endian bytes of `values`.
pub fn f32_bytes(values: &[f32]) -> Vec<u8> {
    values.iter().flat_map(|v| v.to_le_bytes()).collect()
}

/// A triangle whose POSITION accessor has no buffer view (zeros) and a sparse part setting
/// vertices 1 and 2 to (1, 0, 0) and (0, 2, 0); its indices are a base of [0, 0, 0] with a
/// sparse part setting entries 1 and 2 to 1 and 2; its NORMAL accessor is zeros only.
pub fn sparse_triangle() -> (Value, Vec<u8>) {
    let mut bytes = vec![1u8, 2, 0, 0]; // sparse position indices (u8) 1, 2; padding
    bytes.extend(f32_bytes(&[1.0, 0.0, 0.0, 0.0, 2.0, 0.0])); // at 4: sparse positions
    bytes.extend([0u8, 0, 0, 0, 0, 0, 0, 0]); // at 28: index base, u16 [0, 0, 0] + padding
    bytes.extend([1u8, 0, 2, 0]); // at 36: sparse index indices (u16) 1, 2
    bytes.extend([1u8, 0, 2, 0]); // at 40: sparse index values (u16) 1, 2
    let gltf = json!({
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 2},
            {"buffer": 0, "byteOffset": 4, "byteLength": 24},
            {"buffer": 0, "byteOffset": 28, "byteLength": 6},
            {"buffer": 0, "byteOffset": 36, "byteLength": 4},
            {"buffer": 0, "byteOffset": 40, "byteLength": 4},
        ],
        "accessors": [
            {"componentType": 5126, "count": 3, "type": "VEC3",
             "min": [0, 0, 0], "max": [1, 2, 0],
             "sparse": {"count": 2,
                        "indices": {"bufferView": 0, "componentType": 5121},
                        "values": {"bufferView": 1}}},
            {"bufferView": 2, "componentType": 5123, "count": 3, "type": "SCALAR",
             "sparse": {"count": 2,
                        "indices": {"bufferView": 3, "componentType": 5123},
                        "values": {"bufferView": 4}}},
            {"componentType": 5126, "count": 3, "type": "VEC3"},
        ],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 2}, "indices": 1}]}],
        "nodes": [{"mesh": 0}],
        "scenes": [{"nodes": [0]}],
    });
    (gltf, bytes)
}

/// One triangle of float positions (accessor 0) in scene 0, with a material of base colour
/// (0.25, 0.5, 0.75, 1), for the tests that are about something else.
pub fn material_triangle() -> (Value, Vec<u8>) {
    let bytes = f32_bytes(&[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]);
    let gltf = json!({
        "bufferViews": [{"buffer": 0, "byteLength": 36}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                       "min": [0, 0, 0], "max": [1, 1, 0]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "material": 0}]}],
        "nodes": [{"mesh": 0}],
        "scenes": [{"nodes": [0]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.25, 0.5, 0.75, 1.0]}}],
    });
    (gltf, bytes)
}

/// A small deterministic generator (64-bit LCG, high 24 bits as a float in [0, 1)), so
/// failures reproduce; the ray tests draw origins and directions from it.
pub struct Lcg(pub u64);

impl Lcg {
    pub fn next(&mut self) -> f32 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }
    pub fn vec3(&mut self) -> Vec3 {
        Vec3::new(self.next(), self.next(), self.next())
    }
    pub fn direction(&mut self) -> Vec3 {
        loop {
            let v = self.vec3() * 2.0 - Vec3::ONE;
            if let Some(d) = v.try_normalize() {
                return d;
            }
        }
    }
}
