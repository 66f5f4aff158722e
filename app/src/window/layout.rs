//! The window's layout: the side panel (its controls: panel.rs) at the width it keeps, the
//! image fitted into the area beside it, the ray inspector's panel, the status line and the
//! overlays.

use super::panel::{side_panel, PanelActions, PanelInfo};
use super::viewer::Viewer;

/// Width of the side panel at start, in points.
pub const PANEL_WIDTH: f32 = 300.0;

/// The least width (points) the ray inspector's panel leaves the image, where the room beside
/// the side panel is twice that: else half of it.
pub const MIN_IMAGE_WIDTH: f32 = 200.0;

/// The image's width (points) under which the side panel's top says that P hides the panel
/// (the status line, under the image, is then too narrow to read).
const NARROW_IMAGE: f32 = 100.0;

/// The side panel's width once its scroll bar is gone. egui keeps a panel at the width it was
/// last drawn at: what it was given or, where its rows need more, what they need. The scroll
/// bar a window too short for the panel shows takes its room (10 points) beside the rows, so
/// the panel grew by it, and kept that width once the window was tall again. So the width kept
/// before the bar came is given back once the bar's room is gone and the panel is taller than
/// when the bar came (the window grew), unless the panel's edge was dragged meanwhile (then the
/// width dragged to stays). Not when the bar went because the rows got shorter: rows that
/// change with each frame (the cracks' counts, at the edge of the panel's height) would then
/// take the bar away and bring it back frame after frame, each time changing the image's width,
/// a new view to render and count, without end.
struct KeptWidth {
    id: egui::Id,
    /// The panel's edge is being dragged (or was let go) this frame.
    dragged: bool,
    /// The width egui kept from the last frame (the width given to a new panel where none).
    kept: f32,
}

impl KeptWidth {
    /// Before the panel `id` (`width` points wide at first) is shown.
    fn before(ui: &egui::Ui, id: egui::Id, width: f32) -> Self {
        let edge = ui.ctx().read_response(id.with("__resize"));
        let dragged = edge.is_some_and(|r| r.dragged() || r.drag_stopped());
        let kept = egui::containers::panel::PanelState::load(ui.ctx(), id);
        let kept = kept.map_or(width, |k| k.size().x);
        Self { id, dragged, kept }
    }

    /// After the panel was shown in `drawn`, its scroll bar taking `bar` points of it and its
    /// rows shown in `visible` points of height.
    fn after(self, ui: &egui::Ui, drawn: egui::Rect, bar: f32, visible: f32) {
        let before_bar = self.id.with("width before the scroll bar");
        let ctx = ui.ctx();
        // The width before the bar came, and the least height the rows were shown in since.
        let mut width: Option<(f32, f32)> = ctx.data(|d| d.get_temp(before_bar)).flatten();
        if self.dragged {
            width = None;
        } else if bar > 0.01 {
            let (w, low) = width.unwrap_or((self.kept, visible));
            width = Some((w, low.min(visible)));
        } else if let Some((w, _)) = width.filter(|&(_, low)| visible > low + 0.5) {
            width = None;
            let mut outer_rect = drawn;
            outer_rect.set_width(w);
            let state = egui::containers::panel::PanelState { outer_rect };
            ctx.data_mut(|d| d.insert_persisted(self.id, state));
        }
        ctx.data_mut(|d| d.insert_temp(before_bar, width));
    }
}

/// What one layout pass found.
pub struct Layout {
    pub actions: PanelActions,
    /// The area beside the panel, in physical pixels.
    pub image_area: (u32, u32),
    /// The width of the area beside the side panel (physical pixels): the image area's and
    /// the inspector's panel's.
    pub beside_width: u32,
    /// Where the image was drawn (points), if there is one.
    pub image_rect: Option<egui::Rect>,
    /// Where the error banner was drawn over the image (points): a click there is the
    /// banner's, not the image's.
    pub banner_rect: Option<egui::Rect>,
}

