//! The window shell: a winit event loop over the core. Only this module imports winit, egui
//! and pixels.
//!
//! Rendering runs on a worker thread (see [`worker`]); the event loop never waits for it. Any
//! change (camera, settings, scene, window size) bumps a generation counter; for the newest
//! generation the app shows a quick preview while things change, then refines to the full
//! resolution and then to full supersampling once they stop (levels 0, 1, 2). With nothing
//! left to do it sleeps in `ControlFlow::Wait`.

mod gpu;
mod input;
mod panel;
mod script;
mod worker;

use anyhow::{anyhow, bail, Context as _, Result};
use input::{InputState, Key};
use raylab::controller::CameraController;
use raylab::geometry::Method;
use raylab::render::{self, LabStep, RenderSettings, RenderStats, MAX_SIDE};
use raylab::Scene;
use script::{Action, Script};
use std::path::PathBuf;
use std::sync::Arc;
use std::time::{Duration, Instant};
use winit::application::ApplicationHandler;
use winit::dpi::{LogicalSize, PhysicalSize};
use winit::event::{
    DeviceEvent, DeviceId, ElementState, MouseButton, MouseScrollDelta, WindowEvent,
};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop, EventLoopProxy};
use winit::keyboard::PhysicalKey;
use winit::window::{CursorGrabMode, Window, WindowId};

/// How the viewer was started.
#[derive(Debug, Default, Clone)]
pub struct ViewerOptions {
    /// An OBJ file to open instead of the Cornell box.
    pub scene: Option<PathBuf>,
    /// How OBJ coordinates are read.
    pub obj_frame: raylab::scene::ObjFrame,
    /// Run this many frames (plus the script and refinement), save `screenshot`, exit.
    pub frames: Option<u64>,
    /// Where `--frames` saves what the window showed.
    pub screenshot: Option<PathBuf>,
    /// Scripted input.
    pub script: Option<PathBuf>,
}

/// The render resolution: a fraction of the image area, or fixed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Resolution {
    /// This fraction of the image area's physical pixels.
    WindowScale(f32),
    /// A fixed size.
    Fixed(u32, u32),
}

/// Everything on the panel that changes the image (besides the camera).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViewSettings {
    pub step: LabStep,
    pub method: Method,
    pub spp: u32,
    pub resolution: Resolution,
    pub adaptive: bool,
    pub target_ms: f32,
    pub preview_scale: f32,
    pub light: [f32; 3],
    pub cracks: bool,
}

/// Events sent to the event loop from other threads.
enum AppEvent {
    /// The render worker finished an image.
    FrameReady,
    /// An OBJ finished loading (or failed).
    SceneLoaded(PathBuf, Result<Scene, String>),
    /// An F12 screenshot was written (or failed).
    ScreenshotSaved(Result<PathBuf, String>),
}

/// How long after the last change the app keeps previewing before it refines.
const SETTLE: Duration = Duration::from_millis(120);
/// A scripted run that has not finished by then fails.
const SCRIPTED_TIMEOUT: Duration = Duration::from_secs(120);
const PANEL_WIDTH: f32 = 300.0;

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
            let text = std::fs::read_to_string(p)
                .with_context(|| format!("cannot read script '{}'", p.display()))?;
            Some(Script::parse(&p.display().to_string(), &text).map_err(|e| anyhow!(e))?)
        }
        None => None,
    };
    let scene = match &opts.scene {
        Some(p) => raylab::scene::load_obj_file(p, opts.obj_frame)?,
        None => Scene::cornell(),
    };
    let event_loop = EventLoop::<AppEvent>::with_user_event().build().map_err(|e| {
        anyhow!("cannot open a window: {e} (is a display available? set DISPLAY or WAYLAND_DISPLAY, or use `raylab render`)")
    })?;
    let proxy = event_loop.create_proxy();
    let mut app = App::new(opts, scene, script, proxy);
    event_loop
        .run_app(&mut app)
        .map_err(|e| anyhow!("event loop: {e}"))?;
    app.outcome
}

struct Shown {
    generation: u64,
    level: u8,
    size: (u32, u32),
    stats: RenderStats,
}

