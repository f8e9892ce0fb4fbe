//! The files of a motion run: motion.csv (one row per run), motion_frames.csv (per-frame
//! MAE), motion.json and motion.md. Invariant: every file is rewritten whole, atomically, after
//! each run, so an interrupted bench leaves complete files of the runs that finished.

use std::collections::BTreeMap;
use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::csv;
use crate::images::write_atomic;
use crate::report::BenchMeta;
use crate::run::FrameTimes;
use aograph_app_config::error::{AppError, AppResult};

/// One row of motion.csv: a technique and parameter set over a motion run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MotionRecord {
    /// The scene's label: the procedural name or the glTF path as given.
    pub scene: String,
    /// The view's name ("default": the scene's own camera).
    pub view: String,
    /// How the camera moved: `orbit`, `path` or `scene`.
    pub motion: String,
    /// The technique's registry name.
    pub technique: String,
    /// The parameter set's label (`ParamSet::label`).
    pub label: String,
    /// The parameter set's values by name (empty: the technique's defaults).
    pub params: BTreeMap<String, toml::Value>,
    /// Output width in pixels.
    pub width: u32,
    /// Output height in pixels.
    pub height: u32,
    /// The AO radius R in scene units.
    pub radius: f32,
    /// Rays per pixel of each frame's reference (`--motion-rays`).
    pub rays: u32,
    /// Frames per second of scene time.
    pub fps: f32,
    /// Measured frames, each scored against its own reference.
    pub frames: u32,
    /// Warm-up frames rendered (moving) and discarded first.
    pub warmup: u32,
    /// The technique's passes ("total", g-buffer excluded), the whole frame ("frame", what a
    /// frame rate is made of) and each pass, over the measured frames.
    #[serde(flatten)]
    pub times: FrameTimes,
    /// Mean over the measured frames of each frame's MAE against its own reference (non-sky
    /// pixels, 0..1).
    pub mae_mean: f64,
    /// The largest per-frame MAE.
    pub mae_worst: f64,
    /// Mean edge-band MAE over the frames that have a depth edge; `None` when none has.
    pub edge_mae_mean: Option<f64>,
    /// Mean over the measured frames of each frame's SSIM against its own reference.
    pub ssim_mean: f64,
    /// MAE near surfaces that move on their own (`None`: nothing moves on its own).
    pub moving_mae_mean: Option<f64>,
    /// Mean change of a surface point's accessibility from frame to frame (module docs).
    pub flicker: Option<f64>,
    /// Share of the measured pixels that had a history to compare with.
    pub flicker_coverage: Option<f64>,
    /// Per measured frame: MAE.
    pub frame_mae: Vec<f64>,
    /// The last frame's side-by-side image, relative to the output directory; `None` when no
    /// output directory was given.
    pub image: Option<String>,
}

impl MotionRecord {
    /// motion.csv's header; times in ms, errors 0..1.
    pub const CSV_HEADER: &'static str = "scene,view,motion,technique,label,width,height,radius,rays,fps,frames,warmup,timing_source,total_ms_median,total_ms_q1,total_ms_q3,frame_ms_median,mae_mean,mae_worst,edge_mae_mean,ssim_mean,moving_mae_mean,flicker,flicker_coverage";

    /// This record as one motion.csv line (no newline), in [`MotionRecord::CSV_HEADER`]'s
    /// column order; fields quoted where they need it (crate::csv).
    pub fn csv_row(&self) -> String {
        let opt = |v: Option<f64>| v.map(|v| format!("{v:.6}")).unwrap_or_default();
        format!(
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{:.4},{:.4},{:.4},{:.4},{:.6},{:.6},{},{:.6},{},{},{}",
            csv::field(&self.scene),
            csv::field(&self.view),
            csv::field(&self.motion),
            csv::field(&self.technique),
            csv::field(&self.label),
            self.width,
            self.height,
            self.radius,
            self.rays,
            self.fps,
            self.frames,
            self.warmup,
            self.times.timing_source,
            self.times.total_ms.median,
            self.times.total_ms.q1,
            self.times.total_ms.q3,
            self.times.frame_ms.median,
            self.mae_mean,
            self.mae_worst,
            opt(self.edge_mae_mean),
            self.ssim_mean,
            opt(self.moving_mae_mean),
            opt(self.flicker),
            opt(self.flicker_coverage),
        )
    }
}

