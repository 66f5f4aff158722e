//! The pointer over the image: whether it is the image's (not an egui window's drawn over
//! it), and the image pixel a left click inspects.

use super::App;

impl App {
    /// Whether the mouse pointer is over the image: there the camera takes the wheel and the
    /// right button, even though egui reports the pointer as its own (the image is drawn in
    /// egui's central panel). Not where an egui window, menu or dialog, or the error banner,
    /// is drawn over it: a click there is theirs.
    pub(super) fn pointer_over_image(&self) -> bool {
        let (Some((x, y)), Some(rect), Some(fw)) = (self.cursor, self.image_rect, &self.framework)
        else {
            return false;
        };
        let at = pixel_centre((x, y), fw.pixels_per_point());
        let on_top = fw.window_at(at) || self.banner_rect.is_some_and(|b| b.contains(at));
        rect.contains(at) && !on_top
    }

    /// Whether the wheel is the camera's: over the image, not over a panel, window or dialog.
    /// (By the pointer's place: egui's own answer is its last frame's, so a wheel turned as
    /// the pointer entered the window over a panel zoomed the camera.) Where the place is not
    /// known, egui decides.
    pub(super) fn wheel_turns_camera(&self, egui_consumed: bool, egui_pointer: bool) -> bool {
        match self.cursor {
            Some(_) => self.pointer_over_image(),
            None => !egui_consumed && !egui_pointer,
        }
    }

    /// Whether a mouse button pressed now is the image's (inspecting, looking, orbiting): by
    /// the pointer's place, as the wheel. (egui's answer is its last frame's: a click that
    /// came with the move onto the inspector's fold arrow, drawn over the image, folded it
    /// and inspected the pixel under the arrow.)
    pub(super) fn button_is_cameras(&self, egui_pointer: bool) -> bool {
        match self.cursor {
            Some(_) => self.pointer_over_image(),
            None => !egui_pointer,
        }
    }

    /// A left press over the image and its release within a few pixels (not an orbit drag)
    /// inspect the pixel under the pointer, when the inspector is on (else say it is off).
    pub(super) fn left_click(&mut self, pressed: bool, on_image: bool) {
        if pressed {
            self.press_at = self.cursor.filter(|_| on_image);
            return;
        }
        let (Some((x0, y0)), Some((x, y))) = (self.press_at.take(), self.cursor) else {
            return;
        };
        if (x - x0).abs() > 3.0 || (y - y0).abs() > 3.0 {
            // (A drag that moved nothing said nothing: in fly mode the left button only clicks.)
            if self.viewer.controller.mode == raylab::controller::Mode::Fly {
                let how = "a left drag turns the view in orbit mode (Tab); in fly mode a right \
                           drag looks around";
                self.viewer.set_status(how);
                self.request_redraw();
            }
            return;
        }
        self.click_on_image((x, y));
        self.request_redraw();
    }

    /// Inspects the pixel under window position (`x`, `y`) (a click's), or, while the frame
    /// drawn is the last one squeezed into a new image area (I just opened the inspector's
    /// panel), keeps the click until a frame of the area's shape is drawn: mapped through the
    /// squeezed frame, it inspected a pixel ~125 px from the one under the pointer.
    fn click_on_image(&mut self, (x, y): (f64, f64)) {
        if !self.viewer.inspector_on {
            // (A click that inspects nothing says why.)
            let off = "the ray inspector is off: I or its check box turns it on";
            self.viewer.set_status(off);
            return;
        }
        // (Also where I came with the click, before the frame that lays the panel out: the
        // click had then been taken in the old layout, and depended on the events' timing.)
        let relaying = self.viewer.inspector_on != self.inspector_laid_out;
        if relaying || !self.viewer.shown_fits_layout() {
            log::debug!("click at ({x}, {y}) kept until a frame of the image area's shape");
            self.click_waiting = Some((x, y));
            return;
        }
        self.click_waiting = None;
        if let Some((i, j)) = self.image_pixel(x, y) {
            self.viewer.inspect_pixel(i, j);
        }
    }

    /// A kept click ([`App::click_on_image`]) once the frame drawn is of the image area's full
    /// size (a preview's shape may differ by a pixel).
    pub(super) fn take_waiting_click(&mut self) {
        if let Some(at) = self.click_waiting.filter(|_| self.viewer.shown_full_size()) {
            self.click_on_image(at);
            self.request_redraw();
        }
    }

    /// The pixel of the full-size image under window position (`x`, `y`) (physical pixels):
    /// the one whose square on screen holds the centre of the screen pixel the pointer is on,
    /// which is where the GPU samples the image it draws there.
    fn image_pixel(&self, x: f64, y: f64) -> Option<(u32, u32)> {
        let (rect, fw) = (self.image_rect?, self.framework.as_ref()?);
        let at = pixel_centre((x, y), fw.pixels_per_point());
        let (w, h) = self.viewer.full_size();
        let u = (at.x - rect.min.x) as f64 / rect.width() as f64;
        let v = (at.y - rect.min.y) as f64 / rect.height() as f64;
        let inside = (0.0..1.0).contains(&u) && (0.0..1.0).contains(&v);
        inside.then_some(((u * w as f64) as u32, (v * h as f64) as u32))
    }
}

/// The centre of the window pixel at `(x, y)` (physical pixels, as winit reports the pointer),
/// in egui points: the point the GPU samples for that pixel, so what is drawn there.
fn pixel_centre((x, y): (f64, f64), pixels_per_point: f32) -> egui::Pos2 {
    let centre = |c: f64| ((c.floor() + 0.5) / pixels_per_point as f64) as f32;
    egui::pos2(centre(x), centre(y))
}
