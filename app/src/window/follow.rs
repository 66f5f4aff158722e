//! The ray inspector's pixel, followed: a click (or the next / previous crack key) picks a
//! pixel; whenever the frame shown changes (camera, light, step, method, scene, image size,
//! the inspector's own panel narrowing the image) the inspector answers that pixel again, so
//! that what it says is what the image shows. For the pixel it also says where the exact hit
//! lies on its primitive ([`raylab::geometry::Shape::locate`]) and, where the cracks view
//! marks the pixel, which of its samples is marked and why.

use super::cracks::{self, Census, Legend, Step};
use super::inspected::{Chosen, Detail, Inspected, Marks};
use super::viewer::Viewer;
use std::borrow::Cow;

/// How the status line starts where the inspected ray has left the image ([`Viewer::follow`]).
const OFF_IMAGE: &str = "the ray inspected";

/// How the status line starts where the inspected pixel lies under the inspector's panel.
const UNDER_PANEL: &str = "the pixel inspected";

impl Viewer {
    /// Inspects pixel (`i`, `j`) of the full-size image as now set up (a left click, a
    /// script's `inspect`), saying what it found.
    pub fn inspect_pixel(&mut self, i: u32, j: u32) {
        // (A script's pixel may lie off the image: named as given, not as the first pixel past
        // its edge.)
        let (w, h) = self.full_size();
        if i >= w || j >= h {
            let off = raylab::render::SettingsError::Pixel(i, j, w, h);
            return self.set_status(format!("cannot inspect: {off}"));
        }
        self.off_image_said = None;
        self.answer((i + self.view_offset(), j), true);
    }

    /// The size of the image shown before the inspector's panel crops it
    /// ([`Viewer::view_offset`] columns each side): the view F5 and copy as command write,
    /// at the resolution shown (a fixed size too large for the window is shown smaller).
    fn view_size(&self) -> (u32, u32) {
        let (w, h) = self.full_size();
        (w + 2 * self.view_offset(), h)
    }

    /// Answers pixel `pixel` of the view for the inspector and follows it from now on.
    fn answer(&mut self, pixel: (u32, u32), announce: bool) -> bool {
        self.answer_for(pixel, announce, None)
    }

    /// Answers `pixel` of the view, followed from now on from the pixel `chosen` (itself
    /// where `None`).
    fn answer_for(&mut self, pixel: (u32, u32), announce: bool, chosen: Option<Chosen>) -> bool {
        let size = self.full_size();
        let focal = self.focal(size.0);
        let at = Inspected {
            pixel,
            size,
            focal,
            generation: self.generation,
            chosen: chosen.unwrap_or(Chosen {
                pixel,
                size: self.view_size(),
                focal,
            }),
        };
        let Some(found) = self.trace(at) else {
            return false;
        };
        self.tell(&found, announce);
        true
    }

    /// Says what the inspector found on the status line: `announce`d (a click, a script), or
    /// quietly where the status line still tells of the inspection (following is not news for
    /// the log).
    fn tell(&mut self, found: &raylab::render::inspect::Inspection, announce: bool) {
        let [i, j] = found.pixel;
        let what = match &found.hit {
            Some(h) => format!("primitive {} at t = {}", h.prim, h.t),
            None => "nothing".to_string(),
        };
        let said = format!("inspected pixel ({i}, {j}): {what}");
        if announce {
            self.set_status(said);
            self.status_follows_pixel = true;
        } else if self.status_follows_pixel {
            // The status line still tells of the inspection (or of the crack it stepped to, of
            // a frame no longer shown): it follows the pixel as the inspector does (quietly:
            // following is not news for the log).
            self.status = said;
        }
    }

