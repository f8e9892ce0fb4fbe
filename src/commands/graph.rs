//! `aograph graph`: the compiled plan of a config as a text summary or Graphviz DOT.

use std::sync::Arc;

use aograph_ao::TechniqueRegistry;
use aograph_graph::{CompileOptions, Extent, GraphCompiler, summary, to_dot};

use super::CommonArgs;
use crate::error::AppResult;
use crate::frame_graph::{FrameOutputs, build_frame_graph};
use crate::renderer::shader_library;

pub fn graph(args: &CommonArgs, dot: bool) -> AppResult<()> {
    let registry = TechniqueRegistry::with_builtins();
    let config = args.resolve(&registry)?;
    let scene = Arc::new(crate::load_scene(&config.scene)?);
    let fg = build_frame_graph(
        &registry,
        scene,
        &config.ao,
        FrameOutputs {
            shaded: true,
            ..Default::default()
        },
    )?;
    let plan =
        GraphCompiler::new().compile(fg.decl, &shader_library(), CompileOptions::default())?;
    if dot {
        print!("{}", to_dot(&plan));
    } else {
        println!(
            "technique {} on {} (g-buffer channels: {})",
            config.ao.technique,
            config.scene.label(),
            fg.channels
                .iter()
                .map(|c| c.name())
                .collect::<Vec<_>>()
                .join(", ")
        );
        print!(
            "{}",
            summary(&plan, Extent::new(config.width, config.height))
        );
    }
    Ok(())
}