/// motion.json: the device and settings the runs share (with the command, commit and date,
/// as results.json records them), then one record per finished run.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct MotionFile {
    /// The device and settings every run shares.
    pub meta: BenchMeta,
    /// One record per finished run, in the order they finished.
    pub runs: Vec<MotionRecord>,
}

/// Reads a motion.json that `aograph bench --motion` wrote.
pub fn read_motion(path: &Path) -> AppResult<MotionFile> {
    let text = std::fs::read_to_string(path).map_err(|e| AppError::io("read", path, e))?;
    serde_json::from_str(&text).map_err(|e| AppError::io("parse", path, e))
}

pub(super) fn write_motion_files(
    dir: &Path,
    meta: &BenchMeta,
    records: &[MotionRecord],
) -> AppResult<()> {
    let mut csv = format!("{}\n", MotionRecord::CSV_HEADER);
    let mut per_frame = String::from("scene,view,motion,technique,label,frame,mae\n");
    for r in records {
        csv.push_str(&r.csv_row());
        csv.push('\n');
        for (i, mae) in r.frame_mae.iter().enumerate() {
            per_frame.push_str(&format!(
                "{},{},{},{},{},{},{:.6}\n",
                csv::field(&r.scene),
                csv::field(&r.view),
                csv::field(&r.motion),
                csv::field(&r.technique),
                csv::field(&r.label),
                i,
                mae
            ));
        }
    }
    write_atomic(&dir.join("motion.csv"), csv.as_bytes())?;
    write_atomic(&dir.join("motion_frames.csv"), per_frame.as_bytes())?;
    let file = MotionFile {
        meta: meta.clone(),
        runs: records.to_vec(),
    };
    let json = serde_json::to_string_pretty(&file)
        .map_err(|e| AppError::io("serialise", dir.join("motion.json"), e))?;
    write_atomic(&dir.join("motion.json"), json.as_bytes())?;
    write_atomic(&dir.join("motion.md"), motion_report(records).as_bytes())
}