    /// Traces the inspector's ray for pixel `at` of the view as now set up: the ray of its
    /// first marked sample where the count of its frame marks it (every field the inspector
    /// shows, and the ring it draws, are then that crack's), else its centre ray; and its
    /// crack. `None` (said on the status line) where it cannot be inspected.
    fn trace(&mut self, at: Inspected) -> Option<raylab::render::inspect::Inspection> {
        let camera = self.camera_with_focal(at.focal);
        // (Untinted by a selected push level, whose tint is the image's highlight, not the
        // scene's colour: the inspector answers as `raylab inspect` does.)
        let stage = self.stage_lit();
        let (x, y) = self.traced_position(at).0;
        // (Inspected in the view F5 and copy as command write, of which the image shown is a
        // crop: the same ray, named by the pixel `raylab inspect --pixel` names.)
        let offset = self.view_offset();
        let view_size = (at.size.0 + 2 * offset, at.size.1);
        let settings = self.settings(view_size, 1);
        let x_in_view = x as f64 + offset as f64;
        match raylab::render::inspect::inspect_at(&stage, &camera, &settings, x_in_view, y as f64) {
            Ok(found) => {
                self.inspection = Some(found.clone());
                self.code_inspection = (self.code.as_deref()).map(|code| {
                    let scene = stage.scene();
                    raylab::check::code::inspect_at(code, scene, &camera, at.size, (x, y))
                });
                self.inspected = Some(at);
                self.crack = self.crack_detail();
                Some(found)
            }
            Err(e) => {
                self.set_status(format!("cannot inspect: {e}"));
                None
            }
        }
    }

    /// Answers the inspected pixel again once the frame shown is of a newer view than the
    /// answer (at a new image size or focal length, the pixel whose ray has the direction of
    /// the one chosen).
    pub fn follow(&mut self) {
        let Some(at) = self.inspected else { return };
        let current = (self.shown.as_ref()).is_some_and(|s| s.generation == self.generation);
        if !self.inspector_on || at.generation == self.generation || !current {
            return;
        }
        // At a new size, the pixel of the view that looks the same way: offsets from the
        // image centre scale with the focal length (which goes with the width, but not with
        // the inspector's panel narrowing the image: that crops the view's sides, and a pixel
        // under the panel is still answered).
        let (size, view, chosen) = (self.full_size(), self.view_size(), at.chosen);
        let scale = self.focal(size.0) / chosen.focal;
        let map = |p: u32, from: u32, to: u32| {
            let offset = (p as f64 + 0.5 - from as f64 / 2.0) * scale;
            let at = (offset + to as f64 / 2.0).floor();
            (
                at.clamp(0.0, to as f64 - 1.0) as u32,
                at < 0.0 || at >= to as f64,
            )
        };
        let ((x, off_x), (y, off_y)) = (
            map(chosen.pixel.0, chosen.size.0, view.0),
            map(chosen.pixel.1, chosen.size.1, view.1),
        );
        // (Off the view, the edge pixel of the image shown: one under the panel is not seen.)
        let offset = self.view_offset();
        let x = match off_x {
            true => x.clamp(offset, offset + size.0 - 1),
            false => x,
        };
        let side = cropped_side(x, offset, size.0);
        let under_panel = side.is_some();
        let (off, said) = (off_x || off_y, [OFF_IMAGE, UNDER_PANEL]);
        if !off && !under_panel {
            self.off_image_said = None;
            if said.iter().any(|s| self.status.starts_with(s)) {
                // Back on the image: the status line follows the pixel again.
                self.status_follows_pixel = true;
            }
        }
        if !self.answer_for((x, y), false, Some(chosen)) || !(off || under_panel) {
            return;
        }
        // (Said, not silent: a zoom that loses the ray would otherwise swap in another,
        // and a ring under the panel is not seen.) (Both the view's pixels, as the
        // inspector names them; the first of the view it was chosen in.)
        // (Of the view it was chosen in, where that was another size: a window resized since
        // named a pixel of a view no longer shown.)
        let (i, j) = chosen.pixel;
        let of_view = match chosen.size == view {
            true => String::new(),
            false => format!(" of the {}x{} view then", chosen.size.0, chosen.size.1),
        };
        let notice = match off {
            true => format!(
                "{OFF_IMAGE} at pixel ({i}, {j}){of_view} lies off the image at this focal \
                 length: the inspector shows the edge pixel ({x}, {y}) until it is back"
            ),
            // (Which side: the crop is both sides' and the panel on the right, so "under the
            // panel" sent the eye right for a pixel cropped off on the left.)
            false => format!(
                "{UNDER_PANEL}, ({x}, {y}), lies off the image's {} side, which the ray \
                 inspector's panel crops: the inspector shows its ray (a wider window shows \
                 its ring)",
                side.unwrap_or_default()
            ),
        };
        // An error the status line holds stays: this notice follows on its own, from
        // whatever moved the view, and would wipe what failed before the eye read it. Said
        // once while the pixel stays off the image, on that side: again at each frame, it
        // wiped what the step, R or a field had just said. (Still on the status line, it
        // follows the edge pixel shown: a further zoom left it naming the one before.)
        let place = (chosen.pixel, off, x < offset);
        let news = self.off_image_said != Some(place);
        let still_said = said.iter().any(|s| self.status.starts_with(s));
        match (news, self.status_is_error) {
            (false, false) if still_said => self.status = notice,
            (false, _) => log::debug!("{notice}"),
            (true, true) => log::info!("{notice}"),
            (true, false) => self.set_status(notice),
        }
        self.off_image_said = Some(place);
        self.status_follows_pixel = false;
    }

