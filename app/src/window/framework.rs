//! The framework part of the window, in the shape of the pixels crate's `minimal-egui`
//! example: it owns the egui context, the egui-winit state and the GPU side ([`Gpu`]: the
//! surface, the framebuffer texture and the egui-wgpu renderer), and turns a UI closure into a
//! drawn frame. The viewer's state never sees egui-winit or wgpu.

use super::gpu::{Drawn, Gpu};
use std::sync::Arc;
use std::time::Duration;
use winit::event::WindowEvent;
use winit::event_loop::ActiveEventLoop;
use winit::window::Window;

/// egui and the GPU for one window.
pub struct Framework {
    ctx: egui::Context,
    state: egui_winit::State,
    /// Input that came after a pass's end (its one pointer button change, or an Enter after
    /// text), for the passes after it, each with the time it came ([`next_pass`]).
    held: Vec<Timed>,
    pub gpu: Gpu,
}

/// One UI pass, laid out and tessellated, ready to draw.
pub struct Prepared {
    paint_jobs: Vec<egui::ClippedPrimitive>,
    textures: egui::TexturesDelta,
    pixels_per_point: f32,
    /// When egui wants to be drawn again (zero: at once; very large: not for itself).
    pub repaint_delay: Duration,
}

impl Framework {
    /// The GPU surface for `window` (physical size `surface`) with a framebuffer of `buffer`
    /// pixels, and egui's state at the window's scale factor.
    pub fn new(
        event_loop: &ActiveEventLoop,
        window: Arc<Window>,
        surface: (u32, u32),
        buffer: (u32, u32),
    ) -> Result<Self, String> {
        let ppp = window.scale_factor() as f32;
        let gpu = Gpu::new(window, surface, buffer)?;
        let ctx = egui::Context::default();
        let state = egui_winit::State::new(
            ctx.clone(),
            egui::ViewportId::ROOT,
            event_loop,
            Some(ppp),
            None,
            Some(gpu.max_texture_side()),
        );
        Ok(Self {
            ctx,
            state,
            held: Vec::new(),
            gpu,
        })
    }

    /// Lets egui see a window event first.
    pub fn handle_event(
        &mut self,
        window: &Window,
        event: &WindowEvent,
    ) -> egui_winit::EventResponse {
        self.state.on_window_event(window, event)
    }

    /// Whether egui is taking the keyboard: a text field has focus. (Not egui's
    /// `egui_wants_keyboard_input`, which holds for any focused widget: a button focused by a
    /// click or by Tab would then swallow every camera key.)
    pub fn wants_keyboard(&self) -> bool {
        self.ctx.text_edit_focused()
    }

    /// Whether Esc is egui's: a text field has focus (Esc leaves it) or a menu or drop-down
    /// is open (Esc closes it).
    pub fn takes_escape(&self) -> bool {
        self.ctx.text_edit_focused() || self.ctx.any_popup_open()
    }

    /// Whether an egui window, menu or dialog (anything above the panels) is drawn at `pos`
    /// (points) in the last frame.
    pub fn window_at(&self, pos: egui::Pos2) -> bool {
        (self.ctx.layer_id_at(pos)).is_some_and(|layer| layer.order != egui::Order::Background)
    }

    /// Whether egui is taking the pointer (over a widget, or dragging one).
    pub fn wants_pointer(&self) -> bool {
        self.ctx.egui_wants_pointer_input()
    }

    /// Physical pixels per egui point.
    pub fn pixels_per_point(&self) -> f32 {
        self.ctx.pixels_per_point()
    }

