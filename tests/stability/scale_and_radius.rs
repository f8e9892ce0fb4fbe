//! Scene scale, a scene far from the origin, and R from 1e-4 to far larger than the scene.

use std::time::Instant;

use aograph_frame::DepthFormat;
use aograph_graph::{Extent, test_gpu};
use glam::Vec3;

use super::*;

#[test]
fn scene_scale_offset_and_radius() {
    let Some(gpu) = test_gpu() else { return };
    let started = Instant::now();
    let mut report = Report::default();
    let mut invariance = Invariance::default();
    for v in &variants() {
        // The baseline frame: the occluders at scale 1, R = 1, at the origin.
        let baseline = Rig::new(
            &gpu,
            &mut report,
            v,
            "box-on-plane x 1 (baseline)",
            box_scene(1.0, Vec3::ZERO, false, false),
            1.0,
            DepthFormat::Depth32Float,
        )
        .case(
            &mut report,
            "occluders",
            occluders(1.0, Vec3::ZERO),
            SIZE,
            2,
            FRAME,
            Expect::Occluded,
        );
        // Scale 1e-3 to 1e4, R scaled alike: the same frame up to rounding.
        for scale in [1e-3f32, 1e-2, 0.1, 10.0, 1e2, 1e3, 1e4] {
            let mut rig = Rig::new(
                &gpu,
                &mut report,
                v,
                &format!("box-on-plane x {scale:e}"),
                box_scene(scale, Vec3::ZERO, false, false),
                scale,
                DepthFormat::Depth32Float,
            );
            let frame = rig.case(
                &mut report,
                "occluders",
                occluders(scale, Vec3::ZERO),
                SIZE,
                2,
                FRAME,
                Expect::Occluded,
            );
            invariance.check(
                &mut report,
                format!("{}: scene and R scaled by {scale:e}", v.label()),
                frame.as_deref(),
                baseline.as_deref(),
                TOL_SCALE,
            );
            rig.case(
                &mut report,
                "open floor",
                open_floor(scale, Vec3::ZERO),
                SIZE,
                2,
                FRAME,
                Expect::Flat,
            );
            rig.case(
                &mut report,
                "plane at 89.9 degrees",
                grazing(scale, Vec3::ZERO),
                SIZE,
                1,
                FRAME,
                Expect::Flat,
            );
            rig.case(
                &mut report,
                "occluders at 97x61",
                occluders(scale, Vec3::ZERO),
                Extent::new(97, 61),
                1,
                FRAME,
                Expect::Occluded,
            );
        }
        // 1e5 units from the origin on two axes.
        let offset = Vec3::new(1e5, 0.0, 1e5);
        let mut rig = Rig::new(
            &gpu,
            &mut report,
            v,
            "box-on-plane at (1e5, 0, 1e5)",
            box_scene(1.0, offset, false, false),
            1.0,
            DepthFormat::Depth32Float,
        );
        let frame = rig.case(
            &mut report,
            "occluders",
            occluders(1.0, offset),
            SIZE,
            2,
            FRAME,
            Expect::Occluded,
        );
        invariance.check(
            &mut report,
            format!("{}: scene moved to (1e5, 0, 1e5)", v.label()),
            frame.as_deref(),
            baseline.as_deref(),
            if rig.traces_geometry() {
                TOL_OFFSET_TRACED
            } else {
                TOL_OFFSET
            },
        );
        rig.case(
            &mut report,
            "open floor",
            open_floor(1.0, offset),
            SIZE,
            2,
            FRAME,
            Expect::Flat,
        );
        rig.case(
            &mut report,
            "open floor, near 1e-3 far 1e7",
            with_planes(open_floor(1.0, offset), 1e-3, 1e7),
            SIZE,
            1,
            FRAME,
            Expect::Flat,
        );
        rig.case(
            &mut report,
            "plane at 89.9 degrees",
            grazing(1.0, offset),
            SIZE,
            1,
            FRAME,
            Expect::Flat,
        );
        rig.case(
            &mut report,
            "occluders at 97x61",
            occluders(1.0, offset),
            Extent::new(97, 61),
            1,
            FRAME,
            Expect::Occluded,
        );
        // R = 1e-4: nothing can occlude, not even at the box's contact.
        let mut rig = Rig::new(
            &gpu,
            &mut report,
            v,
            "box-on-plane, R = 1e-4",
            box_scene(1.0, Vec3::ZERO, false, false),
            1e-4,
            DepthFormat::Depth32Float,
        );
        rig.case(
            &mut report,
            "occluders (R = 1e-4: no occlusion)",
            occluders(1.0, Vec3::ZERO),
            SIZE,
            2,
            FRAME,
            Expect::Flat,
        );
        rig.case(
            &mut report,
            "occluders close up (R = 1e-4: no occlusion)",
            perspective(
                Vec3::new(0.8, 0.3, 1.2),
                Vec3::new(0.0, 0.2, 0.0),
                1e-3,
                100.0,
            ),
            SIZE,
            2,
            FRAME,
            Expect::Flat,
        );
        rig.case(
            &mut report,
            "open floor",
            open_floor(1.0, Vec3::ZERO),
            SIZE,
            1,
            FRAME,
            Expect::Flat,
        );
        rig.case(
            &mut report,
            "occluders at 97x61 (R = 1e-4: no occlusion)",
            occluders(1.0, Vec3::ZERO),
            Extent::new(97, 61),
            1,
            FRAME,
            Expect::Flat,
        );
        // R from small to larger than the whole scene (the floor is 200 across).
        for radius in [1e-2f32, 10.0, 1e3, 1e6] {
            let mut rig = Rig::new(
                &gpu,
                &mut report,
                v,
                &format!("box-on-plane, R = {radius:e}"),
                box_scene(1.0, Vec3::ZERO, false, false),
                radius,
                DepthFormat::Depth32Float,
            );
            // R = 1e-2 projects to well under a pixel at 32x32: nothing visibly occludes. R of
            // 1e3 and 1e6 dwarf the scene: a technique that places its samples in view space
            // within R (ssdo) puts every sample off screen and sees nothing; valid is enough.
            let occluded = if (1.0..=10.0).contains(&radius) {
                Expect::Occluded
            } else {
                Expect::Valid
            };
            rig.case(
                &mut report,
                "occluders",
                occluders(1.0, Vec3::ZERO),
                SIZE,
                2,
                FRAME,
                occluded,
            );
            // Another view of the same scene: a cut, as the viewer makes on a jump. Without one
            // a temporal filter rightly keeps the occluders view's history of the floor points
            // both views see (Eq. 13 holds: same points, same depths), and at R >= 10 that
            // history holds the box's occlusion, which R reaches and this view cannot see.
            rig.cut();
            rig.case(
                &mut report,
                "open floor",
                open_floor(1.0, Vec3::ZERO),
                SIZE,
                2,
                FRAME,
                Expect::Flat,
            );
            rig.case(
                &mut report,
                "plane at 89.9 degrees",
                grazing(1.0, Vec3::ZERO),
                SIZE,
                1,
                FRAME,
                Expect::Flat,
            );
            rig.case(
                &mut report,
                "occluders at 97x61",
                occluders(1.0, Vec3::ZERO),
                Extent::new(97, 61),
                1,
                FRAME,
                occluded,
            );
        }
    }
    invariance.print("scene_scale_offset_and_radius");
    // Per technique variant: 68 cases and 8 invariance checks (7 scales and the offset).
    report.finish(
        "scene_scale_offset_and_radius",
        started,
        76 * variants().len(),
    );
}
