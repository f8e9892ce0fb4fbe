//! The scene's two-level BVH on the CPU, in the GPU's layout: one bottom level (BLAS) per mesh
//! in object space, shared by every rigid instance of it; one per skinned instance in world
//! space (its vertices move independently); a top level (TLAS) over the instances' world boxes.
//! [`SceneBvh::update`] moves it to another time doing only what motion requires: a skinned
//! instance that moves has its triangles rewritten and its BLAS refit (topology kept); a rigid
//! instance that moves has its matrix rewritten; the TLAS is rebuilt when anything moved.
//! A static scene builds once and never again ([`BvhWork`] counts it all).
//!
//! Buffer layout (shaders/common/bvh.wgsl): `nodes` holds the TLAS at [0, tlas_len), then every
//! BLAS, with global indices (an inner node's `first` is a node index, a BLAS leaf's a
//! triangle index, a TLAS leaf's an instance index); `instances` one record per placed
//! instance; `triangles` every BLAS's triangles in leaf order.
//!
//! Invariants: the node, instance and triangle counts never change after the build (updates
//! rewrite in place, so the GPU buffers keep their size); what each update rewrote is listed in
//! its [`BvhUpdate`]; instances whose mesh is missing, whose triangles are all untraceable, or
//! whose transform is singular or non-finite are left out (no ray could hit them).

use crate::error::TracingError;
use std::ops::Range;

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3, Vec3A};
use obvhs::aabb::Aabb;

use super::flat_bvh::{BuildQuality, FlatBvh, FlatNode, triangle_box};
use aograph_scene::model::{Mesh, Scene};
use aograph_scene::reference::is_traceable;

/// Depth limits of the traversal stacks in shaders/common/bvh.wgsl (`TLAS_STACK`,
/// `BLAS_STACK`): a tree deeper than these is a build error, never a truncated traversal.
pub const TLAS_STACK: u32 = 64;
/// Deepest bottom-level (per-mesh) tree the GPU traversal walks, in nodes; must match
/// `BLAS_STACK` in shaders/common/bvh.wgsl.
pub const BLAS_STACK: u32 = 64;

/// One triangle (shaders/common/bvh.wgsl `BvhTriangle`); `primitive` is its index among the
/// mesh's valid triangles (`Mesh::valid_triangles`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub struct GpuTriangle {
    /// First vertex, in its BLAS's space: object space for a rigid mesh, world space for a
    /// skinned instance.
    pub v0: [f32; 3],
    /// The triangle's index among its mesh's valid triangles, so a hit can find its normals
    /// and material.
    pub primitive: u32,
    /// Second vertex (counter-clockwise from `v0` seen from the front).
    pub v1: [f32; 3],
    /// Padding to 16 bytes for WGSL's `vec3` alignment; always 0.
    pub _pad0: u32,
    /// Third vertex.
    pub v2: [f32; 3],
    /// Padding to 16 bytes; always 0.
    pub _pad1: u32,
}

/// One placed instance (shaders/common/bvh.wgsl `BvhInstance`): the world-to-object matrix's
/// three rows (object = rows x (world, 1)), its BLAS root, its scene instance index, and 1 in
/// `moving` when it moves (animated or skinned), for techniques that must know what a ray hit
/// may change from frame to frame.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub struct GpuInstance {
    /// The first three rows of the inverse of the instance's object-to-world matrix (all
    /// zeros for a singular transform, which no ray then hits; identity for a skinned
    /// instance, whose BLAS is already in world space).
    pub world_to_object: [[f32; 4]; 3],
    /// Global index in [`SceneBvh::nodes`] of the root of the instance's BLAS.
    pub blas_root: u32,
    /// Index of the instance in [`Scene::instances`](aograph_scene::model::Scene::instances).
    pub instance: u32,
    /// 1 when the instance is animated or has a moving skin, else 0.
    pub moving: u32,
    /// Padding to a 16-byte multiple; always 0.
    pub _pad: u32,
}

/// What builds and updates did: the figures a test and the bench count.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct BvhWork {
    /// Bottom levels built from scratch.
    pub blas_builds: u32,
    /// Bottom levels refit (skinned instances that moved).
    pub blas_refits: u32,
    /// Top levels built.
    pub tlas_builds: u32,
    /// Triangles whose vertices were rewritten.
    pub triangles_written: u64,
}

