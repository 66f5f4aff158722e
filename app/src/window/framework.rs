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
    /// Input that came after a pass's one pointer button change, for the passes after it
    /// ([`one_button_change`]).
    held: Vec<egui::Event>,
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
    /// most one press or release of a pointer button: the input after it waits for the next
    /// pass, which is asked for at once ([`one_button_change`]).
    pub fn run(&mut self, window: &Window, ui: impl FnMut(&mut egui::Ui)) -> Prepared {
        let mut raw = self.state.take_egui_input(window);
        let mut events = std::mem::take(&mut self.held);
        events.append(&mut raw.events);
        self.held = one_button_change(&mut events);
        raw.events = events;
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

/// Cuts `events` after its first pointer button change (a press or a release), returning the
/// rest. egui reads a pass's input as one moment: a press and its release in the same pass
/// are not a drag, so a slider ignored the click, and two clicks in one pass are one click
/// (a check box toggled once for two). Events that arrive between two redraws (a click's
/// press and release, quick clicks while a frame is drawn) came to egui together.
fn one_button_change(events: &mut Vec<egui::Event>) -> Vec<egui::Event> {
    let mut buttons =
        (events.iter().enumerate()).filter(|(_, e)| matches!(e, egui::Event::PointerButton { .. }));
    match buttons.nth(1) {
        Some((second, _)) => events.split_off(second),
        None => Vec::new(),
    }
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