struct App {
    opts: ViewerOptions,
    proxy: EventLoopProxy<AppEvent>,
    window: Option<Arc<Window>>,
    gpu: Option<gpu::Gpu>,
    egui_ctx: egui::Context,
    egui_state: Option<egui_winit::State>,
    scene: Arc<Scene>,
    controller: CameraController,
    view: ViewSettings,
    input: InputState,
    worker: worker::Worker,
    generation: u64,
    last_change: Instant,
    last_update: Instant,
    shown: Option<Shown>,
    last_full_ms: Option<f64>,
    image_area: (u32, u32),
    image_rect: Option<egui::Rect>,
    mouse_look: bool,
    esc_armed: bool,
    show_help: bool,
    status: String,
    obj_path: String,
    loading: bool,
    frames_presented: u64,
    /// Draws that failed in a row (a lost surface is retried at once, a broken one is not
    /// retried in a loop).
    failed_draws: u32,
    script: Option<Script>,
    script_start: Option<Instant>,
    started: Instant,
    minimised: bool,
    egui_repaint_at: Option<Instant>,
    /// Rendered frames that arrived while a key held the camera moving (the preview works).
    frames_while_moving: u64,
    screenshots_pending: usize,
    outcome: Result<()>,
}

impl App {
    fn new(
        opts: ViewerOptions,
        scene: Scene,
        script: Option<Script>,
        proxy: EventLoopProxy<AppEvent>,
    ) -> Self {
        let wake = proxy.clone();
        let controller = controller_for(&scene, opts.scene.is_none());
        let light = scene.light.position;
        Self {
            obj_path: opts
                .scene
                .as_ref()
                .map(|p| p.display().to_string())
                .unwrap_or_default(),
            opts,
            proxy,
            window: None,
            gpu: None,
            egui_ctx: egui::Context::default(),
            egui_state: None,
            scene: Arc::new(scene),
            controller,
            view: ViewSettings {
                step: LabStep::Indirect,
                method: Method::Adaptive,
                spp: 2,
                resolution: Resolution::WindowScale(1.0),
                adaptive: true,
                target_ms: 16.0,
                preview_scale: 0.5,
                light,
                cracks: false,
            },
            input: InputState::default(),
            worker: worker::Worker::new(move || {
                let _ = wake.send_event(AppEvent::FrameReady);
            }),
            generation: 0,
            last_change: Instant::now(),
            last_update: Instant::now(),
            shown: None,
            last_full_ms: None,
            image_area: (640, 480),
            image_rect: None,
            mouse_look: false,
            esc_armed: false,
            show_help: false,
            status: String::new(),
            loading: false,
            frames_presented: 0,
            failed_draws: 0,
            script,
            script_start: None,
            started: Instant::now(),
            minimised: false,
            egui_repaint_at: None,
            frames_while_moving: 0,
            screenshots_pending: 0,
            outcome: Ok(()),
        }
    }

    fn fail(&mut self, event_loop: &ActiveEventLoop, e: anyhow::Error) {
        if self.outcome.is_ok() {
            self.outcome = Err(e);
        }
        event_loop.exit();
    }

    /// A message for the panel (and the log, so scripted runs can be checked).
    fn set_status(&mut self, message: impl Into<String>) {
        self.status = message.into();
        log::info!("{}", self.status);
    }

    fn changed(&mut self) {
        self.generation += 1;
        self.last_change = Instant::now();
        self.worker.set_generation(self.generation);
    }

    fn request_redraw(&self) {
        if let Some(w) = &self.window {
            w.request_redraw();
        }
    }

    /// The full render size for the current image area and resolution setting.
    fn full_size(&self) -> (u32, u32) {
        let clamp = |x: f32| (x.round() as u32).clamp(1, MAX_SIDE);
        match self.view.resolution {
            Resolution::WindowScale(s) => {
                let s = s.clamp(0.05, 1.0);
                (
                    clamp(self.image_area.0 as f32 * s),
                    clamp(self.image_area.1 as f32 * s),
                )
            }
            Resolution::Fixed(w, h) => (w, h),
        }
    }

    fn max_level(&self) -> u8 {
        if self.view.spp > 1 {
            2
        } else {
            1
        }
    }

