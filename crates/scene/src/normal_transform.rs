//! How an object-to-world transform carries surface normals: the one rule the GPU g-buffer
//! (through the per-instance normal matrix it uploads) and every CPU-side normal (the CPU
//! g-buffer, the reference's shading normals) share.
//!
//! A normal n of a surface transforms with the inverse transpose of the model matrix's linear
//! part M, not with M: for any tangent t (n . t = 0), (M^-T n) . (M t) = n . t = 0, so the
//! transformed normal stays perpendicular to the transformed surface under non-uniform scale and
//! shear. We use the cofactor matrix cof(M) = det(M) M^-T instead of the inverse: it is the same
//! direction up to the factor det(M), always finite (no division), and still right for a
//! singular M (a scale of 0 flattens a sphere to a disc, whose normals it maps to the disc's
//! axis). The sign of det(M) is divided back out, so a mirrored node (det < 0) keeps its
//! normals on the side they were on in object space (outwards stays outwards).
//! Invariants: for every M, `normal_matrix(M) * n` is perpendicular to every `M * t` with
//! n . t = 0; for a rotation times a positive uniform scale it is that rotation's direction.

use glam::{Mat3, Mat4, Vec3};

/// The matrix that carries object-space normals to world space under `model` (see the module
/// docs): sign(det M) cof(M) of the linear part M, unnormalised. Renormalise its products.
pub fn normal_matrix(model: Mat4) -> Mat3 {
    let m = Mat3::from_mat4(model);
    let [c0, c1, c2] = [m.x_axis, m.y_axis, m.z_axis];
    // The cofactor matrix's columns (cof(M) = det(M) M^-T): cross products of M's columns.
    let cofactor = Mat3::from_cols(c1.cross(c2), c2.cross(c0), c0.cross(c1));
    let sign = if c0.dot(c1.cross(c2)) < 0.0 {
        -1.0
    } else {
        1.0
    };
    cofactor * sign
}

/// `normal` (object space) carried to world space by `model` and renormalised; `None` when the
/// transform flattens it to zero or any input is not finite.
pub fn transform_normal(model: Mat4, normal: Vec3) -> Option<Vec3> {
    (normal_matrix(model) * normal)
        .try_normalize()
        .filter(|n| n.is_finite())
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Quat;

    /// Perpendicularity of the transformed normal to transformed tangents, for a few normals.
    fn assert_perpendicular(model: Mat4) {
        for n in [
            Vec3::X,
            Vec3::Y,
            Vec3::Z,
            Vec3::new(1.0, 2.0, -3.0).normalize(),
        ] {
            let (t1, t2) = (n.any_orthonormal_pair().0, n.any_orthonormal_pair().1);
            let world = transform_normal(model, n).expect("non-degenerate");
            for t in [t1, t2] {
                let tw = model.transform_vector3(t).normalize();
                assert!(world.dot(tw).abs() < 1e-5, "{model:?}: n {n} t {t}");
            }
        }
    }

    #[test]
    fn normals_stay_perpendicular_under_scale_shear_and_mirroring() {
        let stretched = Mat4::from_scale(Vec3::new(1.0, 8.0, 1.0));
        let roof = Mat4::from_scale(Vec3::new(2.3, 8.25, 2.3))
            * Mat4::from_rotation_z(std::f32::consts::FRAC_PI_2);
        let sheared = Mat4::from_scale(Vec3::new(1.0, 3.0, 1.0))
            * Mat4::from_rotation_z(std::f32::consts::FRAC_PI_4);
        let mirrored = Mat4::from_scale(Vec3::new(-1.5, 0.5, 1.0));
        for m in [stretched, roof, sheared, mirrored] {
            assert_perpendicular(m);
        }
    }

    #[test]
    fn the_model_matrix_itself_would_fail_under_non_uniform_scale() {
        // The old rule (M n): a 45-degree normal under scale (1, 8, 1) leans far off the normal.
        let m = Mat4::from_scale(Vec3::new(1.0, 8.0, 1.0));
        let n = Vec3::new(1.0, 1.0, 0.0).normalize();
        let tangent = Vec3::new(1.0, -1.0, 0.0).normalize();
        let wrong = m.transform_vector3(n).normalize();
        let tw = m.transform_vector3(tangent).normalize();
        assert!(wrong.dot(tw).abs() > 0.9, "{}", wrong.dot(tw));
        let right = transform_normal(m, n).unwrap();
        assert!(right.dot(tw).abs() < 1e-6);
        // The known answer: M^-T n = (1, 1/8, 0) normalised.
        assert!((right - Vec3::new(1.0, 0.125, 0.0).normalize()).length() < 1e-6);
    }

    #[test]
    fn rotation_and_uniform_scale_act_as_the_rotation() {
        let q = Quat::from_euler(glam::EulerRot::XYZ, 0.3, -1.1, 2.0);
        let m =
            Mat4::from_scale_rotation_translation(Vec3::splat(0.01), q, Vec3::new(5.0, 1e4, -3.0));
        let n = Vec3::new(0.2, 0.9, -0.4).normalize();
        let got = transform_normal(m, n).unwrap();
        assert!((got - q * n).length() < 1e-6, "{got} vs {}", q * n);
    }

    #[test]
    fn mirrored_node_keeps_outward_normals_outward() {
        // A unit sphere mirrored in X: the point (1, 0, 0) moves to (-1, 0, 0), and its outward
        // normal must follow it to (-1, 0, 0), not point back into the sphere.
        let m = Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0));
        assert_eq!(transform_normal(m, Vec3::X), Some(Vec3::NEG_X));
        assert_eq!(transform_normal(m, Vec3::Y), Some(Vec3::Y));
    }

    #[test]
    fn flattening_scale_maps_normals_to_the_flat_axis_and_degenerate_input_is_none() {
        let flat = Mat4::from_scale(Vec3::new(1.0, 0.0, 1.0));
        let n = transform_normal(flat, Vec3::new(0.3, 0.5, 0.2).normalize()).unwrap();
        assert!((n - Vec3::Y).length() < 1e-6, "{n}");
        assert_eq!(transform_normal(flat, Vec3::X), None);
        assert_eq!(transform_normal(Mat4::from_scale(Vec3::NAN), Vec3::X), None);
    }
}
