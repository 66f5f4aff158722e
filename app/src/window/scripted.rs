//! The scripted-run driver of `raylab --frames N --screenshot FILE [--script FILE]`: replays
//! the script's events in time from the first frame shown, decides when the run is done (enough
//! frames, script finished, nothing loading or moving, the image fully refined), saves what
//! the window showed and prints the final state for the window tests. Its first N frames are
//! drawn back to back; after them it draws as a user's window does, when something changes,
//! so a run waiting for its driver idles as a user's window would.

use super::gpu::Capture;
use super::script::{Action, Script};
use super::viewer::Resolution;
use super::viewer::Viewer;
use super::App;
use anyhow::{anyhow, Result};
use raylab::render;
use std::borrow::Cow;
use std::path::PathBuf;
use std::time::{Duration, Instant};
use winit::dpi::PhysicalSize;
use winit::event_loop::ActiveEventLoop;

/// A scripted run that has not finished by then fails.
const TIMEOUT: Duration = super::script::RUN_LIMIT;

/// A run under `--frames`.
pub struct ScriptedRun {
    frames: u64,
    screenshot: PathBuf,
    script: Option<Script>,
    /// When the first frame was shown: script times count from there.
    start: Option<Instant>,
    started: Instant,
    /// Whether the screenshot was written.
    saved: bool,
}

/// What the final line reports of the window.
pub struct Final {
    pub frames_presented: u64,
    /// The image's rectangle in physical pixels: x, y, width, height.
    pub image_rect: [f32; 4],
    /// The side panel's content height and the height it is shown in (points).
    pub panel_fit: (f32, f32),
    /// The side panel's width (points).
    pub panel_width: f32,
}

impl ScriptedRun {
    pub fn new(frames: u64, screenshot: PathBuf, script: Option<Script>) -> Self {
        Self {
            frames,
            screenshot,
            script,
            start: None,
            started: Instant::now(),
            saved: false,
        }
    }

    /// The events due now, each with when it was due; the clock starts once a frame has been
    /// shown.
    pub fn due(&mut self, frames_presented: u64) -> Vec<(Instant, Action)> {
        if self.start.is_none() && frames_presented > 0 {
            self.start = Some(Instant::now());
        }
        let (Some(script), Some(start)) = (&mut self.script, self.start) else {
            return Vec::new();
        };
        let due = script.due(start.elapsed());
        due.into_iter().map(|(at, a)| (start + at, a)).collect()
    }

    /// Whether the run draws its next frame at once, not on an event as a user's window does:
    /// only until its first `frames` frames are shown.
    pub fn draws_back_to_back(&self, frames_presented: u64) -> bool {
        frames_presented < self.frames
    }

    /// Looks for an awaited file where the script waits for one (no frame is drawn for that);
    /// while it still waits, [`ScriptedRun::next_due`] is the next look.
    pub fn look_for_awaited(&mut self) {
        if let (Some(script), Some(start)) = (&mut self.script, self.start) {
            script.still_held(start.elapsed());
        }
    }

    /// When the script's next event is due.
    pub fn next_due(&self) -> Option<Instant> {
        let next = self.script.as_ref().and_then(Script::next_due)?;
        Some(self.start? + next)
    }

    /// Done once enough frames were shown, the script ran out and the image is fully refined.
    pub fn is_done(&self, viewer: &Viewer, frames_presented: u64) -> bool {
        self.waiting_for(viewer, frames_presented).is_empty()
    }