    /// The preview size: a fixed fraction, or (adaptive) what the last full frame's time says
    /// will hold the target frame time.
    fn preview_size(&self) -> (u32, u32) {
        let (w, h) = self.full_size();
        let scale = if self.view.adaptive {
            match self.last_full_ms {
                Some(ms) if ms > 0.0 => {
                    ((self.view.target_ms as f64 / ms).sqrt() as f32).clamp(0.1, 1.0)
                }
                _ => 0.5,
            }
        } else {
            self.view.preview_scale.clamp(0.05, 1.0)
        };
        (
            ((w as f32 * scale) as u32).max(1),
            ((h as f32 * scale) as u32).max(1),
        )
    }

    /// Submits the next render if the worker is free and something is left to do.
    fn pump(&mut self) {
        if !self.worker.is_idle() || self.minimised {
            return;
        }
        log::trace!("pump: generation {}", self.generation);
        let settling = self.last_change.elapsed() < SETTLE || self.input.is_moving();
        let level = match &self.shown {
            Some(s) if s.generation == self.generation => {
                if settling || s.level >= self.max_level() {
                    return;
                }
                s.level + 1
            }
            _ if settling => 0,
            _ => 1,
        };
        let (w, h) = if level == 0 {
            self.preview_size()
        } else {
            self.full_size()
        };
        let mut scene = self.scene.clone();
        if scene.light.position != self.view.light {
            Arc::make_mut(&mut scene).light.position = self.view.light;
            self.scene = scene.clone();
        }
        let settings = RenderSettings {
            width: w,
            height: h,
            step: self.view.step,
            spp: if level == 2 { self.view.spp } else { 1 },
            method: self.view.method,
            cracks: self.view.cracks,
            ..Default::default()
        };
        self.worker.submit(worker::Job {
            scene,
            camera: self.controller.camera(w),
            settings,
            generation: self.generation,
            level,
        });
    }

    fn frame_ready(&mut self) {
        let Some(done) = self.worker.take_latest() else {
            return;
        };
        match done.image {
            Ok(None) => {} // cancelled by a newer change
            Ok(Some((rgba, stats))) => {
                let s = done.job.settings;
                if done.job.level == 1 {
                    self.last_full_ms = Some(stats.elapsed.as_secs_f64() * 1e3);
                }
                if let Some(gpu) = &mut self.gpu {
                    if let Err(e) = gpu.set_frame(s.width, s.height, &rgba) {
                        self.set_status(e);
                    }
                }
                if self.input.is_moving() {
                    self.frames_while_moving += 1;
                }
                self.shown = Some(Shown {
                    generation: done.job.generation,
                    level: done.job.level,
                    size: (s.width, s.height),
                    stats,
                });
            }
            Err(e) => self.set_status(format!("render failed: {e}")),
        }
        self.pump();
        self.request_redraw();
    }

    fn load_obj(&mut self, path: PathBuf) {
        if self.loading {
            return;
        }
        self.loading = true;
        self.set_status(format!("loading {}...", path.display()));
        let proxy = self.proxy.clone();
        let frame = self.opts.obj_frame;
        std::thread::spawn(move || {
            let result = raylab::scene::load_obj_file(&path, frame).map_err(|e| e.to_string());
            let _ = proxy.send_event(AppEvent::SceneLoaded(path, result));
        });
    }

    /// F12: renders the current view at full resolution and quality (the window may be
    /// showing a preview) and writes it, on a thread of its own so the window keeps going.
    fn screenshot(&mut self) {
        let path = PathBuf::from(format!("raylab-{}.png", timestamp()));
        let (w, h) = self.full_size();
        let settings = RenderSettings {
            width: w,
            height: h,
            step: self.view.step,
            spp: self.view.spp,
            method: self.view.method,
            cracks: self.view.cracks,
            ..Default::default()
        };
        let (scene, camera, proxy) = (
            self.scene.clone(),
            self.controller.camera(w),
            self.proxy.clone(),
        );
        self.screenshots_pending += 1;
        self.set_status(format!("saving {}...", path.display()));
        std::thread::spawn(move || {
            let result = render::render_image(&scene, &camera, &settings)
                .map_err(|e| e.to_string())
                .and_then(|(rgba, _)| {
                    render::write_png(&path, w, h, &rgba)
                        .map_err(|e| format!("{}: {e}", path.display()))
                })
                .map(|()| std::fs::canonicalize(&path).unwrap_or(path));
            let _ = proxy.send_event(AppEvent::ScreenshotSaved(result));
        });
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
    }

