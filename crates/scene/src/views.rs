//! Viewpoints: the ones a scene names (glTF cameras) and the ones aograph finds itself when a
//! scene names none, so that any scene can be measured from where a user would stand.
//!
//! Heuristics (all on the scene's content, `Scene::content_bounds`, so a procedural scene's
//! 1000-unit backdrop floor does not push the camera away):
//! - **outside**: looks at the centre of the content's bounding sphere from the +Z side,
//!   30 degrees above the horizon, at the distance where that sphere just fills a 45-degree
//!   vertical field of view (r / sin(22.5 degrees); wider images see it whole too).
//! - **outside-2**: a closer view (0.7 times that distance, so the content's detail takes more
//!   pixels), 30 degrees above the horizon, from whichever of the seven other azimuths (45 to
//!   315 degrees from +Z, in steps of 45) shows the most occlusion: the lowest mean
//!   accessibility in a coarse trace of the reference (32 x 24 pixels, 16 rays each) at the
//!   scene's automatic radius. A view of the back of a wall, or of a closed box from outside,
//!   shows none and is not chosen.
//! - **enclosed**: a scene is enclosed when some point of its content bounds sees geometry in at
//!   least 90% of 64 directions spread over the sphere, without being inside a solid (at most a
//!   quarter of those hits on back faces).
//! - **interior-1, interior-2**: candidate eyes on a 7 x 7 grid over the content's footprint,
//!   each at "eye height": halfway between the surface below and the surface above it (both
//!   must exist). The candidates that are enclosed are ranked by clearance (the nearest hit over
//!   26 directions); interior-1 stands at the best one and looks along the content's longest
//!   horizontal axis, towards the side with more room; interior-2 stands at the best candidate
//!   at least a quarter of the footprint away from it and looks the opposite way. Both have a
//!   60-degree vertical field of view and a near plane at 1% of their clearance.
//! - A scene of backdrops only (`plane`, `wall`, `corner`: unbounded planes) has no size; its
//!   views frame a sphere 9 units across (where the automatic radius is its 1 unit) around its
//!   own camera's target.
//! - **default** (a scene without a camera of its own): interior-1 for an enclosed scene (its
//!   outside is a closed box), else outside.
//!
//! Invariant: every camera returned is finite, with near < far, whatever the scene (an empty
//! or degenerate scene gets the unit-sphere outside view).

use crate::bounds::Aabb;
use crate::camera::{Camera, CameraMotion};
use crate::model::Scene;
use glam::Vec3;
use std::f32::consts::FRAC_PI_6;

mod probe;
use probe::{Tracer, sphere_directions};

/// Vertical field of view of the outside view.
pub const OUTSIDE_FOV_DEGREES: f32 = 45.0;
/// Vertical field of view of the interior views.
pub const INTERIOR_FOV_DEGREES: f32 = 60.0;
/// Share of directions that must hit geometry for a point to be enclosed.
pub const ENCLOSED_FRACTION: f32 = 0.9;

/// A named viewpoint of a scene.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneView {
    /// The view's name: the file's camera name, "default", "outside", "outside-2" or
    /// "interior-N".
    pub name: String,
    /// The camera at t = 0.
    pub camera: Camera,
    /// How the camera moves, if it does (an animated glTF camera).
    pub motion: Option<CameraMotion>,
}

/// The content's bounding sphere (centre, radius). A scene of backdrops only (unbounded
/// planes) has no size: its views frame a sphere of diameter 9 units, the size at which the
/// automatic radius would be its 1 unit, around its own camera's target.
fn bounding_sphere(scene: &Scene) -> (Vec3, f32) {
    let content = scene.content_bounds();
    if content.is_empty() && !scene.instances.is_empty() {
        let target = scene.camera.target;
        let centre = if target.is_finite() {
            target
        } else {
            Vec3::ZERO
        };
        return (centre, 0.5 * crate::radius::AUTO_RADIUS_DIVISOR);
    }
    sphere_of(&content)
}

fn sphere_of(b: &Aabb) -> (Vec3, f32) {
    let r = 0.5 * b.diagonal();
    if b.is_empty() || !(r.is_finite() && r > 0.0) {
        let c = if b.is_empty() { Vec3::ZERO } else { b.centre() };
        return (if c.is_finite() { c } else { Vec3::ZERO }, 1.0);
    }
    (b.centre(), r)
}