    /// Runs `ui` for one frame and readies its output for [`Framework::draw`]. A pass sees at
    /// most one press or release of a pointer button, and no Enter after text typed in it: the
    /// input after it waits for the next pass, which is asked for at once ([`next_pass`]).
    pub fn run(&mut self, window: &Window, ui: impl FnMut(&mut egui::Ui)) -> Prepared {
        let mut raw = self.state.take_egui_input(window);
        let held = std::mem::take(&mut self.held);
        (raw.events, raw.time, self.held) =
            next_pass(held, std::mem::take(&mut raw.events), raw.time);
        if !self.held.is_empty() {
            window.request_redraw();
        }
        let output = self.ctx.run_ui(raw, ui);
        self.state
            .handle_platform_output(window, output.platform_output);
        let paint_jobs = self.ctx.tessellate(output.shapes, output.pixels_per_point);
        let repaint_delay = output
            .viewport_output
            .get(&egui::ViewportId::ROOT)
            .map_or(Duration::MAX, |v| v.repaint_delay);
        Prepared {
            paint_jobs,
            textures: output.textures_delta,
            pixels_per_point: output.pixels_per_point,
            repaint_delay,
        }
    }

    /// Matches the surface to the window as it is now (a resize that lands after its Resized
    /// event was handled leaves the surface out of date; one landing during the draw is the
    /// draw's to catch). `Ok(false)` where the window is 0×0 or larger than the device's
    /// largest texture: nothing to draw.
    pub fn fit_surface(&mut self, window: &Window) -> Result<bool, String> {
        let size = window.inner_size();
        let max = self.gpu.max_texture_side() as u32;
        if size.width == 0 || size.height == 0 || size.width > max || size.height > max {
            return Ok(false);
        }
        self.gpu.resize_surface(size.width, size.height)?;
        Ok(true)
    }

    /// Draws a prepared frame (which includes the framebuffer image) to the window; with
    /// `capture`, reads it back too.
    pub fn draw(&mut self, frame: &Prepared, capture: bool) -> Result<Drawn, String> {
        self.gpu.draw(
            &frame.paint_jobs,
            &frame.textures,
            frame.pixels_per_point,
            capture,
        )
    }
}

/// An input event and when it came (egui's clock, seconds).
type Timed = (Option<f64>, egui::Event);

/// The input of the next pass, its time and what is held for the pass after it, from the
/// events held so far and the `new` ones, come at `now`. A pass ends with its first pointer
/// button change (a press or a release): egui reads a pass's input as one moment, so a press
/// and its release in the same pass are not a drag (a slider ignored the click) and two
/// clicks in one pass are one (a check box toggled once for two). Events that arrive between
/// two redraws (a click's press and release, quick clicks while a frame is drawn) come
/// together. A pass is timed when its newest event came, not when it runs: a release passed
/// on after a slow frame (over egui's 0.8 s for a click) still ends a click. A pass also ends
/// before an Enter pressed after text typed in it: the file dialog reads a pass's Enter before
/// its name field takes the pass's text (egui-file-dialog's keys go first), so a name typed
/// quickly and Entered in one pass was saved without its last characters.
fn next_pass(
    held: Vec<Timed>,
    new: Vec<egui::Event>,
    now: Option<f64>,
) -> (Vec<egui::Event>, Option<f64>, Vec<Timed>) {
    let mut events: Vec<Timed> = held;
    events.extend(new.into_iter().map(|e| (now, e)));
    let mut typed = false;
    let end = (events.iter().enumerate()).find_map(|(i, (_, e))| match e {
        egui::Event::PointerButton { .. } => Some(i + 1),
        egui::Event::Key {
            key: egui::Key::Enter,
            pressed: true,
            ..
        } if typed => Some(i),
        egui::Event::Text(_)
        | egui::Event::Paste(_)
        | egui::Event::Ime(egui::ImeEvent::Commit(_)) => {
            typed = true;
            None
        }
        _ => None,
    });
    let rest = match end {
        Some(end) => events.split_off(end),
        None => Vec::new(),
    };
    let time = events.last().map_or(now, |(came, _)| *came);
    (events.into_iter().map(|(_, e)| e).collect(), time, rest)
}

