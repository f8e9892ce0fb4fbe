//! The hardware backend of the GPU ray tracer: the scene as Vulkan acceleration structures,
//! traversed by WGSL ray queries (wgpu's `EXPERIMENTAL_RAY_QUERY`: a ray-tracing GPU, or
//! lavapipe from Mesa 24.1), answering the same questions as the compute BVH of
//! [`super::GpuSceneBvh`]: every GPU tracer takes either ([`super::GpuTraceScene`]).
//!
//! Layout, as the compute tracer's: one BLAS per mesh in object space, shared by every rigid
//! instance of it; one world-space BLAS per skinned instance; one TLAS over the placed instances
//! with their transforms. Each BLAS holds the mesh's valid, traceable triangles in
//! `Mesh::valid_triangles` order, and a primitive table maps the BLAS's primitive index back to
//! that order, so a hit names the same (instance, primitive) as the compute tracer's.
//!
//! Per frame ([`HardwareSceneAs::update`]): wgpu 30 cannot refit an acceleration structure, so
//! a static scene builds once and updates nothing; moving rigid instances rebuild the TLAS
//! only; a moving skin rewrites its world-space vertices and rebuilds its own BLAS (its
//! triangle count is fixed at build: triangles that are not finite become degenerate ones at
//! the origin, which no ray hits), then the TLAS.
//!
//! Invariant: built only on a device with ray queries ([`TracingError::Unsupported`] names what the
//! adapter has otherwise); every placed instance's TLAS custom index is its row in the
//! instance table, below 2^24.

use crate::error::TracingError;
use aograph_graph::GpuContext;
use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3};
use wgpu::util::DeviceExt;

use super::gpu_io::{buffer_of, check_gpu_errors, check_storage};
use super::scene_bvh::traceable_mesh_triangles;
use aograph_scene::error::SceneError;
use aograph_scene::model::Scene;

/// Largest TLAS custom index (24 bits).
const MAX_CUSTOM_INDEX: usize = 1 << 24;

/// One placed instance's row: its scene instance and where its BLAS's primitive table starts.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct HardwareInstance {
    instance: u32,
    primitive_offset: u32,
    /// 1 when the instance moves (animated or a moving skin).
    moving: u32,
    pad: u32,
}

/// A BLAS and what it was built from.
struct BottomLevel {
    blas: wgpu::Blas,
    vertices: wgpu::Buffer,
    size: wgpu::BlasTriangleGeometrySizeDescriptor,
    /// Offset of its primitives in the primitive table.
    primitive_offset: u32,
}

impl BottomLevel {
    fn build_entry(&self) -> wgpu::BlasBuildEntry<'_> {
        wgpu::BlasBuildEntry {
            blas: &self.blas,
            geometry: wgpu::BlasGeometries::TriangleGeometries(vec![wgpu::BlasTriangleGeometry {
                size: &self.size,
                vertex_buffer: &self.vertices,
                first_vertex: 0,
                vertex_stride: 12,
                index_buffer: None,
                first_index: None,
                transform_buffer: None,
                transform_buffer_offset: None,
            }]),
        }
    }
}

/// One TLAS instance: which scene instance, which BLAS, and how it moves.
#[derive(Clone, Copy)]
struct Placed {
    instance: usize,
    bottom: usize,
    skinned: bool,
    moving: bool,
}

/// What one build or update did (counted by the tests, timed by the bench).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct AsWork {
    /// Bottom levels built (meshes, and skins that moved).
    pub blas_builds: u32,
    /// Top-level builds (0 or 1).
    pub tlas_builds: u32,
}

/// The scene's acceleration structures at one time, built on the device.
pub struct HardwareSceneAs {
    /// The top level, bound to the shaders as `acceleration_structure`.
    pub tlas: wgpu::Tlas,
    /// Per placed instance: (scene instance, primitive offset).
    pub instances: wgpu::Buffer,
    /// Per BLAS primitive: its index among the mesh's valid triangles.
    pub primitives: wgpu::Buffer,
    /// What the last build or update did.
    pub work: AsWork,
    bottom: Vec<BottomLevel>,
    placed: Vec<Placed>,
}

/// The named error for a device without ray queries.
fn unsupported(gpu: &GpuContext) -> TracingError {
    TracingError::Unsupported {
        what: "the hardware ray tracer".into(),
        detail: format!(
            "adapter '{}' ({:?}, driver '{} {}') has no ray queries (wgpu's EXPERIMENTAL_RAY_QUERY); \
             use the compute tracer, or a ray-tracing GPU, or lavapipe from Mesa 24.1 \
             (scripts/ensure-vulkan.sh installs one on Debian 12)",
            gpu.info.name, gpu.info.device_type, gpu.info.driver, gpu.info.driver_info
        ),
    }
}

