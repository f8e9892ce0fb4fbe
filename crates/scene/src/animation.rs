//! Transforms over time: keyframed TRS tracks (from glTF) and simple procedural paths.
//!
//! An [`Animation`] is a chain of [`AnimatedTransform`] layers multiplied parent first, which is
//! how a glTF node hierarchy with some animated nodes becomes one world transform per instance.
//! Invariants: a [`Track`] always has at least one key, as many values as times, and finite,
//! non-decreasing times (its constructor refuses anything else), so sampling never indexes out of
//! range or divides by zero; sampling before the first key or after the last clamps (glTF
//! semantics); procedural paths with a non-positive or non-finite period stand still.

use glam::{Mat4, Quat, Vec3};
use std::f32::consts::TAU;

/// How a [`Track`] moves between two keys.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interpolation {
    /// Linear for vectors, spherical linear (slerp) for rotations.
    Linear,
    /// Hold the earlier key's value until the next key.
    Step,
}

/// Keyframes of one value over time.
#[derive(Clone, Debug, PartialEq)]
pub struct Track<T> {
    times: Vec<f32>,
    values: Vec<T>,
    interpolation: Interpolation,
}

impl<T: Copy> Track<T> {
    /// A track from key times (seconds) and values; `None` when the lengths differ, there is no
    /// key, or the times are not finite and non-decreasing.
    pub fn new(times: Vec<f32>, values: Vec<T>, interpolation: Interpolation) -> Option<Self> {
        let sorted = times.windows(2).all(|w| w[0] <= w[1]);
        let finite = times.iter().all(|t| t.is_finite());
        if times.is_empty() || times.len() != values.len() || !sorted || !finite {
            return None;
        }
        Some(Track {
            times,
            values,
            interpolation,
        })
    }

    /// Key times in seconds.
    pub fn times(&self) -> &[f32] {
        &self.times
    }

    /// Key values, one per time.
    pub fn values(&self) -> &[T] {
        &self.values
    }

    /// Time of the last key.
    pub fn end_time(&self) -> f32 {
        self.times.last().copied().unwrap_or(0.0)
    }

    /// The value at time `t`, blending neighbouring keys with `blend(a, b, s)`, `s` in [0, 1].
    pub fn sample(&self, t: f32, blend: impl Fn(T, T, f32) -> T) -> T {
        let after = self.times.partition_point(|&key| key <= t);
        if after == 0 {
            return self.values[0];
        }
        if after == self.times.len() {
            return self.values[after - 1];
        }
        let (a, b) = (after - 1, after);
        let span = self.times[b] - self.times[a];
        if span <= 0.0 || self.interpolation == Interpolation::Step {
            return self.values[a];
        }
        blend(self.values[a], self.values[b], (t - self.times[a]) / span)
    }
}

/// Translation, rotation and scale keyframes of one node; channels without a track keep the
/// node's rest value.
#[derive(Clone, Debug, PartialEq)]
pub struct TrsKeyframes {
    /// The node's own translation (in its parent's space), used when `translation` is `None`.
    pub rest_translation: Vec3,
    /// The node's own rotation (unit quaternion), used when `rotation` is `None`.
    pub rest_rotation: Quat,
    /// The node's own per-axis scale, used when `scale` is `None`.
    pub rest_scale: Vec3,
    /// Translation keys, in the parent's space; sampled with linear or step interpolation.
    pub translation: Option<Track<Vec3>>,
    /// Rotation keys (quaternions); sampled with slerp or step, and renormalised.
    pub rotation: Option<Track<Quat>>,
    /// Per-axis scale keys; sampled with linear or step interpolation.
    pub scale: Option<Track<Vec3>>,
}