/// The outside view of a box: its bounding sphere fits a 45-degree vertical field of view,
/// seen from the +Z side 30 degrees above the horizon.
pub fn outside_camera(bounds: &Aabb) -> Camera {
    let (centre, r) = sphere_of(bounds);
    fit_sphere(centre, r, 4.0 * r)
}

/// The outside camera on a sphere, with the far plane reaching `beyond` past its centre.
fn fit_sphere(centre: Vec3, r: f32, beyond: f32) -> Camera {
    let direction = Vec3::new(0.0, FRAC_PI_6.sin(), FRAC_PI_6.cos());
    sphere_view(centre, r, beyond, direction, 1.0)
}

/// Looks at a sphere from `direction` (unit, from the centre towards the eye) at `scale`
/// times the distance where it fills the outside field of view.
fn sphere_view(centre: Vec3, r: f32, beyond: f32, direction: Vec3, scale: f32) -> Camera {
    let fov = OUTSIDE_FOV_DEGREES.to_radians();
    let distance = scale * r / (0.5 * fov).sin();
    Camera::perspective(
        centre + direction * distance,
        centre,
        fov,
        (0.5 * (distance - r)).max(1e-3 * r),
        distance + beyond.max(r),
    )
}

/// The outside view of `scene` (its content's bounding sphere fills the view; the far plane
/// reaches past any backdrop).
pub fn outside_view(scene: &Scene) -> Camera {
    let (centre, r) = bounding_sphere(scene);
    let whole = scene.bounds();
    let beyond = if whole.is_empty() {
        r
    } else {
        whole.diagonal().min(1e7)
    };
    fit_sphere(centre, r, 2.0 * beyond)
}

/// The closer outside view from the side that shows the most occlusion (module docs).
pub fn outside_view_2(scene: &Scene) -> Camera {
    outside_view_2_with(scene, &Tracer::new(scene))
}

fn outside_view_2_with(scene: &Scene, tracer: &Tracer) -> Camera {
    let (centre, r) = bounding_sphere(scene);
    let whole = scene.bounds();
    let beyond = if whole.is_empty() {
        r
    } else {
        whole.diagonal().min(1e7)
    };
    let radius = crate::radius::suggested_radius(scene).radius;
    let elevation = 30f32.to_radians();
    // Azimuths 45 to 315 degrees from +Z in steps of 45 (the front, 0, is `outside`).
    (1..8)
        .map(|k| {
            let azimuth = (45.0 * k as f32).to_radians();
            let direction = Vec3::new(
                azimuth.sin() * elevation.cos(),
                elevation.sin(),
                azimuth.cos() * elevation.cos(),
            );
            let camera = sphere_view(centre, r, 2.0 * beyond, direction, 0.7);
            (tracer.mean_accessibility(&camera, radius), k, camera)
        })
        .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)))
        .map(|(_, _, camera)| camera)
        .unwrap_or_else(|| outside_view(scene))
}

/// An enclosed candidate eye and its clearance.
#[derive(Clone, Copy)]
struct Eye {
    position: Vec3,
    clearance: f32,
}

/// The enclosed eye candidates of the content bounds, best clearance first.
fn interior_eyes(scene: &Scene, tracer: &Tracer) -> Vec<Eye> {
    let content = scene.content_bounds();
    if content.is_empty() {
        return Vec::new();
    }
    let (lo, hi) = (content.min, content.max);
    let mid_y = 0.5 * (lo.y + hi.y);
    let around = sphere_directions(64);
    let clearance_dirs = sphere_directions(26);
    let mut eyes = Vec::new();
    const GRID: usize = 7;
    for i in 0..GRID {
        for k in 0..GRID {
            let fx = (i as f32 + 0.5) / GRID as f32;
            let fz = (k as f32 + 0.5) / GRID as f32;
            let column = Vec3::new(lo.x + fx * (hi.x - lo.x), mid_y, lo.z + fz * (hi.z - lo.z));
            let (Some(down), Some(up)) = (
                tracer
                    .rays
                    .closest_hit(column, Vec3::NEG_Y, 0.0, tracer.reach),
                tracer.rays.closest_hit(column, Vec3::Y, 0.0, tracer.reach),
            ) else {
                continue;
            };
            let floor = column.y - down.distance;
            let ceiling = column.y + up.distance;
            let eye = Vec3::new(column.x, 0.5 * (floor + ceiling), column.z);
            let s = tracer.surroundings(eye, &around);
            if !tracer.enclosed(&s) {
                continue;
            }
            let clearance = tracer.surroundings(eye, &clearance_dirs).clearance;
            if clearance.is_finite() && clearance > 0.0 {
                eyes.push(Eye {
                    position: eye,
                    clearance,
                });
            }
        }
    }
    eyes.sort_by(|a, b| b.clearance.total_cmp(&a.clearance));
    eyes
}