/// Why no window could be opened, in one line a user can act on (winit's own message names
/// its source file).
pub fn no_window_reason() -> String {
    let unset = |v: &str| std::env::var_os(v).is_none_or(|x| x.is_empty());
    if unset("DISPLAY") && unset("WAYLAND_DISPLAY") {
        "cannot open a window: no display (neither DISPLAY nor WAYLAND_DISPLAY is set); \
         run raylab in a desktop session, or render headless with `raylab render --out FILE.png`"
            .into()
    } else {
        "cannot open a window: the display named by DISPLAY / WAYLAND_DISPLAY does not answer; \
         check it, or render headless with `raylab render --out FILE.png`"
            .into()
    }
}

/// Keeps libwayland from printing "error: XDG_RUNTIME_DIR is invalid or not set in the
/// environment" on every start under a plain X server (Xvfb, ssh -X, a container): Mesa's
/// device-selection Vulkan layer asks libwayland for a display when the adapter is chosen,
/// and libwayland complains where there is no runtime directory to look in. With no Wayland
/// display named and no runtime directory, there is no Wayland session for the layer to
/// find, so it is turned off with Mesa's own switch (`NODEVICE_SELECT=1`), and the debug log
/// says so. Left alone where a device is being chosen (`DRI_PRIME`, `MESA_VK_DEVICE_SELECT`,
/// `NODEVICE_SELECT` set): the layer is what honours those. Called at the very top of `main`,
/// before any thread exists (setting a variable while another thread may read the
/// environment is undefined behaviour).
pub fn quiet_wayland_probe() {
    let named = |v: &str| std::env::var_os(v).is_some_and(|x| !x.is_empty());
    let wayland = named("WAYLAND_DISPLAY") || named("WAYLAND_SOCKET");
    let chosen = named("NODEVICE_SELECT") || named("MESA_VK_DEVICE_SELECT") || named("DRI_PRIME");
    let runtime_dir =
        std::env::var_os("XDG_RUNTIME_DIR").is_some_and(|d| std::path::Path::new(&d).is_absolute());
    if wayland || chosen || runtime_dir {
        return;
    }
    log::debug!(
        "no Wayland display and no XDG_RUNTIME_DIR: Mesa's device-select layer is turned off \
         (NODEVICE_SELECT=1), whose Wayland probe would make libwayland print an error"
    );
    std::env::set_var("NODEVICE_SELECT", "1");
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One pass of a window holding a check box, with `events` at egui's clock `time`; where
    /// the box is.
    fn pass(
        ctx: &egui::Context,
        on: &mut bool,
        events: Vec<egui::Event>,
        time: Option<f64>,
    ) -> egui::Rect {
        let screen = egui::Rect::from_min_size(egui::Pos2::ZERO, egui::vec2(400.0, 300.0));
        let raw = egui::RawInput {
            events,
            time,
            screen_rect: Some(screen),
            ..Default::default()
        };
        let mut rect = egui::Rect::NOTHING;
        let _ = ctx.run_ui(raw, |ui| rect = ui.checkbox(on, "box").rect);
        rect
    }

    fn button(pos: egui::Pos2, pressed: bool) -> egui::Event {
        let (button, modifiers) = (egui::PointerButton::Primary, egui::Modifiers::NONE);
        egui::Event::PointerButton {
            pos,
            button,
            pressed,
            modifiers,
        }
    }

    /// Three quick clicks on a check box that reach the window together, then passes of a
    /// second each (a slow machine's frames): each pass takes one button change, and the box
    /// toggles three times. Timed when each pass ran, the releases came 1 s after their
    /// presses, over egui's 0.8 s for a click, and the box did not toggle at all.
    #[test]
    fn quick_clicks_passed_on_over_slow_frames_each_count() {
        let ctx = egui::Context::default();
        let mut on = false;
        let at = pass(&ctx, &mut on, Vec::new(), Some(0.0)).center();
        let mut clicks = vec![egui::Event::PointerMoved(at)];
        for _ in 0..3 {
            clicks.extend([button(at, true), button(at, false)]);
        }
        let (mut new, mut held, mut toggles, mut passes) = (clicks, Vec::new(), 0, 0);
        loop {
            let now = Some(1.0 + passes as f64);
            let (events, time, rest) = next_pass(held, std::mem::take(&mut new), now);
            let buttons =
                (events.iter()).filter(|e| matches!(e, egui::Event::PointerButton { .. }));
            assert!(buttons.count() <= 1, "{events:?}");
            let before = on;
            pass(&ctx, &mut on, events, time);
            toggles += (on != before) as usize;
            passes += 1;
            held = rest;
            if held.is_empty() {
                break;
            }
        }
        assert_eq!(passes, 6, "a pass per button change");
        assert_eq!(toggles, 3);
        assert!(on);
    }

    /// A name typed and Entered in one batch, as a quick typist's keys reach a busy window,
    /// read by a UI that takes Enter before its field's text, as the file dialog does: the
    /// Enter waits for the pass after the text, and the UI reads the whole name.
    #[test]
    fn enter_after_text_in_one_batch_waits_for_the_next_pass() {
        let ctx = egui::Context::default();
        let mut name = String::new();
        // (What the UI submitted in the pass, if anything.)
        let mut pass = |events: Vec<egui::Event>| {
            let raw = egui::RawInput {
                events,
                screen_rect: Some(egui::Rect::from_min_size(
                    egui::Pos2::ZERO,
                    egui::vec2(400.0, 300.0),
                )),
                ..Default::default()
            };
            let mut submitted = None;
            let _ = ctx.run_ui(raw, |ui| {
                if ui.input(|i| i.key_pressed(egui::Key::Enter)) {
                    submitted = Some(name.clone());
                }
                ui.text_edit_singleline(&mut name).request_focus();
            });
            submitted
        };
        pass(Vec::new());
        let enter = |pressed| egui::Event::Key {
            key: egui::Key::Enter,
            physical_key: None,
            pressed,
            repeat: false,
            modifiers: egui::Modifiers::NONE,
        };
        let mut batch: Vec<egui::Event> = "chosen"
            .chars()
            .map(|c| egui::Event::Text(c.to_string()))
            .collect();
        batch.extend([enter(true), enter(false)]);
        let (events, _, rest) = next_pass(Vec::new(), batch, Some(1.0));
        assert_eq!((events.len(), rest.len()), (6, 2), "{events:?}");
        assert_eq!(pass(events), None);
        let (events, _, rest) = next_pass(rest, Vec::new(), Some(2.0));
        assert!(rest.is_empty());
        assert_eq!(pass(events).as_deref(), Some("chosen"));
        // Text an input method committed counts as typed.
        let composed = egui::Event::Ime(egui::ImeEvent::Commit("選んだ".into()));
        let (events, _, rest) = next_pass(Vec::new(), vec![composed, enter(true)], Some(3.0));
        assert_eq!((events.len(), rest.len()), (1, 1));
        // An Enter alone, or first in its batch, is passed on at once.
        let (events, _, rest) = next_pass(Vec::new(), vec![enter(true)], Some(3.0));
        assert_eq!((events.len(), rest.len()), (1, 0));
    }

    /// A pass with nothing held is timed now; one of held input only, when it came.
    #[test]
    fn a_pass_is_timed_when_its_newest_input_came() {
        let at = egui::pos2(5.0, 5.0);
        let (events, time, rest) =
            next_pass(Vec::new(), vec![egui::Event::PointerMoved(at)], Some(2.0));
        assert_eq!((events.len(), time, rest.len()), (1, Some(2.0), 0));
        let (_, time, rest) = next_pass(
            Vec::new(),
            vec![button(at, true), button(at, false)],
            Some(3.0),
        );
        assert_eq!((time, rest.len()), (Some(3.0), 1));
        let (events, time, rest) = next_pass(rest, vec![egui::Event::PointerMoved(at)], Some(7.0));
        assert_eq!((events.len(), time, rest.len()), (1, Some(3.0), 1));
        let (events, time, rest) = next_pass(rest, Vec::new(), Some(8.0));
        assert_eq!((events.len(), time, rest.len()), (1, Some(7.0), 0));
    }
}
