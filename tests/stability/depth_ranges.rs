//! Near and far planes, depth formats, reversed-Z and orthographic projections.

use std::time::Instant;

use aograph_ao_passes::IntermediateFormat;
use aograph_frame::DepthFormat;
use aograph_graph::test_gpu;
use aograph_scene::{Camera, Projection};
use glam::Vec3;

use super::*;

/// Near planes 1e-4..10 and far planes 10..1e7 on the occluders (valid) and on open floor (flat).
/// The near/far sweep; returns the frame of the occluders at near 0.05, far 1e4 (the baseline
/// of the depth-format invariance).
fn depth_range_cases(rig: &mut Rig, report: &mut Report) -> Option<Vec<f32>> {
    let mut baseline = None;
    for near in [1e-4, 1e-3, 1e-2, 0.1, 1.0, 10.0] {
        // Near 10 clips the box and column (about 8 units away): only the floor is left.
        rig.case(
            report,
            &format!("near {near:e}, far 1e4, occluders"),
            with_planes(occluders(1.0, Vec3::ZERO), near, 1e4),
            SIZE,
            1,
            FRAME,
            if near < 10.0 {
                Expect::Occluded
            } else {
                Expect::Valid
            },
        );
        // The open floor seen from 3 units up: near 10 clips the floor nearer than 10.
        rig.case(
            report,
            &format!("near {near:e}, far 1e4, open floor"),
            with_planes(open_floor(1.0, Vec3::ZERO), near, 1e4),
            SIZE,
            1,
            FRAME,
            Expect::Flat,
        );
    }
    for far in [10.0, 100.0, 1e4, 1e5, 1e7] {
        let frame = rig.case(
            report,
            &format!("near 0.05, far {far:e}, occluders"),
            with_planes(occluders(1.0, Vec3::ZERO), 0.05, far),
            SIZE,
            1,
            FRAME,
            Expect::Occluded,
        );
        if far == 1e4 {
            baseline = frame;
        }
        rig.case(
            report,
            &format!("near 0.05, far {far:e}, open floor"),
            with_planes(open_floor(1.0, Vec3::ZERO), 0.05, far),
            SIZE,
            1,
            FRAME,
            Expect::Flat,
        );
    }
    rig.case(
        report,
        "near 1e-4, far 1e7, occluders",
        with_planes(occluders(1.0, Vec3::ZERO), 1e-4, 1e7),
        SIZE,
        1,
        FRAME,
        Expect::Occluded,
    );
    rig.case(
        report,
        "near 1e-4, far 1e7, open floor",
        with_planes(open_floor(1.0, Vec3::ZERO), 1e-4, 1e7),
        SIZE,
        1,
        FRAME,
        Expect::Flat,
    );
    for (near, far) in [(1e-4, 1e7), (0.01, 100.0), (1.0, 1e4)] {
        rig.case(
            report,
            &format!("near {near:e}, far {far:e}, plane at 89.9 degrees"),
            with_planes(grazing(1.0, Vec3::ZERO), near, far),
            SIZE,
            1,
            FRAME,
            Expect::Flat,
        );
    }
    baseline
}