impl std::ops::AddAssign for BvhWork {
    fn add_assign(&mut self, o: BvhWork) {
        self.blas_builds += o.blas_builds;
        self.blas_refits += o.blas_refits;
        self.tlas_builds += o.tlas_builds;
        self.triangles_written += o.triangles_written;
    }
}

impl BvhWork {
    /// True when nothing was done.
    pub fn is_none(&self) -> bool {
        *self == BvhWork::default()
    }
}

/// The element ranges an update rewrote, for the GPU upload.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BvhUpdate {
    /// What the update did.
    pub work: BvhWork,
    /// Ranges of [`SceneBvh::nodes`] rewritten: the whole TLAS when anything moved, plus
    /// each refit skinned BLAS.
    pub nodes: Vec<Range<usize>>,
    /// The range of [`SceneBvh::instances`] rewritten (all of them when anything moved).
    pub instances: Option<Range<usize>>,
    /// Ranges of [`SceneBvh::triangles`] rewritten (the triangles of moved skinned instances).
    pub triangles: Vec<Range<usize>>,
}

/// One bottom level: its tree (local indices) and where it sits in the global arrays.
struct Blas {
    tree: FlatBvh,
    node_offset: usize,
    triangle_offset: usize,
}

enum Placement {
    /// Object-space BLAS shared by the mesh's rigid instances.
    Rigid { moving: bool },
    /// World-space BLAS of its own, refit when the skin moves.
    Skinned { moving: bool },
}

/// One instance that is traced.
struct Placed {
    instance: usize,
    blas: usize,
    placement: Placement,
    /// World box at the last update.
    world_box: Aabb,
}

/// The scene's BVH in GPU layout (see the module docs).
pub struct SceneBvh {
    /// The TLAS (indices `0..tlas_len()`, root at 0), then every BLAS, with global indices.
    pub nodes: Vec<FlatNode>,
    /// One record per traced instance, addressed by the TLAS leaves.
    pub instances: Vec<GpuInstance>,
    /// Every BLAS's triangles, each BLAS's in its leaf order, addressed by the BLAS leaves.
    pub triangles: Vec<GpuTriangle>,
    tlas_len: usize,
    blas: Vec<Blas>,
    placed: Vec<Placed>,
    time: f32,
}

/// The world box of `local` under `m` (its eight corners transformed).
/// A mesh's triangles a ray can hit, in object space, each with its index among the mesh's
/// valid triangles: the primitive both backends' hits name (their bottom levels are built from
/// this list).
pub(super) fn traceable_mesh_triangles(mesh: &Mesh) -> Vec<(u32, [Vec3; 3])> {
    mesh.valid_triangles()
        .enumerate()
        .map(|(p, tri)| (p as u32, tri.map(|i| mesh.positions[i])))
        .filter(|(_, t)| is_traceable(t))
        .collect()
}

fn transformed_box(local: &Aabb, m: &Mat4) -> Aabb {
    let mut b = Aabb::empty();
    for i in 0..8 {
        let corner = Vec3::new(
            if i & 1 == 0 { local.min.x } else { local.max.x },
            if i & 2 == 0 { local.min.y } else { local.max.y },
            if i & 4 == 0 { local.min.z } else { local.max.z },
        );
        b.extend(Vec3A::from(m.transform_point3(corner)));
    }
    b
}

/// The world-to-object rows of `object_to_world`, or `None` when it is singular or not finite.
fn world_to_object(object_to_world: &Mat4) -> Option<[[f32; 4]; 3]> {
    if !object_to_world.is_finite() || object_to_world.determinant() == 0.0 {
        return None;
    }
    let inv = object_to_world.inverse();
    if !inv.is_finite() {
        return None;
    }
    let t = inv.transpose();
    Some([t.x_axis.into(), t.y_axis.into(), t.z_axis.into()])
}

fn gpu_triangle(t: &[Vec3; 3], primitive: u32) -> GpuTriangle {
    GpuTriangle {
        v0: t[0].into(),
        primitive,
        v1: t[1].into(),
        _pad0: 0,
        v2: t[2].into(),
        _pad1: 0,
    }
}

/// A finite triangle within the tracer's coordinate range (zero area allowed: a skinned
/// triangle may open up later; the triangle test misses it while it is flat).
fn is_finite_triangle(t: &[Vec3; 3]) -> bool {
    t.iter()
        .all(|v| v.is_finite() && v.abs().max_element() <= 1e15)
}

