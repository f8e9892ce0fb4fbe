//! GPU-free checks of `mssao`: the plan's passes by name for 1, 4 and 8 levels (compiled
//! against the real WGSL, so bindings and formats are checked too), parameter validation and
//! the uniform layout.

use aograph_frame::GBufferChannel;
use aograph_graph::{CompiledGraph, ShaderLibrary};

use super::passes::MssaoUniform;
use super::{Mssao, MssaoParams};
use crate::contract::compile_plan;
use crate::technique::AoTechnique;
use crate::{AoError, TechniqueRegistry};

fn shaders() -> ShaderLibrary {
    crate::shader_library().unwrap()
}

/// The compiled plan of `mssao` with `params` over an imported g-buffer.
fn plan(params: &str) -> Result<CompiledGraph, AoError> {
    let table: toml::Table = params.parse().expect("test TOML");
    let registry = TechniqueRegistry::with_builtins();
    let technique = registry.get(Mssao::NAME)?.clone().configure(&table)?;
    compile_plan(
        technique.as_ref(),
        &shaders(),
        wgpu::TextureFormat::R32Float,
    )
}

fn expected(levels: u32) -> Vec<String> {
    let mut names: Vec<String> = (1..levels)
        .map(|l| format!("mssao.downsample{l}"))
        .collect();
    for l in (1..levels).rev() {
        names.push(format!("mssao.ao{l}"));
        names.push(format!("mssao.blur{l}"));
    }
    names.push("mssao.ao0".into());
    names
}

#[test]
fn plan_has_one_downsample_and_one_ao_pass_per_level_and_the_upsample_chain() {
    let four = plan("").unwrap();
    assert_eq!(
        four.pass_names(),
        [
            "mssao.downsample1",
            "mssao.downsample2",
            "mssao.downsample3",
            "mssao.ao3",
            "mssao.blur3",
            "mssao.ao2",
            "mssao.blur2",
            "mssao.ao1",
            "mssao.blur1",
            "mssao.ao0"
        ]
    );
    let one = plan("levels = 1").unwrap();
    assert_eq!(one.pass_names(), ["mssao.ao0"]);
    let eight = plan("levels = 8").unwrap();
    assert_eq!(eight.pass_names(), expected(8));
    assert_eq!(eight.pass_names().len(), 7 + 8 + 7);
    for p in [&one, &four, &eight] {
        assert!(
            p.culled.is_empty(),
            "nothing is culled: {:?}",
            p.culled_names()
        );
    }
}

#[test]
fn every_level_count_compiles_against_the_shaders() {
    for levels in 1..=8 {
        let p = plan(&format!("levels = {levels}"))
            .unwrap_or_else(|e| panic!("levels = {levels}: {e}"));
        assert_eq!(p.pass_names(), expected(levels));
    }
}

#[test]
fn temporal_filter_appends_the_shared_block() {
    // The harness provides every channel asked for, motion included: no zero-motion pass.
    let p = plan("temporal = true").unwrap();
    let mut want = expected(4);
    want.extend(["mssao.temporal.reproject", "mssao.temporal.accumulate"].map(String::from));
    assert_eq!(p.pass_names(), want);
    let c = AoTechnique::channels(
        &Mssao,
        &MssaoParams {
            temporal: true,
            ..Default::default()
        },
    );
    assert!(
        c.contains(GBufferChannel::LinearDepth)
            && c.contains(GBufferChannel::Motion)
            && c.face_normals
    );
    assert!(AoTechnique::is_temporal(
        &Mssao,
        &MssaoParams {
            temporal: true,
            ..Default::default()
        }
    ));
    assert!(!AoTechnique::is_temporal(&Mssao, &MssaoParams::default()));
}

#[test]
fn defaults_are_the_papers() {
    let p = MssaoParams::default();
    assert_eq!(
        (
            p.levels,
            p.d_threshold,
            p.r_max,
            p.normal_power,
            p.depth_power,
            p.temporal,
            p.temporal_k
        ),
        (crate::Levels::Auto, 1.0, 5.0, 8.0, 16.0, false, 0.5)
    );
    assert_eq!(
        p.temporal_epsilon,
        crate::blocks::temporal::TemporalAccumulation::mssao().epsilon
    );
}

#[test]
fn reads_linear_depth_and_compact_face_normals_only() {
    let c = AoTechnique::channels(&Mssao, &MssaoParams::default());
    assert!(
        c.contains(GBufferChannel::LinearDepth)
            && c.contains(GBufferChannel::NormalsOct)
            && c.face_normals
    );
    for wide in [
        GBufferChannel::Positions,
        GBufferChannel::Normals,
        GBufferChannel::Motion,
    ] {
        assert!(!c.contains(wide), "{wide:?}");
    }
}

#[test]
fn every_pyramid_level_holds_8_bytes_a_texel() {
    // Depth (R32Float) and an octahedral normal (R32Uint) per level, g-buffer included: the
    // plan at 1024x1024 is the g-buffer's 8 MiB, a third more for the pyramid, the tuples and
    // the output (docs/results/memory.md, "Memory").
    let plan = plan("levels = 4").unwrap();
    for l in 1..4 {
        for (name, format) in [
            (format!("mssao.depth{l}"), wgpu::TextureFormat::R32Float),
            (format!("mssao.normals{l}"), wgpu::TextureFormat::R32Uint),
        ] {
            let r = plan.decl.resource_by_name(&name).expect(&name);
            assert_eq!(
                plan.decl.resources[r].texture_desc().map(|d| d.format),
                Some(format),
                "{name}"
            );
        }
    }
}

#[test]
fn uniform_block_matches_the_wgsl_struct() {
    assert_eq!(std::mem::size_of::<MssaoUniform>(), 48);
    let info = shaders().load("ao/mssao/ao_level.wgsl").unwrap();
    match &info.binding("params").unwrap().kind {
        aograph_graph::ShaderBindingKind::Uniform { size } => assert_eq!(*size, 48),
        k => panic!("{k:?}"),
    }
    let u = MssaoUniform::new(&MssaoParams::default(), 2.0, 3);
    assert_eq!(
        (u.level, u.d_max, u.r_max, u.bilateral_blur),
        (3, 2.0, 5.0, 1)
    );
}