#[test]
fn depth_ranges_formats_and_projections() {
    let Some(gpu) = test_gpu() else { return };
    let started = Instant::now();
    let mut report = Report::default();
    let mut invariance = Invariance::default();
    for v in &variants() {
        let mut rig = Rig::new(
            &gpu,
            &mut report,
            v,
            "box-on-plane (Depth32Float)",
            box_scene(1.0, Vec3::ZERO, false, false),
            1.0,
            DepthFormat::Depth32Float,
        );
        let depth32 = depth_range_cases(&mut rig, &mut report);
        let ortho = Camera {
            projection: Projection::Orthographic {
                height: 8.0,
                near: 0.05,
                far: 1000.0,
            },
            ..occluders(1.0, Vec3::ZERO)
        };
        rig.case(
            &mut report,
            "orthographic, occluders",
            ortho,
            SIZE,
            1,
            FRAME,
            Expect::Valid,
        );
        // The scene's camera is not reversed; a frame's camera may be (the g-buffer switches
        // its depth test per frame).
        let a = occluders(1.0, Vec3::ZERO);
        let pair = rig.same_surfaces(
            &mut report,
            "reversed-Z camera on a scene whose camera is not",
            a,
            reversed(a),
        );
        invariance.check(
            &mut report,
            format!("{}: reversed-Z camera against the plain one", v.label()),
            pair.as_ref().map(|p| p.1.as_slice()),
            pair.as_ref().map(|p| p.0.as_slice()),
            TOL_REVERSED_Z,
        );
        let ortho = Camera {
            projection: Projection::Orthographic {
                height: 8.0,
                near: 0.05,
                far: 1000.0,
            },
            ..open_floor(1.0, Vec3::ZERO)
        };
        rig.case(
            &mut report,
            "orthographic, open floor",
            ortho,
            SIZE,
            1,
            FRAME,
            Expect::Flat,
        );

        let mut rig = Rig::new(
            &gpu,
            &mut report,
            v,
            "box-on-plane (Depth24Plus)",
            box_scene(1.0, Vec3::ZERO, false, false),
            1.0,
            DepthFormat::Depth24Plus,
        );
        let depth24 = depth_range_cases(&mut rig, &mut report);
        invariance.check(
            &mut report,
            format!("{}: Depth24Plus against Depth32Float", v.label()),
            depth24.as_deref(),
            depth32.as_deref(),
            TOL_DEPTH24,
        );

        // The other intermediate precision (the rest of the suite runs the default).
        let other = match IntermediateFormat::default() {
            IntermediateFormat::R16Float => IntermediateFormat::R32Float,
            IntermediateFormat::R32Float => IntermediateFormat::R16Float,
        };
        let mut rig = Rig::with_format(
            &gpu,
            &mut report,
            v,
            &format!("box-on-plane ({other:?} intermediates)"),
            box_scene(1.0, Vec3::ZERO, false, false),
            1.0,
            DepthFormat::Depth32Float,
            other,
        );
        depth_range_cases(&mut rig, &mut report);

        // The g-buffer clears depth to 0 and tests Greater when the scene's camera is reversed.
        let mut rig = Rig::new(
            &gpu,
            &mut report,
            v,
            "box-on-plane (reversed-Z infinite)",
            box_scene(1.0, Vec3::ZERO, false, true),
            1.0,
            DepthFormat::Depth32Float,
        );
        for near in [1e-4, 0.05, 1.0] {
            rig.case(
                &mut report,
                &format!("reversed-Z infinite, near {near:e}, occluders"),
                with_planes(reversed(occluders(1.0, Vec3::ZERO)), near, 0.0),
                SIZE,
                1,
                FRAME,
                Expect::Valid,
            );
            rig.case(
                &mut report,
                &format!("reversed-Z infinite, near {near:e}, open floor"),
                with_planes(reversed(open_floor(1.0, Vec3::ZERO)), near, 0.0),
                SIZE,
                1,
                FRAME,
                Expect::Flat,
            );
            rig.case(
                &mut report,
                &format!("reversed-Z infinite, near {near:e}, plane at 89.9 degrees"),
                with_planes(reversed(grazing(1.0, Vec3::ZERO)), near, 0.0),
                SIZE,
                1,
                FRAME,
                Expect::Flat,
            );
        }
        let a = occluders(1.0, Vec3::ZERO);
        let pair = rig.same_surfaces(
            &mut report,
            "plain camera on a reversed-Z scene",
            reversed(a),
            a,
        );
        invariance.check(
            &mut report,
            format!(
                "{}: plain camera on a reversed-Z scene against reversed",
                v.label()
            ),
            pair.as_ref().map(|p| p.1.as_slice()),
            pair.as_ref().map(|p| p.0.as_slice()),
            TOL_REVERSED_Z,
        );
        let mut rig = Rig::new(
            &gpu,
            &mut report,
            v,
            "box-on-plane (reversed-Z, Depth24Plus)",
            box_scene(1.0, Vec3::ZERO, false, true),
            1.0,
            DepthFormat::Depth24Plus,
        );
        rig.case(
            &mut report,
            "reversed-Z infinite, occluders",
            reversed(occluders(1.0, Vec3::ZERO)),
            SIZE,
            1,
            FRAME,
            Expect::Valid,
        );
        rig.case(
            &mut report,
            "reversed-Z infinite, open floor",
            reversed(open_floor(1.0, Vec3::ZERO)),
            SIZE,
            1,
            FRAME,
            Expect::Flat,
        );
    }
    invariance.print("depth_ranges_formats_and_projections");
    // Per technique variant: 101 cases and 3 invariance checks (Depth24Plus and the two
    // reversed-Z pairs).
    report.finish(
        "depth_ranges_formats_and_projections",
        started,
        104 * variants().len(),
    );
}