/// True when the scene is enclosed (see the module docs).
pub fn is_enclosed(scene: &Scene) -> bool {
    !interior_eyes(scene, &Tracer::new(scene)).is_empty()
}

/// Whether an eye at `p` is enclosed (the module docs' rule: geometry in at least 90% of 64
/// directions over the sphere, at most a quarter of those hits on back faces): an interior
/// viewpoint, not one in the open or inside a solid.
pub fn is_enclosed_at(scene: &Scene, p: Vec3) -> bool {
    let tracer = Tracer::new(scene);
    tracer.enclosed(&tracer.surroundings(p, &sphere_directions(64)))
}

/// The interior views of an enclosed scene (none for an open one), see the module docs.
pub fn interior_views(scene: &Scene) -> Vec<Camera> {
    interior_views_with(scene, &Tracer::new(scene))
}

fn interior_views_with(scene: &Scene, tracer: &Tracer) -> Vec<Camera> {
    let eyes = interior_eyes(scene, tracer);
    let Some(best) = eyes.first().copied() else {
        return Vec::new();
    };
    let size = scene.content_bounds().size();
    let axis = if size.x >= size.z { Vec3::X } else { Vec3::Z };
    let footprint = size.x.max(size.z);
    let towards_room = |eye: Vec3| {
        if tracer.free_distance(eye, axis) >= tracer.free_distance(eye, -axis) {
            axis
        } else {
            -axis
        }
    };
    let camera = |eye: Eye, direction: Vec3| {
        Camera::perspective(
            eye.position,
            eye.position + direction,
            INTERIOR_FOV_DEGREES.to_radians(),
            0.01 * eye.clearance,
            tracer.reach,
        )
    };
    let first = towards_room(best.position);
    let mut views = vec![camera(best, first)];
    if let Some(second) = eyes
        .iter()
        .find(|e| e.position.distance(best.position) >= 0.25 * footprint)
    {
        views.push(camera(*second, -first));
    }
    views
}

/// The camera a scene without one of its own starts from: interior-1 for an enclosed scene,
/// else the outside view.
pub fn default_camera(scene: &Scene) -> Camera {
    interior_views(scene)
        .into_iter()
        .next()
        .unwrap_or_else(|| outside_view(scene))
}

/// The views aograph finds itself: "outside", "outside-2", then "interior-1" and
/// "interior-2" for an enclosed scene.
pub fn auto_views(scene: &Scene) -> Vec<SceneView> {
    let tracer = Tracer::new(scene);
    let mut views = vec![
        SceneView {
            name: "outside".into(),
            camera: outside_view(scene),
            motion: None,
        },
        SceneView {
            name: "outside-2".into(),
            camera: outside_view_2_with(scene, &tracer),
            motion: None,
        },
    ];
    for (i, camera) in interior_views_with(scene, &tracer).into_iter().enumerate() {
        views.push(SceneView {
            name: format!("interior-{}", i + 1),
            camera,
            motion: None,
        });
    }
    views
}

/// Every view of `scene`: each camera the file names, then the automatic views, with
/// "default" (the scene's own camera) first when it is none of those (a procedural scene's
/// authored camera); a view whose camera repeats an earlier one is left out.
pub fn scene_views(scene: &Scene) -> Vec<SceneView> {
    let mut views: Vec<SceneView> = scene
        .cameras
        .iter()
        .map(|c| SceneView {
            name: c.name.clone(),
            camera: c.camera,
            motion: c.motion.clone(),
        })
        .collect();
    views.extend(auto_views(scene));
    if !views.iter().any(|v| v.camera == scene.camera) {
        views.insert(
            0,
            SceneView {
                name: "default".into(),
                camera: scene.camera,
                motion: scene.camera_motion.clone(),
            },
        );
    }
    let mut unique: Vec<SceneView> = Vec::new();
    for v in views {
        if !unique.iter().any(|u| u.camera == v.camera) {
            unique.push(v);
        }
    }
    unique
}