/// A TLAS transform: the first three rows of `m`, row-major.
fn rows_3x4(m: Mat4) -> [f32; 12] {
    let r = m.transpose().to_cols_array();
    let mut out = [0.0; 12];
    out.copy_from_slice(&r[..12]);
    out
}

impl HardwareSceneAs {
    /// Builds the acceleration structures of `scene` posed at time `t` and waits for the build.
    pub fn build(gpu: &GpuContext, scene: &Scene, t: f32) -> Result<HardwareSceneAs, TracingError> {
        if !gpu.has_ray_queries() {
            return Err(unsupported(gpu));
        }
        let device = &gpu.device;
        let mut bottom: Vec<BottomLevel> = Vec::new();
        let mut primitives: Vec<u32> = Vec::new();
        let mut mesh_blas: Vec<Option<Option<usize>>> = vec![None; scene.meshes.len()];
        let mut placed: Vec<(usize, usize, Mat4)> = Vec::new();
        let mut add_blas = |tris: Vec<(u32, [Vec3; 3])>| -> usize {
            let vertices: Vec<[f32; 3]> = tris
                .iter()
                .flat_map(|(_, t)| t.map(|v| v.to_array()))
                .collect();
            let primitive_offset = primitives.len() as u32;
            primitives.extend(tris.iter().map(|(p, _)| *p));
            let size = wgpu::BlasTriangleGeometrySizeDescriptor {
                vertex_format: wgpu::VertexFormat::Float32x3,
                vertex_count: vertices.len() as u32,
                index_format: None,
                index_count: None,
                flags: wgpu::AccelerationStructureGeometryFlags::OPAQUE,
            };
            let blas = device.create_blas(
                &wgpu::CreateBlasDescriptor {
                    label: Some("scene blas"),
                    flags: wgpu::AccelerationStructureFlags::PREFER_FAST_TRACE,
                    update_mode: wgpu::AccelerationStructureUpdateMode::Build,
                },
                wgpu::BlasGeometrySizeDescriptors::Triangles {
                    descriptors: vec![size.clone()],
                },
            );
            let vertices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("blas vertices"),
                contents: bytemuck::cast_slice(&vertices),
                usage: wgpu::BufferUsages::BLAS_INPUT | wgpu::BufferUsages::COPY_DST,
            });
            bottom.push(BottomLevel {
                blas,
                vertices,
                size,
                primitive_offset,
            });
            bottom.len() - 1
        };
        for (index, instance) in scene.instances.iter().enumerate() {
            let Some(mesh) = scene.meshes.get(instance.mesh) else {
                continue;
            };
            if instance.skin_for(mesh).is_some() {
                let tris: Vec<(u32, [Vec3; 3])> = skinned_triangles(scene, index, t)
                    .into_iter()
                    .enumerate()
                    .map(|(p, t)| (p as u32, t))
                    .collect();
                if !tris.is_empty() {
                    placed.push((index, add_blas(tris), Mat4::IDENTITY));
                }
            } else {
                let b = *mesh_blas[instance.mesh].get_or_insert_with(|| {
                    let tris = traceable_mesh_triangles(mesh);
                    (!tris.is_empty()).then(|| add_blas(tris))
                });
                let m = instance.transform_at(t);
                if let Some(b) = b
                    && m.is_finite()
                {
                    placed.push((index, b, m));
                }
            }
        }
        if placed.len() >= MAX_CUSTOM_INDEX {
            return Err(SceneError::InvalidParameter {
                name: "instances",
                value: placed.len().to_string(),
                allowed: "fewer than 2^24 placed instances for the hardware tracer",
            }
            .into());
        }
        check_storage(gpu, "primitive table", primitives.len() as u64 * 4)?;
        let mut tlas = device.create_tlas(&wgpu::CreateTlasDescriptor {
            label: Some("scene tlas"),
            max_instances: placed.len().max(1) as u32,
            flags: wgpu::AccelerationStructureFlags::PREFER_FAST_TRACE,
            update_mode: wgpu::AccelerationStructureUpdateMode::Build,
        });
        let mut rows = Vec::with_capacity(placed.len());
        for (k, (index, b, m)) in placed.iter().enumerate() {
            tlas[k] = Some(wgpu::TlasInstance::new(
                &bottom[*b].blas,
                rows_3x4(*m),
                k as u32,
                0xff,
            ));
            rows.push(HardwareInstance {
                instance: *index as u32,
                primitive_offset: bottom[*b].primitive_offset,
                moving: scene.instances[*index].is_moving() as u32,
                pad: 0,
            });
        }
        let mut enc = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("acceleration structure build"),
        });
        let entries: Vec<wgpu::BlasBuildEntry> =
            bottom.iter().map(BottomLevel::build_entry).collect();
        enc.build_acceleration_structures(entries.iter(), [&tlas]);
        gpu.queue.submit([enc.finish()]);
        check_gpu_errors(gpu, "building acceleration structures")?;
        let work = AsWork {
            blas_builds: bottom.len() as u32,
            tlas_builds: 1,
        };
        let placed = placed
            .iter()
            .map(|(index, b, _)| {
                let instance = &scene.instances[*index];
                Placed {
                    instance: *index,
                    bottom: *b,
                    skinned: scene
                        .meshes
                        .get(instance.mesh)
                        .is_some_and(|m| instance.skin_for(m).is_some()),
                    moving: instance.is_moving(),
                }
            })
            .collect();
        Ok(HardwareSceneAs {
            tlas,
            instances: buffer_of(
                gpu,
                "hardware instances",
                &rows,
                wgpu::BufferUsages::STORAGE,
            ),
            primitives: buffer_of(
                gpu,
                "hardware primitives",
                &primitives,
                wgpu::BufferUsages::STORAGE,
            ),
            work,
            bottom,
            placed,
        })
    }

    /// Moves the structures to time `t` doing only what motion requires (module docs), and
    /// records what it did in [`Self::work`].
    pub fn update(
        &mut self,
        gpu: &GpuContext,
        scene: &Scene,
        t: f32,
    ) -> Result<AsWork, TracingError> {
        let mut work = AsWork::default();
        let mut rebuilt = Vec::new();
        for (k, p) in self.placed.iter().enumerate() {
            if !p.moving {
                continue;
            }
            if p.skinned {
                let vertices: Vec<[f32; 3]> = skinned_triangles(scene, p.instance, t)
                    .iter()
                    .flat_map(|t| t.map(|v| v.to_array()))
                    .collect();
                let b = &self.bottom[p.bottom];
                if vertices.len() as u32 != b.size.vertex_count {
                    return Err(SceneError::InvalidParameter {
                        name: "scene",
                        value: "a skinned instance whose triangle count changed".into(),
                        allowed: "the scene the structures were built from",
                    }
                    .into());
                }
                gpu.queue
                    .write_buffer(&b.vertices, 0, bytemuck::cast_slice(&vertices));
                rebuilt.push(p.bottom);
            } else if let Some(inst) = scene.instances.get(p.instance) {
                let m = inst.transform_at(t);
                // A singular or non-finite transform places the instance nowhere.
                let m = if m.is_finite() { m } else { Mat4::ZERO };
                if let Some(slot) = self.tlas.get_mut_single(k)
                    && let Some(instance) = slot.as_mut()
                {
                    instance.transform = rows_3x4(m);
                }
            }
            work.tlas_builds = 1;
        }
        if work.tlas_builds == 0 {
            self.work = work;
            return Ok(work);
        }
        work.blas_builds = rebuilt.len() as u32;
        let mut enc = gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("acceleration structure update"),
            });
        let entries: Vec<wgpu::BlasBuildEntry> = rebuilt
            .iter()
            .map(|&b| self.bottom[b].build_entry())
            .collect();
        enc.build_acceleration_structures(entries.iter(), [&self.tlas]);
        gpu.queue.submit([enc.finish()]);
        check_gpu_errors(gpu, "updating acceleration structures")?;
        self.work = work;
        Ok(work)
    }
}

/// Skinned instance `index`'s world-space triangles at `t`, one per valid triangle of its
/// mesh; a triangle that is not finite (or out of the tracer's range) becomes a degenerate one
/// at the origin, so the count never changes.
fn skinned_triangles(scene: &Scene, index: usize, t: f32) -> Vec<[Vec3; 3]> {
    let Some(instance) = scene.instances.get(index) else {
        return Vec::new();
    };
    let Some(mesh) = scene.meshes.get(instance.mesh) else {
        return Vec::new();
    };
    let world = instance.pose(mesh, t).positions(mesh);
    mesh.valid_triangles()
        .map(|tri| {
            let t = tri.map(|i| world[i]);
            let finite = t
                .iter()
                .all(|v| v.is_finite() && v.abs().max_element() <= 1e15);
            if finite { t } else { [Vec3::ZERO; 3] }
        })
        .collect()
}
