//! The g-buffer's scene data as shaders/scene/gbuffer.wgsl reads it: the per-instance rows,
//! the joint palette, the skinned vertex stream, the light, and the meshes uploaded once.
//!
//! Invariant: every `#[repr(C)]` row here has the byte layout of its WGSL struct.

use bytemuck::{Pod, Zeroable};
use wgpu::util::DeviceExt;

use aograph_scene::model::Scene;

/// One instance's row of the instance buffer (WGSL `Instance`): its transforms now and at the
/// previous frame, its normal matrix, colour and joint palette range.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub(super) struct InstanceGpu {
    pub(super) model: [[f32; 4]; 4],
    pub(super) prev_model: [[f32; 4]; 4],
    /// WGSL `mat3x3<f32>`: three columns padded to 16 bytes each.
    pub(super) normal_model: [[f32; 4]; 3],
    pub(super) color: [f32; 4],
    /// A skinned instance's first entry in the joint palette (0 when rigid).
    pub(super) palette_first: u32,
    /// A skinned instance's joint count (0 when rigid).
    pub(super) joint_count: u32,
    /// Unused; pads the row to 16 bytes.
    pub(super) pad0: u32,
    /// Unused; pads the row to 16 bytes.
    pub(super) pad1: u32,
}

/// One joint's skinning matrix now and at the previous frame (WGSL `JointPalette`).
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub(super) struct JointGpu {
    pub(super) current: [[f32; 4]; 4],
    pub(super) previous: [[f32; 4]; 4],
}

/// The skinned vertex buffer's element: JOINTS_0 widened to u32 and the normalised weights.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub(super) struct SkinVertexGpu {
    pub(super) joints: [u32; 4],
    pub(super) weights: [f32; 4],
}

/// The WGSL layout of a 3x3 matrix: columns padded to vec4.
pub(super) fn padded_mat3(m: glam::Mat3) -> [[f32; 4]; 3] {
    [m.x_axis, m.y_axis, m.z_axis].map(|c| c.extend(0.0).to_array())
}

/// The scene's sun (WGSL `Light`).
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub(super) struct LightGpu {
    /// World-space direction the light travels (unit).
    pub(super) direction: [f32; 3],
    /// Unused; pads the row to 16 bytes.
    pub(super) pad0: f32,
    /// Linear RGB colour times intensity.
    pub(super) color: [f32; 3],
    /// Unused; pads the row to 16 bytes.
    pub(super) pad1: f32,
}

/// One mesh on the GPU (`upload_meshes`).
pub(super) struct MeshGpu {
    pub(super) vertices: wgpu::Buffer,
    pub(super) indices: wgpu::Buffer,
    pub(super) index_count: u32,
    /// Joints and weights per vertex, for a mesh with skin weights.
    pub(super) skin: Option<wgpu::Buffer>,
}

/// Every mesh of `scene` in vertex and index buffers, with its joints and weights where it is
/// skinned; a mesh with an index past its vertices is drawn with no triangles.
pub(super) fn upload_meshes(scene: &Scene, device: &wgpu::Device) -> Vec<MeshGpu> {
    scene
        .meshes
        .iter()
        .map(|m| {
            let verts: Vec<[f32; 6]> = m
                .positions
                .iter()
                .enumerate()
                .map(|(i, p)| {
                    // No normals: zero, so the fragment uses the geometric normal.
                    let n = m.normals.get(i).copied().unwrap_or(glam::Vec3::ZERO);
                    [p.x, p.y, p.z, n.x, n.y, n.z]
                })
                .collect();
            let indices: Vec<u32> = m
                .indices
                .iter()
                .copied()
                .filter(|&i| (i as usize) < m.positions.len())
                .collect();
            let indices = if indices.len() == m.indices.len() {
                indices
            } else {
                Vec::new()
            };
            MeshGpu {
                vertices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("mesh vertices"),
                    contents: bytemuck::cast_slice(if verts.is_empty() {
                        &[[0f32; 6]]
                    } else {
                        verts.as_slice()
                    }),
                    usage: wgpu::BufferUsages::VERTEX,
                }),
                indices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("mesh indices"),
                    contents: bytemuck::cast_slice(if indices.is_empty() {
                        &[0u32]
                    } else {
                        indices.as_slice()
                    }),
                    usage: wgpu::BufferUsages::INDEX,
                }),
                index_count: (indices.len() / 3 * 3) as u32,
                // Exactly the meshes `Instance::skin_for` skins (palette offsets below).
                skin: (!m.skin_weights.is_empty() && m.skin_weights.len() == m.positions.len())
                    .then(|| {
                        let skin: Vec<SkinVertexGpu> = m
                            .skin_weights
                            .iter()
                            .map(|w| SkinVertexGpu {
                                joints: w.joints.map(u32::from),
                                weights: w.weights,
                            })
                            .collect();
                        device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                            label: Some("mesh joints and weights"),
                            contents: bytemuck::cast_slice(&skin),
                            usage: wgpu::BufferUsages::VERTEX,
                        })
                    }),
            }
        })
        .collect()
}