/// The view of `scene` called `name`: "default" (its own camera), a camera the file names, a
/// camera's index (0 = the first), or an automatic view; `None` when there is no such view.
pub fn find_view(scene: &Scene, name: &str) -> Option<SceneView> {
    if name == "default" {
        return Some(SceneView {
            name: "default".into(),
            camera: scene.camera,
            motion: scene.camera_motion.clone(),
        });
    }
    if let Some(c) = scene.cameras.iter().find(|c| c.name == name) {
        return Some(SceneView {
            name: c.name.clone(),
            camera: c.camera,
            motion: c.motion.clone(),
        });
    }
    if let Ok(i) = name.parse::<usize>() {
        return scene.cameras.get(i).map(|c| SceneView {
            name: c.name.clone(),
            camera: c.camera,
            motion: c.motion.clone(),
        });
    }
    auto_views(scene).into_iter().find(|v| v.name == name)
}

/// The names [`find_view`] accepts for `scene`, for error messages.
pub fn view_names(scene: &Scene) -> Vec<String> {
    let mut names = vec!["default".to_string()];
    for (i, c) in scene.cameras.iter().enumerate() {
        names.push(format!("{} (or {i})", c.name));
    }
    names.extend(auto_views(scene).into_iter().map(|v| v.name));
    names
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::procedural::{ROOM_HALF_X, ROOM_HALF_Z, ROOM_HEIGHT};
    use crate::procedural_scene;

    #[test]
    fn the_outside_view_fits_the_bounding_sphere_to_the_field_of_view() {
        let bounds = Aabb::from_points([Vec3::splat(-1.0), Vec3::splat(1.0)]);
        let camera = outside_camera(&bounds);
        let r = 3f32.sqrt();
        let d = camera.position.distance(Vec3::ZERO);
        // The sphere's silhouette is seen at exactly half the vertical field of view.
        let half_angle = (r / d).asin().to_degrees();
        assert!(
            (half_angle - 0.5 * OUTSIDE_FOV_DEGREES).abs() < 1e-3,
            "{half_angle}"
        );
        assert!(camera.near() < d - r && camera.far() > d + r);
        let elevation = (camera.position.y / d).asin().to_degrees();
        assert!((elevation - 30.0).abs() < 1e-3, "{elevation}");
    }

    #[test]
    fn backdrops_do_not_push_the_outside_view_away() {
        // sphere-on-plane's floor is 200 units wide; its sphere has radius 1.
        let scene = procedural_scene("sphere-on-plane").unwrap();
        let camera = outside_view(&scene);
        let d = camera.position.distance(scene.content_bounds().centre());
        assert!(d < 5.0, "{d}");
        assert!(
            camera.far() > 200.0,
            "the far plane still reaches the floor's edge"
        );
    }

    #[test]
    fn a_closed_room_is_enclosed_and_gets_two_interior_views_along_its_long_axis() {
        let room = procedural_scene("room").unwrap();
        assert!(is_enclosed(&room));
        let views = interior_views(&room);
        assert_eq!(views.len(), 2, "{views:?}");
        let inside = |p: Vec3| {
            p.x.abs() < ROOM_HALF_X && p.z.abs() < ROOM_HALF_Z && p.y > 0.0 && p.y < ROOM_HEIGHT
        };
        for v in &views {
            assert!(inside(v.position), "{:?}", v.position);
            // Looking along x, the room's long axis (10 against 6 units), horizontally.
            assert!(v.forward().x.abs() > 0.999, "{:?}", v.forward());
            // At eye height: halfway between floor and ceiling where no furniture stands.
            assert!(
                (v.position.y - 0.5 * ROOM_HEIGHT).abs() < 0.6,
                "{:?}",
                v.position
            );
        }
        assert!(views[0].position.distance(views[1].position) >= 0.25 * 2.0 * ROOM_HALF_X);
        assert!(views[0].forward().dot(views[1].forward()) < -0.999);
        // Free space around the eye: nothing within 0.5 units in 26 directions.
        let tracer = Tracer::new(&room);
        for v in &views {
            let s = tracer.surroundings(v.position, &sphere_directions(26));
            assert!(s.clearance > 0.5, "clearance {}", s.clearance);
        }
        // Without a camera of its own the room would be seen from inside.
        assert_eq!(default_camera(&room), views[0]);
        let names: Vec<String> = auto_views(&room).into_iter().map(|v| v.name).collect();
        assert_eq!(names, ["outside", "outside-2", "interior-1", "interior-2"]);
        // Each looks towards the side of its eye with more room.
        for v in &views {
            let ahead = tracer.free_distance(v.position, v.forward());
            let behind = tracer.free_distance(v.position, -v.forward());
            assert!(ahead >= behind, "{ahead} ahead, {behind} behind");
        }
    }

    #[test]
    fn open_scenes_are_not_enclosed_and_are_seen_from_outside() {
        for name in ["sphere-on-plane", "thin-bars", "stairs", "node-transforms"] {
            let scene = procedural_scene(name).unwrap();
            assert!(!is_enclosed(&scene), "{name}");
            assert_eq!(default_camera(&scene), outside_view(&scene), "{name}");
        }
    }

    #[test]
    fn views_are_found_by_name_and_degenerate_scenes_get_finite_cameras() {
        let room = procedural_scene("room").unwrap();
        assert_eq!(find_view(&room, "default").unwrap().camera, room.camera);
        assert!(find_view(&room, "interior-2").is_some());
        assert!(find_view(&room, "attic").is_none());
        assert!(view_names(&room).contains(&"interior-1".to_string()));
        let empty = crate::scene_builder::SceneBuilder::new().build(room.camera);
        let camera = default_camera(&empty);
        assert!(camera.position.is_finite() && camera.view().is_finite());
        assert!(camera.near() < camera.far());
    }
}

