//! Cameras: view and projection matrices (wgpu conventions), primary rays and camera motion
//! over time (automatic viewpoints are in `crate::views`).
//!
//! Conventions: right-handed view space looking down -Z, clip-space depth in [0, 1] (wgpu), NDC
//! y up. A reversed-Z infinite perspective maps the near plane to depth 1 and infinity to 0.
//! Invariant: the matrices and rays are finite for any camera, even a degenerate one (position
//! on the target, `up` parallel to the view direction, zero or NaN fov/near/aspect): such values
//! are replaced by safe fallbacks instead of producing NaN.

use crate::animation::Animation;
use glam::{Mat4, Vec2, Vec3};
use std::f32::consts::{FRAC_PI_4, TAU};

/// How a [`Camera`] projects view space to clip space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Projection {
    /// Perspective with vertical field of view `fov_y` (radians). With `reversed_z_infinite`
    /// the far plane is at infinity, depth is reversed (near = 1) and `far` is ignored.
    Perspective {
        /// Vertical field of view in radians; values outside (0, pi) or non-finite render as
        /// 45 degrees.
        fov_y: f32,
        /// Distance from the camera to the near plane along the view direction, in world
        /// units; a non-positive or non-finite value becomes 1e-6.
        near: f32,
        /// Distance to the far plane, in world units; NaN or not beyond `near` means infinite.
        far: f32,
        /// Use an infinite far plane with reversed depth (near plane at depth 1, infinity at
        /// 0) for better depth precision far away.
        reversed_z_infinite: bool,
    },
    /// Orthographic with a view volume `height` units tall (width = height * aspect).
    Orthographic {
        /// Height of the view volume in world units (non-positive or non-finite: 1).
        height: f32,
        /// Distance to the near plane along the view direction, in world units (made positive
        /// like the perspective one).
        near: f32,
        /// Distance to the far plane; NaN or not beyond `near` means `near + 1e6` in the matrix
        /// and an unbounded primary ray.
        far: f32,
    },
}

/// A camera at `position` looking at `target`, with `up` giving the roll.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Eye position in world space.
    pub position: Vec3,
    /// World-space point the camera looks at; only the direction to it matters (looking down
    /// -Z when it equals `position`).
    pub target: Vec3,
    /// Approximate world-space up direction; need not be unit or orthogonal to the view
    /// direction (when parallel to it, +Y or +Z is used instead).
    pub up: Vec3,
    /// How view space maps to clip space.
    pub projection: Projection,
}

/// A world-space ray; `direction` is unit length and `t_min..t_max` is the part of the ray
/// between the near and far planes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraRay {
    /// World-space start: the eye (perspective) or a point on the plane through the eye
    /// (orthographic).
    pub origin: Vec3,
    /// Unit world-space direction.
    pub direction: Vec3,
    /// Distance along `direction` at which the ray crosses the near plane.
    pub t_min: f32,
    /// Distance along `direction` at which the ray crosses the far plane (may be infinite).
    pub t_max: f32,
}

const MIN_NEAR: f32 = 1e-6;

fn positive_or(value: f32, fallback: f32) -> f32 {
    if value.is_finite() && value > 0.0 {
        value
    } else {
        fallback
    }
}

impl Camera {
    /// A perspective camera with +Y up and a finite far plane.
    pub fn perspective(position: Vec3, target: Vec3, fov_y: f32, near: f32, far: f32) -> Camera {
        Camera {
            position,
            target,
            up: Vec3::Y,
            projection: Projection::Perspective {
                fov_y,
                near,
                far,
                reversed_z_infinite: false,
            },
        }
    }

    /// Unit view direction (-Z if the target sits on the position).
    pub fn forward(&self) -> Vec3 {
        (self.target - self.position)
            .try_normalize()
            .unwrap_or(Vec3::NEG_Z)
    }

    /// Orthonormal (right, up, forward) frame of the camera.
    pub fn basis(&self) -> (Vec3, Vec3, Vec3) {
        let forward = self.forward();
        let mut up = self.up.try_normalize().unwrap_or(Vec3::Y);
        if forward.dot(up).abs() > 0.9999 {
            up = if forward.y.abs() < 0.9 {
                Vec3::Y
            } else {
                Vec3::Z
            };
        }
        let right = forward.cross(up).normalize();
        (right, right.cross(forward), forward)
    }