/// motion.md: one table per scene, view and motion.
pub fn motion_report(records: &[MotionRecord]) -> String {
    let mut md = String::from("# aograph bench: techniques under motion\n\n");
    md.push_str(
        "Every measured frame is scored against its own reference. Flicker: mean change of a \
         surface point's accessibility from one frame to the next (pixels with a history on \
         the same surface; coverage = their share). Near moving: MAE within R of surfaces that \
         move on their own.\n",
    );
    let mut keys: Vec<(String, String, String)> = Vec::new();
    for r in records {
        let k = (r.scene.clone(), r.view.clone(), r.motion.clone());
        if !keys.contains(&k) {
            keys.push(k);
        }
    }
    let opt = |v: Option<f64>| v.map(|v| format!("{v:.4}")).unwrap_or_else(|| "-".into());
    for (scene, view, motion) in keys {
        let rows: Vec<&MotionRecord> = records
            .iter()
            .filter(|r| r.scene == scene && r.view == view && r.motion == motion)
            .collect();
        let first = rows[0];
        md.push_str(&format!(
            "\n## {scene} / {view}, motion `{motion}`\n\n{}x{}, {} frames at {} fps after {} warm-up, R = {}, {} rays/pixel, {}\n\n",
            first.width, first.height, first.frames, first.fps, first.warmup, first.radius,
            first.rays, first.times.timing_source
        ));
        md.push_str("| technique | parameters | total ms | frame ms | MAE mean | MAE worst | edge MAE | SSIM | near moving MAE | flicker | coverage |\n|---|---|---|---|---|---|---|---|---|---|---|\n");
        for r in rows {
            md.push_str(&format!(
                "| {} | {} | {:.2} | {:.2} | {:.4} | {:.4} | {} | {:.3} | {} | {} | {} |\n",
                r.technique,
                r.label,
                r.times.total_ms.median,
                r.times.frame_ms.median,
                r.mae_mean,
                r.mae_worst,
                opt(r.edge_mae_mean),
                r.ssim_mean,
                opt(r.moving_mae_mean),
                opt(r.flicker),
                r.flicker_coverage
                    .map(|c| format!("{:.0}%", 100.0 * c))
                    .unwrap_or_else(|| "-".into()),
            ));
        }
        md.push_str("\nPer pass (median ms over the measured frames, in execution order):\n\n");
        for r in records
            .iter()
            .filter(|r| r.scene == scene && r.view == view && r.motion == motion)
        {
            let passes: Vec<String> = r
                .times
                .passes
                .iter()
                .map(|p| format!("{} {:.2}", p.name, p.ms.median))
                .collect();
            md.push_str(&format!(
                "- {} {}: {}\n",
                r.technique,
                r.label,
                passes.join(", ")
            ));
        }
    }
    md
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stats::Spread;

    fn record(scene: &str, view: &str, label: &str) -> MotionRecord {
        let spread = Spread::of(&[1.0]);
        MotionRecord {
            scene: scene.into(),
            view: view.into(),
            motion: "orbit".into(),
            technique: "gtao".into(),
            label: label.into(),
            params: BTreeMap::new(),
            width: 64,
            height: 36,
            radius: 1.0,
            rays: 16,
            fps: 30.0,
            frames: 2,
            warmup: 0,
            times: FrameTimes {
                timing_source: "cpu-wall".into(),
                total_ms: spread,
                frame_ms: spread,
                passes: Vec::new(),
            },
            mae_mean: 0.1,
            mae_worst: 0.2,
            edge_mae_mean: None,
            ssim_mean: 0.5,
            moving_mae_mean: None,
            flicker: None,
            flicker_coverage: None,
            frame_mae: vec![0.1, 0.2],
            image: None,
        }
    }

    #[test]
    fn motion_files_quote_names_with_commas_and_keep_every_column() {
        let r = record("scenes/hall, east.gltf", "Camera \"A\"", "x, \"y\"");
        let dir = std::env::temp_dir().join(format!("aograph-motion-csv-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temp dir");
        let meta = BenchMeta {
            device: "test device".into(),
            backend: "Vulkan".into(),
            software: true,
            timestamps: false,
            width: 8,
            height: 8,
            frames: 2,
            warmup: 0,
            radius: None,
            rays: 4,
            mode: "binary".into(),
            normals: "geometric".into(),
            ssim: String::new(),
            edge_band: 3,
            edge_jump: 0.1,
            peaks: None,
            command: "aograph bench --motion orbit".into(),
            commit: None,
            date: "2026-12-06".into(),
        };
        write_motion_files(&dir, &meta, std::slice::from_ref(&r)).expect("written");
        // motion.json holds the meta beside the runs.
        let file = read_motion(&dir.join("motion.json")).expect("motion.json");
        assert_eq!((file.meta, file.runs), (meta, vec![r]));
        let names = [
            "scenes/hall, east.gltf",
            "Camera \"A\"",
            "orbit",
            "gtao",
            "x, \"y\"",
        ];
        let motion = std::fs::read_to_string(dir.join("motion.csv")).expect("motion.csv");
        let row = csv::split_row(motion.lines().nth(1).expect("one row"));
        assert_eq!(row.len(), MotionRecord::CSV_HEADER.split(',').count());
        assert_eq!(row[..5], names);
        let frames = std::fs::read_to_string(dir.join("motion_frames.csv")).expect("frames");
        let lines: Vec<&str> = frames.lines().collect();
        assert_eq!(lines.len(), 3, "a header and one line per frame");
        let row = csv::split_row(lines[2]);
        assert_eq!(row.len(), lines[0].split(',').count());
        assert_eq!(row[..5], names);
        assert_eq!(row[5..], ["1", "0.200000"]);
        let _ = std::fs::remove_dir_all(&dir);
    }
}
