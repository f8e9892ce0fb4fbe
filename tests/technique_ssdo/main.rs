//! `ssdo`: the g-buffer writes colour and direct light only for SSDO (GPU-free); on the GPU, no
//! self-occlusion on a plane, valid outputs, colour bleeding from the Cornell box's red wall
//! onto the floor (and none without the bounce), accessibility against the reference next to
//! `ssao` at the same N, `aograph render` writing the radiance PNGs, and the cost of the direct
//! term and of the bounce as ratios to `ssao` (printed; speed targets live in benchmarks).
//!
//! Files: `outputs.rs` (the g-buffer's channels, a plane's known radiance, valid outputs, the
//! render command), `bounce.rs` (colour bleeding in the Cornell box, accessibility next to
//! `ssao`), `cost.rs` (the direct term's and the bounce's cost against `ssao`); what they
//! share is here.

#[path = "../common/mod.rs"]
mod common;

mod bounce;
mod cost;
mod outputs;

const RADIUS: f32 = 1.0;

/// Accessibility valid, radiance finite, non-negative and zero on sky.
fn assert_valid(run: &common::AoRun, what: &str) {
    common::assert_valid_ao(&run.ao, &run.depth, what);
    for name in [
        aograph_ao_passes::techniques::ssdo::DIRECT_OUTPUT,
        aograph_ao_passes::techniques::ssdo::INDIRECT_OUTPUT,
    ] {
        let rgba = run
            .renderer
            .read_extra(name)
            .expect("extra output reads back");
        assert_eq!(
            rgba.len(),
            run.depth.len() * 4,
            "{what}: {name} is full size"
        );
        for (i, (px, d)) in rgba.chunks_exact(4).zip(&run.depth).enumerate() {
            assert!(
                px.iter().all(|v| v.is_finite() && *v >= 0.0),
                "{what}: {name} pixel {i} = {px:?}"
            );
            if *d <= 0.0 {
                assert_eq!(&px[..3], &[0.0; 3], "{what}: {name} sky pixel {i}");
            }
        }
    }
}
