//! One BVH level flattened for the GPU: a binary tree (BVH2) of 32-byte nodes in one array,
//! built on the CPU by obvhs (PLOC, then reinsertion and SAH leaf collapse for meshes), and
//! refit in place when its primitives move.
//!
//! Why BVH2 and not obvhs's 8-wide CWBVH: the CWBVH's compressed child boxes need a
//! per-ray octant decode and its node test skips boxes the ray leaves before t = 1e-4 (see
//! `reference::bvh`), which the GPU traversal would have to mirror; a BVH2 traverses with one
//! slab test per child, refits in one reverse sweep (a CWBVH must be rebuilt), and its depth
//! bounds the fixed traversal stack. Measured speed in docs/results/gpu-ray-tracer.md ("GPU ray
//! tracer").
//!
//! Invariants: a parent's index is below its children's (so one reverse sweep refits the tree);
//! the two children of an inner node are adjacent (`first`, `first + 1`); a leaf's primitives
//! are contiguous (`first .. first + count`) in [`FlatBvh::order`]; depth never exceeds the
//! traversal stack of shaders/common/bvh.wgsl (checked at build, an error otherwise); an empty
//! primitive set gives a single leaf with an inverted box, which every ray misses.

use bytemuck::{Pod, Zeroable};
use glam::{Vec3, Vec3A};
use obvhs::aabb::Aabb;
use obvhs::bvh2::Bvh2;
use obvhs::bvh2::reinsertion::ReinsertionOptimizer;
use obvhs::ploc::{PlocBuilder, PlocSearchDistance, SortPrecision};

/// One node (shaders/common/bvh.wgsl `BvhNode`): inner when `count` is 0 (children at
/// `first` and `first + 1`), else a leaf of `count` primitives from `first`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub struct FlatNode {
    /// Minimum corner of the node's box, in the tree's space (world for the instance level,
    /// object for a mesh level).
    pub min: [f32; 3],
    /// Inner node: index of the left child (the right one follows it); leaf: index of its
    /// first primitive in [`FlatBvh::order`]. Local to this tree until placed in a scene BVH.
    pub first: u32,
    /// Maximum corner of the node's box (below `min` on every axis for [`FlatNode::EMPTY`]).
    pub max: [f32; 3],
    /// Number of primitives in a leaf; 0 marks an inner node.
    pub count: u32,
}

impl FlatNode {
    /// A leaf no ray enters (min > max).
    pub const EMPTY: FlatNode = FlatNode {
        min: [f32::MAX; 3],
        first: 0,
        max: [-f32::MAX; 3],
        count: 0,
    };
    fn with_box(mut self, b: &Aabb) -> Self {
        self.min = Vec3::from(b.min).into();
        self.max = Vec3::from(b.max).into();
        self
    }
    fn bounds(&self) -> Aabb {
        Aabb::new(Vec3A::from(self.min), Vec3A::from(self.max))
    }
}

/// Leaves of a mesh BVH hold at most this many triangles (SAH collapse; obvhs's limit is 255).
const MAX_LEAF_TRIANGLES: u32 = 4;

/// A flattened BVH over primitives given as boxes.
#[derive(Clone, Debug)]
pub struct FlatBvh {
    /// Nodes, root first, indices local to this tree.
    pub nodes: Vec<FlatNode>,
    /// Primitive order: entry k is the caller's index of the k-th primitive the leaves address.
    pub order: Vec<u32>,
    /// Longest root-to-leaf path, in nodes (1 for a root leaf).
    pub depth: u32,
}

/// How the tree is built: meshes collapse leaves and optimise by reinsertion (built once),
/// instance levels keep one instance per leaf (rebuilt every frame something moves).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BuildQuality {
    /// A mesh's triangles: PLOC, reinsertion optimisation and SAH leaf collapse (up to four
    /// triangles a leaf); slower to build, faster to trace.
    Mesh,
    /// A scene's instances: PLOC only, one instance per leaf; cheap enough to rebuild per frame.
    Instances,
}

impl FlatBvh {
    /// Builds over `boxes` (every box finite and non-inverted; the caller filters).
    pub fn build(boxes: &[Aabb], quality: BuildQuality) -> FlatBvh {
        if boxes.is_empty() {
            return FlatBvh {
                nodes: vec![FlatNode::EMPTY],
                order: Vec::new(),
                depth: 1,
            };
        }
        let mut bvh = PlocBuilder::with_capacity(boxes.len()).build(
            PlocSearchDistance::Medium,
            boxes,
            (0..boxes.len() as u32).collect(),
            SortPrecision::U64,
            1,
        );
        if quality == BuildQuality::Mesh {
            ReinsertionOptimizer::default().run(&mut bvh, 0.05, None);
            obvhs::bvh2::leaf_collapser::collapse(&mut bvh, MAX_LEAF_TRIANGLES, 1.0);
        }
        Self::flatten(&bvh)
    }