    /// What the run still waits for before it can end (nothing: it is done).
    fn waiting_for(&self, viewer: &Viewer, frames_presented: u64) -> Vec<Cow<'static, str>> {
        let script_left = self.script.as_ref().is_some_and(|s| !s.finished());
        let script = match self.script.as_ref().and_then(Script::awaited) {
            Some(file) => Cow::Owned(format!("the script's await of '{}'", file.display())),
            None => Cow::Borrowed("the script's events"),
        };
        [
            (frames_presented < self.frames, "frames shown".into()),
            (viewer.loading, "a scene loading".into()),
            (viewer.screenshots_pending > 0, "a screenshot".into()),
            (script_left, script),
            (viewer.input.is_moving(), "the camera to stop".into()),
            (!viewer.is_idle(), "a render".into()),
            (!viewer.is_refined(), "refinement".into()),
            (!viewer.cracks_settled(), "the cracks count".into()),
        ]
        .into_iter()
        .filter_map(|(waiting, what)| waiting.then_some(what))
        .collect()
    }

    /// Says so where the window closed (Esc twice, the window manager) before the run saved
    /// its screenshot: its exit is a user's, status 0, but nothing was written.
    pub fn closed_early(&self) {
        if !self.saved {
            log::warn!(
                "the window closed before its scripted run finished: {} not written",
                self.screenshot.display()
            );
        }
    }

    /// When the run fails if it has not finished: the event loop wakes then, drawing or not
    /// (a window that stopped drawing still ends its run).
    pub fn deadline(&self) -> Instant {
        self.started + TIMEOUT
    }

    /// An error, naming what the run still waits for, once the run has taken too long.
    pub fn check_time(&self, viewer: &Viewer, frames_presented: u64) -> Result<()> {
        match Instant::now() >= self.deadline() {
            true => Err(anyhow!(
                "the scripted run did not finish within {} s (waiting for: {}; {} frames shown)",
                TIMEOUT.as_secs(),
                self.waiting_for(viewer, frames_presented).join(", "),
                frames_presented,
            )),
            false => Ok(()),
        }
    }

    /// Saves what the window showed and prints the final state.
    pub fn finish(&mut self, viewer: &Viewer, shot: Capture, window: Final) -> Result<()> {
        let path = &self.screenshot;
        render::write_png(path, shot.width, shot.height, &shot.rgba)
            .map_err(|e| anyhow!("cannot write '{}': {e}", path.display()))?;
        let c = &viewer.controller;
        let (w, h) = viewer.shown.as_ref().map(|s| s.size).unwrap_or((0, 0));
        let r = window.image_rect;
        let controls = raylab::render::settings::controls_text(&viewer.view.controls);
        // The counts of the frame shown, with the cracks view on.
        let cracks = viewer.counted().map_or(String::new(), |c| {
            let n = &c.counts;
            format!(
                " leaks={} false_hits={} wrong={} ties={} marked={}",
                n.leaks,
                n.false_hits,
                n.wrong,
                n.ties,
                c.marked.len()
            )
        });
        println!(
            "raylab-final camera={},{},{} yaw={} pitch={} focal={} size={}x{} view_offset={} rect={},{},{},{} {controls} spp_shown={} status_whole={} figures_whole={} refine_wakes={} frames={} moving_frames={} mode={} speed={} scene_size={} inspector={} inspector_over={} inspected_cropped={} help={} banner={} panel_content={} panel_visible={} panel_width={} warnings={} warnings_list={} peak_kib={} primitives={} accel={} code={}{cracks} scene={}",
            c.position.x,
            c.position.y,
            c.position.z,
            super::values::degrees(c.yaw),
            super::values::degrees(c.pitch),
            viewer.focal(w),
            w,
            h,
            viewer.view_offset(),
            r[0],
            r[1],
            r[2],
            r[3],
            viewer.shown.as_ref().map_or(0, |s| s.spp),
            ["off", "on"][viewer.status_whole as usize],
            ["off", "on"][viewer.figures_whole as usize],
            viewer.refine_wakes,
            window.frames_presented,
            viewer.frames_while_moving,
            match c.mode {
                raylab::controller::Mode::Fly => "fly",
                raylab::controller::Mode::Orbit => "orbit",
            },
            c.speed,
            c.scene_size,
            ["off", "on"][viewer.inspector_on as usize],
            ["off", "on"][viewer.inspector_over as usize],
            viewer.inspected_side_cropped().unwrap_or("none"),
            ["off", "on"][viewer.show_help as usize],
            ["off", "on"][viewer.banner.is_some() as usize],
            window.panel_fit.0,
            window.panel_fit.1,
            window.panel_width,
            viewer.stage.scene().warnings.len(),
            ["off", "on"][viewer.show_all_warnings as usize],
            peak_kib(),
            viewer.stage.scene().len(),
            viewer.stage.accel().kind(),
            // Linked code: chosen in the method selector (on), offered (off), or none.
            match (&viewer.code, viewer.view.yours) {
                (None, _) => "none",
                (Some(_), true) => "on",
                (Some(_), false) => "off",
            },
            viewer.stage.scene().name,
        );
        if !viewer.status.is_empty() {
            println!("status: {}", viewer.status);
        }
        println!("path field: {}", viewer.obj_path);
        if let Some(text) = &viewer.banner {
            println!("banner: {text}");
        }
        if let Some(census) = viewer.counted() {
            println!("cracks: {}", census.summary());
        }
        if let Some(inspection) = &viewer.inspection {
            for line in inspection.to_string().lines() {
                println!("inspector {line}");
            }
        }
        if let Some(yours) = &viewer.code_inspection {
            for line in yours.to_string().lines() {
                println!("inspector {line}");
            }
        }
        for (name, value) in viewer.crack.iter().flat_map(|d| d.rows()) {
            println!("inspector {name}: {value}");
        }
        println!("saved {}", path.display());
        self.saved = true;
        Ok(())
    }
}

