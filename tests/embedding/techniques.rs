//! Every screen-space technique from an application's frame on five scenes, and what normals
//! rebuilt from depth cost against the reference.

use aograph_graph::test_gpu;

use super::*;

/// How far AO from normals rebuilt from depth may move from AO from the g-buffer's normals,
/// on average over geometry and technique by technique: the rebuilt normals are the faces'
/// (exact on a plane away from edges, `reconstructed_normals_match_the_faces_away_from_depth_edges`);
/// the g-buffer's are interpolated, so the two differ across curved meshes (suzanne, the
/// columns) and at every crease and silhouette. Measured: 0.001 to 0.021 (gtao on suzanne,
/// whose interpolated normals are furthest from its faces; see the printout).
pub(crate) const RECONSTRUCTED_MEAN: f32 = 0.03;

#[test]
pub(crate) fn every_screen_space_technique_on_five_scenes_gives_the_g_buffers_ao() {
    let Some(gpu) = test_gpu() else { return };
    let mut failures = Vec::new();
    for (name, scene) in
        five_scenes("every_screen_space_technique_on_five_scenes_gives_the_g_buffers_ao")
    {
        let radius = aograph_scene::suggested_radius(&scene).radius;
        for (technique, params) in SCREEN_SPACE {
            let config = common::ao_config(technique, radius, params);
            let own = own_frame(&scene, &config, None).unwrap();
            let (given, rebuilt) = given_and_rebuilt(&gpu, &config, &own);
            failures.extend(compare(
                &format!("{name}, {technique}, normals given"),
                &given,
                &own,
                SAME_INPUTS,
            ));
            let mean = mean_diff(&rebuilt, &own.ao, &own.linear_depth);
            println!("{name}, {technique}, normals rebuilt from depth: mean difference {mean:.4}");
            if mean > RECONSTRUCTED_MEAN {
                failures.push(format!(
                    "{name}, {technique}: with normals rebuilt from depth the AO moves by \
                     {mean} on average (allowed {RECONSTRUCTED_MEAN})"
                ));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// What normals rebuilt from depth cost each technique against the ray-traced reference (the
/// MAE over geometry with aograph's own normals, with the application's given normals, and
/// with none), on the five scenes. A measurement for docs/guide/embedding.md, not a check.
#[test]
#[ignore = "measurement: cargo test --release --test embedding mae_lost -- --ignored --nocapture"]
pub(crate) fn mae_lost_with_normals_rebuilt_from_depth() {
    let Some(gpu) = test_gpu() else { return };
    println!(
        "| scene | technique | MAE, aograph's g-buffer | MAE, normals given | MAE, normals rebuilt | lost |"
    );
    println!("|---|---|---|---|---|---|");
    for (name, scene) in five_scenes("mae_lost_with_normals_rebuilt_from_depth") {
        let radius = aograph_scene::suggested_radius(&scene).radius;
        let mut reference: Option<Vec<f32>> = None;
        for (technique, params) in SCREEN_SPACE {
            let config = common::ao_config(technique, radius, params);
            let own = own_frame(&scene, &config, None).unwrap();
            let reference = reference.get_or_insert_with(|| {
                aograph_renderer::frame_reference(
                    &own.renderer,
                    &aograph_renderer::ReferenceSettings::new(radius, 256),
                    false,
                )
                .unwrap()
                .accessibility
            });
            let (given, rebuilt) = given_and_rebuilt(&gpu, &config, &own);
            let mae = |a: &[f32]| common::mae(a, reference, &own.linear_depth);
            let (m_own, m_given, m_rebuilt) = (mae(&own.ao), mae(&given), mae(&rebuilt));
            println!(
                "| {name} | {technique} | {m_own:.4} | {m_given:.4} | {m_rebuilt:.4} | {:+.4} |",
                m_rebuilt - m_given
            );
        }
    }
}
