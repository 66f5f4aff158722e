//! The window shell: a winit event loop over the core. Only this module imports winit, egui
//! and wgpu. Three parts, as in the pixels crate's `minimal-egui` example:
//! - [`framework`] (with [`gpu`]): egui, egui-winit and egui-wgpu state and the GPU draw;
//! - [`viewer`]: the viewer's state: camera controller, settings, render worker, refinement;
//! - [`scripted`]: the driver of scripted runs (`--frames`, `--script`).
//!
//! This file holds the app that ties them together; [`events`] feeds it winit's events.
//!
//! Rendering runs on a worker thread (see [`worker`]); the event loop never waits for it. Any
//! change (camera, settings, scene, window size) bumps a generation counter; for the newest
//! generation the viewer shows a quick preview while things change, then refines to the full
//! resolution and then to full supersampling once they stop (levels 0, 1, 2). With nothing
//! left to do it sleeps in `ControlFlow::Wait`.

mod args;
mod bounds;
mod cracks;
mod events;
mod fields;
mod files;
mod follow;
mod framework;
mod gpu;
mod input;
mod inspected;
mod inspector;
mod layout;
mod notices;
mod panel;
mod pointer;
mod scene_tree;
mod script;
mod scripted;
mod shortcuts;
pub mod values;
mod viewer;
mod worker;

pub use args::{main_with_code, WindowArgs};
pub use framework::quiet_wayland_probe;
/// The ray inspector's crack rows, which `raylab inspect` prints too.
pub use inspected::Detail;

use anyhow::{anyhow, bail, Context as _, Result};
use framework::Framework;
use gpu::Drawn;
use input::Key;
use raylab::check::LabCode;
use raylab::render::Stage;
use raylab::Scene;
use script::Script;
use scripted::ScriptedRun;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::{Duration, Instant};
use viewer::{Resolution, Viewer};
use winit::dpi::PhysicalSize;
use winit::event_loop::{ActiveEventLoop, EventLoop};
use winit::window::{CursorGrabMode, Window};

/// What the first Esc says (with nothing else for it to do).
const QUIT_PROMPT: &str = "press Esc again to quit";

/// How long the quit prompt holds: a later Esc asks again.
const QUIT_PROMPT_FOR: Duration = Duration::from_secs(5);

/// How the viewer was started.
#[derive(Default, Clone)]
pub struct ViewerOptions {
    /// An OBJ file to open instead of the Cornell box.
    pub scene: Option<PathBuf>,
    /// How OBJ coordinates are read.
    pub obj_frame: raylab::scene::ObjFrame,
    /// The acceleration structure of every scene opened.
    pub accel: raylab::accel::AccelChoice,
    /// Run this many frames back to back, then the script and refinement drawn as a user's
    /// window draws (on events), save `screenshot`, exit.
    pub frames: Option<u64>,
    /// Where `--frames` saves what the window showed.
    pub screenshot: Option<PathBuf>,
    /// Scripted input.
    pub script: Option<PathBuf>,
    /// Code that is not raylab's (the lab crate's), offered as "your code" in the method
    /// selector and shown by the ray inspector beside the exact answer.
    pub code: Option<Arc<dyn LabCode>>,
}

/// Events sent to the event loop from other threads.
pub enum AppEvent {
    /// The render worker finished an image.
    FrameReady,
    /// A scene or OBJ finished loading (or failed): the load as asked for, and its scene.
    SceneLoaded(viewer::LoadRequest, Box<Result<Stage, String>>),
    /// The file of the scene shown changed on disk.
    SourceChanged(PathBuf),
    /// An F12 screenshot was written (or failed).
    ScreenshotSaved(Result<PathBuf, String>),
    /// The cracks of a frame shown were counted.
    CracksCounted,
}

