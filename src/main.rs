//! The `aograph` command line: parse arguments, run one command, print errors a user can act on.

use std::path::PathBuf;
use std::process::ExitCode;

use aograph::commands::{self, RenderArgs};
use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(
    name = "aograph",
    version,
    about = "Render-graph SSAO techniques on wgpu, measured against a ray-traced reference"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(clap::Args, Clone, Debug, Default)]
struct Common {
    /// Config file (TOML; see configs/reference.toml for every key).
    #[arg(long)]
    config: Option<PathBuf>,
    /// Scene: a procedural name (columns, plane, ...) or a .gltf/.glb file.
    #[arg(long)]
    scene: Option<String>,
    /// AO technique (see `aograph techniques`).
    #[arg(long)]
    technique: Option<String>,
    /// Output width in pixels.
    #[arg(long)]
    width: Option<u32>,
    /// Output height in pixels.
    #[arg(long)]
    height: Option<u32>,
    /// Shared AO radius R: `auto` (the default: the scene's size / 9) or world units.
    // A negative value reaches the range check (clap would read "-1" as a flag).
    #[arg(long, allow_hyphen_values = true)]
    radius: Option<String>,
    /// Camera: a view (default, outside, outside-2, interior-1, interior-2, a [[views]] name),
    /// a glTF camera's name or index, or inline "pos=x,y,z target=x,y,z fov=60".
    #[arg(long)]
    camera: Option<String>,
}

#[derive(Subcommand)]
enum Command {
    /// Render a scene with a technique: writes ao.png, shaded.png and timings.txt.
    Render {
        #[command(flatten)]
        common: Common,
        /// Output directory.
        #[arg(long, default_value = "out")]
        out: PathBuf,
        /// Number of frames to render (animated scenes move; temporal techniques converge).
        #[arg(long)]
        frames: Option<u32>,
        /// Write every frame (ao_0000.png, ...) instead of only the last.
        #[arg(long)]
        every: bool,
    },
    /// Open the interactive viewer: swap techniques live, tune parameters, fly the camera,
    /// compare with the ray-traced reference (needs an X11 display; see docs/guide/viewer.md).
    View {
        #[command(flatten)]
        common: Common,
        /// Run the actions of this script, then exit (see docs/guide/viewer.md: tests and
        /// screenshots).
        #[arg(long)]
        script: Option<PathBuf>,
    },
    /// Print the compiled plan of a config (or its Graphviz DOT with --dot).
    Graph {
        #[command(flatten)]
        common: Common,
        /// Print DOT instead of the text summary.
        #[arg(long)]
        dot: bool,
    },
    /// List the techniques with their parameters, defaults and allowed ranges.
    Techniques {
        /// Print each technique's settings as a Markdown table (what docs/techniques/ holds).
        #[arg(long)]
        markdown: bool,
        /// Instead, check each technique's plan against WebGPU's default limits and core
        /// storage formats (what a browser gives a page that asks for nothing more).
        #[arg(long)]
        webgpu_limits: bool,
    },
    /// Rewrite the text of README.md and docs/ that a tool owns (parameter tables, results
    /// tables from docs/results/*/results.json), between its markers; run in the repository.
    Docs {
        /// Write nothing; fail naming every file whose text differs (what CI runs).
        #[arg(long)]
        check: bool,
    },
    /// Ray-trace the reference AO of a scene.
    Reference {
        #[command(flatten)]
        common: Common,
        /// Rays per pixel.
        #[arg(long)]
        rays: Option<u32>,
        /// binary or obscurance.
        #[arg(long)]
        mode: Option<String>,
        /// The normal that orients each pixel's hemisphere: geometric (default) or shading.
        #[arg(long)]
        normals: Option<String>,
        #[arg(long, default_value = "out")]
        out: PathBuf,
    },
    /// Measure techniques against the reference: tables, Pareto plot, images (or --scaling).
    Bench(commands::BenchArgs),
    /// Print the most accurate config whose AO time fits a budget on this device.
    Tune(commands::TuneArgs),
    /// The shaded scene, the reference and techniques side by side in one PNG.
    Montage {
        #[command(flatten)]
        common: Common,
        /// Techniques, comma-separated.
        #[arg(long, value_delimiter = ',', default_value = "ssao,hbao,pyramid-hbao")]
        techniques: Vec<String>,
        /// Reference rays per pixel.
        #[arg(long, default_value_t = 256)]
        rays: u32,
        /// The PNG to write.
        #[arg(long, default_value = "out/montage.png")]
        out: PathBuf,
    },
    /// Scenes: export one as .glb, describe one, list the procedural ones.
    Scene {
        #[command(subcommand)]
        action: SceneAction,
    },
}

