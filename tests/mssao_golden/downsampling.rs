//! Table 2's continuity test as aograph states it: the spread of a 2x2 block about the
//! median's plane, not the depth range (crates/ao-passes/src/techniques/mssao.rs, "At every
//! output size").

use super::*;

#[test]
fn downsampling_tests_the_spread_about_the_medians_plane_not_the_depth_range() {
    // 4x2 -> 2x1. Both blocks span more than d_threshold = 1 in depth, which Table 2's range
    // test calls a discontinuity. Block (0, 0) is a shallow crease (depths 2.3, 2.6, 3.2, 3.5,
    // every sub-pixel within 0.9 of the median's plane, seen through the 60-degree camera's
    // pixel rays): the median, whose normal is the mean
    // of (0, 0.6, 0.8) and (0, 0, 1). Block (1, 0) is a step (2.0, 2.1 | 4.0, 4.1): the
    // second-nearest (2.1) as it is, normal (0.6, 0, 0.8).
    let mut g = GBuffer::sky(4, 2);
    let mut put =
        |bx: usize, i: usize, z: f32, n: V3| g.set(2 * bx + (i & 1), i >> 1, [0.0, 0.0, -z], n);
    put(0, 0, 2.3, [0.0, 0.0, 1.0]);
    put(0, 1, 2.6, [0.0, 0.6, 0.8]);
    put(0, 2, 3.2, [0.0, 0.0, 1.0]);
    put(0, 3, 3.5, [0.0, 0.0, 1.0]);
    put(1, 0, 2.0, [0.0, 0.0, 1.0]);
    put(1, 1, 2.1, [0.6, 0.0, 0.8]);
    put(1, 2, 4.0, [0.0, 0.0, 1.0]);
    put(1, 3, 4.1, [0.0, 0.0, 1.0]);
    let Some(mut m) = Mssao::new(4, 2, 1.0, "levels = 2\nd_threshold = 1.0") else {
        return;
    };
    m.frame(&g, front_camera());
    let l1 = m.level(1, &g);
    let mean = 1.8f32.hypot(0.6);
    let want_n: [V3; 2] = [[0.0, 0.6 / mean, 1.8 / mean], [0.6, 0.0, 0.8]];
    for c in 0..3 {
        let want: Vec<f32> = want_n.iter().map(|n| n[c]).collect();
        assert_within(
            &channel(&l1.n, c),
            &want,
            |_| 2e-4,
            &format!("normals[{c}]"),
        );
    }
    // And the whole level is the CPU mirror's, depths included.
    let cpu = downsample(&m.level(0, &g), 1.0, &m.grid(0), &m.grid(1));
    assert_eq!(l1.z, cpu.z, "depths");
}