    /// The side of the image (`"left"` or `"right"`) past which the inspected pixel lies in
    /// the strip the inspector's panel crops from the view, if it does: the inspector says so
    /// at its top (said on the status line alone, a crack N stepped to had no ring in sight
    /// and nothing in the panel said why).
    pub fn inspected_side_cropped(&self) -> Option<&'static str> {
        let at = self.inspected?;
        cropped_side(at.pixel.0, self.view_offset(), at.size.0)
    }

    /// N / Shift+N or the panel's buttons: the next (previous) marked pixel of the frame shown,
    /// in reading order from the inspected one, in the ray inspector.
    pub fn step_crack(&mut self, step: Step) {
        if !self.view.controls.cracks {
            self.cracks.pending = None;
            return self.set_status("no cracks to step through: show cracks is off");
        }
        // (Where the frame shown marks none, its crop beside the inspector marks none: the
        // panel is not opened to say so.)
        if let Some(none) = self.final_census().filter(|c| c.marked.is_empty()) {
            let said = no_marked_cracks(none);
            return self.say_no_cracks(said);
        }
        self.inspector_on = true;
        self.cracks.pending = Some(step);
        self.resolve_step();
        if self.cracks.pending.is_some() {
            self.set_status("finding the next crack once this frame is counted...");
        }
    }

    /// The count of the frame shown, once that frame is the last refinement of the view.
    fn final_census(&self) -> Option<&Census> {
        let c = self.cracks.census.as_ref()?;
        let last = c.generation == self.generation && c.level >= self.max_level();
        (last && c.size == self.full_size()).then_some(c)
    }

    /// Carries out a step asked for, once the frame it needs is counted and shown with the
    /// inspector's panel open (opening it narrows the image: a new frame).
    pub fn resolve_step(&mut self) {
        let Some(step) = self.cracks.pending else {
            return;
        };
        // (Show cracks or the inspector turned off meanwhile: the step is dropped.)
        if !self.view.controls.cracks || !self.inspector_on {
            self.cracks.pending = None;
            return;
        }
        if !self.inspector_shown {
            return;
        }
        let Some(census) = self.final_census() else {
            return;
        };
        // (The view's pixels: the count's, which reach under the inspector's panel.)
        let from = (self.inspected)
            .filter(|a| a.size == census.size && a.generation == census.generation)
            .map(|a| a.pixel);
        let (count, shown) = (census.marked.len(), census.size.0);
        let Some((k, m)) = census.step(from, step).map(|(k, m)| (k, *m)) else {
            let said = no_marked_cracks(census);
            return self.say_no_cracks(said);
        };
        self.cracks.pending = None;
        let (i, j) = m.pixel;
        // (Its ring is not seen there: said, as for a click; last, after what the crack is,
        // which the status line cut off behind it.)
        let under = match cropped_side(i, self.view_offset(), shown) {
            None => "",
            Some(_) => " (under the inspector's panel: a wider window shows its ring)",
        };
        if self.answer((i, j), false) {
            let what = self.crack.as_ref().map(Detail::summary).unwrap_or_default();
            let n = k + 1;
            self.set_status(format!(
                "crack {n} of {count}: pixel ({i}, {j}): {what}{under}"
            ));
            self.status_follows_pixel = true;
        }
    }

    /// Says that a step found no crack in the frame shown (`said`), until the view changes;
    /// the step is done.
    fn say_no_cracks(&mut self, said: String) {
        self.cracks.pending = None;
        self.set_status(said);
        self.status_of_frame = true;
    }

    /// A count finished: the panel's counts, the inspector's crack and a waiting step follow.
    pub fn cracks_counted(&mut self) {
        if !self.cracks.take() {
            return;
        }
        let counted = self.inspected.filter(|&at| self.census_of(at).is_some());
        match counted {
            // The count may mark the pixel: every field is then its marked sample's.
            Some(at) if at.generation == self.generation => {
                if let Some(found) = self.trace(at) {
                    self.tell(&found, false);
                }
            }
            Some(_) => self.crack = self.crack_detail(),
            None => {}
        }
        self.resolve_step();
    }

    /// The count of the frame pixel `at` was answered for (its generation and size).
    fn census_of(&self, at: Inspected) -> Option<&Census> {
        (self.cracks.census.as_ref()).filter(|c| c.generation == at.generation && c.size == at.size)
    }

    /// The count matching the frame shown (its generation and refinement level).
    fn shown_census(&self) -> Option<&Census> {
        let (c, s) = (self.cracks.census.as_ref()?, self.shown.as_ref()?);
        (c.generation == s.generation && c.level == s.level).then_some(c)
    }

    /// What the panel shows beside the "show cracks" box, while it is ticked.
    pub fn crack_legend(&self) -> Option<Legend> {
        if !self.view.controls.cracks {
            return None;
        }
        let census = self.shown_census();
        let line = match census {
            Some(c) => Ok(c.summary()),
            None if self.cracks.is_counting() => Err("counting this frame's cracks..."),
            None => Err("counted once the view settles"),
        };
        Some(Legend {
            code: self.code.is_some() && self.view.yours,
            line,
            marked: census.map(|c| c.marked.len()),
        })
    }

    /// Whether the frame shown has been counted (or needs no count) and no step waits.
    pub fn cracks_settled(&self) -> bool {
        let counted = !self.view.controls.cracks || self.shown_census().is_some();
        counted && self.cracks.pending.is_none()
    }

    /// The count of the frame shown, for the scripted run's final line.
    pub fn counted(&self) -> Option<&Census> {
        self.shown_census().filter(|_| self.view.controls.cracks)
    }

    /// The inspected pixel's crack: its first marked sample where the frame shown marks it
    /// (else its centre), graded, and where the exact hit lies.
    fn crack_detail(&self) -> Option<Detail> {
        let at = self.inspected?;
        let (pos, marked) = self.traced_position(at);
        let code = self.code.as_deref().filter(|_| self.view.yours);
        let shapes = match code {
            Some(_) => cracks::all_shapes(&self.stage),
            None => Cow::Borrowed(&[][..]),
        };
        let camera = self.camera_with_focal(at.focal);
        let trace = (&self.stage, &camera, self.view.controls.method, code);
        let mut detail = Detail::of_ray(trace, &shapes, at.size, pos, Some(marked));
        // (The view's position, as the inspector's own rows name it.)
        detail.at.0 += self.view_offset() as f32;
        detail.marks = match (self.view.controls.cracks, self.census_of(at).is_some()) {
            (false, _) => Marks::Off,
            (true, false) => Marks::Counting,
            (true, true) => Marks::Counted,
        };
        Some(detail)
    }

    /// The position on the image shown that the inspector traces for pixel `at`: its first
    /// marked sample where the count of its frame marks it, else its centre (left of the
    /// image, or right of it, where the pixel lies under the inspector's panel); and whether
    /// it is marked.
    fn traced_position(&self, at: Inspected) -> ((f32, f32), bool) {
        let census = self.census_of(at);
        let marked = census.and_then(|c| c.find(at.pixel));
        let n = census.map_or(1, |c| c.spp);
        let (x, y) = match marked {
            Some((_, m)) => cracks::sample_position(at.pixel, m.sample, n),
            None => (at.pixel.0 as f32 + 0.5, at.pixel.1 as f32 + 0.5),
        };
        ((x - self.view_offset() as f32, y), marked.is_some())
    }
}

/// The side (`"left"` or `"right"`) of the image shown, `width` columns from column `offset`
/// of the view, past which view column `x` lies, in the strip the inspector's panel crops; `None`
/// where `x` is shown.
fn cropped_side(x: u32, offset: u32, width: u32) -> Option<&'static str> {
    match (offset..offset + width).contains(&x) {
        true => None,
        false if x < offset => Some("left"),
        false => Some("right"),
    }
}

/// What N says of a frame whose count marks no crack. (A method's wrong primitives are
/// counted, not marked: not every sample is then right.)
fn no_marked_cracks(census: &Census) -> String {
    let who = &census.who;
    match census.counts.wrong {
        0 => {
            format!("no cracks in this frame: {who} gives every sample the exact answer (or a tie)")
        }
        n => format!(
            "no marked cracks in this frame: {who} neither leaks nor hits falsely; {} another \
             primitive than the exact one (counted, not marked)",
            raylab::words::count(n as usize, "sample names", "samples name")
        ),
    }
}
