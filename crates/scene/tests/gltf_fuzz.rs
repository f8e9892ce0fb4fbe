//! Loading corrupted glTF files returns errors (or a scene), never panics, and what comes back
//! is checked: a scene that loads keeps every invariant of the scene model
//! (`Scene::check_invariants`: in-range indices, finite positions, unit normals, valid mesh and
//! material references); an error is one of the loader's variants for a bad file and names the
//! file. The share of each outcome is reported and bounded from below, so the mutations keep
//! reaching past the JSON parser into validation, buffers and geometry. Deterministic: the
//! corruptions come from a fixed-seed generator.

use aograph_scene::{SceneError, export_glb, load_scene, procedural_scene};
use serde_json::Value;
use std::collections::BTreeMap;
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

/// Loads `path` (which must not panic), checks the outcome and returns its kind.
fn load_and_check(path: &Path, what: &str) -> &'static str {
    let result = catch_unwind(AssertUnwindSafe(|| load_scene(path)));
    let Ok(result) = result else {
        panic!("loading panicked after {what}");
    };
    match result {
        Ok(scene) => {
            if let Err(e) = scene.check_invariants() {
                panic!("a scene loaded after {what} breaks an invariant: {e}");
            }
            "loaded"
        }
        Err(e) => {
            let message = e.to_string();
            let name = path.file_name().unwrap().to_string_lossy();
            assert!(
                message.contains(&*name),
                "the error after {what} does not name the file: {message}"
            );
            match e {
                SceneError::MalformedJson { .. } => "malformed JSON",
                SceneError::InvalidGltf { .. } => "invalid glTF",
                SceneError::MissingBuffer { .. } => "missing buffer",
                SceneError::NonFiniteVertex { .. } => "non-finite vertex",
                SceneError::EmptyScene { .. } => "no triangles",
                other => panic!("unexpected error variant after {what}: {other:?}"),
            }
        }
    }
}

/// Prints the outcome shares and checks each named one reached at least `min` of the rounds.
fn assert_shares(
    kind: &str,
    counts: &BTreeMap<&'static str, usize>,
    rounds: usize,
    min: &[(&str, f64)],
) {
    let shares: Vec<String> = counts
        .iter()
        .map(|(k, n)| format!("{k} {:.1}%", 100.0 * *n as f64 / rounds as f64))
        .collect();
    eprintln!("{kind}, {rounds} rounds: {}", shares.join(", "));
    for (outcome, share) in min {
        let got = counts.get(outcome).copied().unwrap_or(0) as f64 / rounds as f64;
        assert!(
            got >= *share,
            "{kind}: {outcome} in {:.1}% of rounds, expected at least {:.1}%",
            100.0 * got,
            100.0 * share
        );
    }
}

/// Floors of the outcome shares, about half the measured ones (JSON leaf mutations: malformed
/// JSON 63.8%, loaded 20.0%, invalid glTF 16.2%; glb byte corruption: malformed JSON 72.0%,
/// invalid glTF 23.7%, loaded 4.0%, non-finite vertex 0.3%): a generator that stopped reaching
/// validation or loading would fail them.
const MIN_JSON_SHARES: [(&str, f64); 3] = [
    ("malformed JSON", 0.30),
    ("loaded", 0.10),
    ("invalid glTF", 0.08),
];
const MIN_GLB_SHARES: [(&str, f64); 3] = [
    ("malformed JSON", 0.35),
    ("invalid glTF", 0.10),
    ("loaded", 0.02),
];

#[test]
fn a_node_transform_that_overflows_f32_is_an_error_naming_the_node() {
    // Found by the checks below: a matrix entry of f64::MAX became an infinite instance
    // transform that loaded.
    let dir = std::env::temp_dir().join(format!("aograph-scene-overflow-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let glb = dir.join("base.glb");
    export_glb(&procedural_scene("stairs").unwrap(), &glb).unwrap();
    let bytes = std::fs::read(&glb).unwrap();
    let json_len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let mut json: Value = serde_json::from_slice(&bytes[20..20 + json_len]).unwrap();
    std::fs::write(dir.join("base.bin"), &bytes[20 + json_len + 8..]).unwrap();
    json["buffers"][0]["uri"] = Value::from("base.bin");
    let node = json["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .position(|n| n.get("mesh").is_some())
        .unwrap();
    json["nodes"][node]["matrix"] = Value::from(vec![
        1e39f64, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0,
    ]);
    json["nodes"][node]
        .as_object_mut()
        .unwrap()
        .remove("translation");
    json["nodes"][node]
        .as_object_mut()
        .unwrap()
        .remove("rotation");
    json["nodes"][node].as_object_mut().unwrap().remove("scale");
    let target = dir.join("overflow.gltf");
    std::fs::write(&target, serde_json::to_vec(&json).unwrap()).unwrap();
    let e = load_scene(&target).unwrap_err().to_string();
    assert!(
        e.contains("overflow.gltf")
            && e.contains(&format!("node {node}"))
            && e.contains("not finite"),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn structurally_corrupted_gltf_never_panics_and_every_outcome_is_checked() {
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
    let mut counts: BTreeMap<&'static str, usize> = BTreeMap::new();
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
        let outcome = load_and_check(&target, &format!("round {round}: {}", described.join(", ")));
        *counts.entry(outcome).or_default() += 1;
    }
    // Measured shares are printed; the floors sit at about half of them.
    assert_shares("JSON leaf mutations", &counts, 400, &MIN_JSON_SHARES);
    // Byte-level corruption of the binary container and its BIN chunk.
    let target = dir.join("mutated.glb");
    let mut counts: BTreeMap<&'static str, usize> = BTreeMap::new();
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
        let outcome = load_and_check(&target, &format!("glb round {round}"));
        *counts.entry(outcome).or_default() += 1;
    }
    assert_shares("glb byte corruption", &counts, 300, &MIN_GLB_SHARES);
    let _ = std::fs::remove_dir_all(&dir);
}