impl App {
    /// Carries out the script's events that are due.
    pub(super) fn run_script(&mut self, event_loop: &ActiveEventLoop) {
        let Some(scripted) = &mut self.scripted else {
            return;
        };
        for (at, action) in scripted.due(self.frames_presented) {
            let viewer = &mut self.viewer;
            match action {
                // (Held from when it was due, not when a slow frame let it be carried out: a
                // press and release that one stall delays together still hold for their
                // time, as the keyboard's do in real time.)
                Action::Key(k, down) => self.key(event_loop, k, down, at),
                Action::Mouse(dx, dy) => viewer.input.mouse(dx, dy),
                Action::Wheel(lines) => viewer.input.wheel(lines),
                Action::Set(name, value) => {
                    let control = raylab::render::settings::control(name).expect("checked");
                    let set = control.set_text(&mut viewer.view.controls, &value);
                    set.expect("checked when the script was read");
                    viewer.changed();
                }
                Action::Drop(path) => viewer.load(path),
                Action::Changed(path) => viewer.reload(path),
                Action::Focal(f) => {
                    viewer.set_focal(f);
                    viewer.changed();
                }
                Action::Scale(s) => {
                    viewer.view.resolution = Resolution::WindowScale(s);
                    viewer.changed();
                }
                Action::Resize(w, h) => {
                    let Some(window) = self.window.clone() else {
                        continue;
                    };
                    if w == 0 || h == 0 {
                        self.on_resized(&window, PhysicalSize::new(0, 0));
                    } else {
                        let _ = window.request_inner_size(PhysicalSize::new(w, h));
                    }
                }
                Action::Restore => {
                    if let Some(window) = self.window.clone() {
                        self.on_resized(&window, window.inner_size());
                    }
                }
                Action::Select(level) => viewer.select_level(level),
                Action::Inspect(i, j) => viewer.inspect_pixel(i, j),
                Action::FailRender => viewer.fail_next_render = true,
                // (Its file exists: the script goes on.)
                Action::Await(_) => {}
                Action::ResizeInDraw(w, h) => {
                    if let Some(fw) = &mut self.framework {
                        fw.gpu.resize_in_next_draw = Some(PhysicalSize::new(w, h));
                    }
                    self.request_redraw();
                }
                Action::LoseSurface => {
                    if let Some(fw) = &mut self.framework {
                        fw.gpu.lose_next_draw = true;
                    }
                    self.request_redraw();
                }
            }
        }
    }
}

/// The process's peak resident memory in KiB (Linux's VmHWM; 0 where unknown), for the tests
/// that hold the window's memory to the stated bound.
fn peak_kib() -> u64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    let line = status.lines().find_map(|l| l.strip_prefix("VmHWM:"));
    let kib = line.and_then(|l| l.trim().trim_end_matches("kB").trim().parse().ok());
    kib.unwrap_or(0)
}