    /// A key press or release from the keyboard or the script.
    fn key(&mut self, event_loop: &ActiveEventLoop, key: Key, pressed: bool) {
        if self.input.key(key, pressed) {
            if pressed {
                self.esc_armed = false;
            }
            return;
        }
        if !pressed {
            return;
        }
        match key {
            Key::R => {
                self.controller.reset();
                self.changed();
            }
            Key::H | Key::F1 => self.show_help = !self.show_help,
            Key::F12 => self.screenshot(),
            Key::Escape => {
                if self.mouse_look {
                    self.set_mouse_look(false);
                } else if self.esc_armed {
                    event_loop.exit();
                } else {
                    self.esc_armed = true;
                    self.set_status("press Esc again to quit");
                }
            }
            _ => {}
        }
        self.request_redraw();
    }

    fn run_script(&mut self, event_loop: &ActiveEventLoop) {
        let Some(start) = self.script_start else {
            return;
        };
        let Some(script) = &mut self.script else {
            return;
        };
        for action in script.due(start.elapsed()) {
            match action {
                Action::Key(k, down) => self.key(event_loop, k, down),
                Action::Mouse(dx, dy) => self.input.mouse(dx, dy),
                Action::Wheel(lines) => self.input.wheel(lines),
                Action::Step(step) => {
                    self.view.step = step;
                    self.changed();
                }
                Action::Drop(path) => self.load_obj(path),
                Action::Focal(f) => {
                    let width = self.full_size().0;
                    self.controller.set_focal(f, width);
                    self.changed();
                }
                Action::Scale(s) => {
                    self.view.resolution = Resolution::WindowScale(s);
                    self.changed();
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
                Action::LoseSurface => {
                    if let Some(gpu) = &mut self.gpu {
                        gpu.lose_next_draw = true;
                    }
                    if let Some(window) = &self.window {
                        window.request_redraw();
                    }
                }
            }
        }
    }

    /// For `--frames`: done once enough frames were shown, the script ran out and the image
    /// is fully refined.
    fn scripted_run_done(&self) -> bool {
        let Some(n) = self.opts.frames else {
            return false;
        };
        self.frames_presented >= n
            && !self.loading
            && self.screenshots_pending == 0
            && self.script.as_ref().is_none_or(|s| s.finished())
            && !self.input.is_moving()
            && self.worker.is_idle()
            && self
                .shown
                .as_ref()
                .is_some_and(|s| s.generation == self.generation && s.level >= self.max_level())
    }

    /// A new window size; 0×0 (minimised) pauses rendering until a real size comes back.
    fn on_resized(&mut self, window: &Window, size: PhysicalSize<u32>) {
        let minimised = size.width == 0 || size.height == 0;
        if minimised != self.minimised {
            log::info!(
                "window {}",
                if minimised {
                    "minimised: rendering paused"
                } else {
                    "restored: rendering resumed"
                }
            );
        }
        self.minimised = minimised;
        if !minimised {
            if let Some(gpu) = &mut self.gpu {
                if let Err(e) = gpu.resize_surface(size.width, size.height) {
                    self.set_status(e);
                }
            }
            self.pump();
        }
        window.request_redraw();
    }

    fn redraw(&mut self, event_loop: &ActiveEventLoop) {
        let (Some(window), Some(_)) = (self.window.clone(), self.gpu.as_ref()) else {
            return;
        };
        if self.script_start.is_none() && self.frames_presented > 0 {
            self.script_start = Some(Instant::now());
        }
        // The script runs while minimised too (it may be what restores the window).
        self.run_script(event_loop);
        if self.minimised {
            return;
        }

        let now = Instant::now();
        let dt = now.duration_since(self.last_update).as_secs_f64();
        self.last_update = now;
        let control = self.input.take();
        if self.controller.update(&control, dt) {
            self.changed();
        }

        // The egui pass: panel, image area, overlay.
        let before = (self.view, self.controller, self.full_size());
        let raw = self
            .egui_state
            .as_mut()
            .expect("set with the window")
            .take_egui_input(&window);
        let texture_id = self.gpu.as_ref().expect("checked").texture_id;
        let buffer_size = self.gpu.as_ref().expect("checked").buffer_size;
        let info_size = self.full_size();
        let threads = rayon::current_num_threads();
        let mut actions = panel::PanelActions::default();
        let mut image_area = self.image_area;
        let mut image_rect = None;
        let has_image = self.shown.is_some();
        let ppp = self.egui_ctx.pixels_per_point();
        let ctx = self.egui_ctx.clone();
        let output = ctx.run_ui(raw, |ui| {
            let shown = self
                .shown
                .as_ref()
                .map(|s| (s.size.0, s.size.1, s.level, s.stats));
            let info = panel::PanelInfo {
                scene_name: &self.scene.name,
                primitives: self.scene.len(),
                warnings: &self.scene.warnings,
                full_size: info_size,
                shown,
                status: &self.status,
                loading: self.loading,
                threads,
            };
            egui::Panel::left("controls")
                .resizable(true)
                .default_size(PANEL_WIDTH)
                .show(ui, |ui| {
                    actions = panel::side_panel(
                        ui,
                        &mut self.view,
                        &mut self.controller,
                        &mut self.obj_path,
                        &info,
                    );
                });
            egui::CentralPanel::no_frame().show(ui, |ui| {
                let area = ui.max_rect();
                image_area = (
                    ((area.width() * ppp).round() as u32).max(1),
                    ((area.height() * ppp).round() as u32).max(1),
                );
                if has_image {
                    let (bw, bh) = buffer_size;
                    let aspect = bw as f32 / bh as f32;
                    let size = if area.width() / area.height() > aspect {
                        egui::vec2(area.height() * aspect, area.height())
                    } else {
                        egui::vec2(area.width(), area.width() / aspect)
                    };
                    let rect = egui::Rect::from_center_size(area.center(), size);
                    ui.painter().image(
                        texture_id,
                        rect,
                        egui::Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(1.0, 1.0)),
                        egui::Color32::WHITE,
                    );
                    image_rect = Some(rect);
                }
            });
            panel::help_window(ui.ctx(), &mut self.show_help);
        });
        self.image_area = image_area;
        self.image_rect = image_rect;
        if actions.reset_camera {
            self.controller.reset();
        }
        if let Some(p) = actions.load {
            self.load_obj(PathBuf::from(p));
        }
        if actions.screenshot {
            self.screenshot();
        }
        if before != (self.view, self.controller, self.full_size()) || actions.reset_camera {
            log::debug!(
                "change: {:?} -> {:?}",
                before,
                (self.view, self.controller, self.full_size())
            );
            self.changed();
        }
        self.egui_state
            .as_mut()
            .expect("set with the window")
            .handle_platform_output(&window, output.platform_output);
        let paint_jobs = self
            .egui_ctx
            .tessellate(output.shapes, output.pixels_per_point);

        let capture = self.scripted_run_done();
        let gpu = self.gpu.as_mut().expect("checked");
        // Match the surface to the window as it is now: a resize that lands after its
        // Resized event was handled leaves the surface outdated, and pixels 0.17 retries an
        // outdated surface at its old size forever (a hang seen under X11).
        let size = window.inner_size();
        if size.width == 0 || size.height == 0 {
            return;
        }
        if let Err(e) = gpu.resize_surface(size.width, size.height) {
            self.set_status(e);
            return;
        }
        match gpu.draw(
            &paint_jobs,
            &output.textures_delta,
            output.pixels_per_point,
            capture,
        ) {
            Ok(Some(shot)) => {
                self.finish_scripted_run(event_loop, shot);
                return;
            }
            Ok(None) => {}
            Err(e) => {
                // A lost or failed surface: say so and draw again (pixels reconfigures a lost
                // surface on its next frame); nothing was presented this time.
                log::warn!("{e}");
                self.set_status(e);
                self.failed_draws += 1;
                if self.failed_draws <= 3 {
                    window.request_redraw();
                }
                return;
            }
        }
        self.failed_draws = 0;
        self.frames_presented += 1;

        if self.opts.frames.is_some() && self.started.elapsed() > SCRIPTED_TIMEOUT {
            self.fail(
                event_loop,
                anyhow!(
                    "the scripted run did not finish within {} s",
                    SCRIPTED_TIMEOUT.as_secs()
                ),
            );
            return;
        }
        self.pump();
        let repaint_delay = output
            .viewport_output
            .get(&egui::ViewportId::ROOT)
            .map_or(Duration::MAX, |v| v.repaint_delay);
        let repaint_now = repaint_delay.is_zero();
        // egui animations (tooltips, collapsing) ask for a repaint a little later.
        self.egui_repaint_at =
            (repaint_delay < Duration::from_secs(3600)).then(|| Instant::now() + repaint_delay);
        log::trace!(
            "frame {}: moving {} repaint {} shown {:?}",
            self.frames_presented,
            self.input.is_moving(),
            repaint_now,
            self.shown.as_ref().map(|s| (s.generation, s.level)),
        );
        if self.input.is_moving() || repaint_now || self.opts.frames.is_some() {
            window.request_redraw();
        }
    }

