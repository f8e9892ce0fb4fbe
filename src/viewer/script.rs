//! `aograph view --script FILE`: a list of actions run against the viewer, one per line, for
//! tests and demos. The whole file is parsed before the window opens (an unknown action or a
//! malformed value is an error naming the line); an action that fails while running ends the
//! viewer with an error naming the line.
//!
//! ```text
//! # comments and blank lines are skipped
//! technique mssao              # switch technique
//! param samples 16             # set a parameter of the current technique (a TOML value)
//! radius 0.5                   # the shared R (or: radius auto)
//! precision r32float           # intermediate precision
//! display split                # ao, shaded, split, error or temporal (accumulated | this frame)
//! split 0.4                    # where the split falls (0 to 1)
//! view outside                 # a named view of the scene
//! camera pos=0,2,5 target=0,0,0 fov=60
//! orbit 120 -30                # drag the camera by pixels
//! zoom 2                       # wheel steps
//! move forward 0.5             # fly: forward/back/left/right/up/down, seconds
//! scene teapot.gltf            # a procedural name or a file (a failure fails the script)
//! open teapot.gltf             # as the panel opens one: a failure is a message, the scene stays
//! size 160 96                  # render size
//! wait 10                      # render 10 frames
//! wait-reference 8             # until the reference has a complete pass of >= 8 rays
//! screenshot out/a.png         # the picture as shown
//! window-screenshot out/w.png  # the whole window, panel included (after the next frame)
//! save out/view.toml           # the settings as a config
//! mark                         # remember the pipelines created so far
//! expect-no-new-pipelines      # fail if any pipeline was created since `mark`
//! stats                        # print frame times since the last change
//! quit
//! ```

use std::path::{Path, PathBuf};

use super::camera_control::MoveKeys;
use super::display::DisplayMode;
use super::session::Session;
use aograph_app_config::config::{RadiusSetting, SceneSource};
use aograph_app_config::error::{AppError, AppResult};

/// One action.
#[derive(Clone, Debug, PartialEq)]
pub enum Action {
    Technique(String),
    Param(String, toml::Value),
    Radius(RadiusSetting),
    Precision(aograph_ao_passes::IntermediateFormat),
    Display(DisplayMode),
    Split(f32),
    View(String),
    Camera(String),
    Orbit(f32, f32),
    Zoom(f32),
    Move(MoveKeys, f32),
    Scene(SceneSource),
    Open(SceneSource),
    Size(u32, u32),
    Wait(u32),
    WaitReference(u32),
    Screenshot(PathBuf),
    WindowScreenshot(PathBuf),
    Save(PathBuf),
    Mark,
    ExpectNoNewPipelines,
    Stats,
    Quit,
}

/// A parsed script and where it stands.
pub struct Script {
    path: PathBuf,
    actions: Vec<(usize, Action)>,
    next: usize,
    /// Frames left to render before the next action.
    waiting: u32,
    /// Waiting for the reference to reach this many rays (with a frame budget).
    waiting_reference: Option<(u32, u32)>,
    mark: u64,
}

/// What the viewer does after a step.
#[derive(Debug, PartialEq)]
pub enum Step {
    /// Render a frame, then step again.
    Frame,
    Quit,
}

fn line_error(path: &Path, line: usize, message: impl std::fmt::Display) -> AppError {
    AppError::Config {
        path: format!("{}:{line}", path.display()),
        message: message.to_string(),
    }
}

/// The actions a script knows, for error messages.
const ACTIONS: &str = "technique, param, radius, precision, display, split, view, camera, orbit, \
     zoom, move, scene, open, size, wait, wait-reference, screenshot, window-screenshot, save, mark, \
     expect-no-new-pipelines, stats, quit";

