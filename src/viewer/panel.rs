//! The viewer's control panel (egui): scene, technique, parameters generated from each
//! technique's parameter descriptions (`aograph_ao_passes::ParamDesc`: a user technique gets its
//! controls with no code of its own), the shared R and the intermediate precision, display mode, camera,
//! per-pass timings as bars with moving averages, texture memory, culled passes, the
//! reference's progress, and saving. Every change goes through the session, which checks it;
//! a rejected change shows its message and changes nothing.

use std::path::PathBuf;

use aograph_ao_passes::{IntermediateFormat, ParamDesc, ParamKind, Radius};
use aograph_graph::texture_bytes;

use super::camera_control::CameraMode;
use super::display::DisplayMode;
use super::session::Session;
use aograph_app_config::config::{RadiusSetting, SceneSource};

/// What the panel keeps between frames.
#[derive(Default)]
pub struct PanelState {
    pub scene_path: String,
    pub save_path: String,
    pub screenshot_path: String,
    /// The last message: (is an error, text).
    pub message: Option<(bool, String)>,
}

impl PanelState {
    pub fn new() -> Self {
        Self {
            save_path: "out/view.toml".into(),
            screenshot_path: "out/view.png".into(),
            ..Default::default()
        }
    }
    /// Shows the outcome of an action.
    pub fn report(&mut self, result: aograph_app_config::AppResult<String>) {
        self.message = Some(match result {
            Ok(m) => (false, m),
            Err(e) => (true, e.to_string()),
        });
    }
}

/// Draws the side panel into the root `ui`; changes go to the session as they are made.
pub fn side_panel(ui: &mut egui::Ui, s: &mut Session, p: &mut PanelState) {
    egui::Panel::left("controls")
        .resizable(true)
        .default_size(340.0)
        .min_size(300.0)
        .show(ui, |ui| {
            egui::ScrollArea::vertical().show(ui, |ui| {
                if let Some((error, text)) = &p.message {
                    let color = if *error {
                        egui::Color32::from_rgb(255, 110, 110)
                    } else {
                        egui::Color32::from_rgb(150, 220, 150)
                    };
                    ui.colored_label(color, text);
                    ui.separator();
                }
                technique_section(ui, s, p);
                display_section(ui, s);
                timing_section(ui, s);
                params_section(ui, s, p);
                camera_section(ui, s, p);
                scene_section(ui, s, p);
                save_section(ui, s, p);
            });
        });
}

fn scene_section(ui: &mut egui::Ui, s: &mut Session, p: &mut PanelState) {
    egui::CollapsingHeader::new("Scene")
        .default_open(false)
        .show(ui, |ui| {
            let current = s.settings.scene.label();
            let mut picked = None;
            egui::ComboBox::from_label("procedural")
                .selected_text(&current)
                .show_ui(ui, |ui| {
                    for name in aograph_scene::PROCEDURAL_SCENE_NAMES {
                        if ui.selectable_label(current == *name, *name).clicked() {
                            picked = Some(SceneSource::Procedural(name.to_string()));
                        }
                    }
                });
            ui.horizontal(|ui| {
                ui.text_edit_singleline(&mut p.scene_path)
                    .on_hover_text("a .gltf or .glb file (or drop one on the window)");
                if ui.button("Open").clicked() && !p.scene_path.trim().is_empty() {
                    picked = Some(SceneSource::File(PathBuf::from(p.scene_path.trim())));
                }
            });
            if let Some(source) = picked {
                let label = source.label();
                p.report(s.load_scene(source).map(|_| format!("opened {label}")));
            }
        });
}

fn technique_section(ui: &mut egui::Ui, s: &mut Session, p: &mut PanelState) {
    egui::CollapsingHeader::new("Technique")
        .default_open(true)
        .show(ui, |ui| {
            let current = s.settings.ao.technique.clone();
            let names = s.registry.names();
            ui.horizontal_wrapped(|ui| {
                for name in names {
                    if ui.selectable_label(current == name, &name).clicked() && current != name {
                        p.report(s.set_technique(&name).map(|_| format!("technique {name}")));
                    }
                }
            });
        })
        .header_response
        .on_hover_text("switching is live; plans seen before are reused");
}