    /// Re-emits `bvh` breadth-first from its root: parents before children, siblings
    /// adjacent, leaf primitives contiguous in visiting order.
    fn flatten(bvh: &Bvh2) -> FlatBvh {
        let mut nodes = vec![FlatNode::EMPTY];
        let mut order = Vec::with_capacity(bvh.primitive_indices.len());
        // (source node, destination slot, depth)
        let mut queue = std::collections::VecDeque::from([(0usize, 0usize, 1u32)]);
        let mut depth = 1;
        while let Some((src, dst, d)) = queue.pop_front() {
            depth = depth.max(d);
            let node = &bvh.nodes[src];
            if node.prim_count == 0 {
                let first = nodes.len();
                nodes.push(FlatNode::EMPTY);
                nodes.push(FlatNode::EMPTY);
                let child = node.first_index as usize;
                queue.push_back((child, first, d + 1));
                queue.push_back((child + 1, first + 1, d + 1));
                nodes[dst] = FlatNode {
                    first: first as u32,
                    count: 0,
                    ..FlatNode::EMPTY
                }
                .with_box(&node.aabb);
            } else {
                let first = order.len() as u32;
                let range =
                    node.first_index as usize..(node.first_index + node.prim_count) as usize;
                order.extend_from_slice(&bvh.primitive_indices[range]);
                nodes[dst] = FlatNode {
                    first,
                    count: node.prim_count,
                    ..FlatNode::EMPTY
                }
                .with_box(&node.aabb);
            }
        }
        FlatBvh {
            nodes,
            order,
            depth,
        }
    }

    /// Recomputes every box bottom-up from `primitive_box(k)`, the box of the k-th primitive
    /// in [`FlatBvh::order`] (the topology stays: a refit, not a rebuild).
    pub fn refit(&mut self, mut primitive_box: impl FnMut(usize) -> Aabb) {
        for i in (0..self.nodes.len()).rev() {
            let n = self.nodes[i];
            let b = if n.count > 0 {
                (n.first..n.first + n.count)
                    .map(|k| primitive_box(k as usize))
                    .fold(Aabb::empty(), |a, b| a.union(&b))
            } else if n.first as usize > i {
                let f = n.first as usize;
                self.nodes[f].bounds().union(&self.nodes[f + 1].bounds())
            } else {
                // The empty tree's root leaf.
                continue;
            };
            self.nodes[i] = n.with_box(&b);
        }
    }

    /// The root's box.
    pub fn bounds(&self) -> Aabb {
        self.nodes[0].bounds()
    }
}

/// The box of three points.
pub(crate) fn triangle_box(t: &[Vec3; 3]) -> Aabb {
    let mut b = Aabb::empty();
    for v in t {
        b.extend(Vec3A::from(*v));
    }
    b
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid_boxes(n: usize) -> Vec<Aabb> {
        (0..n)
            .map(|i| {
                let p = Vec3A::new((i % 7) as f32, (i / 7) as f32, (i % 3) as f32 * 0.5);
                Aabb::new(p, p + Vec3A::splat(0.75))
            })
            .collect()
    }

    /// Every primitive appears in exactly one leaf, every child box lies in its parent's, and
    /// children come after their parents.
    fn check_tree(bvh: &FlatBvh, boxes: &[Aabb]) {
        let mut seen = vec![0u32; boxes.len()];
        for (i, n) in bvh.nodes.iter().enumerate() {
            if n.count > 0 {
                for k in n.first..n.first + n.count {
                    let p = bvh.order[k as usize] as usize;
                    seen[p] += 1;
                    assert!(n.bounds().contains_point(boxes[p].min));
                    assert!(n.bounds().contains_point(boxes[p].max));
                }
            } else {
                let f = n.first as usize;
                assert!(f > i, "children after their parent");
                for c in [f, f + 1] {
                    let cb = bvh.nodes[c].bounds();
                    assert!(n.bounds().contains_point(cb.min) && n.bounds().contains_point(cb.max));
                }
            }
        }
        assert!(seen.iter().all(|&s| s == 1), "{seen:?}");
    }

    #[test]
    fn mesh_and_instance_trees_hold_every_primitive_once_under_boxes_that_contain_them() {
        for n in [1, 2, 3, 50, 333] {
            let boxes = grid_boxes(n);
            for q in [BuildQuality::Mesh, BuildQuality::Instances] {
                let bvh = FlatBvh::build(&boxes, q);
                check_tree(&bvh, &boxes);
                if q == BuildQuality::Instances {
                    // One instance per leaf: a full binary tree of 2n - 1 nodes.
                    assert_eq!(bvh.nodes.len(), 2 * n - 1);
                }
            }
        }
    }

    #[test]
    fn empty_tree_is_one_inverted_leaf() {
        let bvh = FlatBvh::build(&[], BuildQuality::Mesh);
        assert_eq!(bvh.nodes, vec![FlatNode::EMPTY]);
        assert!(bvh.order.is_empty());
    }

    #[test]
    fn refit_after_moving_every_primitive_equals_the_boxes_a_fresh_sweep_gives() {
        let boxes = grid_boxes(40);
        let mut bvh = FlatBvh::build(&boxes, BuildQuality::Mesh);
        let shift = Vec3A::new(3.0, -1.0, 0.25);
        let moved: Vec<Aabb> = boxes
            .iter()
            .map(|b| Aabb::new(b.min + shift, b.max + shift))
            .collect();
        let order = bvh.order.clone();
        bvh.refit(|k| moved[order[k] as usize]);
        check_tree(&bvh, &moved);
        // The root box is exactly the union of the moved boxes.
        let all = moved.iter().fold(Aabb::empty(), |a, b| a.union(b));
        assert_eq!(bvh.bounds().min, all.min);
        assert_eq!(bvh.bounds().max, all.max);
    }
}