impl SceneBvh {
    /// Builds the BVH of `scene` posed at time `t`, and what the build did.
    pub fn build(scene: &Scene, t: f32) -> Result<(SceneBvh, BvhWork), TracingError> {
        let mut work = BvhWork::default();
        let mut blas: Vec<Blas> = Vec::new();
        let mut triangles: Vec<GpuTriangle> = Vec::new();
        let mut mesh_blas: Vec<Option<Option<usize>>> = vec![None; scene.meshes.len()];
        let mut placed = Vec::new();
        let mut add_blas = |tris: Vec<(u32, [Vec3; 3])>, work: &mut BvhWork| {
            let boxes: Vec<Aabb> = tris.iter().map(|(_, t)| triangle_box(t)).collect();
            let tree = FlatBvh::build(&boxes, BuildQuality::Mesh);
            check_depth("bottom", tree.depth, BLAS_STACK)?;
            let triangle_offset = triangles.len();
            triangles.extend(tree.order.iter().map(|&k| {
                let (p, t) = &tris[k as usize];
                gpu_triangle(t, *p)
            }));
            work.blas_builds += 1;
            work.triangles_written += tree.order.len() as u64;
            blas.push(Blas {
                tree,
                node_offset: 0,
                triangle_offset,
            });
            Ok::<usize, TracingError>(blas.len() - 1)
        };
        for (index, instance) in scene.instances.iter().enumerate() {
            let Some(mesh) = scene.meshes.get(instance.mesh) else {
                continue;
            };
            let pose = instance.pose(mesh, t);
            if instance.skin_for(mesh).is_some() {
                let world = pose.positions(mesh);
                let tris: Vec<(u32, [Vec3; 3])> = mesh
                    .valid_triangles()
                    .enumerate()
                    .map(|(p, tri)| (p as u32, tri.map(|i| world[i])))
                    .filter(|(_, t)| is_finite_triangle(t))
                    .collect();
                if tris.is_empty() {
                    continue;
                }
                let b = add_blas(tris, &mut work)?;
                placed.push(Placed {
                    instance: index,
                    blas: b,
                    placement: Placement::Skinned {
                        moving: instance.is_moving(),
                    },
                    world_box: Aabb::empty(),
                });
            } else {
                let b = match mesh_blas[instance.mesh] {
                    Some(b) => b,
                    None => {
                        let tris = traceable_mesh_triangles(mesh);
                        let b = if tris.is_empty() {
                            None
                        } else {
                            Some(add_blas(tris, &mut work)?)
                        };
                        mesh_blas[instance.mesh] = Some(b);
                        b
                    }
                };
                let Some(b) = b else { continue };
                placed.push(Placed {
                    instance: index,
                    blas: b,
                    placement: Placement::Rigid {
                        moving: instance.is_moving(),
                    },
                    world_box: Aabb::empty(),
                });
            }
        }
        let tlas_len = if placed.is_empty() {
            1
        } else {
            2 * placed.len() - 1
        };
        let mut nodes = vec![FlatNode::EMPTY; tlas_len];
        for b in &mut blas {
            b.node_offset = nodes.len();
            nodes.extend(globalise(b));
        }
        let mut bvh = SceneBvh {
            nodes,
            instances: vec![GpuInstance::zeroed(); placed.len()],
            triangles,
            tlas_len,
            blas,
            placed,
            time: t,
        };
        for k in 0..bvh.placed.len() {
            bvh.place(scene, k, t);
        }
        bvh.build_tlas()?;
        work.tlas_builds += 1;
        Ok((bvh, work))
    }

    /// Writes placed instance `k`'s record and world box for time `t`.
    fn place(&mut self, scene: &Scene, k: usize, t: f32) {
        let p = &self.placed[k];
        let b = &self.blas[p.blas];
        let moving = matches!(
            p.placement,
            Placement::Rigid { moving: true } | Placement::Skinned { moving: true }
        );
        let (rows, world_box) = match p.placement {
            Placement::Skinned { .. } => (
                world_to_object(&Mat4::IDENTITY).expect("identity is invertible"),
                b.tree.bounds(),
            ),
            Placement::Rigid { .. } => {
                let m = scene.instances[p.instance].transform_at(t);
                match world_to_object(&m) {
                    Some(rows) => (rows, transformed_box(&b.tree.bounds(), &m)),
                    // Singular: every ray maps to a zero direction and misses.
                    None => ([[0.0; 4]; 3], Aabb::from_point(Vec3A::ZERO)),
                }
            }
        };
        self.instances[k] = GpuInstance {
            world_to_object: rows,
            blas_root: b.node_offset as u32,
            instance: p.instance as u32,
            moving: moving as u32,
            _pad: 0,
        };
        self.placed[k].world_box = world_box;
    }