/// Opens the window and runs until it is closed.
pub fn run(opts: ViewerOptions) -> Result<()> {
    if opts.frames.is_some() != opts.screenshot.is_some() {
        bail!("--frames and --screenshot go together");
    }
    if opts.script.is_some() && opts.frames.is_none() {
        bail!("--script needs --frames N --screenshot FILE");
    }
    let script = match &opts.script {
        Some(p) => {
            let text = raylab::input::read_text(p, raylab::input::max_input_bytes())
                .with_context(|| format!("cannot read script '{}'", p.display()))?;
            Some(Script::parse(&p.display().to_string(), &text).map_err(|e| anyhow!(e))?)
        }
        None => None,
    };
    // A saved view opens as the File menu opens it: its camera, light and settings, then its
    // scene (checked here, so a bad view is an error before the window opens).
    let view = (opts.scene.as_ref()).filter(|p| {
        p.extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("view"))
    });
    let scene = match (&opts.scene, view) {
        (_, Some(p)) => {
            let text = raylab::input::read_text(p, raylab::input::max_input_bytes())?;
            raylab::view::View::parse(&p.display().to_string(), &text)?;
            Scene::cornell()
        }
        (Some(p), None) => {
            let spec = p.to_string_lossy();
            Scene::open(&spec, opts.obj_frame).map_err(anyhow::Error::msg)?
        }
        (None, None) => Scene::cornell(),
    };
    let stage = Stage::new(scene, opts.accel);
    let event_loop = EventLoop::<AppEvent>::with_user_event()
        .build()
        .map_err(|e| {
            log::debug!("event loop: {e}");
            anyhow!("{}", framework::no_window_reason())
        })?;
    // (`cornell` names the built-in box: no file to watch or name in a view.)
    let file =
        (opts.scene.as_ref()).filter(|p| p.as_os_str() != raylab::scene::CORNELL && view.is_none());
    let mut viewer = Viewer::new(
        stage,
        file,
        (opts.obj_frame, opts.accel),
        opts.code.clone(),
        event_loop.create_proxy(),
    );
    if let Some(p) = view {
        viewer.load(p.clone());
    }
    let scripted = match (opts.frames, opts.screenshot) {
        (Some(frames), Some(shot)) => Some(ScriptedRun::new(frames, shot, script)),
        _ => None,
    };
    let mut app = App {
        window: None,
        framework: None,
        viewer,
        scripted,
        image_rect: None,
        banner_rect: None,
        panel_fit: (0.0, 0.0),
        panel_width: 0.0,
        cursor: None,
        drag: None,
        press_at: None,
        click_waiting: None,
        inspector_laid_out: true,
        mouse_look: false,
        raw_motion: false,
        esc_armed: None,
        oversized: false,
        surface_max: u32::MAX,
        frames_presented: 0,
        image_on_screen: false,
        failed_draws: 0,
        egui_repaint_at: None,
        drawn_at: Instant::now(),
        outcome: Ok(()),
    };
    event_loop
        .run_app(&mut app)
        .map_err(|e| anyhow!("event loop: {e}"))?;
    if let (Some(run), Ok(())) = (&app.scripted, &app.outcome) {
        run.closed_early();
    }
    app.outcome
}

/// The event loop's handler: the window, its framework, the viewer and the scripted run.
struct App {
    window: Option<Arc<Window>>,
    framework: Option<Framework>,
    viewer: Viewer,
    scripted: Option<ScriptedRun>,
    /// Where the image was drawn last (egui points).
    image_rect: Option<egui::Rect>,
    /// Where the error banner was drawn last over the image (egui points).
    banner_rect: Option<egui::Rect>,
    /// The side panel's content height and visible height (points) in the last frame.
    panel_fit: (f32, f32),
    /// The side panel's width (points) in the last frame.
    panel_width: f32,
    /// The mouse pointer in the window (physical pixels), while it is inside.
    cursor: Option<(f64, f64)>,
    /// An orbit-mode drag under way over the image: `true` orbits, `false` pans.
    drag: Option<bool>,
    /// Where a left press over the image began (a click there inspects its pixel).
    press_at: Option<(f64, f64)>,
    /// A click on the image kept until the frame drawn fits the image area
    /// ([`App::take_waiting_click`]).
    click_waiting: Option<(f64, f64)>,
    /// Whether the inspector was on when the image area was last laid out: where I has turned
    /// it since, the layout (its panel) is about to change, and a click waits for it.
    inspector_laid_out: bool,
    mouse_look: bool,
    /// Whether raw mouse motion has come (then mouse look takes only that, not the cursor's
    /// moves: [`WindowEvent::CursorMoved`] turns the view only where it never comes).
    raw_motion: bool,
    /// When Esc asked "press Esc again to quit": a second Esc quits only while that prompt is
    /// the status shown, within [`QUIT_PROMPT_FOR`], with no click or banner since.
    esc_armed: Option<Instant>,
    /// The window is larger than the graphics device draws: drawing is paused.
    oversized: bool,
    /// The largest window side the graphics device draws (its largest texture side), as
    /// [`Framework::fit_surface`] checks it.
    surface_max: u32,
    frames_presented: u64,
    /// Whether a rendered image has been presented yet.
    image_on_screen: bool,
    /// Draws that failed in a row (a lost surface is retried at once, a broken one is not
    /// retried in a loop).
    failed_draws: u32,
    egui_repaint_at: Option<Instant>,
    /// When the last frame was drawn.
    drawn_at: Instant,
    outcome: Result<()>,
}