#[cfg(test)]
mod outside_tests {
    use super::*;
    use crate::primitives::{cuboid, quad};
    use crate::scene_builder::SceneBuilder;
    use glam::Mat4;

    #[test]
    fn the_second_outside_view_looks_into_an_open_corner_not_at_the_back_of_its_walls() {
        // Two solid walls along x = -2 and z = -2 on a 4 x 4 floor, plus a box in the corner:
        // the occlusion is on the walls' fronts, seen from the (+x, +z) side.
        let mut b = SceneBuilder::new();
        let m = b.material([0.7; 3]);
        b.add(quad(4.0, 4.0, m), Mat4::IDENTITY);
        b.add(
            cuboid(Vec3::new(0.2, 2.0, 4.0), m),
            Mat4::from_translation(Vec3::new(-2.1, 1.0, 0.0)),
        );
        b.add(
            cuboid(Vec3::new(4.0, 2.0, 0.2), m),
            Mat4::from_translation(Vec3::new(0.0, 1.0, -2.1)),
        );
        b.add(
            cuboid(Vec3::new(0.8, 0.8, 0.8), m),
            Mat4::from_translation(Vec3::new(-1.5, 0.4, -1.5)),
        );
        let scene = b.build(Camera::perspective(
            Vec3::new(0.0, 2.0, 8.0),
            Vec3::ZERO,
            0.8,
            0.1,
            100.0,
        ));
        let c = outside_view_2(&scene);
        let centre = scene.content_bounds().centre();
        let from = c.position - centre;
        // Not from behind either wall (x < 0 or z < 0 of the centre).
        assert!(
            from.x > -1e-3 && from.z > -1e-3,
            "outside-2 looks from {from}"
        );
        // And the view it chose shows more occlusion than the back of the walls would.
        let tracer = Tracer::new(&scene);
        let radius = crate::radius::suggested_radius(&scene).radius;
        let (_, r) = bounding_sphere(&scene);
        let back = sphere_view(centre, r, 10.0, Vec3::new(-0.6, 0.5, -0.6).normalize(), 0.7);
        assert!(tracer.mean_accessibility(&c, radius) < tracer.mean_accessibility(&back, radius));
    }
}