fn parse_line(text: &str) -> Result<Option<Action>, String> {
    let text = text.split('#').next().unwrap_or("").trim();
    if text.is_empty() {
        return Ok(None);
    }
    let (word, rest) = text.split_once(char::is_whitespace).unwrap_or((text, ""));
    let rest = rest.trim();
    let args: Vec<&str> = rest.split_whitespace().collect();
    let need = |n: usize| {
        if args.len() == n {
            Ok(())
        } else {
            Err(format!(
                "`{word}` takes {n} argument(s), got {}",
                args.len()
            ))
        }
    };
    let num = |s: &str| {
        s.parse::<f32>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| format!("`{s}` is not a number"))
    };
    let count = |s: &str| {
        s.parse::<u32>()
            .map_err(|_| format!("`{s}` is not a whole number"))
    };
    Ok(Some(match word {
        "technique" => {
            need(1)?;
            Action::Technique(args[0].into())
        }
        "param" => {
            let (name, value) = rest
                .split_once(char::is_whitespace)
                .ok_or("`param` takes a name and a value")?;
            let value = format!("v = {}", value.trim())
                .parse::<toml::Table>()
                .ok()
                .and_then(|t| t.get("v").cloned())
                .ok_or_else(|| format!("`{}` is not a TOML value", value.trim()))?;
            Action::Param(name.into(), value)
        }
        "radius" => {
            need(1)?;
            Action::Radius(RadiusSetting::parse("radius", args[0]).map_err(|e| e.to_string())?)
        }
        "precision" => {
            need(1)?;
            Action::Precision(
                aograph_ao_passes::IntermediateFormat::parse(args[0]).map_err(|e| e.to_string())?,
            )
        }
        "display" => {
            need(1)?;
            Action::Display(DisplayMode::parse(args[0]).map_err(|e| e.to_string())?)
        }
        "split" => {
            need(1)?;
            let v = num(args[0])?;
            if !(0.0..=1.0).contains(&v) {
                return Err(format!("split {v}: allowed 0 to 1"));
            }
            Action::Split(v)
        }
        "view" => {
            need(1)?;
            Action::View(args[0].into())
        }
        "camera" => Action::Camera(rest.into()),
        "orbit" => {
            need(2)?;
            Action::Orbit(num(args[0])?, num(args[1])?)
        }
        "zoom" => {
            need(1)?;
            Action::Zoom(num(args[0])?)
        }
        "move" => {
            need(2)?;
            let mut keys = MoveKeys::default();
            match args[0] {
                "forward" => keys.forward = true,
                "back" => keys.back = true,
                "left" => keys.left = true,
                "right" => keys.right = true,
                "up" => keys.up = true,
                "down" => keys.down = true,
                d => {
                    return Err(format!(
                        "move {d}: allowed forward, back, left, right, up, down"
                    ));
                }
            }
            Action::Move(keys, num(args[1])?)
        }
        "scene" => {
            need(1)?;
            Action::Scene(SceneSource::parse(args[0]))
        }
        "open" => {
            need(1)?;
            Action::Open(SceneSource::parse(args[0]))
        }
        "size" => {
            need(2)?;
            Action::Size(count(args[0])?, count(args[1])?)
        }
        "wait" => {
            need(1)?;
            Action::Wait(count(args[0])?)
        }
        "wait-reference" => {
            need(1)?;
            Action::WaitReference(count(args[0])?)
        }
        "screenshot" => Action::Screenshot(PathBuf::from(rest)),
        "window-screenshot" => Action::WindowScreenshot(PathBuf::from(rest)),
        "save" => Action::Save(PathBuf::from(rest)),
        "mark" => Action::Mark,
        "expect-no-new-pipelines" => Action::ExpectNoNewPipelines,
        "stats" => Action::Stats,
        "quit" => Action::Quit,
        other => return Err(format!("unknown action `{other}` (known: {ACTIONS})")),
    }))
}

impl Script {
    /// Reads and parses `path`.
    pub fn load(path: &Path) -> AppResult<Self> {
        let text =
            std::fs::read_to_string(path).map_err(|e| AppError::io("read script", path, e))?;
        Self::parse(&text, path)
    }

    pub fn parse(text: &str, path: &Path) -> AppResult<Self> {
        let mut actions = Vec::new();
        for (i, line) in text.lines().enumerate() {
            if let Some(a) = parse_line(line).map_err(|m| line_error(path, i + 1, m))? {
                if matches!(a, Action::Screenshot(ref p) | Action::WindowScreenshot(ref p) | Action::Save(ref p) if p.as_os_str().is_empty())
                {
                    return Err(line_error(path, i + 1, "needs a file path"));
                }
                actions.push((i + 1, a));
            }
        }
        Ok(Self {
            path: path.to_path_buf(),
            actions,
            next: 0,
            waiting: 0,
            waiting_reference: None,
            mark: 0,
        })
    }

    /// True when the script sets the render size (the window's panel does not then).
    pub fn fixed_size(&self) -> bool {
        self.actions
            .iter()
            .any(|(_, a)| matches!(a, Action::Size(..)))
    }

    /// Runs actions until one needs frames rendered (or the script ends: then it quits).
    pub fn step(&mut self, s: &mut Session) -> AppResult<Step> {
        if self.waiting > 0 {
            self.waiting -= 1;
            return Ok(Step::Frame);
        }
        if let Some((rays, budget)) = self.waiting_reference {
            if s.reference_rays >= rays {
                self.waiting_reference = None;
            } else if budget == 0 {
                let line = self.actions[self.next - 1].0;
                return Err(line_error(
                    &self.path,
                    line,
                    format!("the reference did not reach {rays} rays per pixel in time"),
                ));
            } else {
                self.waiting_reference = Some((rays, budget - 1));
                std::thread::sleep(std::time::Duration::from_millis(20));
                return Ok(Step::Frame);
            }
        }
        while let Some((line, action)) = self.actions.get(self.next).cloned() {
            self.next += 1;
            let result = self.run(s, &action);
            match result {
                Ok(Some(step)) => return Ok(step),
                Ok(None) => {}
                Err(e) => return Err(line_error(&self.path, line, e)),
            }
        }
        Ok(Step::Quit)
    }