fn params_section(ui: &mut egui::Ui, s: &mut Session, p: &mut PanelState) {
    egui::CollapsingHeader::new("Parameters")
        .default_open(true)
        .show(ui, |ui| {
            // The shared radius R and the intermediate precision.
            let mut r = s.radius();
            let speed = r as f64 * 0.01;
            ui.horizontal(|ui| {
                let drag = ui.add(
                    egui::DragValue::new(&mut r)
                        .range(1e-4..=1e5)
                        .speed(speed)
                        .prefix("R = "),
                );
                if drag.changed() {
                    p.report(
                        Radius::new("R", r)
                            .map_err(Into::into)
                            .and_then(|r| s.set_radius(RadiusSetting::Units(r)))
                            .map(|_| format!("R = {r}")),
                    );
                }
                if ui.button("auto").clicked() {
                    p.report(s.set_radius(RadiusSetting::Auto).map(|_| "R auto".into()));
                }
            });
            ui.small(&s.radius_note);
            let mut f = s.settings.ao.intermediate_format;
            egui::ComboBox::from_label("intermediate precision")
                .selected_text(match f {
                    IntermediateFormat::R16Float => "r16float",
                    IntermediateFormat::R32Float => "r32float",
                })
                .show_ui(ui, |ui| {
                    ui.selectable_value(&mut f, IntermediateFormat::R16Float, "r16float");
                    ui.selectable_value(&mut f, IntermediateFormat::R32Float, "r32float");
                });
            if f != s.settings.ao.intermediate_format {
                p.report(s.set_intermediate(f).map(|_| "precision changed".into()));
            }
            ui.separator();
            let Ok(technique) = s.technique().cloned() else {
                return;
            };
            let name = technique.name();
            let current = s.settings.ao.params_for(name);
            for desc in technique.parameters() {
                let value = current.get(desc.name).or(desc.default.as_ref()).cloned();
                let changed = ui
                    .horizontal(|ui| {
                        let out = control(ui, &desc, value.as_ref());
                        if current.contains_key(desc.name) && ui.small_button("reset").clicked() {
                            return Some(None);
                        }
                        out.map(Some)
                    })
                    .inner;
                ui.small(desc.doc);
                match changed {
                    Some(Some(v)) => {
                        let text = format!("{} = {v}", desc.name);
                        p.report(s.set_param(desc.name, v).map(|_| text));
                    }
                    Some(None) => p.report(
                        s.reset_param(desc.name)
                            .map(|_| format!("{} reset", desc.name)),
                    ),
                    None => {}
                }
            }
        });
}

/// One parameter's control, from its description (a slider bounded by its range, odd counts
/// stepping by two, a list of its choices, a checkbox); returns the new value when the user
/// changed it. `value` is the table's, else the default; `None` for an unset override (shown
/// as what leaving it out means).
fn control(
    ui: &mut egui::Ui,
    desc: &ParamDesc,
    value: Option<&toml::Value>,
) -> Option<toml::Value> {
    let name = desc.name;
    if value.is_none() {
        ui.weak(format!("({})", desc.unset.unwrap_or("default")));
    }
    match &desc.kind {
        ParamKind::Bool => {
            let mut b = value.and_then(|v| v.as_bool()).unwrap_or(false);
            ui.checkbox(&mut b, name)
                .changed()
                .then_some(toml::Value::Boolean(b))
        }
        ParamKind::Choice(options) => {
            let current = value.and_then(|v| v.as_str()).unwrap_or("").to_string();
            let mut picked = None;
            egui::ComboBox::from_label(name)
                .selected_text(current.as_str())
                .show_ui(ui, |ui| {
                    for o in options.iter() {
                        if ui.selectable_label(*o == current, *o).clicked() && *o != current {
                            picked = Some(toml::Value::String(o.to_string()));
                        }
                    }
                });
            picked
        }
        ParamKind::Range {
            min,
            max,
            integer: true,
            odd,
            ..
        } => {
            let (min, max) = (*min as i64, *max as i64);
            let mut v = value.and_then(|v| v.as_integer()).unwrap_or(min);
            let slider = egui::Slider::new(&mut v, min..=max).text(name);
            let slider = if *odd { slider.step_by(2.0) } else { slider };
            ui.add(slider)
                .changed()
                .then_some(toml::Value::Integer(if *odd { v | 1 } else { v }))
        }
        ParamKind::Range {
            min,
            max,
            above_min,
            ..
        } => {
            // An open lower end: the smallest value a slider offers is just above it.
            let min = if *above_min {
                min + (max - min) * 1e-4
            } else {
                *min
            };
            let mut v = value
                .and_then(|v| v.as_float().or_else(|| v.as_integer().map(|i| i as f64)))
                .unwrap_or(min);
            let log = min > 0.0 && max / min > 100.0;
            ui.add(
                egui::Slider::new(&mut v, min..=*max)
                    .logarithmic(log)
                    .text(name),
            )
            .changed()
            .then_some(toml::Value::Float(v))
        }
        ParamKind::WordOrNumber { word, min, max } => {
            let (min, max) = (*min as i64, *max as i64);
            let mut is_word = value.is_some_and(|v| v.as_str() == Some(*word));
            let mut n = value.and_then(|v| v.as_integer()).unwrap_or(min);
            let mut out = None;
            if ui.checkbox(&mut is_word, *word).changed() {
                out = Some(if is_word {
                    toml::Value::String(word.to_string())
                } else {
                    toml::Value::Integer(n)
                });
            }
            if !is_word
                && ui
                    .add(egui::Slider::new(&mut n, min..=max).text(name))
                    .changed()
            {
                out = Some(toml::Value::Integer(n));
            }
            out
        }
    }
}

