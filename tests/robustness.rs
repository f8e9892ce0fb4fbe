//! Robustness: fuzzed configs and glTF files never panic (bounded time, fixed seed), a long run
//! with resizes does not grow the texture pool, and the same config renders bit-identically.

mod common;

use std::sync::Arc;

use aograph::{AppConfig, FrameOutputs, Renderer};
use aograph_ao::{AoConfig, TechniqueRegistry};
use aograph_graph::{Extent, test_gpu};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};

fn runner(cases: u32) -> TestRunner {
    let config = Config {
        cases,
        failure_persistence: None,
        ..Config::default()
    };
    TestRunner::new_with_rng(config, TestRng::deterministic_rng(RngAlgorithm::ChaCha))
}

/// A byte-level mutation: overwrite, insert, delete or truncate.
fn mutate(base: &[u8], ops: &[(u8, usize, u8)]) -> Vec<u8> {
    let mut v = base.to_vec();
    for &(kind, pos, byte) in ops {
        if v.is_empty() {
            v.push(byte);
            continue;
        }
        let i = pos % v.len();
        match kind % 4 {
            0 => v[i] = byte,
            1 => v.insert(i, byte),
            2 => {
                v.remove(i);
            }
            _ => v.truncate(i),
        }
    }
    v
}

#[test]
fn fuzzed_configs_never_panic() {
    let registry = TechniqueRegistry::with_builtins();
    let base = std::fs::read(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/configs/reference.toml"
    ))
    .unwrap();
    let ops = prop::collection::vec(
        (
            any::<u8>(),
            any::<usize>(),
            prop::sample::select(b"[]=\".,-0123456789aeiorstxyz_#\n ".to_vec()),
        ),
        1..8,
    );
    runner(3000)
        .run(&ops, |ops| {
            let text = String::from_utf8_lossy(&mutate(&base, &ops)).to_string();
            let _ = AppConfig::parse(&text, "fuzz.toml", &registry);
            Ok(())
        })
        .unwrap();
    // Random key/value soup too.
    let soup = prop::collection::vec(("[a-z_]{1,12}", "[-0-9a-z.\"\\[\\]]{0,8}"), 0..6);
    runner(1000)
        .run(&soup, |kv| {
            let text: String = kv.iter().map(|(k, v)| format!("{k} = {v}\n")).collect();
            let _ = AppConfig::parse(&format!("[ao]\n{text}"), "soup.toml", &registry);
            Ok(())
        })
        .unwrap();
}

#[test]
fn fuzzed_gltf_files_never_panic() {
    let dir = std::env::temp_dir().join(format!("aograph-fuzz-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let glb = dir.join("base.glb");
    aograph_scene::export_glb(
        &aograph_scene::procedural_scene("sphere-on-plane").unwrap(),
        &glb,
    )
    .unwrap();
    let glb_bytes = std::fs::read(&glb).unwrap();
    let gltf_text = std::fs::read(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../shared/scenes/suzanne.gltf"
    ))
    .ok();
    let ops = prop::collection::vec((any::<u8>(), any::<usize>(), any::<u8>()), 1..6);
    let target = dir.join("mutated.glb");
    runner(400)
        .run(&ops, |ops| {
            std::fs::write(&target, mutate(&glb_bytes, &ops)).unwrap();
            let _ = aograph_scene::load_scene(&target);
            Ok(())
        })
        .unwrap();
    if let Some(text) = gltf_text {
        let target = dir.join("mutated.gltf");
        let ops = prop::collection::vec(
            (
                any::<u8>(),
                any::<usize>(),
                prop::sample::select(b"{}[]:,\"0123456789-.e ".to_vec()),
            ),
            1..6,
        );
        runner(200)
            .run(&ops, |ops| {
                std::fs::write(&target, mutate(&text, &ops)).unwrap();
                let _ = aograph_scene::load_scene(&target);
                Ok(())
            })
            .unwrap();
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The default technique when it is registered, else `none`.
fn default_technique() -> String {
    let registry = TechniqueRegistry::with_builtins();
    let d = AoConfig::default().technique;
    if registry.get(&d).is_ok() {
        d
    } else {
        "none".into()
    }
}

#[test]
fn thousand_frames_with_resizes_do_not_grow_the_pool() {
    let Some(gpu) = test_gpu() else { return };
    let registry = TechniqueRegistry::with_builtins();
    let ao = AoConfig {
        technique: default_technique(),
        ..AoConfig::default()
    };
    let scene = Arc::new(aograph_scene::procedural_scene("columns").unwrap());
    let sizes = [Extent::new(24, 16), Extent::new(17, 11), Extent::new(32, 8)];
    let mut r = Renderer::new(
        gpu,
        aograph::shader_library(),
        &registry,
        scene,
        &ao,
        FrameOutputs {
            shaded: true,
            ..Default::default()
        },
        sizes[0],
    )
    .unwrap();
    let mut high_water = 0;
    for frame in 0..1000u32 {
        if frame % 10 == 0 {
            r.resize(sizes[(frame / 10) as usize % sizes.len()])
                .unwrap();
        }
        r.render(0.0).unwrap();
        if frame == 30 {
            high_water = r.exec.texture_count();
        }
        if frame > 30 {
            assert!(
                r.exec.texture_count() <= high_water,
                "frame {frame}: {} textures, had {high_water}",
                r.exec.texture_count()
            );
        }
    }
    assert!(r.gpu.take_errors().is_empty());
    println!(
        "pool holds {} textures (high water {high_water}), {} created over 1000 frames",
        r.exec.texture_count(),
        r.exec.pool_created_count()
    );
}

#[test]
fn same_config_renders_bit_identical_ao_png() {
    if test_gpu().is_none() {
        return;
    }
    let base = std::env::temp_dir().join(format!("aograph-determinism-{}", std::process::id()));
    let mut images = Vec::new();
    for run in 0..2 {
        let out = base.join(format!("run{run}"));
        let args = aograph::commands::RenderArgs {
            common: aograph::commands::CommonArgs {
                technique: Some(default_technique()),
                width: Some(96),
                height: Some(64),
                ..Default::default()
            },
            out: out.clone(),
            frames: Some(2),
            every: false,
        };
        aograph::commands::render(&args).unwrap();
        images.push(std::fs::read(out.join("ao.png")).unwrap());
    }
    assert_eq!(images[0], images[1]);
    let _ = std::fs::remove_dir_all(&base);
}
