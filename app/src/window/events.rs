//! The event loop's handler: winit's events (window, input, raw motion, the worker's
//! messages) to the [`App`] of the window shell.

use super::input::Key;
use super::scripted::ScriptedRun;
use super::{layout, App, AppEvent, Framework, QUIT_PROMPT, QUIT_PROMPT_FOR};
use anyhow::anyhow;
use raylab::controller::Mode;
use std::sync::Arc;
use std::time::Instant;
use winit::application::ApplicationHandler;
use winit::dpi::{LogicalSize, PhysicalSize, Size};
use winit::event::{
    DeviceEvent, DeviceId, ElementState, MouseButton, MouseScrollDelta, WindowEvent,
};
use winit::event_loop::{ActiveEventLoop, ControlFlow};
use winit::keyboard::{KeyCode, PhysicalKey};
use winit::window::{Window, WindowId};

/// The window's starting size: 90% of the primary monitor, at most 1600×1000 logical pixels,
/// at least the 1100×620 that shows the panel and a useful image where the monitor has room
/// for that (else 90% of it); 1100×620 logical where the monitor is unknown. In the monitor's
/// own pixels: winit turns a logical size into pixels with the scale factor of the monitor
/// the window opens on, and a size that fits one monitor in its points may not fit it in
/// another's (at scale 2 on a 1280×800 screen, 1100×620 points are 2200×1240 pixels).
fn default_window_size(event_loop: &ActiveEventLoop) -> Size {
    let fallback = LogicalSize::new(1100.0, 620.0);
    // (X11 names a 1×1 stand-in the primary monitor where no monitor is marked primary.)
    let real = |m: &winit::monitor::MonitorHandle| m.size().width > 1 && m.size().height > 1;
    let monitor = (event_loop.primary_monitor().filter(real))
        .or_else(|| event_loop.available_monitors().find(real));
    let Some(monitor) = monitor else {
        return fallback.into();
    };
    let (screen, scale) = (monitor.size(), monitor.scale_factor());
    let side = |screen: u32, least: f64, most: f64| {
        let (screen, least, most) = (screen as f64, least * scale, most * scale);
        let fit = (0.9 * screen).min(most);
        match least <= screen {
            true => fit.max(least).round(),
            false => fit.round(),
        }
    };
    PhysicalSize::new(
        side(screen.width, fallback.width, 1600.0),
        side(screen.height, fallback.height, 1000.0),
    )
    .into()
}

