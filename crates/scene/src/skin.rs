//! Skeletal deformation (glTF 2.0 §3.7.3, linear blend skinning): a [`Skin`] is a list of
//! joints, each a node whose world transform moves over time and the inverse of its bind-pose
//! world transform; a skinned vertex carries up to four (joint, weight) pairs
//! ([`JointWeights`]) and lands at sum_k w_k J_k p, where J_k = world_k(t) inverse_bind_k is
//! joint k's entry of the skin's palette at time t (the skinned node's own transform is ignored,
//! as glTF specifies). The CPU (`Scene::world_triangles`, the reference's geometry) and the GPU
//! g-buffer (`vs_skinned` in shaders/scene/gbuffer.wgsl) blend the same palette in the same
//! order, so both see one surface.
//! Invariants the importer keeps: weights are finite, non-negative and sum to 1; joint indices
//! are below the skin's joint count; inverse bind matrices are finite. [`JointWeights::blend`]
//! skips a pair whose joint is outside the palette instead of panicking.

use crate::animation::Animation;
use glam::Mat4;

/// One joint of a [`Skin`].
#[derive(Clone, Debug, PartialEq)]
pub struct Joint {
    /// The joint node's name (or "node N"), used in messages.
    pub name: String,
    /// The joint node's world transform over time (its whole parent chain).
    pub world: Animation,
    /// The inverse of its world transform in the bind pose (glTF `inverseBindMatrices`).
    pub inverse_bind: Mat4,
}

/// A skeleton that deforms the vertices of the meshes it is attached to.
#[derive(Clone, Debug, PartialEq)]
pub struct Skin {
    /// The glTF skin's name (or "skin N").
    pub name: String,
    /// The joints, in the order [`JointWeights::joints`] indexes them (glTF `skin.joints`).
    pub joints: Vec<Joint>,
}

impl Skin {
    /// The palette at time `t`: one matrix per joint taking a bind-pose vertex to world space.
    pub fn palette(&self, t: f32) -> Vec<Mat4> {
        self.joints
            .iter()
            .map(|joint| joint.world.matrix_at(t) * joint.inverse_bind)
            .collect()
    }

    /// True when some joint moves over time.
    pub fn is_moving(&self) -> bool {
        self.joints.iter().any(|joint| joint.world.is_moving())
    }

    /// The longest joint animation (seconds).
    pub fn duration(&self) -> f32 {
        self.joints
            .iter()
            .map(|joint| joint.world.duration())
            .fold(0.0, f32::max)
    }
}

/// A vertex's influences: up to four joints (indices into its skin) and their weights.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct JointWeights {
    /// Indices into [`Skin::joints`] (glTF JOINTS_0); unused slots have weight 0.
    pub joints: [u16; 4],
    /// The weight of each joint (glTF WEIGHTS_0): finite, non-negative, summing to 1.
    pub weights: [f32; 4],
}

impl JointWeights {
    /// The vertex's skinning matrix, `sum_k w_k palette[j_k]` (glTF §3.7.3.3), summed in k order
    /// as the GPU does; pairs with a joint outside `palette` are skipped.
    pub fn blend(&self, palette: &[Mat4]) -> Mat4 {
        let mut m = Mat4::ZERO;
        for (joint, weight) in self.joints.iter().zip(self.weights) {
            if let Some(j) = palette.get(*joint as usize) {
                m += *j * weight;
            }
        }
        m
    }

    /// The same influences with weights made non-negative and scaled to sum to 1, and the
    /// joint of every zero weight set to 0 (files leave any index there); `None` when no weight
    /// is positive and finite (the vertex follows no joint).
    pub fn normalised(&self) -> Option<JointWeights> {
        let weights = self
            .weights
            .map(|w| if w.is_finite() && w > 0.0 { w } else { 0.0 });
        let sum: f32 = weights.iter().sum();
        let mut joints = self.joints;
        for (j, w) in joints.iter_mut().zip(weights) {
            if w == 0.0 {
                *j = 0;
            }
        }
        (sum > 0.0 && sum.is_finite()).then(|| JointWeights {
            joints,
            weights: weights.map(|w| w / sum),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::animation::{AnimatedTransform, Animation};
    use glam::Vec3;

    fn fixed(m: Mat4) -> Animation {
        Animation::new(vec![AnimatedTransform::Static(m)])
    }

    #[test]
    fn palette_is_world_times_inverse_bind() {
        // A joint bound at x = 1, now at x = 3 and turned a quarter about +Y: a vertex bound
        // one unit above it, at (1, 1, 0), is (0, 1, 0) in the joint's frame, stays so when
        // turned, and lands at (3, 1, 0); one bound at (2, 0, 0), (1, 0, 0) in the joint's
        // frame, turns to (0, 0, -1) and lands at (3, 0, -1). The other order
        // (inverse_bind * world) would put it at (2, 0, -2).
        let skin = Skin {
            name: "s".into(),
            joints: vec![Joint {
                name: "j".into(),
                world: fixed(
                    Mat4::from_translation(Vec3::X * 3.0)
                        * Mat4::from_rotation_y(std::f32::consts::FRAC_PI_2),
                ),
                inverse_bind: Mat4::from_translation(Vec3::X * -1.0),
            }],
        };
        let palette = skin.palette(0.0);
        let up = palette[0].transform_point3(Vec3::new(1.0, 1.0, 0.0));
        assert!((up - Vec3::new(3.0, 1.0, 0.0)).length() < 1e-6, "{up}");
        let side = palette[0].transform_point3(Vec3::new(2.0, 0.0, 0.0));
        assert!((side - Vec3::new(3.0, 0.0, -1.0)).length() < 1e-6, "{side}");
        assert!(!skin.is_moving());
    }

    #[test]
    fn blend_is_the_weighted_sum_of_the_palette() {
        // Half on a joint that stays, half on one that moved by (2, 0, 0): the vertex moves by
        // (1, 0, 0), the closed form of linear blend skinning.
        let palette = [Mat4::IDENTITY, Mat4::from_translation(Vec3::X * 2.0)];
        let w = JointWeights {
            joints: [0, 1, 0, 0],
            weights: [0.5, 0.5, 0.0, 0.0],
        };
        assert_eq!(
            w.blend(&palette).transform_point3(Vec3::Y),
            Vec3::new(1.0, 1.0, 0.0)
        );
        // An out-of-range joint is skipped, not a panic.
        let bad = JointWeights {
            joints: [7, 0, 0, 0],
            weights: [1.0, 0.0, 0.0, 0.0],
        };
        assert_eq!(bad.blend(&palette), Mat4::ZERO);
    }

    #[test]
    fn normalising_scales_weights_to_one_and_refuses_none() {
        let w = JointWeights {
            joints: [0, 1, 2, 3],
            weights: [2.0, 2.0, -1.0, f32::NAN],
        };
        let n = w.normalised().unwrap();
        assert_eq!(n.weights, [0.5, 0.5, 0.0, 0.0]);
        assert_eq!(n.joints, [0, 1, 0, 0], "unweighted joints point at joint 0");
        let zero = JointWeights::default();
        assert!(zero.normalised().is_none());
    }
}
