//! Intermediate precision (issue 9): every registered technique on `columns` at 128x96 with
//! `intermediate_format = "r32float"` and `"r16float"`, each against the ray-traced reference
//! (binary, R = 1) and against each other. Prints the table for docs/results/reference.md and
//! checks that the default `IntermediateFormat` is the cheapest format losing under 0.002 MAE
//! for every technique ("loss" = the MAE between the two precisions' outputs, which bounds the
//! change of the MAE against the reference). Also checks on the device that r16float storage
//! works: the half-precision frames must render without a wgpu error and be valid.

mod common;

use std::sync::Arc;

use aograph_ao_passes::{AoConfig, IntermediateFormat, TechniqueRegistry};
use aograph_graph::{Extent, test_gpu};
use aograph_renderer::FrameOutputs;
use aograph_renderer::Renderer;
use aograph_scene::procedural_scene;

const SIZE: Extent = Extent {
    width: 128,
    height: 96,
};
const RADIUS: f32 = 1.0;
/// Rays per pixel of the reference.
const RAYS: u32 = 256;
/// Frames rendered per run: temporal techniques accumulate on the static camera.
const FRAMES: u32 = 8;
/// The loss a cheaper default may cost (issue 9).
const MAX_LOSS: f32 = 0.002;

fn render(technique: &str, format: IntermediateFormat) -> Option<Renderer> {
    let gpu = test_gpu()?;
    let config = AoConfig {
        intermediate_format: format,
        ..common::ao_config(technique, RADIUS, "")
    };
    let registry = TechniqueRegistry::with_builtins();
    let outputs = FrameOutputs {
        linear_depth: true,
        ..Default::default()
    };
    let scene = Arc::new(procedural_scene("columns").unwrap());
    let _ = gpu.take_errors();
    let mut r = Renderer::new(
        gpu.clone(),
        aograph::shader_library(),
        &registry,
        scene,
        &config,
        outputs,
        SIZE,
    )
    .unwrap_or_else(|e| panic!("{technique} {format:?}: {e}"));
    for _ in 0..FRAMES {
        r.render(0.0)
            .unwrap_or_else(|e| panic!("{technique} {format:?}: {e}"));
    }
    let errors = gpu.take_errors();
    assert!(
        errors.is_empty(),
        "{technique} {format:?}: wgpu errors {errors:?}"
    );
    Some(r)
}

fn mae(a: &[f32], b: &[f32], depth: &[f32]) -> f64 {
    let (sum, n) = a
        .iter()
        .zip(b)
        .zip(depth)
        .filter(|(_, d)| **d > 0.0)
        .fold((0.0f64, 0usize), |(s, n), ((x, y), _)| {
            (s + (x - y).abs() as f64, n + 1)
        });
    sum / n.max(1) as f64
}

#[test]
fn r16float_intermediates_against_r32float_on_columns() {
    let registry = TechniqueRegistry::with_builtins();
    let mut rows = Vec::new();
    let mut worst: f64 = 0.0;
    for name in registry.names() {
        let Some(full) = render(&name, IntermediateFormat::R32Float) else {
            return;
        };
        let Some(half) = render(&name, IntermediateFormat::R16Float) else {
            return;
        };
        let (a32, a16) = (full.read_ao().unwrap(), half.read_ao().unwrap());
        let depth = full.read_linear_depth().unwrap();
        common::assert_valid_ao(&a32, &depth, &format!("{name} r32float"));
        common::assert_valid_ao(
            &a16,
            &half.read_linear_depth().unwrap(),
            &format!("{name} r16float"),
        );
        let run = common::AoRun {
            ao: a32.clone(),
            depth: depth.clone(),
            renderer: full,
        };
        let reference = common::reference(&run, RADIUS, RAYS);
        let (m32, m16, loss) = (
            mae(&a32, &reference, &depth),
            mae(&a16, &reference, &depth),
            mae(&a16, &a32, &depth),
        );
        let max_diff = a16
            .iter()
            .zip(&a32)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0f32, f32::max);
        worst = worst.max(loss);
        rows.push(format!(
            "| `{name}` | {m32:.4} | {m16:.4} | {:+.5} | {loss:.5} | {max_diff:.4} |",
            m16 - m32
        ));
    }
    println!(
        "columns, {}x{}, R = {RADIUS}, binary reference with {RAYS} rays, {FRAMES} frames (static camera):\n",
        SIZE.width, SIZE.height
    );
    println!(
        "| technique | MAE r32float | MAE r16float | change | MAE r16 vs r32 (loss) | max abs diff |"
    );
    println!("|---|---|---|---|---|---|");
    for r in &rows {
        println!("{r}");
    }
    let cheapest = if worst < MAX_LOSS as f64 {
        IntermediateFormat::R16Float
    } else {
        IntermediateFormat::R32Float
    };
    println!(
        "\nworst loss {worst:.5} (limit {MAX_LOSS}): the cheapest format within it is {cheapest:?}"
    );
    assert_eq!(
        AoConfig::default().intermediate_format,
        cheapest,
        "the default intermediate format must be the cheapest that loses under {MAX_LOSS} MAE for every technique (worst loss {worst:.5})"
    );
}
