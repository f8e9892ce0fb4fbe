//! The viewer's camera: orbit (drag to turn around the target, wheel to zoom) and fly (WASD to
//! move, Q/E down and up, drag to look), starting from any camera and giving back a
//! `Camera` with the starting camera's projection.
//!
//! Invariant: `camera()` of a controller made by `from_camera(c)` and not moved since is `c`'s
//! position and target exactly (so a saved view reproduces the scene's own camera bit for bit).

use aograph_scene::Camera;
use glam::Vec3;

/// How input moves the camera.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum CameraMode {
    #[default]
    Orbit,
    Fly,
}

/// Keys held this frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MoveKeys {
    pub forward: bool,
    pub back: bool,
    pub left: bool,
    pub right: bool,
    pub up: bool,
    pub down: bool,
}

impl MoveKeys {
    pub fn any(&self) -> bool {
        self.forward || self.back || self.left || self.right || self.up || self.down
    }
}

/// The camera being steered.
#[derive(Clone, Copy, Debug)]
pub struct CameraController {
    pub mode: CameraMode,
    base: Camera,
    position: Vec3,
    target: Vec3,
    /// Scene units per second when flying.
    pub speed: f32,
    moved: bool,
}

/// Radians per pixel of drag.
const TURN: f32 = 0.005;

impl CameraController {
    /// Steers `camera`; `scene_size` sets the flying speed (a quarter of it per second).
    pub fn from_camera(camera: Camera, scene_size: f32) -> Self {
        Self {
            mode: CameraMode::Orbit,
            base: camera,
            position: camera.position,
            target: camera.target,
            speed: (scene_size * 0.25).max(1e-3),
            moved: false,
        }
    }

    /// The camera now.
    pub fn camera(&self) -> Camera {
        if !self.moved {
            return self.base;
        }
        Camera {
            position: self.position,
            target: self.target,
            ..self.base
        }
    }

    /// Back to the camera it started from.
    pub fn reset(&mut self) {
        *self = Self::from_camera(self.base, self.speed * 4.0);
    }

    fn up(&self) -> Vec3 {
        self.base.up.normalize_or(Vec3::Y)
    }

    /// A drag of `dx`, `dy` pixels: orbit turns the camera around the target, fly turns the
    /// view direction.
    pub fn drag(&mut self, dx: f32, dy: f32) {
        if dx == 0.0 && dy == 0.0 {
            return;
        }
        let up = self.up();
        let (pivot, arm) = match self.mode {
            CameraMode::Orbit => (self.target, self.position - self.target),
            CameraMode::Fly => (self.position, self.target - self.position),
        };
        // Dragging right turns the view right in both modes.
        let yaw = glam::Quat::from_axis_angle(up, -dx * TURN);
        let arm = yaw * arm;
        let side = arm.cross(up).normalize_or_zero();
        let pitched = glam::Quat::from_axis_angle(side, -dy * TURN) * arm;
        // Stop short of the poles, where the view would flip.
        let arm = if pitched.normalize_or_zero().dot(up).abs() < 0.98 {
            pitched
        } else {
            arm
        };
        match self.mode {
            CameraMode::Orbit => self.position = pivot + arm,
            CameraMode::Fly => self.target = pivot + arm,
        }
        self.moved = true;
    }

    /// A wheel step (positive zooms in): orbit moves towards the target, fly moves ahead.
    pub fn scroll(&mut self, steps: f32) {
        if steps == 0.0 {
            return;
        }
        let arm = self.position - self.target;
        match self.mode {
            CameraMode::Orbit => {
                let d = arm.length() * 0.9f32.powf(steps);
                self.position = self.target + arm.normalize_or(Vec3::Z) * d.max(1e-4);
            }
            CameraMode::Fly => {
                let step = -arm.normalize_or(Vec3::Z) * self.speed * 0.25 * steps;
                self.position += step;
                self.target += step;
            }
        }
        self.moved = true;
    }

    /// Moves with the held keys for `dt` seconds (both modes: the target moves along).
    pub fn fly(&mut self, keys: MoveKeys, dt: f32) {
        if !keys.any() || dt <= 0.0 {
            return;
        }
        let up = self.up();
        let ahead = (self.target - self.position).normalize_or(-Vec3::Z);
        let right = ahead.cross(up).normalize_or(Vec3::X);
        let axis = |a: bool, b: bool| a as i32 as f32 - b as i32 as f32;
        let step = (ahead * axis(keys.forward, keys.back)
            + right * axis(keys.right, keys.left)
            + up * axis(keys.up, keys.down))
            * self.speed
            * dt;
        self.position += step;
        self.target += step;
        self.moved = true;
    }

    /// Moves the camera to `position` looking at `target` (a script's or a view's camera).
    pub fn set(&mut self, camera: Camera) {
        self.base = camera;
        self.position = camera.position;
        self.target = camera.target;
        self.moved = false;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera() -> Camera {
        Camera::perspective(Vec3::new(0.0, 1.0, 5.0), Vec3::ZERO, 1.0, 0.1, 100.0)
    }

    #[test]
    fn an_unmoved_controller_gives_back_its_camera_exactly() {
        let c = CameraController::from_camera(camera(), 10.0);
        assert_eq!(c.camera(), camera());
    }

    #[test]
    fn orbiting_keeps_the_distance_to_the_target() {
        let mut c = CameraController::from_camera(camera(), 10.0);
        let d0 = (camera().position - camera().target).length();
        c.drag(120.0, -40.0);
        let cam = c.camera();
        assert_eq!(cam.target, Vec3::ZERO);
        assert!(((cam.position - cam.target).length() - d0).abs() < 1e-4);
        assert!(cam.position.distance(camera().position) > 0.1);
        c.reset();
        assert_eq!(c.camera(), camera());
    }

    #[test]
    fn flying_forward_moves_along_the_view_by_speed_times_time() {
        let mut c = CameraController::from_camera(camera(), 8.0);
        c.mode = CameraMode::Fly;
        let keys = MoveKeys {
            forward: true,
            ..Default::default()
        };
        c.fly(keys, 0.5);
        let ahead = (camera().target - camera().position).normalize();
        let moved = c.camera().position - camera().position;
        assert!((moved - ahead * 2.0 * 0.5).length() < 1e-5, "{moved:?}");
        assert!((c.camera().target - camera().target - moved).length() < 1e-5);
    }
}