impl TrsKeyframes {
    /// The local matrix at time `t`.
    pub fn matrix_at(&self, t: f32) -> Mat4 {
        let translation = self
            .translation
            .as_ref()
            .map_or(self.rest_translation, |track| track.sample(t, Vec3::lerp));
        let rotation = self.rotation.as_ref().map_or(self.rest_rotation, |track| {
            track.sample(t, |a, b, s| a.slerp(b, s)).normalize()
        });
        let scale = self
            .scale
            .as_ref()
            .map_or(self.rest_scale, |track| track.sample(t, Vec3::lerp));
        Mat4::from_scale_rotation_translation(scale, rotation, translation)
    }

    /// Time of the last key of any channel.
    pub fn end_time(&self) -> f32 {
        let t = self.translation.as_ref().map_or(0.0, Track::end_time);
        let r = self.rotation.as_ref().map_or(0.0, Track::end_time);
        let s = self.scale.as_ref().map_or(0.0, Track::end_time);
        t.max(r).max(s)
    }
}

/// One layer of an [`Animation`]: a fixed matrix, keyframes, or a procedural path.
#[derive(Clone, Debug, PartialEq)]
pub enum AnimatedTransform {
    /// A matrix that does not change.
    Static(Mat4),
    /// Keyframed translation, rotation and scale.
    Keyframes(TrsKeyframes),
    /// Translation around a horizontal circle (in the XZ plane) of `radius` about `centre`,
    /// one turn per `period` seconds, starting `phase` turns in.
    Orbit {
        /// Centre of the circle, in the parent's space.
        centre: Vec3,
        /// Radius of the circle, in scene units.
        radius: f32,
        /// Seconds per turn; not positive or not finite means standing still at the start.
        period: f32,
        /// Starting angle in turns (0.5 = half way round), measured from +X towards +Z.
        phase: f32,
    },
    /// Translation back and forth between `from` (at t = 0) and `to`, smoothly (cosine
    /// easing), one round trip per `period` seconds.
    Oscillate {
        /// Translation at t = 0 and at every whole period.
        from: Vec3,
        /// Translation at half a period.
        to: Vec3,
        /// Seconds per round trip; not positive or not finite means staying at `from`.
        period: f32,
    },
    /// Rotation about `axis` through the origin, one turn per `period` seconds.
    Spin {
        /// Rotation axis; need not be unit length (a zero axis spins about +Y).
        axis: Vec3,
        /// Seconds per turn, counter-clockwise about `axis` (right-hand rule); not positive or
        /// not finite means no rotation.
        period: f32,
    },
}

/// Fraction of a cycle of length `period` at time `t`; zero when the period is unusable.
fn cycle_fraction(t: f32, period: f32) -> f32 {
    if period > 0.0 && period.is_finite() && t.is_finite() {
        (t / period).rem_euclid(1.0)
    } else {
        0.0
    }
}

impl AnimatedTransform {
    /// The matrix of this layer at time `t`.
    pub fn matrix_at(&self, t: f32) -> Mat4 {
        match self {
            AnimatedTransform::Static(m) => *m,
            AnimatedTransform::Keyframes(keys) => keys.matrix_at(t),
            AnimatedTransform::Orbit {
                centre,
                radius,
                period,
                phase,
            } => {
                let angle = TAU * (cycle_fraction(t, *period) + phase);
                let offset = Vec3::new(angle.cos(), 0.0, angle.sin()) * *radius;
                Mat4::from_translation(*centre + offset)
            }
            AnimatedTransform::Oscillate { from, to, period } => {
                let s = 0.5 - 0.5 * (TAU * cycle_fraction(t, *period)).cos();
                Mat4::from_translation(from.lerp(*to, s))
            }
            AnimatedTransform::Spin { axis, period } => {
                let axis = axis.try_normalize().unwrap_or(Vec3::Y);
                Mat4::from_axis_angle(axis, TAU * cycle_fraction(t, *period))
            }
        }
    }

    /// True when the layer's matrix depends on time.
    pub fn is_moving(&self) -> bool {
        match self {
            AnimatedTransform::Static(_) => false,
            AnimatedTransform::Keyframes(keys) => keys.end_time() > 0.0,
            AnimatedTransform::Orbit { radius, period, .. } => *radius != 0.0 && *period > 0.0,
            AnimatedTransform::Oscillate { from, to, period } => from != to && *period > 0.0,
            AnimatedTransform::Spin { period, .. } => *period > 0.0,
        }
    }