impl ApplicationHandler<AppEvent> for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.window.is_some() {
            return;
        }
        let attrs = Window::default_attributes()
            .with_title(format!("raylab - {}", self.viewer.stage.scene().name))
            .with_inner_size(default_window_size(event_loop))
            .with_min_inner_size(LogicalSize::new(320.0, 240.0));
        let window = match event_loop.create_window(attrs) {
            Ok(w) => Arc::new(w),
            Err(e) => return self.fail(event_loop, anyhow!("cannot create a window: {e}")),
        };
        let size = window.inner_size();
        let surface = (size.width.max(1), size.height.max(1));
        let ppp = window.scale_factor() as f32;
        self.viewer.image_area = (
            ((size.width as f32 - layout::PANEL_WIDTH * ppp).max(1.0)) as u32,
            size.height.max(1),
        );
        self.viewer.beside_width = self.viewer.image_area.0;
        let buffer = self.viewer.full_size();
        match Framework::new(event_loop, window.clone(), surface, buffer) {
            Ok(fw) => {
                let device_side = fw.gpu.max_texture_side() as u32;
                self.viewer.max_side = device_side.min(raylab::render::MAX_SIDE);
                self.surface_max = device_side;
                self.framework = Some(fw);
            }
            Err(e) => return self.fail(event_loop, anyhow!(e)),
        }
        self.window = Some(window.clone());
        self.viewer.changed();
        self.viewer.pump();
        window.request_redraw();
    }

    fn user_event(&mut self, _event_loop: &ActiveEventLoop, event: AppEvent) {
        match event {
            AppEvent::FrameReady => self.frame_ready(),
            AppEvent::ScreenshotSaved(result) => {
                self.viewer.screenshot_saved(result);
                self.request_redraw();
            }
            AppEvent::SceneLoaded(request, result) => {
                let loaded = self.viewer.scene_loaded(request, *result);
                if let (Some(name), Some(w)) = (loaded, &self.window) {
                    w.set_title(&format!("raylab - {name}"));
                }
                self.viewer.pump();
                self.request_redraw();
            }
            AppEvent::SourceChanged(path) => {
                self.viewer.reload(path);
                self.request_redraw();
            }
            AppEvent::CracksCounted => {
                self.viewer.cracks_counted();
                self.request_redraw();
            }
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let (Some(window), Some(fw)) = (self.window.clone(), &mut self.framework) else {
            return;
        };
        let egui_keyboard = fw.wants_keyboard();
        // (Before egui sees the press: the field or dialog Esc closes is still open.)
        let dialog_open = self.viewer.files.is_open();
        let egui_escape = fw.takes_escape() || dialog_open;
        // Tab is the camera's (fly/orbit) unless a text field is typing: egui would take it to
        // move its keyboard focus between widgets.
        let tab = matches!(&event, WindowEvent::KeyboardInput { event, .. }
            if event.physical_key == PhysicalKey::Code(KeyCode::Tab));
        let response = match tab && !egui_keyboard {
            true => egui_winit::EventResponse::default(),
            false => fw.handle_event(&window, &event),
        };
        let (egui_keyboard, egui_pointer) = (fw.wants_keyboard(), fw.wants_pointer());
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
                self.viewer.input.release_all();
                self.set_mouse_look(false);
            }
            WindowEvent::DroppedFile(path) => self.viewer.load(path),
            WindowEvent::KeyboardInput {
                event,
                is_synthetic,
                ..
            } => {
                let PhysicalKey::Code(code) = event.physical_key else {
                    return;
                };
                let Some(key) = Key::from_code(code) else {
                    return;
                };
                let pressed = event.state == ElementState::Pressed;
                // Releases always count (no stuck keys); presses only when egui is not typing.
                // (A window gaining focus replays the keys held as synthetic presses: a key
                // pressed just then arrives twice, so only held motion takes them.) Esc that
                // leaves a field or closes a dialog or menu is egui's alone, unless it frees
                // the captured mouse.
                let replayed = is_synthetic && !key.is_held_motion();
                // (The file dialog takes every key while open: its search box starts with the
                // first one typed, which also chose a lab step or flew the camera.)
                let egui_takes = match key {
                    Key::Escape => egui_escape && !self.mouse_look,
                    _ => egui_keyboard || dialog_open,
                };
                if pressed && (event.repeat || replayed || egui_takes) {
                    // (A function key types nothing: say why it did nothing, where it had
                    // done so in silence.)
                    let function_key = matches!(key, Key::F1 | Key::F5 | Key::F12);
                    if function_key && egui_keyboard && !dialog_open {
                        // (Not done later: "waits" read as if it would be.)
                        let said = format!(
                            "{key:?} did nothing: a text field has the keyboard (Enter or Esc \
                             ends the edit; then press {key:?} again)"
                        );
                        self.viewer.set_status(said);
                        window.request_redraw();
                    }
                    return;
                }
                self.key(event_loop, key, pressed, Instant::now());
                window.request_redraw();
            }
            WindowEvent::CursorMoved { position, .. } => {
                let (x, y) = (position.x, position.y);
                if let (Some(orbit), Some((px, py))) = (self.drag, self.cursor) {
                    match orbit {
                        true => self.viewer.input.orbit(x - px, y - py),
                        false => self.viewer.input.pan(x - px, y - py),
                    }
                    window.request_redraw();
                } else if let (true, false, Some((px, py))) =
                    (self.mouse_look, self.raw_motion, self.cursor)
                {
                    // An absolute pointer (VNC, a tablet, a VM's mouse integration) sends no
                    // raw motion: the cursor's moves turn the view instead.
                    self.viewer.input.mouse(x - px, y - py);
                    window.request_redraw();
                }
                self.cursor = Some((x, y));
            }
            WindowEvent::CursorLeft { .. } => self.cursor = None,
            WindowEvent::MouseInput { state, button, .. } => {
                let pressed = state == ElementState::Pressed;
                if pressed {
                    // (A click is something else done: Esc asks again before quitting.)
                    self.esc_armed = None;
                }
                let on_image = self.button_is_cameras(egui_pointer);
                let orbit_mode = self.viewer.controller.mode == Mode::Orbit;
                if button == MouseButton::Left {
                    self.left_click(pressed, on_image);
                }
                match button {
                    _ if !pressed => {
                        self.drag = None;
                        if button == MouseButton::Right && self.mouse_look {
                            self.set_mouse_look(false);
                        }
                    }
                    MouseButton::Left if orbit_mode && on_image => self.drag = Some(true),
                    MouseButton::Middle | MouseButton::Right if orbit_mode && on_image => {
                        self.drag = Some(false)
                    }
                    MouseButton::Right if on_image => self.set_mouse_look(true),
                    _ => {}
                }
            }
            WindowEvent::MouseWheel { delta, .. }
                if self.wheel_turns_camera(response.consumed, egui_pointer) =>
            {
                let lines = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y as f64,
                    MouseScrollDelta::PixelDelta(p) => p.y / 40.0,
                };
                self.viewer.input.wheel(lines);
                self.viewer.field_slip_outdated();
                window.request_redraw();
            }
            WindowEvent::RedrawRequested => self.redraw(event_loop),
            _ => {}
        }
    }

    fn device_event(&mut self, _event_loop: &ActiveEventLoop, _id: DeviceId, event: DeviceEvent) {
        if let DeviceEvent::MouseMotion { delta } = event {
            self.raw_motion = true;
            if self.mouse_look {
                self.viewer.input.mouse(delta.0, delta.1);
                self.request_redraw();
            }
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        self.viewer.pump();
        if self.viewer.status == QUIT_PROMPT && !self.quit_armed() {
            // (A click, a key or time since: the prompt no longer holds.)
            self.viewer.status.clear();
            self.esc_armed = None;
            log::info!("quit prompt withdrawn");
            self.request_redraw();
        }
        // A scripted run past its limit ends here, drawing or not.
        let scripted = self.scripted.as_ref();
        let late = scripted.map(|run| run.check_time(&self.viewer, self.frames_presented));
        if let Some(Err(e)) = late {
            return self.fail(event_loop, e);
        }
        // A script held by an `await` looks for its file here, drawing no frame for it.
        let now = Instant::now();
        if let Some(run) = &mut self.scripted {
            if run.next_due().is_some_and(|t| t <= now) {
                run.look_for_awaited();
            }
        }
        // Sleep until something happens, or until the preview has settled and refinement can
        // start, or until the script's next event, or until egui wants to draw again (a
        // tooltip shows once the pointer has rested on its widget), or until a scripted run's
        // limit.
        let script_at = self.scripted.as_ref().and_then(ScriptedRun::next_due);
        let deadline = self.scripted.as_ref().map(ScriptedRun::deadline);
        let prompt_ends = self.esc_armed.map(|t| t + QUIT_PROMPT_FOR);
        let wake = [
            self.viewer.refine_at(),
            self.viewer.progress_redraw_at(self.drawn_at),
            script_at,
            self.egui_repaint_at,
            deadline,
            prompt_ends,
        ]
        .into_iter()
        .flatten()
        .min();
        if self.viewer.refine_at().is_some_and(|t| t <= now) {
            self.viewer.refine_wakes += 1;
        }
        match wake {
            Some(t) if t > now => event_loop.set_control_flow(ControlFlow::WaitUntil(t)),
            Some(_) => {
                self.egui_repaint_at = None;
                event_loop.set_control_flow(ControlFlow::Wait);
                self.request_redraw();
            }
            None => event_loop.set_control_flow(ControlFlow::Wait),
        }
    }
}
