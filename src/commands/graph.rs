//! `aograph graph`: the compiled plan of a config as a text summary or Graphviz DOT.

use aograph_ao::TechniqueRegistry;
use aograph_graph::{CompileOptions, Extent, GraphCompiler, summary, to_dot};

use super::CommonArgs;
use crate::error::AppResult;
use crate::frame_graph::{FrameOutputs, build_frame_graph};
use crate::renderer::shader_library;

pub fn graph(args: &CommonArgs, dot: bool) -> AppResult<()> {
    let registry = TechniqueRegistry::with_builtins();
    let config = args.resolve(&registry)?;
    let prepared = config.prepare_scene()?;
    let fg = build_frame_graph(
        &registry,
        prepared.scene.clone(),
        &prepared.ao(&config.ao),
        FrameOutputs {
            shaded: true,
            ..Default::default()
        },
        Extent::new(config.width, config.height),
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
            && let Some(reach) = crate::reach::radius_reach(
                &registry,
                &prepared.ao(&config.ao),
                &prepared.scene,
                size,
            )?
        {
            println!("{}", reach.line(&config.ao.technique));
        }
        print!("{}", summary(&plan, size));
    }
    Ok(())
}