    /// World-to-view matrix (right-handed, looking down -Z).
    pub fn view(&self) -> Mat4 {
        let (_, up, forward) = self.basis();
        Mat4::look_to_rh(self.position, forward, up)
    }

    /// The vertical field of view in radians a perspective camera renders with (degenerate
    /// values replaced by 45 degrees, as `projection` does); `None` for orthographic.
    pub fn fov_y(&self) -> Option<f32> {
        match self.projection {
            Projection::Perspective { fov_y, .. } => Some(fov_y_or_default(fov_y)),
            Projection::Orthographic { .. } => None,
        }
    }

    /// Near plane distance (always positive).
    pub fn near(&self) -> f32 {
        match self.projection {
            Projection::Perspective { near, .. } | Projection::Orthographic { near, .. } => {
                positive_or(near, MIN_NEAR)
            }
        }
    }

    /// Far plane distance (infinite for a reversed-Z infinite perspective).
    pub fn far(&self) -> f32 {
        let near = self.near();
        match self.projection {
            Projection::Perspective {
                reversed_z_infinite: true,
                ..
            } => f32::INFINITY,
            Projection::Perspective { far, .. } | Projection::Orthographic { far, .. } => {
                if far.is_nan() || far <= near {
                    f32::INFINITY
                } else {
                    far
                }
            }
        }
    }

    /// View-to-clip matrix for a viewport of `aspect` = width / height, depth range 0..1.
    pub fn projection(&self, aspect: f32) -> Mat4 {
        let aspect = positive_or(aspect, 1.0);
        let (near, far) = (self.near(), self.far());
        match self.projection {
            Projection::Perspective {
                fov_y,
                reversed_z_infinite,
                ..
            } => {
                let fov_y = fov_y_or_default(fov_y);
                if reversed_z_infinite {
                    Mat4::perspective_infinite_reverse_rh(fov_y, aspect, near)
                } else if far.is_finite() {
                    Mat4::perspective_rh(fov_y, aspect, near, far)
                } else {
                    Mat4::perspective_infinite_rh(fov_y, aspect, near)
                }
            }
            Projection::Orthographic { height, .. } => {
                let half_h = 0.5 * positive_or(height, 1.0);
                let half_w = half_h * aspect;
                let far = if far.is_finite() { far } else { near + 1e6 };
                Mat4::orthographic_rh(-half_w, half_w, -half_h, half_h, near, far)
            }
        }
    }

    /// `projection(aspect) * view()`.
    pub fn view_projection(&self, aspect: f32) -> Mat4 {
        self.projection(aspect) * self.view()
    }

    /// The ray through normalised device coordinates `ndc` (x right, y up, both in -1..1),
    /// limited to the depth range between the near and far planes.
    pub fn primary_ray(&self, ndc: Vec2, aspect: f32) -> CameraRay {
        let aspect = positive_or(aspect, 1.0);
        let (right, up, forward) = self.basis();
        let (near, far) = (self.near(), self.far());
        match self.projection {
            Projection::Perspective { fov_y, .. } => {
                let half_h = (0.5 * fov_y_or_default(fov_y)).tan();
                let direction =
                    (forward + right * (ndc.x * half_h * aspect) + up * (ndc.y * half_h))
                        .normalize();
                // Depth along `forward` is t * cos(angle to forward).
                let cos = direction.dot(forward).max(1e-6);
                CameraRay {
                    origin: self.position,
                    direction,
                    t_min: near / cos,
                    t_max: far / cos,
                }
            }
            Projection::Orthographic { height, .. } => {
                let half_h = 0.5 * positive_or(height, 1.0);
                let origin =
                    self.position + right * (ndc.x * half_h * aspect) + up * (ndc.y * half_h);
                CameraRay {
                    origin,
                    direction: forward,
                    t_min: near,
                    t_max: far,
                }
            }
        }
    }
}

fn fov_y_or_default(fov_y: f32) -> f32 {
    if fov_y.is_finite() && fov_y > 1e-4 && fov_y < std::f32::consts::PI - 1e-4 {
        fov_y
    } else {
        FRAC_PI_4
    }
}

