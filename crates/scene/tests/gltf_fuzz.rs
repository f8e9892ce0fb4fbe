//! Loading corrupted glTF files returns errors (or a scene), never panics. Deterministic: the
//! corruptions come from a fixed-seed generator.

use aograph_scene::{export_glb, load_scene, procedural_scene};
use serde_json::Value;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::Path;

/// A small deterministic generator (64-bit LCG, high bits).
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> u64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        self.0 >> 33
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

/// Every (pointer, value) leaf of a JSON document.
fn leaves(value: &Value, pointer: String, out: &mut Vec<String>) {
    match value {
        Value::Object(map) => map
            .iter()
            .for_each(|(k, v)| leaves(v, format!("{pointer}/{k}"), out)),
        Value::Array(items) => items
            .iter()
            .enumerate()
            .for_each(|(i, v)| leaves(v, format!("{pointer}/{i}"), out)),
        _ => out.push(pointer),
    }
}

fn load_must_not_panic(path: &Path, what: &str) {
    let result = catch_unwind(AssertUnwindSafe(|| load_scene(path)));
    assert!(result.is_ok(), "loading panicked after {what}");
}

#[test]
fn structurally_corrupted_gltf_never_panics() {
    let dir = std::env::temp_dir().join(format!("aograph-scene-fuzz-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let glb = dir.join("base.glb");
    export_glb(&procedural_scene("cornell-box").unwrap(), &glb).unwrap();
    let bytes = std::fs::read(&glb).unwrap();
    let json_len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let mut json: Value = serde_json::from_slice(&bytes[20..20 + json_len]).unwrap();
    let bin = bytes[20 + json_len + 8..].to_vec();
    json["buffers"][0]["uri"] = Value::from("base.bin");
    std::fs::write(dir.join("base.bin"), &bin).unwrap();
    let mut pointers = Vec::new();
    leaves(&json, String::new(), &mut pointers);
    let replacements = [
        Value::from(0),
        Value::from(1),
        Value::from(-1),
        Value::from(3),
        Value::from(4_000_000_000u64),
        Value::from(0.5),
        Value::from(f64::MAX),
        Value::from("x"),
        Value::Null,
    ];
    let mut rng = Lcg(0x5eed);
    let target = dir.join("mutated.gltf");
    for round in 0..400 {
        let mut mutated = json.clone();
        let mut described = Vec::new();
        for _ in 0..1 + rng.below(3) {
            let pointer = &pointers[rng.below(pointers.len())];
            let value = replacements[rng.below(replacements.len())].clone();
            if let Some(slot) = mutated.pointer_mut(pointer) {
                described.push(format!("{pointer} = {value}"));
                *slot = value;
            }
        }
        std::fs::write(&target, serde_json::to_vec(&mutated).unwrap()).unwrap();
        load_must_not_panic(&target, &format!("round {round}: {}", described.join(", ")));
    }
    // Byte-level corruption of the binary container and its BIN chunk.
    let target = dir.join("mutated.glb");
    for round in 0..300 {
        let mut corrupted = bytes.clone();
        for _ in 0..1 + rng.below(4) {
            let at = rng.below(corrupted.len());
            corrupted[at] = rng.next() as u8;
        }
        if rng.below(4) == 0 {
            corrupted.truncate(rng.below(corrupted.len()));
        }
        std::fs::write(&target, &corrupted).unwrap();
        load_must_not_panic(&target, &format!("glb round {round}"));
    }
    let _ = std::fs::remove_dir_all(&dir);
}
