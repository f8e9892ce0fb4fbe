//! What an application's projection matrix says about its depth buffer: perspective or
//! orthographic, standard or reversed Z, the near plane and the far plane (or none). The user
//! states the convention once, by the matrix they render with; the depth adapter
//! (shaders/embed/linear_depth.wgsl) inverts the same z and w rows.
//!
//! Invariant: only right-handed view spaces looking down -Z with wgpu's 0..1 clip depth are
//! accepted; any other matrix is a named error, never a silently wrong depth.

use glam::Mat4;

use crate::error::{EmbedError, EmbedResult};

/// How clip depth relates to distance, read from a projection matrix.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DepthConvention {
    /// Orthographic (clip w = 1) rather than perspective (clip w = -z_view).
    pub orthographic: bool,
    /// The near plane maps to depth 1 and the far plane to 0.
    pub reversed_z: bool,
    /// Near plane distance (positive).
    pub near: f32,
    /// Far plane distance; infinity for an infinite far plane.
    pub far: f32,
}

/// Relative tolerance on the matrix's fixed entries (-1 and 0 in the w row).
const ENTRY_TOLERANCE: f32 = 1e-5;

impl DepthConvention {
    /// Reads the convention of `proj` (column-major, as glam and WGSL store it). With
    /// `P22 = proj[2][2]`, `P32 = proj[3][2]` and linear depth `l = -z_view`, clip depth is
    /// `P32 / l - P22` for a perspective (`proj[2][3] = -1`, `proj[3][3] = 0`) and
    /// `P32 - P22 l` for an orthographic projection (`proj[2][3] = 0`, `proj[3][3] = 1`).
    pub fn of(proj: Mat4) -> EmbedResult<Self> {
        if !proj.is_finite() {
            return Err(EmbedError::Projection(
                "it has infinite or NaN entries; pass the matrix you render with".into(),
            ));
        }
        let (w_z, w_w) = (proj.z_axis.w, proj.w_axis.w);
        let (p22, p32) = (proj.z_axis.z, proj.w_axis.z);
        let near_one = |v: f32, to: f32| (v - to).abs() <= ENTRY_TOLERANCE;
        let convention = if near_one(w_z, -1.0) && near_one(w_w, 0.0) {
            if p32 == 0.0 {
                return Err(EmbedError::Projection(
                    "its depth row maps every distance to one depth (proj[3][2] = 0)".into(),
                ));
            }
            // d(l) = P32 / l - P22 falls with distance exactly when P32 > 0: reversed Z.
            let reversed_z = p32 > 0.0;
            let (near, far) = if reversed_z {
                (p32 / (1.0 + p22), p32 / p22)
            } else {
                (p32 / p22, p32 / (1.0 + p22))
            };
            Self {
                orthographic: false,
                reversed_z,
                near,
                // Infinite far plane: the far depth value is never reached (P22 = 0 reversed,
                // P22 = -1 standard), or it comes out behind the camera.
                far: if far.is_finite() && far > near {
                    far
                } else {
                    f32::INFINITY
                },
            }
        } else if near_one(w_z, 0.0) && near_one(w_w, 1.0) {
            if p22 == 0.0 {
                return Err(EmbedError::Projection(
                    "its depth row ignores distance (proj[2][2] = 0)".into(),
                ));
            }
            // d(l) = P32 - P22 l rises with distance exactly when P22 < 0: standard Z.
            let reversed_z = p22 > 0.0;
            let (near, far) = if reversed_z {
                ((p32 - 1.0) / p22, p32 / p22)
            } else {
                (p32 / p22, (p32 - 1.0) / p22)
            };
            Self {
                orthographic: true,
                reversed_z,
                near,
                far,
            }
        } else if near_one(w_z, 1.0) && near_one(w_w, 0.0) {
            return Err(EmbedError::Projection(
                "it is left-handed (proj[2][3] = +1, the camera looks down +Z); aograph's view \
                 space is right-handed looking down -Z: pass a right-handed projection and view"
                    .into(),
            ));
        } else {
            return Err(EmbedError::Projection(format!(
                "its w row (proj[2][3], proj[3][3]) = ({w_z}, {w_w}) is neither a perspective's \
                 (-1, 0) nor an orthographic projection's (0, 1)"
            )));
        };
        // A perspective's near plane lies in front of the eye; an orthographic one may sit on
        // the camera's plane (bevy's default 3D orthographic projection has near = 0), where
        // linear depth 0 is only the plane itself.
        let near_allowed = if convention.orthographic {
            convention.near >= 0.0
        } else {
            convention.near > 0.0
        };
        if !(near_allowed && convention.near.is_finite()) {
            return Err(EmbedError::Projection(format!(
                "its near plane comes out at {} (it must lie in front of the camera, or on its \
                 plane for an orthographic projection); aograph reads wgpu's 0..1 clip depth, not \
                 OpenGL's -1..1",
                convention.near
            )));
        }
        if convention.orthographic
            && convention.far.partial_cmp(&convention.near) != Some(std::cmp::Ordering::Greater)
        {
            return Err(EmbedError::Projection(format!(
                "its far plane ({}) is not beyond its near plane ({})",
                convention.far, convention.near
            )));
        }
        Ok(convention)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_every_convention_glam_builds() {
        let (fov, aspect, n, f) = (1.0, 16.0 / 9.0, 0.1, 250.0);
        let cases = [
            (Mat4::perspective_rh(fov, aspect, n, f), false, false, f),
            (
                Mat4::perspective_infinite_rh(fov, aspect, n),
                false,
                false,
                f32::INFINITY,
            ),
            (
                Mat4::perspective_infinite_reverse_rh(fov, aspect, n),
                false,
                true,
                f32::INFINITY,
            ),
            // Reversed Z with a finite far plane: the standard matrix with near and far swapped.
            (Mat4::perspective_rh(fov, aspect, f, n), false, true, f),
            (
                Mat4::orthographic_rh(-2.0, 2.0, -1.0, 1.0, n, f),
                true,
                false,
                f,
            ),
            (
                Mat4::orthographic_rh(-2.0, 2.0, -1.0, 1.0, f, n),
                true,
                true,
                f,
            ),
        ];
        for (i, (proj, ortho, reversed, far)) in cases.into_iter().enumerate() {
            let c = DepthConvention::of(proj).unwrap();
            assert_eq!(
                (c.orthographic, c.reversed_z),
                (ortho, reversed),
                "case {i}"
            );
            // The plane at depth 1 comes from a difference with 1, which cancels: relative
            // error up to ulp(1) * far / near; the other plane is one division away.
            let tolerance = f32::EPSILON * f / n;
            assert!(
                (c.near - n).abs() <= tolerance * n,
                "case {i}: near {}",
                c.near
            );
            if far.is_finite() {
                assert!(
                    (c.far - far).abs() <= tolerance * far,
                    "case {i}: far {}",
                    c.far
                );
            } else {
                assert_eq!(c.far, f32::INFINITY, "case {i}");
            }
        }
    }

    #[test]
    fn refuses_left_handed_and_opengl_matrices_by_name() {
        let lh = DepthConvention::of(Mat4::perspective_lh(1.0, 1.0, 0.1, 10.0)).unwrap_err();
        assert!(lh.to_string().contains("left-handed"), "{lh}");
        let gl = DepthConvention::of(Mat4::perspective_rh_gl(1.0, 1.0, 0.1, 10.0));
        // OpenGL's -1..1 matrix reads as a standard 0..1 one with a different near plane; it is
        // accepted only when that plane is in front of the camera, so it cannot be told apart
        // by the matrix alone: the docs state wgpu's convention.
        assert!(gl.is_ok());
        let nan = DepthConvention::of(Mat4::from_cols_array(&[f32::NAN; 16])).unwrap_err();
        assert!(nan.to_string().contains("NaN"), "{nan}");
        let view = DepthConvention::of(Mat4::IDENTITY).unwrap_err();
        assert!(
            view.to_string().contains("in front of the camera"),
            "{view}"
        );
        let behind = Mat4::orthographic_rh(-4.0, 4.0, -3.0, 3.0, -1.0, 10.0);
        let behind = DepthConvention::of(behind).unwrap_err();
        assert!(behind.to_string().contains("on its plane"), "{behind}");
    }

    #[test]
    fn an_orthographic_near_plane_may_sit_on_the_camera() {
        // bevy's default 3D orthographic projection: reversed Z, near 0, far 1000.
        let bevy_ortho = Mat4::orthographic_rh(-4.0, 4.0, -3.0, 3.0, 1000.0, 0.0);
        let c = DepthConvention::of(bevy_ortho).unwrap();
        assert!(c.orthographic && c.reversed_z, "{c:?}");
        assert_eq!(c.near, 0.0);
        // far = P32 / P22 from f32 entries: to f32 rounding of 1/1000.
        assert!((c.far - 1000.0).abs() < 1e-3, "{}", c.far);
        // A perspective's may not: its depth would divide by zero there.
        let at_eye = Mat4::perspective_infinite_reverse_rh(1.0, 1.0, 0.0);
        assert!(DepthConvention::of(at_eye).is_err());
    }
}