/// How the camera moves over time.
#[derive(Clone, Debug, PartialEq)]
pub enum CameraMotion {
    /// Circle `centre` at horizontal `radius` and `height` above it, looking at `centre`, one
    /// turn per `period` seconds, starting on the +Z side.
    Orbit {
        /// World-space point circled and looked at.
        centre: Vec3,
        /// Horizontal distance from `centre`, in world units.
        radius: f32,
        /// Height of the camera above `centre` (along +Y), in world units.
        height: f32,
        /// Seconds per turn, counter-clockwise seen from above (+Z towards +X); not positive
        /// or not finite means the camera stays on the +Z side.
        period: f32,
    },
    /// A camera-to-world matrix over time (an animated glTF camera node): the camera sits at
    /// the matrix's origin, looks down its -Z and has its +Y as up.
    Node(Animation),
}

impl CameraMotion {
    /// `base` moved to where this motion puts it at time `t` (projection unchanged).
    pub fn camera_at(&self, base: &Camera, t: f32) -> Camera {
        match self {
            CameraMotion::Orbit {
                centre,
                radius,
                height,
                period,
            } => {
                let turns = if *period > 0.0 && period.is_finite() && t.is_finite() {
                    (t / period).rem_euclid(1.0)
                } else {
                    0.0
                };
                let angle = TAU * turns;
                let offset = Vec3::new(angle.sin() * radius, *height, angle.cos() * radius);
                Camera {
                    position: *centre + offset,
                    target: *centre,
                    ..*base
                }
            }
            CameraMotion::Node(animation) => {
                let m = animation.matrix_at(t);
                let position = m.transform_point3(Vec3::ZERO);
                let forward = m
                    .transform_vector3(Vec3::NEG_Z)
                    .try_normalize()
                    .unwrap_or(Vec3::NEG_Z);
                let up = m
                    .transform_vector3(Vec3::Y)
                    .try_normalize()
                    .unwrap_or(Vec3::Y);
                Camera {
                    position,
                    target: position + forward,
                    up,
                    ..*base
                }
            }
        }
    }

    /// True when the camera actually moves.
    pub fn is_moving(&self) -> bool {
        match self {
            CameraMotion::Orbit { radius, period, .. } => *radius != 0.0 && *period > 0.0,
            CameraMotion::Node(animation) => animation.is_moving(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec4;

    fn clip_depth(camera: &Camera, world: Vec3) -> f32 {
        let clip = camera.view_projection(1.0) * world.extend(1.0);
        clip.z / clip.w
    }

    #[test]
    fn perspective_maps_near_to_zero_and_far_to_one() {
        let camera = Camera::perspective(Vec3::ZERO, Vec3::NEG_Z, 1.0, 0.5, 100.0);
        assert!((clip_depth(&camera, Vec3::new(0.0, 0.0, -0.5)) - 0.0).abs() < 1e-5);
        assert!((clip_depth(&camera, Vec3::new(0.0, 0.0, -100.0)) - 1.0).abs() < 1e-5);
    }

    #[test]
    fn reversed_infinite_perspective_maps_near_to_one() {
        let mut camera = Camera::perspective(Vec3::ZERO, Vec3::NEG_Z, 1.0, 0.5, 100.0);
        camera.projection = Projection::Perspective {
            fov_y: 1.0,
            near: 0.5,
            far: 100.0,
            reversed_z_infinite: true,
        };
        assert!((clip_depth(&camera, Vec3::new(0.0, 0.0, -0.5)) - 1.0).abs() < 1e-5);
        assert!(clip_depth(&camera, Vec3::new(0.0, 0.0, -1e6)) < 1e-5);
    }

    #[test]
    fn primary_ray_through_corner_projects_back_to_that_corner() {
        let camera = Camera::perspective(Vec3::new(1.0, 2.0, 3.0), Vec3::ZERO, 0.9, 0.1, 50.0);
        let ndc = Vec2::new(0.7, -0.4);
        let ray = camera.primary_ray(ndc, 1.5);
        let p = ray.origin + ray.direction * 10.0;
        let clip: Vec4 = camera.view_projection(1.5) * p.extend(1.0);
        assert!((clip.x / clip.w - ndc.x).abs() < 1e-4);
        assert!((clip.y / clip.w - ndc.y).abs() < 1e-4);
    }

    #[test]
    fn degenerate_camera_gives_finite_matrices() {
        let camera = Camera {
            position: Vec3::ONE,
            target: Vec3::ONE,
            up: Vec3::ZERO,
            projection: Projection::Perspective {
                fov_y: f32::NAN,
                near: 0.0,
                far: -1.0,
                reversed_z_infinite: false,
            },
        };
        assert!(camera.view().is_finite());
        assert!(camera.projection(0.0).is_finite());
    }
}