#[derive(Subcommand)]
enum SceneAction {
    /// Export a scene as .glb: a procedural one, or a glTF file's pose at t = 0 (skins baked).
    Export {
        /// A procedural scene's name or a .gltf/.glb file.
        scene: String,
        file: PathBuf,
    },
    /// Bounds, counts, cameras, materials, transforms, views and the suggested radius.
    Info {
        /// A procedural scene's name or a .gltf/.glb file (or give it as --scene, as the
        /// other commands take it).
        #[arg(required_unless_present = "scene_flag", conflicts_with = "scene_flag")]
        scene: Option<String>,
        #[arg(long = "scene", id = "scene_flag", value_name = "SCENE")]
        scene_flag: Option<String>,
    },
    /// List the procedural scenes.
    List,
}

impl Common {
    fn into_args(self) -> commands::CommonArgs {
        commands::CommonArgs {
            config: self.config,
            scene: self.scene,
            technique: self.technique,
            width: self.width,
            height: self.height,
            radius: self.radius,
            camera: self.camera,
        }
    }
}

/// `aograph view`: the flags over the config file, then the viewer.
#[cfg(feature = "viewer")]
fn view(
    common: commands::CommonArgs,
    script: Option<std::path::PathBuf>,
) -> aograph_app_config::AppResult<()> {
    let config = common.resolve(&aograph_ao_passes::TechniqueRegistry::with_builtins())?;
    // A size is fixed only when asked for; the config's default size is not a request.
    let size = match (common.width, common.height) {
        (Some(w), Some(h)) => Some(aograph_graph::Extent::new(w, h)),
        (None, None) => None,
        _ => Some(aograph_graph::Extent::new(config.width, config.height)),
    };
    aograph::viewer::view(&aograph::viewer::ViewArgs {
        config,
        size,
        script,
    })
}

fn main() -> ExitCode {
    aograph::runtime_dir::ensure_runtime_dir();
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Render {
            common,
            out,
            frames,
            every,
        } => commands::render(&RenderArgs {
            common: common.into_args(),
            out,
            frames,
            every,
        }),
        #[cfg(feature = "viewer")]
        Command::View { common, script } => view(common.into_args(), script),
        #[cfg(not(feature = "viewer"))]
        Command::View { .. } => Err(aograph_app_config::AppError::InvalidArgument {
            name: "view".into(),
            value: "this aograph was built without the viewer".into(),
            allowed: "a build with the `viewer` feature (on by default: cargo build, or \
                      cargo build --features viewer)"
                .into(),
        }),
        Command::Graph { common, dot } => commands::graph(&common.into_args(), dot),
        Command::Techniques {
            markdown,
            webgpu_limits,
        } => commands::techniques(markdown, webgpu_limits),
        Command::Docs { check } => commands::docs(check),
        Command::Reference {
            common,
            rays,
            mode,
            normals,
            out,
        } => commands::reference(
            &common.into_args(),
            rays,
            mode.as_deref(),
            normals.as_deref(),
            &out,
        ),
        Command::Bench(args) => commands::bench(&args),
        Command::Tune(args) => commands::tune(&args),
        Command::Montage {
            common,
            techniques,
            rays,
            out,
        } => commands::montage(&common.into_args(), &techniques, rays, &out),
        Command::Scene {
            action: SceneAction::Export { scene, file },
        } => commands::scene_export(&scene, &file),
        Command::Scene {
            action: SceneAction::Info { scene, scene_flag },
        } => match scene.or(scene_flag) {
            Some(scene) => commands::scene_info(&scene),
            None => Err(aograph_app_config::AppError::InvalidArgument {
                name: "scene info".into(),
                value: "no scene".into(),
                allowed: "a scene name or file, as an argument or --scene".into(),
            }),
        },
        Command::Scene {
            action: SceneAction::List,
        } => {
            println!("{}", aograph_scene::PROCEDURAL_SCENE_NAMES.join("\n"));
            Ok(())
        }
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
