//! `tracer = "auto" | "compute" | "hardware"` on a technique that traces rays against the
//! scene (rtao): which backend of the GPU ray tracer its passes use. `compute` traverses the
//! two-level BVH in a compute shader on any device; `hardware` uses ray queries on the scene's
//! acceleration structures (wgpu's `EXPERIMENTAL_RAY_QUERY`: a ray-tracing GPU, or lavapipe
//! from Mesa 24.1); `auto` picks hardware where the device has it.
//!
//! Invariant: a backend is resolved once, when the graph is built, from what the device running
//! it offers ([`TracingSupport`]); asking for hardware on a device without ray queries is a
//! named error listing the adapter and the backends it has, never a silent fallback.

use aograph_frame::{DeclaredInputs, SceneAcceleration, SceneBvh};
use serde::{Deserialize, Serialize};

use crate::error::{AoError, AoResult};
use crate::param::ParamDesc;

/// The `tracer` parameter.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum RayTracer {
    /// Hardware where the device has ray queries, compute otherwise.
    #[default]
    Auto,
    /// The compute-shader BVH traversal (any device).
    Compute,
    /// Ray queries on acceleration structures.
    Hardware,
}

/// The backend a graph's ray-tracing passes were built for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TraceBackend {
    /// common/scene_trace.wgsl on the compute BVH.
    Compute,
    /// common/scene_trace_hardware.wgsl on the acceleration structures.
    Hardware,
}

impl TraceBackend {
    /// The backend of the GPU ray tracer a graph's passes trace on, from the frame inputs
    /// it declared (`None`: nothing traces rays).
    pub fn declared_by(declared: &DeclaredInputs) -> Option<Self> {
        if declared.contains::<SceneAcceleration>() {
            Some(TraceBackend::Hardware)
        } else if declared.contains::<SceneBvh>() {
            Some(TraceBackend::Compute)
        } else {
            None
        }
    }
    /// The config spelling ("compute" or "hardware").
    pub fn name(self) -> &'static str {
        match self {
            TraceBackend::Compute => "compute",
            TraceBackend::Hardware => "hardware",
        }
    }
}

/// What the device that will run a graph offers ray tracing: set by whoever builds the graph
/// for a device (`TracingSupport::of`); the default, for a graph built without one, has no ray
/// queries.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct TracingSupport {
    /// The device has ray queries (`GpuContext::has_ray_queries`).
    pub ray_queries: bool,
    /// The adapter, for messages (`GpuContext::describe`).
    pub adapter: String,
}

impl TracingSupport {
    /// What `gpu` offers.
    pub fn of(gpu: &aograph_graph::GpuContext) -> Self {
        Self {
            ray_queries: gpu.has_ray_queries(),
            adapter: gpu.describe(),
        }
    }
}

impl RayTracer {
    /// The serde names, in order.
    pub const NAMES: &'static [&'static str] = &["auto", "compute", "hardware"];

    /// The description of `tracer`.
    pub fn param() -> ParamDesc {
        ParamDesc::choice("tracer", Self::NAMES).doc(
            "the GPU ray tracer's backend: compute (BVH traversal in a compute shader, any device), hardware (ray queries on acceleration structures: a ray-tracing GPU or lavapipe from Mesa 24.1), auto (hardware where the device has ray queries)",
        )
    }

    /// The config spelling.
    pub fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }

    /// The backend on a device offering `support`, for `technique`'s messages.
    pub fn resolve(self, support: &TracingSupport, technique: &str) -> AoResult<TraceBackend> {
        match self {
            RayTracer::Compute => Ok(TraceBackend::Compute),
            RayTracer::Auto if support.ray_queries => Ok(TraceBackend::Hardware),
            RayTracer::Auto => Ok(TraceBackend::Compute),
            RayTracer::Hardware if support.ray_queries => Ok(TraceBackend::Hardware),
            RayTracer::Hardware => Err(AoError::InvalidParameter {
                technique: technique.into(),
                name: "tracer".into(),
                value: "\"hardware\"".into(),
                allowed: format!(
                    "\"compute\" or \"auto\" on this device: adapter {} has no ray queries \
                     (wgpu's EXPERIMENTAL_RAY_QUERY; a ray-tracing GPU, or lavapipe from Mesa \
                     24.1, has them); its tracers: compute",
                    if support.adapter.is_empty() {
                        "(none named)"
                    } else {
                        &support.adapter
                    }
                ),
            }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn support(ray_queries: bool) -> TracingSupport {
        TracingSupport {
            ray_queries,
            adapter: "llvmpipe (Vulkan, Cpu)".into(),
        }
    }

    #[test]
    fn auto_picks_hardware_only_where_the_device_has_ray_queries() {
        let r = |t: RayTracer, rq: bool| t.resolve(&support(rq), "rtao").unwrap();
        assert_eq!(r(RayTracer::Auto, true), TraceBackend::Hardware);
        assert_eq!(r(RayTracer::Auto, false), TraceBackend::Compute);
        assert_eq!(r(RayTracer::Compute, true), TraceBackend::Compute);
        assert_eq!(r(RayTracer::Hardware, true), TraceBackend::Hardware);
    }

    #[test]
    fn hardware_without_ray_queries_is_an_error_naming_the_adapter_and_what_it_has() {
        let e = RayTracer::Hardware
            .resolve(&support(false), "rtao")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("tracer") && e.contains("llvmpipe") && e.contains("compute"),
            "{e}"
        );
    }

    #[test]
    fn names_are_the_serde_spellings() {
        for t in [RayTracer::Auto, RayTracer::Compute, RayTracer::Hardware] {
            let v: RayTracer = toml::Value::String(t.name().into()).try_into().unwrap();
            assert_eq!(v, t);
        }
    }
}
