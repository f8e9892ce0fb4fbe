//! `aograph render`: renders frames and writes ao.png, shaded.png and timings.txt (and, for
//! SSDO, its radiance images). The output directory is checked for writability before any GPU
//! work, and every file is written atomically.

use std::path::PathBuf;

use aograph_ao_passes::TechniqueRegistry;
use aograph_graph::Extent;

use super::{CommonArgs, gpu};
use crate::shader_library;
use aograph_app_config::error::AppResult;
use aograph_bench::images::{prepare_output_dir, write_atomic, write_gray_png, write_rgba_png};
use aograph_renderer::frame_graph::FrameOutputs;
use aograph_renderer::renderer::Renderer;

#[derive(Clone, Debug, Default)]
pub struct RenderArgs {
    pub common: CommonArgs,
    pub out: PathBuf,
    pub frames: Option<u32>,
    pub every: bool,
}

pub fn render(args: &RenderArgs) -> AppResult<()> {
    let registry = TechniqueRegistry::with_builtins();
    let config = args.common.resolve(&registry)?;
    let frames = args.frames.unwrap_or(config.frames);
    if frames == 0 {
        return Err(aograph_app_config::AppError::InvalidArgument {
            name: "--frames".into(),
            value: "0".into(),
            allowed: "1 or more".into(),
        });
    }
    let prepared = config.prepare_scene()?;
    prepare_output_dir(&args.out)?;
    let size = Extent::new(config.width, config.height);
    let started = std::time::Instant::now();
    let mut r = Renderer::new(
        gpu()?,
        shader_library(),
        &registry,
        prepared.scene.clone(),
        &prepared.ao(&config.ao),
        FrameOutputs {
            shaded: true,
            ..Default::default()
        },
        size,
    )?;
    // Which backend of the GPU ray tracer the technique's rays take, for a technique that
    // traces (rtao): said before any frame, and in timings.txt.
    let tracer_line = aograph_ao_passes::TraceBackend::declared_by(&r.graph.declared).map(|b| {
        format!(
            "ray tracer: {} ({}) on {}",
            b.name(),
            match b {
                aograph_ao_passes::TraceBackend::Hardware =>
                    "ray queries on acceleration structures",
                aograph_ao_passes::TraceBackend::Compute => "BVH traversal in a compute shader",
            },
            r.gpu.describe()
        )
    });
    if let Some(line) = &tracer_line {
        println!("{line}");
    }
    for f in 0..frames {
        r.render(f as f32 * config.frame_time)?;
        if args.every {
            write_gray_png(
                &args.out.join(format!("ao_{f:04}.png")),
                size.width,
                size.height,
                &r.read_ao()?,
            )?;
            write_rgba_png(
                &args.out.join(format!("shaded_{f:04}.png")),
                size.width,
                size.height,
                &r.read_shaded()?,
            )?;
        }
    }
    let ao = args.out.join("ao.png");
    let shaded = args.out.join("shaded.png");
    write_gray_png(&ao, size.width, size.height, &r.read_ao()?)?;
    write_rgba_png(&shaded, size.width, size.height, &r.read_shaded()?)?;
    let mut written = vec![ao, shaded];
    for (name, _) in r.graph.extra.clone() {
        // Each extra at its own size and channel count: one channel (a per-frame
        // accessibility, a half-size depth) as grey, more as RGB with the sRGB curve.
        let readback = r.read_extra_readback(name)?;
        let (extent, channels) = (readback.extent, readback.channels().max(1));
        let values = readback.to_f32()?;
        let path = args.out.join(format!("{name}.png"));
        if channels == 1 {
            write_gray_png(&path, extent.width, extent.height, &values)?;
        } else {
            let bytes: Vec<u8> = values
                .chunks_exact(channels)
                .flat_map(|c| {
                    [0, 1, 2]
                        .map(|i| c.get(i).copied().unwrap_or(0.0))
                        .map(|v| (v.clamp(0.0, 1.0).powf(1.0 / 2.2) * 255.0).round() as u8)
                        .into_iter()
                        .chain([255])
                })
                .collect();
            write_rgba_png(&path, extent.width, extent.height, &bytes)?;
        }
        written.push(path);
    }
    // A single frame is a cold one: on its first dispatch a driver compiles each pipeline, and
    // that shows up in the passes' times. Its images are written; the times are a repeat of it.
    let timing_line = if frames == 1 {
        let cold = r.timings()?.total_ms();
        r.render((frames - 1) as f32 * config.frame_time)?;
        format!(
            "# times: a warm repeat of the frame (the first, cold one took {cold:.1} ms over its passes, pipeline compilation included)\n"
        )
    } else {
        format!("# times: frame {frames} (warm)\n")
    };
    let timings = r.timings()?;
    let mut text = format!(
        "# aograph render: technique {} on {} (view {}) at {}, frame {} of {}, {}\n# device: {}{}\n",
        config.ao.technique,
        config.scene.label(),
        prepared.view,
        size,
        frames,
        frames,
        prepared.radius_line(),
        r.gpu.describe(),
        if r.gpu.is_software() {
            " (software device: times are CPU times)"
        } else {
            ""
        }
    );
    if let Some(line) = &tracer_line {
        text.push_str(&format!("# {line}\n"));
    }
    text.push_str(&timing_line);
    text.push_str(&timings.table());
    let tpath = args.out.join("timings.txt");
    write_atomic(&tpath, text.as_bytes())?;
    written.push(tpath);
    println!(
        "rendered {} (view {}) with {} at {}, {} ({} frame{}) in {:.2} s",
        config.scene.label(),
        prepared.view,
        config.ao.technique,
        size,
        prepared.radius_line(),
        frames,
        if frames == 1 { "" } else { "s" },
        started.elapsed().as_secs_f64()
    );
    print!("{}", timings.table());
    for p in written {
        println!("wrote {}", p.display());
    }
    Ok(())
}
