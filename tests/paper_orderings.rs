//! The orderings the papers report and docs/results/paper-comparisons.md repeats, checked
//! against our reference on the same frames, on two scenes each, at R = 1 (the radius the
//! comparisons in docs/results/paper-comparisons.md use) and 128x128:
//! - Pyramid HBAO paper, Table 1: Pyramid HBAO at every L >= 3 is at least as accurate (MAE)
//!   as HBAO 32 x 40, and at L = 4 as HBAO 64 x 80, on `columns` and `sphere-on-plane`;
//! - MSSAO paper, Table 6: MSSAO beats HBAO 16 x 8 and SSAO with 32 samples in SSIM on the
//!   room-like scenes, `columns` and `corner`. The paper's third ordering, HBAO 16 x 8 above
//!   SSAO-32, does not hold here: SSAO-32's SSIM is higher on both scenes at 128x128 (columns
//!   0.617 against 0.600, corner 0.892 against 0.815; docs/results/paper-comparisons.md says
//!   so), and the test pins the measured order so a change either way is noticed.

mod common;

use aograph_bench::metrics::{MetricOptions, compare};
use aograph_graph::Extent;

const SIZE: Extent = Extent {
    width: 128,
    height: 128,
};
const RADIUS: f32 = 1.0;
const RAYS: u32 = 256;

/// (MAE, SSIM) of `technique` with `params` on `scene` against the shared reference.
fn score(scene: &str, technique: &str, params: &str) -> Option<(f64, f64)> {
    let run = common::render_ao(
        aograph_scene::procedural_scene(scene).unwrap(),
        &common::ao_config(technique, RADIUS, params),
        SIZE,
        1,
    )?;
    let reference = common::reference(&run, RADIUS, RAYS);
    let m = compare(
        &run.ao,
        &reference,
        &run.depth,
        SIZE.width,
        SIZE.height,
        &MetricOptions::default(),
    )
    .expect("same sizes");
    eprintln!(
        "{scene} {technique} [{}]: MAE {:.4}, SSIM {:.4}",
        params.replace('\n', ", "),
        m.mae,
        m.ssim
    );
    Some((m.mae, m.ssim))
}

#[test]
fn pyramid_hbao_at_three_levels_or_more_is_no_worse_than_hbao_32x40_and_l4_than_64x80() {
    let mut failures = Vec::new();
    for scene in ["columns", "sphere-on-plane"] {
        let Some((hbao_32, _)) = score(scene, "hbao", "directions = 32\nsteps = 40") else {
            return;
        };
        let Some((hbao_64, _)) = score(scene, "hbao", "directions = 64\nsteps = 80") else {
            return;
        };
        for levels in [3, 4, 5] {
            let Some((pyramid, _)) = score(scene, "pyramid-hbao", &format!("levels = {levels}"))
            else {
                return;
            };
            if pyramid > hbao_32 {
                failures.push(format!(
                    "{scene}: pyramid-hbao L = {levels} MAE {pyramid:.4} > hbao 32x40 {hbao_32:.4}"
                ));
            }
            if levels == 4 && pyramid > hbao_64 {
                failures.push(format!(
                    "{scene}: pyramid-hbao L = 4 MAE {pyramid:.4} > hbao 64x80 {hbao_64:.4}"
                ));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn mssao_beats_hbao_16x8_and_ssao_32_in_ssim_on_room_like_scenes() {
    let mut failures = Vec::new();
    for scene in ["columns", "corner"] {
        let Some((_, mssao)) = score(scene, "mssao", "levels = 4") else {
            return;
        };
        let Some((_, hbao)) = score(scene, "hbao", "directions = 16\nsteps = 8") else {
            return;
        };
        let Some((_, ssao)) = score(scene, "ssao", "samples = 32") else {
            return;
        };
        if !(mssao > hbao && mssao > ssao) {
            failures.push(format!(
                "{scene}: SSIM mssao {mssao:.4}, hbao 16x8 {hbao:.4}, ssao-32 {ssao:.4}"
            ));
        }
        // The paper has HBAO 16 x 8 above SSAO-32; measured here it is below on both scenes
        // (module docs). Pinned, so a change either way is seen.
        if hbao > ssao {
            failures.push(format!(
                "{scene}: hbao 16x8 {hbao:.4} now beats ssao-32 {ssao:.4}: update \
                 docs/results/paper-comparisons.md"
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