    /// Runs one action; `Some(step)` when the viewer must render or stop before the next.
    fn run(&mut self, s: &mut Session, action: &Action) -> AppResult<Option<Step>> {
        match action {
            Action::Technique(t) => s.set_technique(t)?,
            Action::Param(n, v) => s.set_param(n, v.clone())?,
            Action::Radius(r) => s.set_radius(*r)?,
            Action::Precision(f) => s.set_intermediate(*f)?,
            Action::Display(m) => {
                s.settings.display = *m;
                s.stats.recent.clear();
            }
            Action::Split(v) => s.settings.split = *v,
            Action::View(v) => s.set_view(v)?,
            Action::Camera(text) => s.set_camera_text(text)?,
            Action::Orbit(dx, dy) => s.camera.drag(*dx, *dy),
            Action::Zoom(steps) => s.camera.scroll(*steps),
            Action::Move(keys, seconds) => s.camera.fly(*keys, *seconds),
            Action::Scene(source) => s.load_scene(source.clone())?,
            Action::Open(source) => match s.load_scene(source.clone()) {
                Ok(()) => println!("opened {}", source.label()),
                Err(e) => println!("open failed, the scene stays: {e}"),
            },
            Action::Size(w, h) => s.resize(aograph_graph::Extent::new(*w, *h))?,
            Action::Wait(n) => {
                if *n > 0 {
                    self.waiting = n - 1;
                    return Ok(Some(Step::Frame));
                }
            }
            Action::WaitReference(rays) => {
                // About two minutes of frames at 20 ms a step: a pass at 256 rays on a 2-core
                // machine at a test's size takes seconds.
                self.waiting_reference = Some((*rays, 6000));
                return Ok(Some(Step::Frame));
            }
            Action::Screenshot(p) => {
                create_parent(p)?;
                s.screenshot(p)?;
                println!("screenshot {}", p.display());
            }
            Action::WindowScreenshot(p) => {
                create_parent(p)?;
                s.window_shot = Some(p.clone());
                return Ok(Some(Step::Frame));
            }
            Action::Save(p) => {
                create_parent(p)?;
                s.save_config(p)?;
                println!("saved {}", p.display());
            }
            Action::Mark => self.mark = s.pipelines_created(),
            Action::ExpectNoNewPipelines => {
                let now = s.pipelines_created();
                if now != self.mark {
                    return Err(AppError::InvalidArgument {
                        name: "expect-no-new-pipelines".into(),
                        value: format!("{} pipelines created since `mark`", now - self.mark),
                        allowed: "none".into(),
                    });
                }
                println!("no pipelines created since mark ({now} in all)");
            }
            Action::Stats => println!("{}", stats_line(s)),
            Action::Quit => return Ok(Some(Step::Quit)),
        }
        Ok(None)
    }
}

/// Frame times since the last change, for `stats` and the exit summary.
pub fn stats_line(s: &Session) -> String {
    let mut v = s.stats.recent.clone();
    v.sort_by(f64::total_cmp);
    let median = v.get(v.len() / 2).copied().unwrap_or(f64::NAN);
    let mean = v.iter().sum::<f64>() / v.len().max(1) as f64;
    format!(
        "stats: {} at {}: {} frames since the last change, frame time median {median:.1} ms, \
         mean {mean:.1} ms (wall clock); pipelines created {}; device {}",
        s.settings.ao.technique,
        s.size(),
        v.len(),
        s.pipelines_created(),
        s.gpu.describe()
    )
}

fn create_parent(p: &Path) -> AppResult<()> {
    match p.parent().filter(|d| !d.as_os_str().is_empty()) {
        Some(d) => std::fs::create_dir_all(d).map_err(|e| AppError::io("create directory", d, e)),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_action_parses_and_mistakes_name_the_line() {
        let text = "# demo\ntechnique mssao\nparam samples 16\nparam preset \"low\"\nradius auto\n\
                    display split\nsplit 0.25\norbit 10 -5\nmove forward 0.5\nsize 64 48\nwait 3\n\
                    screenshot out/a.png\nmark\nexpect-no-new-pipelines\nquit\n";
        let s = Script::parse(text, Path::new("demo.txt")).unwrap();
        assert_eq!(s.actions.len(), 14);
        assert_eq!(
            s.actions[1],
            (3, Action::Param("samples".into(), toml::Value::Integer(16)))
        );
        assert_eq!(s.actions[5], (7, Action::Split(0.25)));
        for (bad, needle) in [
            ("jump 3", "unknown action `jump`"),
            ("wait soon", "not a whole number"),
            ("split 2", "allowed 0 to 1"),
            ("display fancy", "ao, shaded, split, error or temporal"),
            ("param samples", "takes a name and a value"),
            ("screenshot", "needs a file path"),
            ("move sideways 1", "allowed forward"),
        ] {
            let e = Script::parse(&format!("wait 1\n{bad}\n"), Path::new("s.txt"))
                .err()
                .unwrap_or_else(|| panic!("`{bad}` parsed"))
                .to_string();
            assert!(e.contains("s.txt:2") && e.contains(needle), "{bad}: {e}");
        }
    }
}
