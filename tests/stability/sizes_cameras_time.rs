//! Output sizes and resizes, extreme cameras, degenerate geometry, camera jumps and frame times.

use std::time::Instant;

use aograph_frame::DepthFormat;
use aograph_graph::{Extent, test_gpu};
use aograph_scene::Camera;
use glam::Vec3;

use super::*;

#[test]
fn sizes_cameras_geometry_and_time() {
    let Some(gpu) = test_gpu() else { return };
    let started = Instant::now();
    let mut report = Report::default();
    let sizes = [
        Extent::new(1, 1),
        Extent::new(2, 3),
        Extent::new(97, 61),
        Extent::new(4096, 8),
        Extent::new(8, 4096),
        SIZE,
    ];
    for v in &variants() {
        let mut rig = Rig::new(
            &gpu,
            &mut report,
            v,
            "box-on-plane with island",
            box_scene(1.0, Vec3::ZERO, true, false),
            1.0,
            DepthFormat::Depth32Float,
        );
        // Output sizes (pyramids with odd and degenerate levels); each size is a resize
        // between frames, two frames each so temporal history is used at the new size.
        for size in sizes {
            // The slivers (1x1, 2x3, 4096x8, 8x4096) may miss the contact: valid is enough there.
            let occluded = if size == SIZE || size == Extent::new(97, 61) {
                Expect::Occluded
            } else {
                Expect::Valid
            };
            rig.case(
                &mut report,
                "occluders",
                occluders(1.0, Vec3::ZERO),
                size,
                2,
                FRAME,
                occluded,
            );
            rig.case(
                &mut report,
                "island floor",
                island_view(),
                size,
                2,
                FRAME,
                Expect::Flat,
            );
        }
        // A camera inside the box, looking out through its walls.
        let inside = perspective(
            Vec3::new(0.0, 0.5, 0.0),
            Vec3::new(1.0, 0.4, 0.3),
            0.01,
            1000.0,
        );
        rig.case(
            &mut report,
            "camera inside the box",
            inside,
            SIZE,
            2,
            FRAME,
            Expect::Valid,
        );
        // A camera on the floor (in its plane), and one just below it looking up.
        rig.case(
            &mut report,
            "camera in the floor's plane",
            perspective(
                Vec3::new(40.0, 0.0, 8.0),
                Vec3::new(40.0, 0.0, 0.0),
                0.05,
                1000.0,
            ),
            SIZE,
            1,
            FRAME,
            Expect::Valid,
        );
        // Only sky: straight up, and up with the up vector parallel to the view.
        rig.case(
            &mut report,
            "sky only",
            perspective(
                Vec3::new(0.0, 3.0, 8.0),
                Vec3::new(0.0, 10.0, 7.0),
                0.05,
                1000.0,
            ),
            SIZE,
            2,
            FRAME,
            Expect::Sky,
        );
        rig.case(
            &mut report,
            "sky only, straight up",
            perspective(
                Vec3::new(0.0, 3.0, 8.0),
                Vec3::new(0.0, 10.0, 8.0),
                0.05,
                1000.0,
            ),
            SIZE,
            1,
            FRAME,
            Expect::Sky,
        );
        // The island floor at 89.9 degrees to the central ray (grazing by 0.1 degree), 0.1
        // above it: the central ray meets it 57 units ahead. Every size: the island is empty.
        let island_grazing = grazing(1.0, Vec3::new(JUMP - 40.0, 0.0, 0.0));
        for size in sizes {
            rig.case(
                &mut report,
                "plane at 89.9 degrees",
                island_grazing,
                size,
                2,
                FRAME,
                Expect::Flat,
            );
        }
        // Near 1e-4 with the floor 1e-3 below the camera: R covers far more than the screen.
        let low = perspective(
            Vec3::new(JUMP, 1e-3, 0.0),
            Vec3::new(JUMP, 0.0, -1e-3),
            1e-4,
            1000.0,
        );
        rig.case(
            &mut report,
            "camera 1e-3 above the floor, near 1e-4",
            low,
            SIZE,
            2,
            FRAME,
            Expect::Flat,
        );
        rig.case(
            &mut report,
            "camera 1e-3 above the floor, near 1e-4",
            low,
            Extent::new(97, 61),
            1,
            FRAME,
            Expect::Flat,
        );

        // Time: a camera jump of 1e4 units, a 180-degree turn, zero-length frame times. After
        // the jump and the turn the view holds only open floor, so stale (occluded) history
        // leaking into it would fail the flat check.
        rig.cut();
        let a = occluders(1.0, Vec3::ZERO);
        rig.case(
            &mut report,
            "before the jump",
            a,
            SIZE,
            4,
            FRAME,
            Expect::Valid,
        );
        let jumped = Camera {
            position: a.position + Vec3::X * JUMP,
            target: a.target + Vec3::X * JUMP,
            ..a
        };
        rig.case(
            &mut report,
            "first frame after a 1e4 jump",
            jumped,
            SIZE,
            1,
            FRAME,
            Expect::Flat,
        );
        rig.case(
            &mut report,
            "frames after a 1e4 jump",
            jumped,
            SIZE,
            3,
            FRAME,
            Expect::Flat,
        );
        rig.case(&mut report, "jump back", a, SIZE, 3, FRAME, Expect::Valid);
        let turned = Camera {
            target: a.position + (a.position - a.target) * Vec3::new(1.0, -1.0, 1.0),
            ..a
        };
        rig.case(
            &mut report,
            "first frame after a 180-degree turn",
            turned,
            SIZE,
            1,
            FRAME,
            Expect::Flat,
        );
        rig.case(
            &mut report,
            "frames after a 180-degree turn",
            turned,
            SIZE,
            3,
            FRAME,
            Expect::Flat,
        );
        rig.case(&mut report, "turn back", a, SIZE, 3, FRAME, Expect::Valid);
        rig.case(
            &mut report,
            "zero-length frame time, still camera",
            a,
            SIZE,
            3,
            0.0,
            Expect::Valid,
        );
        let nudged = Camera {
            position: a.position + Vec3::new(0.05, 0.0, 0.0),
            ..a
        };
        rig.case(
            &mut report,
            "zero-length frame time, moving camera",
            nudged,
            SIZE,
            1,
            0.0,
            Expect::Valid,
        );
        rig.case(
            &mut report,
            "zero-length frame time, jump",
            jumped,
            SIZE,
            2,
            0.0,
            Expect::Flat,
        );

        let mut rig = Rig::new(
            &gpu,
            &mut report,
            v,
            "degenerate geometry",
            degenerate_scene(),
            1.0,
            DepthFormat::Depth32Float,
        );
        // Only zero-area geometry stands on the floor: the view is an unoccluded plane.
        let at =
            |target: Vec3| perspective(target + Vec3::new(0.0, 2.0, 4.0), target, 0.05, 1000.0);
        rig.case(
            &mut report,
            "degenerate and collinear triangles, collapsed box, sliver",
            at(Vec3::ZERO),
            SIZE,
            2,
            FRAME,
            Expect::Flat,
        );
        rig.case(
            &mut report,
            "degenerate triangles at 97x61",
            at(Vec3::ZERO),
            Extent::new(97, 61),
            1,
            FRAME,
            Expect::Flat,
        );
        rig.case(
            &mut report,
            "coincident unwelded vertices with zero normals (platform)",
            at(Vec3::new(20.0, 0.0, 0.0)),
            SIZE,
            2,
            FRAME,
            Expect::Valid,
        );
        rig.case(
            &mut report,
            "coincident vertices, platform top only",
            perspective(
                Vec3::new(20.0, 1.0, 0.0),
                Vec3::new(20.0, 0.02, -0.5),
                0.05,
                1000.0,
            ),
            SIZE,
            2,
            FRAME,
            Expect::Flat,
        );
    }
    // The deepest pyramids at every size.
    for v in &deepest_pyramids() {
        let mut rig = Rig::new(
            &gpu,
            &mut report,
            v,
            "box-on-plane with island",
            box_scene(1.0, Vec3::ZERO, true, false),
            1.0,
            DepthFormat::Depth32Float,
        );
        for size in sizes {
            // The slivers (1x1, 2x3, 4096x8, 8x4096) may miss the contact: valid is enough there.
            let occluded = if size == SIZE || size == Extent::new(97, 61) {
                Expect::Occluded
            } else {
                Expect::Valid
            };
            rig.case(
                &mut report,
                "occluders",
                occluders(1.0, Vec3::ZERO),
                size,
                2,
                FRAME,
                occluded,
            );
            rig.case(
                &mut report,
                "island floor",
                island_view(),
                size,
                1,
                FRAME,
                Expect::Flat,
            );
            rig.case(
                &mut report,
                "plane at 89.9 degrees",
                grazing(1.0, Vec3::new(JUMP - 40.0, 0.0, 0.0)),
                size,
                1,
                FRAME,
                Expect::Flat,
            );
        }
    }
    // Per technique variant 40 cases (its rig and every case above); per deepest pyramid 19
    // (its rig and 6 sizes x 3).
    report.finish(
        "sizes_cameras_geometry_and_time",
        started,
        40 * variants().len() + 19 * deepest_pyramids().len(),
    );
}
