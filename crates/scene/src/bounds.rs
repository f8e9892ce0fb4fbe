//! Axis-aligned bounding boxes in world space.
//!
//! Invariant: an [`Aabb`] is either empty ([`Aabb::EMPTY`], min = +inf, max = -inf, which
//! `is_empty` reports and which every union absorbs) or has `min <= max` on every axis with
//! finite corners; only the empty box holds infinities.

use glam::{Mat4, Vec3};

/// An axis-aligned box, `min` and `max` corners inclusive.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// The corner with the smallest x, y and z, in world units (+inf on every axis when empty).
    pub min: Vec3,
    /// The corner with the largest x, y and z, in world units (-inf on every axis when empty).
    pub max: Vec3,
}

impl Aabb {
    /// The box containing nothing: the identity of [`Aabb::union`].
    pub const EMPTY: Aabb = Aabb {
        min: Vec3::INFINITY,
        max: Vec3::NEG_INFINITY,
    };

    /// The smallest box containing every point (empty for no points).
    pub fn from_points(points: impl IntoIterator<Item = Vec3>) -> Aabb {
        points.into_iter().fold(Aabb::EMPTY, Aabb::including)
    }

    /// True when the box contains no point.
    pub fn is_empty(&self) -> bool {
        self.min.x > self.max.x || self.min.y > self.max.y || self.min.z > self.max.z
    }

    /// This box grown to contain `point`.
    pub fn including(self, point: Vec3) -> Aabb {
        Aabb {
            min: self.min.min(point),
            max: self.max.max(point),
        }
    }

    /// The smallest box containing both boxes.
    pub fn union(self, other: Aabb) -> Aabb {
        Aabb {
            min: self.min.min(other.min),
            max: self.max.max(other.max),
        }
    }

    /// Centre of the box (the origin for an empty box).
    pub fn centre(&self) -> Vec3 {
        if self.is_empty() {
            Vec3::ZERO
        } else {
            (self.min + self.max) * 0.5
        }
    }

    /// Edge lengths (zero for an empty box).
    pub fn size(&self) -> Vec3 {
        if self.is_empty() {
            Vec3::ZERO
        } else {
            self.max - self.min
        }
    }

    /// Length of the main diagonal (zero for an empty box).
    pub fn diagonal(&self) -> f32 {
        self.size().length()
    }

    /// The box around the eight transformed corners of this box.
    pub fn transformed(&self, matrix: &Mat4) -> Aabb {
        if self.is_empty() {
            return *self;
        }
        let corners = (0..8).map(|i| {
            Vec3::new(
                if i & 1 == 0 { self.min.x } else { self.max.x },
                if i & 2 == 0 { self.min.y } else { self.max.y },
                if i & 4 == 0 { self.min.z } else { self.max.z },
            )
        });
        Aabb::from_points(corners.map(|c| matrix.transform_point3(c)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn empty_box_is_absorbed_by_union() {
        let b = Aabb::from_points([Vec3::ONE, Vec3::ZERO]);
        assert!(Aabb::EMPTY.is_empty());
        assert_eq!(Aabb::EMPTY.union(b), b);
        assert_eq!(b.centre(), Vec3::splat(0.5));
        assert_eq!(Aabb::EMPTY.diagonal(), 0.0);
    }
}
