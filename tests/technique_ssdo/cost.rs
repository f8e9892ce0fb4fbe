//! What the direct term and the bounce cost, as ratios to `ssao` (printed: speed targets live
//! in benchmarks).

use aograph_ao_passes::TechniqueRegistry;
use aograph_graph::Extent;
use aograph_scene::procedural_scene;

use super::*;

/// Per-frame times of one renderer: the technique's passes summed (names starting with
/// `technique.`), the whole frame, and each technique pass.
#[derive(Default)]
struct Times {
    technique: Vec<f64>,
    frame: Vec<f64>,
    passes: Vec<(String, Vec<f64>)>,
}

fn median(v: &[f64]) -> f64 {
    let mut v = v.to_vec();
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied().unwrap_or(f64::NAN)
}

impl Times {
    fn record(&mut self, r: &mut aograph_renderer::Renderer, technique: &str) {
        let t = r.timings().unwrap();
        let mine: Vec<_> = t
            .passes
            .iter()
            .filter(|(n, _)| n.starts_with(&format!("{technique}.")))
            .cloned()
            .collect();
        if mine.is_empty() {
            return; // the first frame's timings arrive a frame later
        }
        self.technique.push(mine.iter().map(|(_, ms)| ms).sum());
        self.frame.push(t.total_ms());
        for (n, ms) in mine {
            match self.passes.iter_mut().find(|(p, _)| *p == n) {
                Some((_, v)) => v.push(ms),
                None => self.passes.push((n, vec![ms])),
            }
        }
    }
    fn passes(&self) -> String {
        self.passes
            .iter()
            .map(|(n, v)| format!("{n} {:.3}", median(v)))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

#[test]
fn cost_of_the_direct_term_and_the_bounce_relative_to_ssao() {
    assert!(
        TechniqueRegistry::with_builtins().get("ssao").is_ok(),
        "ssao is a built-in technique: the cost ratios need it"
    );
    const FRAMES: usize = 24;
    let size = Extent::new(128, 128);
    for samples in [8, 16] {
        let n = format!("samples = {samples}");
        // The three run frame by frame in turn, so load on the (shared) machine hits all alike.
        let mut runs = Vec::new();
        for (technique, params) in [
            ("ssao", n.clone()),
            ("ssdo", format!("{n}\nbounce = false")),
            ("ssdo", n.clone()),
        ] {
            let Some(run) = common::render_ao(
                procedural_scene("columns").unwrap(),
                &common::ao_config(technique, RADIUS, &params),
                size,
                1,
            ) else {
                return;
            };
            runs.push((technique, run.renderer, Times::default()));
        }
        for _ in 0..FRAMES {
            for (technique, r, times) in runs.iter_mut() {
                r.render(0.0).unwrap();
                times.record(r, technique);
            }
        }
        let [ssao, direct, bounce] = [&runs[0].2, &runs[1].2, &runs[2].2];
        let ratio = |a: &Times, b: &Times| {
            median(
                &a.technique
                    .iter()
                    .zip(&b.technique)
                    .map(|(x, y)| x / y)
                    .collect::<Vec<_>>(),
            )
        };
        let fps_drop = |a: &Times| {
            median(
                &a.frame
                    .iter()
                    .zip(&ssao.frame)
                    .map(|(x, y)| 1.0 - y / x)
                    .collect::<Vec<_>>(),
            ) * 100.0
        };
        let device = aograph_graph::test_gpu()
            .map(|g| g.describe())
            .unwrap_or_default();
        println!(
            "cost on columns {size}, N = {samples}, medians over {} interleaved frames on {device}:",
            ssao.technique.len()
        );
        println!(
            "  ssao                {:.3} ms, frame {:.3} ms [{}]",
            median(&ssao.technique),
            median(&ssao.frame),
            ssao.passes()
        );
        println!(
            "  ssdo without bounce {:.3} ms = {:.2} x ssao, frame {:.3} ms (fps -{:.1}%) [{}]",
            median(&direct.technique),
            ratio(direct, ssao),
            median(&direct.frame),
            fps_drop(direct),
            direct.passes()
        );
        println!(
            "  ssdo with bounce    {:.3} ms = {:.2} x ssao, frame {:.3} ms (fps -{:.1}%) [{}]",
            median(&bounce.technique),
            ratio(bounce, ssao),
            median(&bounce.frame),
            fps_drop(bounce),
            bounce.passes()
        );
        println!(
            "  the bounce alone: {:.2} x ssao; the paper (Table 1, fps drop of the whole frame against SSAO): 3.6% direct, 31.1% with the bounce",
            ratio(bounce, ssao) - ratio(direct, ssao)
        );
        assert!(
            ssao.technique.len() + 1 >= FRAMES
                && median(&ssao.technique) > 0.0
                && median(&bounce.technique) > 0.0,
            "timings were measured"
        );
    }
}