    /// Length of one cycle (procedural paths) or time of the last key (keyframes).
    pub fn duration(&self) -> f32 {
        match self {
            AnimatedTransform::Static(_) => 0.0,
            AnimatedTransform::Keyframes(keys) => keys.end_time(),
            AnimatedTransform::Orbit { period, .. }
            | AnimatedTransform::Oscillate { period, .. }
            | AnimatedTransform::Spin { period, .. } => period.max(0.0),
        }
    }
}

/// A transform over time: the product of its layers, parent (first) to child (last).
#[derive(Clone, Debug, PartialEq)]
pub struct Animation {
    /// The layers, outermost (root node) first; the world matrix is
    /// `layers[0] * layers[1] * ... * layers[n - 1]` at the same time.
    pub layers: Vec<AnimatedTransform>,
}

impl Animation {
    /// An animation from parent-first layers.
    pub fn new(layers: Vec<AnimatedTransform>) -> Self {
        Animation { layers }
    }

    /// The world matrix at time `t`.
    pub fn matrix_at(&self, t: f32) -> Mat4 {
        self.layers
            .iter()
            .fold(Mat4::IDENTITY, |acc, layer| acc * layer.matrix_at(t))
    }

    /// True when some layer depends on time.
    pub fn is_moving(&self) -> bool {
        self.layers.iter().any(AnimatedTransform::is_moving)
    }

    /// The longest layer duration (seconds).
    pub fn duration(&self) -> f32 {
        self.layers
            .iter()
            .map(AnimatedTransform::duration)
            .fold(0.0, f32::max)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn track_rejects_mismatched_or_unsorted_keys() {
        assert!(Track::new(vec![0.0, 1.0], vec![1.0f32], Interpolation::Linear).is_none());
        assert!(Track::new(vec![1.0, 0.0], vec![1.0f32, 2.0], Interpolation::Linear).is_none());
        assert!(Track::<f32>::new(vec![], vec![], Interpolation::Linear).is_none());
    }

    #[test]
    fn track_interpolates_linearly_and_clamps_outside_its_keys() {
        let track = Track::new(
            vec![1.0, 3.0],
            vec![Vec3::ZERO, Vec3::X * 4.0],
            Interpolation::Linear,
        )
        .expect("valid track");
        assert_eq!(track.sample(0.0, Vec3::lerp), Vec3::ZERO);
        assert_eq!(track.sample(2.0, Vec3::lerp), Vec3::X * 2.0);
        assert_eq!(track.sample(9.0, Vec3::lerp), Vec3::X * 4.0);
    }

    #[test]
    fn rotation_keys_slerp_halfway() {
        let keys = TrsKeyframes {
            rest_translation: Vec3::ZERO,
            rest_rotation: Quat::IDENTITY,
            rest_scale: Vec3::ONE,
            translation: None,
            rotation: Track::new(
                vec![0.0, 1.0],
                vec![
                    Quat::IDENTITY,
                    Quat::from_rotation_y(std::f32::consts::FRAC_PI_2),
                ],
                Interpolation::Linear,
            ),
            scale: None,
        };
        let m = keys.matrix_at(0.5);
        let expected = Mat4::from_rotation_y(std::f32::consts::FRAC_PI_4);
        assert!(m.abs_diff_eq(expected, 1e-5));
    }

    #[test]
    fn orbit_returns_to_its_start_after_one_period() {
        let orbit = AnimatedTransform::Orbit {
            centre: Vec3::ONE,
            radius: 2.0,
            period: 4.0,
            phase: 0.0,
        };
        assert!(orbit.matrix_at(0.0).abs_diff_eq(orbit.matrix_at(4.0), 1e-5));
        assert!(orbit.is_moving());
        assert!(!AnimatedTransform::Static(Mat4::IDENTITY).is_moving());
    }
}
