//! aograph's measurement layer, what `aograph bench`, `tune`, `render` and the viewer share
//! beyond the renderer: the error metrics against the ray-traced reference ([`metrics`]: MAE,
//! SSIM, edge bands, flicker, radiance), the bench (a [`study`] of runs, [`sweep`]s,
//! [`stats`], results.csv, report.md, Pareto plots, [`roofline`], the [`motion`] bench) and
//! image output.
//!
//! Which crate owns what: `aograph-renderer` renders a scene's frames and their reference;
//! `aograph-app-config` says which frames a command asks for (config files, cameras, R); this
//! crate scores them; the `aograph` binary parses the command line and calls the commands.
//! None of it needs a window (no winit or egui).
//!
//! The bench's pieces:
//! - [`study`]: the plan of one invocation and its runs; [`run`]: one run (timing, metrics),
//!   the per-scene reference; [`sweep`]: parameter grids per technique (TOML);
//! - [`report`]: results.csv, results.json, report.md ([`results_csv`]: the CSV's columns);
//!   [`plot`]: pareto.svg/png (a grid: the summary, then each scene and view);
//!   [`run_images`]: AO | error | reference PNGs;
//! - [`roofline_table`]: report.md's roofline section; [`size_table`]: its table by output
//!   size (`--sizes`);
//! - [`convergence`]: every frame since a reset scored (`--convergence N`), its CSV and plot;
//! - [`scaling`]: times over resolutions and radii; [`search`]: the tune search;
//! - [`stats`]: median/quartiles and the log-log fit; [`csv`]: the quoting every CSV file
//!   uses; [`run_provenance`]: the command, commit and device of a run.
//!
//! ```
//! use aograph_bench::metrics::ssim::{SsimParams, ssim};
//! // A metric on two images, no GPU needed: an image against itself scores SSIM 1.
//! let (w, h) = (32, 24);
//! let image: Vec<f32> = (0..w * h).map(|i| (i % 7) as f32 / 7.0).collect();
//! let everywhere = vec![true; (w * h) as usize];
//! let s = ssim(&image, &image, &everywhere, w, h, &SsimParams::PAPER);
//! assert!((s - 1.0).abs() < 1e-9);
//! ```

#![warn(missing_docs)]

pub mod convergence;
pub mod csv;
pub mod images;
pub mod metrics;
pub mod motion;
pub mod plot;
pub mod reach;
pub mod report;
pub mod results_csv;
pub mod roofline;
pub mod roofline_table;
pub mod run;
pub mod run_images;
pub mod run_provenance;
pub mod scaling;
pub mod search;
mod shader_mount;
pub mod size_table;
pub mod stats;
pub mod study;
pub mod sweep;

pub use report::{BenchMeta, ResultsFile};
pub use run::{BenchContext, BenchSettings, RunRecord};
pub use scaling::ScalingResults;
pub use shader_mount::shader_mount;
pub(crate) use study::file_safe;
pub use study::{BenchPlan, ViewChoice, bench_meta, progress_bar, run_bench, run_scaling};
pub use sweep::{ParamSet, Sweep, plan_param_sets};