    /// Rebuilds the top level over the instances' current world boxes.
    fn build_tlas(&mut self) -> Result<(), TracingError> {
        let boxes: Vec<Aabb> = self.placed.iter().map(|p| p.world_box).collect();
        let tree = FlatBvh::build(&boxes, BuildQuality::Instances);
        check_depth("top", tree.depth, TLAS_STACK)?;
        debug_assert_eq!(tree.nodes.len(), self.tlas_len);
        for (dst, n) in self.nodes[..self.tlas_len].iter_mut().zip(&tree.nodes) {
            *dst = *n;
            if n.count > 0 {
                // One instance per leaf: address it directly.
                dst.first = tree.order[n.first as usize];
            }
        }
        Ok(())
    }

    /// Moves the BVH to time `t`, doing only what motion requires (see the module docs).
    pub fn update(&mut self, scene: &Scene, t: f32) -> Result<BvhUpdate, TracingError> {
        let mut update = BvhUpdate::default();
        if t == self.time {
            return Ok(update);
        }
        // Until this update succeeds the CPU arrays are ahead of the GPU: a failed update
        // leaves no time recorded, so the next call redoes the work instead of skipping it.
        self.time = f32::NAN;
        let mut moved = false;
        for k in 0..self.placed.len() {
            match self.placed[k].placement {
                Placement::Rigid { moving: true } => {
                    self.place(scene, k, t);
                    moved = true;
                }
                Placement::Skinned { moving: true } => {
                    self.refit_skinned(scene, k, t, &mut update);
                    self.place(scene, k, t);
                    moved = true;
                }
                _ => {}
            }
        }
        if moved {
            self.build_tlas()?;
            update.work.tlas_builds += 1;
            update.nodes.push(0..self.tlas_len);
            update.instances = Some(0..self.instances.len());
        }
        self.time = t;
        Ok(update)
    }

    /// Rewrites placed skinned instance `k`'s triangles at `t` and refits its BLAS.
    fn refit_skinned(&mut self, scene: &Scene, k: usize, t: f32, update: &mut BvhUpdate) {
        let p = &self.placed[k];
        let instance = &scene.instances[p.instance];
        let mesh = &scene.meshes[instance.mesh];
        let world = instance.pose(mesh, t).positions(mesh);
        let all: Vec<[usize; 3]> = mesh.valid_triangles().collect();
        let b = &mut self.blas[p.blas];
        let range = b.triangle_offset..b.triangle_offset + b.tree.order.len();
        let mut boxes = Vec::with_capacity(range.len());
        for tri in &mut self.triangles[range.clone()] {
            let mut v = all[tri.primitive as usize].map(|i| world[i]);
            if !is_finite_triangle(&v) {
                // Collapsed to its first vertex: hit by no ray, keeps the boxes finite.
                v = [v[0]; 3];
                if !is_finite_triangle(&v) {
                    v = [Vec3::ZERO; 3];
                }
            }
            *tri = gpu_triangle(&v, tri.primitive);
            boxes.push(triangle_box(&v));
        }
        b.tree.refit(|j| boxes[j]);
        let nodes = globalise(b);
        let node_range = b.node_offset..b.node_offset + nodes.len();
        self.nodes[node_range.clone()].copy_from_slice(&nodes);
        update.work.blas_refits += 1;
        update.work.triangles_written += range.len() as u64;
        update.triangles.push(range);
        update.nodes.push(node_range);
    }

    /// Number of nodes in the top level.
    pub fn tlas_len(&self) -> usize {
        self.tlas_len
    }

    /// Bytes of the three buffers.
    pub fn sizes(&self) -> super::limits::BvhSizes {
        super::limits::BvhSizes {
            nodes: std::mem::size_of_val(self.nodes.as_slice()) as u64,
            instances: std::mem::size_of_val(self.instances.as_slice()) as u64,
            triangles: std::mem::size_of_val(self.triangles.as_slice()) as u64,
        }
    }
}