fn display_section(ui: &mut egui::Ui, s: &mut Session) {
    egui::CollapsingHeader::new("Display")
        .default_open(true)
        .show(ui, |ui| {
            ui.horizontal(|ui| {
                for m in DisplayMode::ALL {
                    ui.selectable_value(&mut s.settings.display, m, m.name());
                }
            });
            if matches!(
                s.settings.display,
                DisplayMode::Split | DisplayMode::Temporal
            ) {
                ui.add(egui::Slider::new(&mut s.settings.split, 0.0..=1.0).text("split"));
            }
            if s.settings.display == DisplayMode::Error {
                ui.add(
                    egui::Slider::new(&mut s.settings.error_scale, 0.01..=1.0)
                        .text("full colour at |error|"),
                );
                ui.small("red: the technique is too bright; blue: too dark");
                // What no screen-space technique can reach here (docs/results/error-sources.md:
                // "two ceilings in every bench row"): the reference re-traced with its own rays
                // against less.
                match &s.reference_ceilings {
                    Some(c) => {
                        ui.small(format!(
                            "ceilings at {} rays, MAE / SSIM against the reference:",
                            c.rays
                        ));
                        ui.small(format!(
                            "(a) the g-buffer's surfaces {:.4} / {:.3}",
                            c.gbuffer.0, c.gbuffer.1
                        ));
                        ui.small(format!(
                            "(b) the triangles the frame sees {:.4} / {:.3}",
                            c.seen.0, c.seen.1
                        ));
                    }
                    None => {
                        ui.small("ceilings: traced after the reference's last pass");
                    }
                }
            }
            ui.checkbox(&mut s.settings.animate, "animate the scene");
        });
}

fn camera_section(ui: &mut egui::Ui, s: &mut Session, p: &mut PanelState) {
    egui::CollapsingHeader::new("Camera")
        .default_open(false)
        .show(ui, |ui| {
            ui.horizontal(|ui| {
                ui.selectable_value(&mut s.camera.mode, CameraMode::Orbit, "orbit");
                ui.selectable_value(&mut s.camera.mode, CameraMode::Fly, "fly");
                if ui.button("reset (R)").clicked() {
                    s.camera.reset();
                }
            });
            let mut picked = None;
            egui::ComboBox::from_label("views")
                .selected_text("choose a view")
                .show_ui(ui, |ui| {
                    for (name, _) in &s.views {
                        if ui.selectable_label(false, name).clicked() {
                            picked = Some(name.clone());
                        }
                    }
                });
            if let Some(name) = picked {
                p.report(s.set_view(&name).map(|_| format!("view {name}")));
            }
            ui.small(
            "drag: orbit (fly: look); wheel: zoom; WASD move, Q/E down/up; F: orbit/fly; R: reset",
        );
        });
}

fn timing_section(ui: &mut egui::Ui, s: &mut Session) {
    egui::CollapsingHeader::new("Timings and memory")
        .default_open(true)
        .show(ui, |ui| {
            let size = s.size();
            ui.label(format!(
                "frame {:.1} ms (moving average, wall clock) at {size}",
                s.stats.frame_ms
            ));
            ui.label(if s.stats.cpu_times {
                "per pass: CPU times (a software device)"
            } else {
                "per pass: GPU timestamps"
            });
            let max = s
                .stats
                .passes
                .iter()
                .map(|p| p.2)
                .fold(0.0f64, f64::max)
                .max(1e-6);
            for (name, last, avg) in &s.stats.passes {
                ui.add(
                    egui::ProgressBar::new((*avg / max) as f32)
                        .text(format!("{name}: {avg:.2} ms (last {last:.2})")),
                );
            }
            let plan = &s.renderer.plan;
            let (bytes, unshared) = texture_bytes(plan, size);
            ui.label(format!(
                "textures: {:.2} MiB ({:.2} MiB without reuse)",
                bytes as f64 / 1048576.0,
                unshared as f64 / 1048576.0
            ));
            let culled = plan.culled_names();
            ui.label(format!(
                "culled passes: {}",
                if culled.is_empty() {
                    "none".to_string()
                } else {
                    culled.join(", ")
                }
            ));
            ui.label(format!("pipelines created: {}", s.pipelines_created()));
            ui.add(egui::ProgressBar::new(s.reference_progress).text(format!(
                "reference: {} rays/pixel done ({:.0}%)",
                s.reference_rays,
                s.reference_progress * 100.0
            )));
        });
}

fn save_section(ui: &mut egui::Ui, s: &mut Session, p: &mut PanelState) {
    egui::CollapsingHeader::new("Save")
        .default_open(false)
        .show(ui, |ui| {
            ui.horizontal(|ui| {
                ui.text_edit_singleline(&mut p.save_path);
                if ui.button("save config").clicked() {
                    let path = PathBuf::from(&p.save_path);
                    p.report(
                        s.save_config(&path)
                            .map(|_| format!("wrote {}", path.display())),
                    );
                }
            });
            ui.horizontal(|ui| {
                ui.text_edit_singleline(&mut p.screenshot_path);
                if ui.button("screenshot").clicked() {
                    let path = PathBuf::from(&p.screenshot_path);
                    p.report(
                        s.screenshot(&path)
                            .map(|_| format!("wrote {}", path.display())),
                    );
                }
            });
        });
}