    fn finish_scripted_run(&mut self, event_loop: &ActiveEventLoop, shot: gpu::Capture) {
        let path = self
            .opts
            .screenshot
            .clone()
            .expect("--frames has --screenshot");
        if let Err(e) = render::write_png(&path, shot.width, shot.height, &shot.rgba) {
            self.fail(
                event_loop,
                anyhow!("cannot write '{}': {e}", path.display()),
            );
            return;
        }
        let c = &self.controller;
        let (w, h) = self.shown.as_ref().map(|s| s.size).unwrap_or((0, 0));
        let r = self.image_rect.unwrap_or(egui::Rect::NOTHING);
        let ppp = self.egui_ctx.pixels_per_point();
        println!(
            "raylab-final camera={},{},{} yaw={} pitch={} focal={} size={}x{} rect={},{},{},{} step={} frames={} moving_frames={} scene={}",
            c.position.x,
            c.position.y,
            c.position.z,
            c.yaw.to_degrees(),
            c.pitch.to_degrees(),
            c.focal(w),
            w,
            h,
            r.min.x * ppp,
            r.min.y * ppp,
            r.width() * ppp,
            r.height() * ppp,
            self.view.step,
            self.frames_presented,
            self.frames_while_moving,
            self.scene.name,
        );
        if !self.status.is_empty() {
            println!("status: {}", self.status);
        }
        println!("saved {}", path.display());
        event_loop.exit();
    }
}