/// `b`'s nodes with global indices.
fn globalise(b: &Blas) -> Vec<FlatNode> {
    b.tree
        .nodes
        .iter()
        .map(|n| {
            let mut g = *n;
            if n.count > 0 {
                g.first += b.triangle_offset as u32;
            } else {
                g.first += b.node_offset as u32;
            }
            g
        })
        .collect()
}

fn check_depth(level: &'static str, depth: u32, limit: u32) -> Result<(), TracingError> {
    if depth > limit {
        return Err(TracingError::BvhTooDeep {
            level,
            depth,
            limit,
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use aograph_scene::camera::Camera;
    use aograph_scene::model::{Instance, Mesh};
    use aograph_scene::scene_builder::SceneBuilder;

    fn quad() -> Mesh {
        Mesh {
            name: "quad".into(),
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y],
            normals: Vec::new(),
            indices: vec![0, 1, 2, 0, 2, 3],
            material: 0,
            skin_weights: Vec::new(),
        }
    }

    fn scene(transforms: &[Mat4]) -> Scene {
        let mut b = SceneBuilder::new();
        let m = b.mesh(quad());
        for t in transforms {
            b.place(m, *t);
        }
        b.build(Camera::perspective(
            Vec3::Z * 5.0,
            Vec3::ZERO,
            1.0,
            0.1,
            100.0,
        ))
    }

    #[test]
    fn an_empty_scene_is_one_inverted_top_node_and_no_instances() {
        let (bvh, work) = SceneBvh::build(&scene(&[]), 0.0).unwrap();
        assert_eq!(bvh.nodes, vec![FlatNode::EMPTY]);
        assert!(bvh.instances.is_empty() && bvh.triangles.is_empty());
        assert_eq!((work.blas_builds, work.tlas_builds), (0, 1));
    }

    #[test]
    fn rigid_instances_share_their_mesh_bottom_level_and_carry_its_inverse_transform() {
        let a = Mat4::from_translation(Vec3::new(3.0, 0.0, 0.0));
        let b = Mat4::from_scale(Vec3::new(2.0, -1.0, 0.5));
        let (bvh, work) = SceneBvh::build(&scene(&[a, b]), 0.0).unwrap();
        assert_eq!(work.blas_builds, 1);
        assert_eq!(bvh.triangles.len(), 2, "two triangles, once");
        assert_eq!(bvh.tlas_len(), 3);
        assert_eq!(bvh.instances[0].blas_root, bvh.instances[1].blas_root);
        // The rows map world points back to object space.
        let rows = bvh.instances[1].world_to_object;
        let world = Vec3::new(2.0, -1.0, 0.5);
        let object: Vec<f32> = rows
            .iter()
            .map(|r| r[0] * world.x + r[1] * world.y + r[2] * world.z + r[3])
            .collect();
        assert_eq!(object, [1.0, 1.0, 1.0]);
        // Every TLAS leaf addresses one placed instance, each once.
        let mut leaves: Vec<u32> = bvh.nodes[..3]
            .iter()
            .filter(|n| n.count > 0)
            .map(|n| n.first)
            .collect();
        leaves.sort();
        assert_eq!(leaves, [0, 1]);
    }

    #[test]
    fn singular_and_missing_instances_are_left_out_or_never_hit() {
        let mut s = scene(&[Mat4::from_scale(Vec3::new(1.0, 0.0, 1.0)), Mat4::IDENTITY]);
        s.instances.push(Instance::fixed(9, Mat4::IDENTITY));
        let (bvh, _) = SceneBvh::build(&s, 0.0).unwrap();
        assert_eq!(
            bvh.instances.len(),
            2,
            "the instance of a missing mesh is left out"
        );
        assert_eq!(bvh.instances[0].world_to_object, [[0.0; 4]; 3]);
    }

    #[test]
    fn a_tree_deeper_than_the_traversal_stack_is_an_error_naming_both_depths() {
        let e = check_depth("bottom", 65, BLAS_STACK)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("bottom-level BVH is 65 nodes deep") && e.contains("stack of 64"),
            "{e}"
        );
        assert!(check_depth("top", TLAS_STACK, TLAS_STACK).is_ok());
    }
}
