//! `aograph graph`: the compiled plan of a config as a text summary or Graphviz DOT, for the
//! device `aograph render` would use (a ray tracer set to `auto` takes the backend that device
//! offers); without a device, for one without ray queries.

use aograph_ao_passes::{TechniqueRegistry, TracingSupport};
use aograph_graph::{CompileOptions, Extent, GraphCompiler, summary, to_dot};
use aograph_renderer::gbuffer::GBufferStates;

use super::{CommonArgs, gpu};
use crate::shader_library;
use aograph_app_config::error::AppResult;
use aograph_renderer::frame_graph::{FrameOutputs, build_frame_graph_with};

pub fn graph(args: &CommonArgs, dot: bool) -> AppResult<()> {
    let registry = TechniqueRegistry::with_builtins();
    let config = args.resolve(&registry)?;
    let prepared = config.prepare_scene()?;
    let tracing = gpu().map_or_else(|_| TracingSupport::default(), |g| TracingSupport::of(&g));
    let fg = build_frame_graph_with(
        &registry,
        prepared.scene.clone(),
        &prepared.ao(&config.ao),
        FrameOutputs {
            shaded: true,
            ..Default::default()
        },
        Extent::new(config.width, config.height),
        &GBufferStates::default(),
        &tracing,
    )?;
    let plan =
        GraphCompiler::new().compile(fg.decl, &shader_library(), CompileOptions::default())?;
    if dot {
        print!("{}", to_dot(&plan));
    } else {
        println!(
            "technique {} on {} (view {}), {} (g-buffer channels: {})",
            config.ao.technique,
            config.scene.label(),
            prepared.view,
            prepared.radius_line(),
            fg.channels
                .iter()
                .map(|c| c.name())
                .collect::<Vec<_>>()
                .join(", ")
        );
        let size = Extent::new(config.width, config.height);
        if !registry.get(&config.ao.technique)?.is_baseline()
            && let Some(reach) = aograph_bench::reach::radius_reach(
                &registry,
                &prepared.ao(&config.ao),
                &prepared.scene,
                size,
            )?
        {
            println!("{}", reach.line(&config.ao.technique));
        }
        if let Some(backend) = aograph_ao_passes::TraceBackend::declared_by(&fg.declared) {
            println!(
                "ray tracer: {} (planned for {})",
                backend.name(),
                if tracing.adapter.is_empty() {
                    "no device: none found"
                } else {
                    &tracing.adapter
                }
            );
        }
        print!("{}", summary(&plan, size));
    }
    Ok(())
}