/// The window's whole UI: the side panel (editing the viewer's settings and camera), the
/// framebuffer `texture` (`buffer_size` pixels) fitted into the area beside it with its
/// aspect ratio, and the shortcuts overlay.
pub fn layout(
    ui: &mut egui::Ui,
    viewer: &mut Viewer,
    texture: egui::TextureId,
    buffer_size: (u32, u32),
) -> Layout {
    let ppp = ui.ctx().pixels_per_point();
    let shown = viewer
        .shown
        .as_ref()
        .map(|s| (s.size.0, s.size.1, s.level, s.spp, s.stats));
    let progress = viewer.progress();
    let has_image = shown.is_some();
    if let Some(picked) = viewer.files.update(ui.ctx()) {
        viewer.apply_picked(picked);
    }
    let full_size = viewer.full_size();
    let focal = (viewer.focal(full_size.0), viewer.focal_width());
    // (The overlay is projected as the image on screen was rendered: its size and focal
    // length, the camera now.)
    let overlay = (viewer.shown.as_ref()).map(|s| (s.size, viewer.camera_with_focal(s.focal)));
    let samples_shown = viewer.spp_shown();
    let legend = viewer.crack_legend();
    let obj_frame = viewer.obj_frame();
    let cropped_side = viewer.inspected_side_cropped();
    let Viewer {
        stage,
        view,
        controller,
        obj_path,
        status,
        status_is_error,
        banner,
        show_all_warnings,
        loading,
        image_area,
        show_help,
        panel_hidden,
        selected_level,
        inspector_on,
        inspection,
        inspected,
        code,
        code_inspection,
        copy_request,
        files,
        crack,
        cracks,
        inspector_shown,
        inspector_over,
        status_whole,
        figures_whole,
        ..
    } = viewer;
    if let Some(text) = copy_request.take() {
        ui.ctx().copy_text(text);
    }
    let scene = stage.scene();
    // (Its edge dragged no further than leaves the image MIN_IMAGE_WIDTH; its rows still
    // widen it to what they take.)
    let most = ui.available_rect_before_wrap().width() - MIN_IMAGE_WIDTH;
    let info = PanelInfo {
        widest: most,
        scene_name: &scene.name,
        primitives: scene.len(),
        warnings: &scene.warnings,
        full_size,
        focal,
        loading: *loading,
        levels: &scene.levels,
        selected_level: *selected_level,
        code_name: code.as_deref().map(|c| c.name()),
        cracks: legend,
        samples_shown,
        obj_frame,
    };
    let mut layout = Layout {
        actions: PanelActions::default(),
        image_area: *image_area,
        beside_width: image_area.0,
        image_rect: None,
        banner_rect: None,
    };
    let controls = egui::Id::new("controls");
    let kept = KeptWidth::before(ui, controls, PANEL_WIDTH);
    let panel = (!*panel_hidden).then(|| egui::Panel::left(controls));
    let image_width_before = layout.beside_width as f32 / ppp;
    // (While a field is typed into, the panel keeps its width: a number box grows with the
    // text typed into it, and the panel grew with it, every control after it moved and the
    // image narrowed, a focal length typed meanwhile taken at the narrower width.)
    let editing = ui.memory(|m| m.focused().is_some());
    let drawn = panel.map(|panel| {
        let panel = panel
            .resizable(true)
            .default_size(PANEL_WIDTH)
            .max_size(most.max(PANEL_WIDTH));
        let panel = match editing {
            true => panel.exact_size(kept.kept),
            false => panel,
        };
        panel.show(ui, |ui| {
            // (The menu bar stays in view however far the panel is scrolled.)
            egui::MenuBar::new().ui(ui, |ui| {
                files.menu(ui);
                if ui.button("Screenshot (F12)").clicked() {
                    layout.actions.screenshot = true;
                }
                if ui.button("Shortcuts (H or F1)").clicked() {
                    *show_help = !*show_help;
                }
            });
            if image_width_before < NARROW_IMAGE {
                let points =
                    raylab::words::count(image_width_before.round() as usize, "point", "points");
                let note = format!("the image has {points} beside this panel: P hides the panel");
                let note = egui::RichText::new(note).color(egui::Color32::YELLOW);
                // (Wrapped in the width in view: at 360 points the panel's last words, "hides
                // the panel", were past its edge.)
                ui.scope(|ui| {
                    ui.set_max_width(super::panel::width_in_view(ui));
                    ui.add(egui::Label::new(note).wrap());
                });
            }
            let inspector = (&mut *inspector_on, inspection.as_ref());
            let screenshot = layout.actions.screenshot;
            layout.actions = side_panel(ui, view, controller, obj_path, &info, inspector);
            layout.actions.screenshot |= screenshot;
        })
    });
    if let Some(drawn) = drawn {
        let (bar, visible) = (layout.actions.bar_room, layout.actions.fit.1);
        kept.after(ui, drawn.response.rect, bar, visible);
        layout.actions.width = drawn.response.rect.width();
    }
    // The status line under the image and the inspector's panel both.
    egui::Panel::bottom("status").show(ui, |ui| {
        let status = (status.as_str(), *status_is_error);
        let threads = rayon::current_num_threads();
        let said = super::notices::status_line(ui, status, (shown, progress), full_size, threads);
        (*status_whole, *figures_whole) = (said.whole, said.figures_whole);
        layout.actions.status_copied = said.copied;
    });
    let beside = ui.available_rect_before_wrap().width();
    layout.beside_width = ((beside * ppp).round() as u32).max(1);
    // The inspected ray's fields beside the image, while there are some or a crack is being
    // found (the side panel keeps its sections in view).
    *inspector_shown = *inspector_on && (inspection.is_some() || cracks.pending.is_some());
    if *inspector_shown {
        // (A width of its own that its rows fit in: a panel that grew with what it shows would
        // narrow the image, a new frame, each time.)
        // (At most what leaves the image MIN_IMAGE_WIDTH, or half the room where that is less.)
        let most = beside - MIN_IMAGE_WIDTH.min(beside / 2.0);
        let placement = super::inspector::panel(ui, super::inspector::WIDTH, most, |ui| {
            // (Both ways: a row wider than the panel scrolls rather than widening it.)
            // (A scroll state per pixel chosen: a new pixel's rows start at the top, where they
            // say what the crack is; the pixel followed through new views keeps its place.)
            let chosen = inspected.as_ref().map(|i| (i.chosen.pixel, i.chosen.size));
            let rows = egui::ScrollArea::both().id_salt(("inspector rows", chosen));
            rows.show(ui, |ui| {
                if let Some(side) = cropped_side {
                    let said = format!(
                        "This pixel lies past the image's {side} edge, in the strip of the view \
                         this panel crops: its ray is below; a wider window shows its ring."
                    );
                    ui.add(
                        egui::Label::new(egui::RichText::new(said).color(egui::Color32::YELLOW))
                            .wrap(),
                    );
                    ui.separator();
                }
                if let Some(detail) = crack.as_ref() {
                    super::inspector::crack_fields(ui, detail);
                    ui.separator();
                }
                match inspection.as_ref() {
                    Some(ins) => super::inspector::fields(ui, ins),
                    None => {
                        ui.strong("Ray inspector");
                        ui.add(
                            egui::Label::new(
                                "finding the next crack once this frame is counted...",
                            )
                            .wrap(),
                        );
                    }
                }
                if let Some(yours) = code_inspection.as_ref() {
                    ui.separator();
                    super::inspector::code_fields(ui, yours);
                }
            });
        });
        *inspector_over = placement == super::inspector::Placement::Over;
    } else {
        *inspector_over = false;
    }
    egui::CentralPanel::no_frame().show(ui, |ui| {
        let area = ui.max_rect();
        layout.image_area = (
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
            // On whole physical pixels, a texel a pixel where the render fills the area: from
            // the panel's edge, at a fraction of a point, the texture was resampled, every
            // edge blurred against the headless render of the same view.
            let texels = egui::vec2(bw as f32, bh as f32) / ppp;
            let size = match ((size - texels) * ppp).abs().max_elem() < 1.0 {
                true => texels,
                false => size,
            };
            let min = ((area.center() - size / 2.0) * ppp).round() / ppp;
            let rect = egui::Rect::from_min_size(min, size);
            ui.painter().image(
                texture,
                rect,
                egui::Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(1.0, 1.0)),
                egui::Color32::WHITE,
            );
            layout.image_rect = Some(rect);
            // (Only while the inspector is on: I hides its ray with its panel.)
            let ins = inspection.as_ref().filter(|_| *inspector_on);
            if let (Some(ins), Some(((w, h), camera))) = (ins, overlay) {
                let projection = camera.ray_projection(w, h);
                let eye = camera.position().to_array();
                let hides = |p| super::inspector::hides(stage.accel(), ins.method, eye, p);
                super::inspector::draw(ui.painter(), rect, (w, h), &projection, ins, hides);
            }
        }
        if let Some(text) = banner.as_deref() {
            let (rect, clicked) = super::notices::banner(ui, area, text);
            layout.banner_rect = Some(rect);
            if clicked {
                *banner = None;
            }
        }
    });
    if layout.actions.show_all_warnings {
        *show_all_warnings = true;
    }
    super::notices::all_warnings(ui.ctx(), &scene.warnings, show_all_warnings);
    super::shortcuts::help_window(ui.ctx(), show_help);
    layout
}
