//! `aograph techniques --webgpu-limits`: which techniques' plans fit a browser's device made
//! with WebGPU's default limits and core formats, checked at compile as on a real device
//! (`aograph_graph::check_plan`), with no browser and no GPU.
//!
//! Each technique is built in aograph's own frame (the g-buffer node, the technique, shading)
//! on the procedural `corner` at 64x64, with R = 0.5 and r32float intermediates: r16float
//! storage is not core WebGPU (the variants below show what each needing more is refused for).
//! The g-buffer raster counts: a technique that reads world positions or radiance makes it
//! write more than WebGPU's default 32 colour bytes per sample. An application's own renderer
//! (aograph-embed, the web page) has no such raster.

use std::sync::Arc;

use aograph_ao_passes::{AoConfig, TechniqueRegistry, TracingSupport};
use aograph_app_config::error::AppResult;
use aograph_graph::{CompileOptions, DeviceProfile, Extent, GraphCompiler};
use aograph_renderer::frame_graph::{FrameOutputs, build_frame_graph_with};
use aograph_renderer::gbuffer::GBufferStates;

use crate::shader_library;

/// The settings checked beyond each technique at its defaults: ones that need more than
/// WebGPU's defaults (r16float storage, ray queries).
const VARIANTS: &[(&str, &str)] = &[
    ("gtao", "intermediate_format = \"r16float\""),
    ("rtao", "[rtao]\ntracer = \"hardware\""),
];

/// One line per technique (and variant): "fits" or the compile error naming the limit.
pub fn webgpu_fit_lines(registry: &TechniqueRegistry) -> AppResult<Vec<String>> {
    let scene = Arc::new(aograph_scene::procedural_scene("corner")?);
    let shaders = shader_library();
    let mut cases: Vec<(String, String)> = registry
        .names()
        .into_iter()
        .map(|name| (name, String::new()))
        .collect();
    cases.extend(VARIANTS.iter().map(|(t, v)| (t.to_string(), v.to_string())));
    let mut lines = Vec::new();
    for (technique, extra) in cases {
        let r32 = if extra.contains("intermediate_format") {
            ""
        } else {
            "intermediate_format = \"r32float\"\n"
        };
        let (top, table) = extra
            .split_once('[')
            .map_or((extra.as_str(), String::new()), |(a, b)| {
                (a, format!("[{b}"))
            });
        let text = format!("technique = \"{technique}\"\nradius = 0.5\n{r32}{top}\n{table}");
        let table: toml::Table = text.parse().map_err(|e: toml::de::Error| {
            aograph_ao_passes::AoError::Config(e.message().to_string())
        })?;
        let config = AoConfig::from_table(&table, registry)?;
        // The hardware tracer is built as if the device had ray queries, so that the plan's
        // check, not the tracer's choice, is what refuses it.
        let tracing = TracingSupport {
            ray_queries: extra.contains("hardware"),
            adapter: "a WebGPU device with default limits".into(),
        };
        let label = if extra.is_empty() {
            technique.clone()
        } else {
            format!("{technique} ({})", extra.replace('\n', " "))
        };
        let built = build_frame_graph_with(
            registry,
            scene.clone(),
            &config,
            FrameOutputs {
                shaded: true,
                ..Default::default()
            },
            Extent::new(64, 64),
            &GBufferStates::default(),
            &tracing,
        );
        let verdict = match built {
            Err(e) => format!("refused: {e}"),
            Ok(fg) => match GraphCompiler::for_device(DeviceProfile::webgpu_defaults()).compile(
                fg.decl,
                &shaders,
                CompileOptions::default(),
            ) {
                Ok(_) => "fits".to_string(),
                Err(e) => format!("refused: {e}"),
            },
        };
        lines.push(format!("{label}: {verdict}"));
    }
    Ok(lines)
}