impl App {
    fn fail(&mut self, event_loop: &ActiveEventLoop, e: anyhow::Error) {
        if self.outcome.is_ok() {
            self.outcome = Err(e);
        }
        event_loop.exit();
    }

    fn request_redraw(&self) {
        if let Some(w) = &self.window {
            w.request_redraw();
        }
    }

    /// The worker finished a frame: show it and start the next.
    fn frame_ready(&mut self) {
        let Some(frame) = self.viewer.take_frame() else {
            return;
        };
        if let (Some(frame), Some(fw)) = (frame, &mut self.framework) {
            if let Err(e) = fw.gpu.set_frame(frame.width, frame.height, &frame.rgba) {
                self.viewer.set_status(e);
            }
        }
        self.viewer.pump();
        self.request_redraw();
    }

    fn set_mouse_look(&mut self, on: bool) {
        let Some(window) = &self.window else { return };
        self.mouse_look = on;
        if on {
            let _ = window
                .set_cursor_grab(CursorGrabMode::Locked)
                .or_else(|_| window.set_cursor_grab(CursorGrabMode::Confined));
        } else {
            let _ = window.set_cursor_grab(CursorGrabMode::None);
        }
        window.set_cursor_visible(!on);
        log::info!(
            "mouse look {}",
            if on {
                "on: the mouse is captured"
            } else {
                "off"
            }
        );
    }

    /// A key press or release from the keyboard or the script, made `at`.
    fn key(&mut self, event_loop: &ActiveEventLoop, key: Key, pressed: bool, at: Instant) {
        if self.viewer.input.key_at(key, pressed, at) {
            if pressed {
                self.esc_armed = None;
                // (A driver of real input waits for this before it lets go: a press and
                // release a busy event loop takes in one batch moves by the time between them.)
                log::info!("{key:?} down");
            }
            return;
        }
        if !pressed {
            return;
        }
        match key {
            Key::R => {
                self.viewer.reset_camera();
                self.viewer.field_slip_outdated();
                self.viewer.changed();
            }
            Key::H | Key::F1 => self.viewer.show_help = !self.viewer.show_help,
            Key::P => {
                self.viewer.panel_hidden = !self.viewer.panel_hidden;
                self.viewer.set_status(match self.viewer.panel_hidden {
                    true => "side panel hidden: P shows it",
                    false => "side panel shown",
                });
            }
            Key::I => {
                self.viewer.inspector_on = !self.viewer.inspector_on;
                self.viewer.say_inspector();
            }
            Key::N => {
                let back = self.viewer.input.holds(Key::Shift);
                let step = [cracks::Step::Next, cracks::Step::Previous][back as usize];
                self.viewer.step_crack(step);
            }
            Key::F12 => self.viewer.screenshot(),
            Key::F5 => self.viewer.save_view(),
            Key::C => self.viewer.copy_command(),
            Key::Tab => {
                self.viewer.controller.toggle_mode();
                self.viewer.changed();
            }
            Key::Step(number) => self.viewer.choose_step(number),
            Key::Plus => self.viewer.controller.scale_speed(1.25),
            Key::Minus => self.viewer.controller.scale_speed(0.8),
            Key::Escape => {
                if self.mouse_look {
                    self.set_mouse_look(false);
                } else if self.viewer.show_help || self.viewer.show_all_warnings {
                    // (A window of text on top is closed first: Esc, Esc had quit from it.)
                    (self.viewer.show_help, self.viewer.show_all_warnings) = (false, false);
                    self.esc_armed = None;
                    log::info!("Esc closed the shortcuts or warnings window");
                } else if self.viewer.banner.take().is_some() {
                    self.esc_armed = None;
                    log::info!("error banner dismissed");
                } else if self.quit_armed() {
                    event_loop.exit();
                } else {
                    self.esc_armed = Some(Instant::now());
                    self.viewer.set_status(QUIT_PROMPT);
                }
            }
            _ => {}
        }
        self.request_redraw();
    }