impl ApplicationHandler<AppEvent> for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.window.is_some() {
            return;
        }
        let attrs = Window::default_attributes()
            .with_title(format!("raylab - {}", self.scene.name))
            .with_inner_size(LogicalSize::new(1100.0, 620.0))
            .with_min_inner_size(LogicalSize::new(320.0, 240.0));
        let window = match event_loop.create_window(attrs) {
            Ok(w) => Arc::new(w),
            Err(e) => return self.fail(event_loop, anyhow!("cannot create a window: {e}")),
        };
        let size = window.inner_size();
        let surface = (size.width.max(1), size.height.max(1));
        let ppp = window.scale_factor() as f32;
        self.image_area = (
            ((size.width as f32 - PANEL_WIDTH * ppp).max(1.0)) as u32,
            size.height.max(1),
        );
        let gpu = match gpu::Gpu::new(window.clone(), surface, self.full_size()) {
            Ok(g) => g,
            Err(e) => return self.fail(event_loop, anyhow!(e)),
        };
        let state = egui_winit::State::new(
            self.egui_ctx.clone(),
            egui::ViewportId::ROOT,
            event_loop,
            Some(ppp),
            None,
            Some(gpu.max_texture_side()),
        );
        self.egui_state = Some(state);
        self.gpu = Some(gpu);
        self.window = Some(window.clone());
        self.changed();
        self.pump();
        window.request_redraw();
    }

    fn user_event(&mut self, _event_loop: &ActiveEventLoop, event: AppEvent) {
        match event {
            AppEvent::FrameReady => self.frame_ready(),
            AppEvent::ScreenshotSaved(result) => {
                self.screenshots_pending -= 1;
                match result {
                    Ok(path) => self.set_status(format!("saved {}", path.display())),
                    Err(e) => self.set_status(format!("screenshot failed: {e}")),
                }
                self.request_redraw();
            }
            AppEvent::SceneLoaded(path, result) => {
                self.loading = false;
                match result {
                    Ok(scene) => {
                        let (w, h) = self.full_size();
                        if let Some(bounds) = scene.bounds() {
                            self.controller = CameraController::framing(bounds, w, h);
                        }
                        self.view.light = scene.light.position;
                        self.set_status(format!(
                            "loaded {} ({} triangles)",
                            path.display(),
                            scene.len()
                        ));
                        if let Some(w) = &self.window {
                            w.set_title(&format!("raylab - {}", scene.name));
                        }
                        self.scene = Arc::new(scene);
                        self.changed();
                    }
                    // The old scene stays.
                    Err(e) => self.set_status(format!("could not load: {e}")),
                }
                self.pump();
                self.request_redraw();
            }
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let Some(window) = self.window.clone() else {
            return;
        };
        let response = match &mut self.egui_state {
            Some(state) => state.on_window_event(&window, &event),
            None => return,
        };
        // egui asks to repaint after every redraw too; that would spin forever.
        if response.repaint && !matches!(event, WindowEvent::RedrawRequested) {
            window.request_redraw();
        }
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::Resized(size) => self.on_resized(&window, size),
            WindowEvent::ScaleFactorChanged { scale_factor, .. } => {
                // egui-winit has taken the new pixels-per-point from this event already.
                log::info!("scale factor changed to {scale_factor}");
                window.request_redraw();
            }
            WindowEvent::Focused(false) => {
                self.input.release_all();
                self.set_mouse_look(false);
            }
            WindowEvent::DroppedFile(path) => self.load_obj(path),
            WindowEvent::KeyboardInput { event, .. } => {
                let PhysicalKey::Code(code) = event.physical_key else {
                    return;
                };
                let Some(key) = Key::from_code(code) else {
                    return;
                };
                let pressed = event.state == ElementState::Pressed;
                // Releases always count (no stuck keys); presses only when egui is not typing.
                if pressed
                    && (event.repeat
                        || (self.egui_ctx.egui_wants_keyboard_input() && key != Key::Escape))
                {
                    return;
                }
                self.key(event_loop, key, pressed);
                window.request_redraw();
            }
            WindowEvent::MouseInput {
                state,
                button: MouseButton::Right,
                ..
            } => {
                let pressed = state == ElementState::Pressed;
                if pressed && !self.egui_ctx.egui_wants_pointer_input() {
                    self.set_mouse_look(true);
                } else if !pressed && self.mouse_look {
                    self.set_mouse_look(false);
                }
            }
            WindowEvent::MouseWheel { delta, .. }
                if !response.consumed && !self.egui_ctx.egui_wants_pointer_input() =>
            {
                let lines = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y as f64,
                    MouseScrollDelta::PixelDelta(p) => p.y / 40.0,
                };
                self.input.wheel(lines);
                window.request_redraw();
            }
            WindowEvent::RedrawRequested => self.redraw(event_loop),
            _ => {}
        }
    }

    fn device_event(&mut self, _event_loop: &ActiveEventLoop, _id: DeviceId, event: DeviceEvent) {
        if let DeviceEvent::MouseMotion { delta } = event {
            if self.mouse_look {
                self.input.mouse(delta.0, delta.1);
                self.request_redraw();
            }
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        self.pump();
        // Sleep until something happens, or until the preview has settled and refinement can
        // start, or until the script's next event.
        let mut wake: Option<Instant> = None;
        let refining = self
            .shown
            .as_ref()
            .is_none_or(|s| s.generation != self.generation || s.level < self.max_level());
        // (Not while minimised: nothing renders then, and waking for it would spin.)
        if refining && self.worker.is_idle() && !self.minimised {
            wake = Some(self.last_change + SETTLE);
        }
        if let (Some(start), Some(next)) = (
            self.script_start,
            self.script.as_ref().and_then(Script::next_due),
        ) {
            let t = start + next;
            wake = Some(wake.map_or(t, |w| w.min(t)));
        }
        match wake {
            Some(t) if t > Instant::now() => event_loop.set_control_flow(ControlFlow::WaitUntil(t)),
            Some(_) => {
                self.egui_repaint_at = None;
                event_loop.set_control_flow(ControlFlow::Wait);
                self.request_redraw();
            }
            None => event_loop.set_control_flow(ControlFlow::Wait),
        }
    }
}

/// The starting controller: the lab camera for the Cornell box, a framing one for a model.
fn controller_for(scene: &Scene, cornell: bool) -> CameraController {
    match (cornell, scene.bounds()) {
        (false, Some(b)) => CameraController::framing(b, 4, 3),
        _ => CameraController::cornell(),
    }
}

/// Seconds since the Unix epoch with milliseconds, for screenshot names that sort in time.
fn timestamp() -> String {
    let t = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .unwrap_or_default();
    format!("{}-{:03}", t.as_secs(), t.subsec_millis())
}