    /// Whether a second Esc quits now: the quit prompt is the status shown (no message, error
    /// or banner came since), it is recent, and nothing was clicked since.
    fn quit_armed(&self) -> bool {
        let recent = self
            .esc_armed
            .is_some_and(|t| t.elapsed() < QUIT_PROMPT_FOR);
        recent && self.viewer.status == QUIT_PROMPT && self.viewer.banner.is_none()
    }

    /// A new window size; 0×0 (minimised) pauses rendering until a real size comes back, and
    /// so does a window larger than the graphics device draws (X windows reach 32767²).
    fn on_resized(&mut self, window: &Window, size: PhysicalSize<u32>) {
        let max = self.surface_max;
        if size.width > max || size.height > max {
            self.viewer.paused = true;
            self.oversized = true;
            self.viewer.set_status(format!(
                "the window is {}x{}, larger than the graphics device draws ({max} pixels a \
                 side): drawing paused until it is smaller",
                size.width, size.height
            ));
            return;
        }
        let minimised = size.width == 0 || size.height == 0;
        if std::mem::take(&mut self.oversized) {
            let (w, h) = (size.width, size.height);
            self.viewer
                .set_status(format!("the window is {w}x{h}: drawing resumed"));
        }
        if minimised != self.viewer.paused {
            log::info!(
                "window {}",
                if minimised {
                    "minimised: rendering paused"
                } else {
                    "restored: rendering resumed"
                }
            );
        }
        self.viewer.paused = minimised;
        if !minimised {
            if let Some(fw) = &mut self.framework {
                if let Err(e) = fw.gpu.resize_surface(size.width, size.height) {
                    self.viewer.set_status(e);
                }
            }
            self.viewer.pump();
        }
        window.request_redraw();
    }

    fn redraw(&mut self, event_loop: &ActiveEventLoop) {
        let (Some(window), true) = (self.window.clone(), self.framework.is_some()) else {
            return;
        };
        // The script runs while minimised too (it may be what restores the window).
        self.run_script(event_loop);
        if self.viewer.paused {
            return;
        }
        self.viewer.update_camera();

        // The egui pass: panel, image area, overlay.
        let viewer = &mut self.viewer;
        let before = viewer.panel_state();
        let inspector_was = viewer.inspector_on;
        let fw = self.framework.as_mut().expect("checked");
        let (texture, buffer_size) = (fw.gpu.texture_id, fw.gpu.buffer_size);
        let mut layout = None;
        let frame = fw.run(&window, |ui| {
            layout = Some(layout::layout(ui, viewer, texture, buffer_size));
        });
        let layout = layout.expect("egui ran the UI");
        viewer.image_area = layout.image_area;
        viewer.beside_width = layout.beside_width;
        viewer.frame_for_image();
        self.image_rect = layout.image_rect;
        self.inspector_laid_out = viewer.inspector_on;
        self.banner_rect = layout.banner_rect;
        self.panel_fit = layout.actions.fit;
        if layout.actions.width != self.panel_width {
            self.panel_width = layout.actions.width;
            log::info!("side panel {} points wide", self.panel_width);
        }
        let actions = layout.actions;
        // (A field typed into, or a path, says what it did itself.)
        let loads = actions.load.is_some();
        let from_a_field = actions.typed.is_some() || loads;
        if actions.reset_camera {
            viewer.reset_camera();
        }
        match actions.load {
            // (An empty field named no file: "could not load: : No such file" said nothing.)
            Some(p) if p.trim().is_empty() => viewer.field_slip(
                "the path field is empty: type `cornell` or a .scene, OBJ or .view file's path"
                    .into(),
            ),
            Some(p) => viewer.load(PathBuf::from(p)),
            None => {}
        }
        match actions.typed {
            Some(fields::Said::Slip(message)) => viewer.field_slip(message),
            Some(fields::Said::Taken(message)) => viewer.field_taken(message),
            None => {}
        }
        if let Some(frame) = actions.obj_frame {
            viewer.set_obj_frame(frame);
        }
        if let Some(level) = actions.select {
            viewer.select_level(level);
        }
        if actions.screenshot {
            viewer.screenshot();
        }
        if actions.save_view {
            viewer.save_view();
        }
        if actions.copy_command {
            viewer.copy_command();
            window.request_redraw(); // (the clipboard is written in the next UI pass)
        }
        if let Some(copied) = actions.status_copied {
            viewer.say_copied(&copied);
        }
        if let Some(step) = actions.crack {
            viewer.step_crack(step);
            window.request_redraw(); // (the inspector's panel opens in the next UI pass)
        }
        if viewer.inspector_on != inspector_was {
            viewer.say_inspector();
        }
        let after = viewer.panel_state();
        // (A radio button said nothing: the status kept "lab step 1 flat" over step 5. A view
        // loaded from the path field sets its step, and says so itself: "lab step 4 shadows"
        // hid "loaded view".)
        if after.0.controls.step != before.0.controls.step && !loads {
            viewer.say_step();
        } else if !loads {
            viewer.say_setting(&before.0);
        }
        if after.1 != before.1 && !actions.reset_camera {
            viewer.camera_moved();
        }
        if before != after || actions.reset_camera {
            log::debug!("change: {before:?} -> {after:?}");
            if !from_a_field {
                viewer.field_slip_outdated();
            }
            viewer.changed();
        }
        // The inspector answers its pixel again for the frame now shown; a crack step waits
        // for its frame's count.
        viewer.follow();
        viewer.resolve_step();
        self.take_waiting_click();

        let capture = self
            .scripted
            .as_ref()
            .is_some_and(|run| run.is_done(&self.viewer, self.frames_presented));
        let fw = self.framework.as_mut().expect("checked");
        match fw.fit_surface(&window) {
            Ok(true) => {}
            Ok(false) => return,
            Err(e) => {
                self.viewer.set_status(e);
                return;
            }
        }
        match fw.draw(&frame, capture) {
            Ok(Drawn::Shown(Some(shot))) => {
                let ppp = fw.pixels_per_point();
                let r = self.image_rect.unwrap_or(egui::Rect::NOTHING);
                let done = scripted::Final {
                    frames_presented: self.frames_presented,
                    image_rect: [r.min.x, r.min.y, r.width(), r.height()].map(|x| x * ppp),
                    panel_fit: self.panel_fit,
                    panel_width: self.panel_width,
                };
                let run = self.scripted.as_mut().expect("capturing a scripted run");
                match run.finish(&self.viewer, shot, done) {
                    Ok(()) => event_loop.exit(),
                    Err(e) => self.fail(event_loop, e),
                }
                return;
            }
            Ok(Drawn::Shown(None) | Drawn::Hidden) => {}
            Ok(Drawn::Skipped) => {
                // (The window was being resized: its next frame is drawn at its new size.)
                log::debug!("frame skipped: the surface did not fit the window");
                window.request_redraw();
                return;
            }
            Err(e) => {
                // A failed surface: say so and draw again; nothing was presented this time.
                log::warn!("{e}");
                self.viewer.set_status(e);
                self.failed_draws += 1;
                if self.failed_draws <= 3 {
                    window.request_redraw();
                }
                return;
            }
        }
        self.failed_draws = 0;
        self.frames_presented += 1;
        self.drawn_at = Instant::now();
        if !self.image_on_screen && self.viewer.shown.is_some() && self.image_rect.is_some() {
            // (Tests that drive the window with real input wait for this line.)
            self.image_on_screen = true;
            log::info!("first image on screen");
        }

        self.viewer.pump();
        let repaint_now = frame.repaint_delay.is_zero();
        // egui animations (tooltips, collapsing) ask for a repaint a little later.
        self.egui_repaint_at = (frame.repaint_delay < Duration::from_secs(3600))
            .then(|| Instant::now() + frame.repaint_delay);
        let moving = self.viewer.input.is_moving();
        log::trace!(
            "frame {}: moving {moving} repaint {repaint_now} shown {:?}",
            self.frames_presented,
            self.viewer.shown.as_ref().map(|s| (s.generation, s.level)),
        );
        // (A run done with this frame draws once more, to be captured: nothing else may ask.)
        let scripted_next = (self.scripted.as_ref()).is_some_and(|run| {
            run.draws_back_to_back(self.frames_presented)
                || run.is_done(&self.viewer, self.frames_presented)
        });
        if moving || repaint_now || scripted_next {
            window.request_redraw();
        }
    }
}
