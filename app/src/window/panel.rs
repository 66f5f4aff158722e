//! The egui side panel and the image area beside it (the shortcuts overlay: shortcuts.rs).

use super::fields::{Said, Typing};
use super::viewer::ViewSettings;
use super::viewer::Viewer;
use raylab::controller::{CameraController, Mode, FOCAL_RATIO_RANGE};
use raylab::render::inspect::Inspection;
use raylab::render::settings::{Control, Kind};
use raylab::render::{RenderSettings, CONTROLS};
use raylab::scene::file::Level;
use raylab::scene::ObjFrame;

/// Preset render resolutions offered besides "a scale of the window".
pub const PRESETS: [(u32, u32); 4] = [(320, 240), (640, 480), (1280, 720), (1920, 1080)];

/// What the panel shows but does not edit.
pub struct PanelInfo<'a> {
    pub scene_name: &'a str,
    pub primitives: usize,
    pub warnings: &'a [String],
    pub full_size: (u32, u32),
    /// The focal length (pixels of the full render), and the width it is a fraction of
    /// ([`super::viewer::Viewer::focal_width`]).
    pub focal: (f64, u32),
    pub loading: bool,
    /// A `.scene` file's push levels, and the one selected.
    pub levels: &'a [Level],
    pub selected_level: Option<usize>,
    /// The name of linked code that is not raylab's, offered in the method selector.
    pub code_name: Option<&'a str>,
    /// The cracks view's legend and counts, while it is on.
    pub cracks: Option<super::cracks::Legend>,
    /// The supersampling (n per axis) the window renders at its size: the slider's, or less
    /// ([`super::bounds::MAX_SHOWN_SAMPLES`]).
    pub samples_shown: u32,
    /// How an OBJ file is read (`--obj-frame`).
    pub obj_frame: ObjFrame,
}

/// What the user asked for with buttons.
#[derive(Default)]
pub struct PanelActions {
    pub reset_camera: bool,
    pub screenshot: bool,
    pub load: Option<String>,
    pub save_view: bool,
    pub copy_command: bool,
    /// A push level clicked in the scene tree (`Some(None)`: the selection cleared).
    pub select: Option<Option<usize>>,
    /// The next or previous crack button.
    pub crack: Option<super::cracks::Step>,
    /// The button that lists every scene warning.
    pub show_all_warnings: bool,
    /// How OBJ files are to be read from now on (and the open one again).
    pub obj_frame: Option<ObjFrame>,
    /// The panel's content height and the height it is shown in (points): it fits when the
    /// first is not larger.
    pub fit: (f32, f32),
    /// The room the panel's scroll bar takes beside its rows (points; 0 where there is none).
    pub bar_room: f32,
    /// The panel's width (points).
    pub width: f32,
    /// What the status line says of a number field whose edit ended ([`Typing`]).
    pub typed: Option<Said>,
}

impl PanelActions {
    /// Keeps what a field said as its edit ended.
    fn note(&mut self, said: Option<Said>) {
        self.typed = said.or(self.typed.take());
    }
}

/// The side panel. Edits `view` and `camera` in place.
pub fn side_panel(
    ui: &mut egui::Ui,
    view: &mut ViewSettings,
    camera: &mut CameraController,
    obj_path: &mut String,
    info: &PanelInfo,
    inspector: (&mut bool, Option<&Inspection>),
) -> PanelActions {
    let mut actions = PanelActions::default();
    let typing = Typing::default();
    // A scroll bar drawn all the time (egui's default floats and shows only under the
    // pointer), its room kept whether the rows overflow or not: a bar that came with the
    // overflow (show cracks' rows on a 1280x800 screen) widened the panel and narrowed the
    // image, so the focal length and the view F5 saves changed with a display option. (egui's
    // solid bar also takes its room in a few frames as it fades in: each a new image size.)
    ui.style_mut().spacing.scroll = solid_bar();
    // (In a child of its own, whose rectangle is the scroll area's with the bar's room.)
    let mut rows = ui.new_child(egui::UiBuilder::new());
    let always = egui::scroll_area::ScrollBarVisibility::AlwaysVisible;
    let area = egui::ScrollArea::vertical().scroll_bar_visibility(always);
    let scrolled = area.show(&mut rows, |ui| {
        ui.heading("raylab");
        ui.label(format!(
            "{}: {}",
            info.scene_name,
            raylab::words::primitives(info.primitives)
        ));
        super::notices::warnings(ui, info.warnings, &mut actions.show_all_warnings);

        if !info.levels.is_empty() {
            ui.separator();
            actions.select = super::scene_tree::scene_tree(
                ui,
                info.levels,
                info.selected_level,
                info.scene_name,
            );
        }

        for control in CONTROLS.iter().filter(|c| c.heading.is_some()) {
            ui.separator();
            let said = control_widget(ui, control, &mut view.controls, None, &typing);
            actions.note(said);
        }

        ui.separator();
        ui.strong("Camera");
        let (mut focal, width) = (info.focal.0, info.focal.1.max(1));
        let range = (FOCAL_RATIO_RANGE.0 * width as f64)..=(FOCAL_RATIO_RANGE.1 * width as f64);
        // (The view's, as F5 saves it; the image shown beside the inspector's panel is a crop.)
        let fov = raylab::camera::fov_of_focal(focal, width as f64);
        let shown = raylab::camera::fov_of_focal(focal, info.full_size.0.max(1) as f64);
        // The slider takes the row's room (a thousandfold range in egui's 100 points moved
        // 7% a point); its box drags by 0.1% a point, for the fine steps.
        let fine = 0.001 * focal;
        let slider = (typing.slider(&mut focal, range))
            .logarithmic(true)
            .text("focal (px)")
            .custom_formatter(|v, _| format!("{v:.1}"))
            .drag_value_speed(fine);
        let beside = egui::WidgetText::from("00000.0 focal (px)");
        let beside = beside.into_galley(ui, None, f32::INFINITY, egui::TextStyle::Body);
        let spacing = ui.spacing().clone();
        let box_margins = 2.0 * spacing.button_padding.x + 2.0 * spacing.item_spacing.x;
        // (Less a little: a row wider than the panel would widen it, frame after frame.)
        let room = ui.available_width() - beside.size().x - box_margins - 10.0;
        ui.spacing_mut().slider_width = room.max(spacing.slider_width);
        let response =
            (ui.add(slider)).on_hover_text("drag the number for fine steps; click it to type one");
        actions.note(typing.said_as_edit_ends(ui, &response, "focal length", focal));
        let changed = response.changed();
        ui.spacing_mut().slider_width = spacing.slider_width;
        if changed {
            camera.set_focal(focal, width);
        }
        let cropped = match info.full_size.0 < width {
            true => format!(" ({:.1}° shown)", shown.to_degrees()),
            false => String::new(),
        };
        ui.label(format!("horizontal field of view {:.1}°{cropped}", fov.to_degrees()))
            .on_hover_text("the view's, as F5 and C write it; beside the inspector's panel the image shows its middle");
        ui.horizontal(|ui| {
            ui.label("position");
            let position = [
                &mut camera.position.x,
                &mut camera.position.y,
                &mut camera.position.z,
            ];
            for (c, name) in position
                .into_iter()
                .zip(["camera x", "camera y", "camera z"])
            {
                let response = ui.add(coordinate(&mut *c, 0.01 * camera.scene_size, &typing));
                actions.note(typing.said_as_edit_ends(ui, &response, name, *c));
            }
        });
        if let Some(from) = super::values::rays_leave_from(camera.position.to_array()) {
            // (To the fields' decimals: f32's shortest digits would read as the field's.)
            let [x, y, z] = from.map(f64::from);
            ui.small(format!(
                "rays leave from {x:.3} {y:.3} {z:.3}: f32 holds no nearer point"
            ));
        }
        ui.horizontal(|ui| {
            let mut yaw = camera.yaw.to_degrees();
            let mut pitch = camera.pitch.to_degrees();
            ui.label("yaw");
            let field = egui::DragValue::new(&mut yaw).speed(0.5).suffix("°");
            let everywhere = f64::NEG_INFINITY..=f64::INFINITY;
            let response = ui.add(typing.drag(field.max_decimals(1), everywhere));
            if response.changed() {
                // (As the field shows a yaw: 720 typed is said to be taken as 0.)
                camera.yaw = raylab::math::degrees_within_half_turn(yaw).to_radians();
                // (Said as F5 writes it.)
                yaw = super::values::degrees(camera.yaw);
            }
            actions.note(typing.said_as_edit_ends(ui, &response, "yaw", yaw));
            ui.label("pitch");
            let field = egui::DragValue::new(&mut pitch).speed(0.5).suffix("°");
            let response = ui.add(typing.drag(field.max_decimals(1), -89.0..=89.0));
            actions.note(typing.said_as_edit_ends(ui, &response, "pitch", pitch));
            if response.changed() {
                camera.pitch = pitch.to_radians();
            }
        });
        ui.horizontal(|ui| {
            let (now, other) = match camera.mode {
                Mode::Fly => ("fly", "orbit"),
                Mode::Orbit => ("orbit", "fly"),
            };
            ui.label(format!("mode: {now}"));
            if ui.button(format!("{other} (Tab)")).clicked() {
                camera.toggle_mode();
            }
            let field = egui::DragValue::new(&mut camera.speed)
                .speed(0.02)
                .prefix("speed ×")
                .max_decimals(2);
            let range = CameraController::SPEED_RANGE.0..=CameraController::SPEED_RANGE.1;
            let response = (ui.add(typing.drag(field, range)))
                .on_hover_text("moving speed (+ / -); Shift 4x, Ctrl 1/4");
            actions.note(typing.said_as_edit_ends(ui, &response, "speed", camera.speed));
        });
        ui.horizontal(|ui| {
            if ui.button("Reset camera (R)").clicked() {
                actions.reset_camera = true;
            }
            if ui
                .button("Save view (F5)")
                .on_hover_text(
                    "camera, light and settings to a file `raylab render --view` renders",
                )
                .clicked()
            {
                actions.save_view = true;
            }
            if ui
                .button("Copy as command (C)")
                .on_hover_text(
                    "the `raylab render` command that renders this view, to the clipboard",
                )
                .clicked()
            {
                actions.copy_command = true;
            }
        });
        ui.collapsing("world_from_camera (4x4)", |ui| {
            let m = camera.stack().matrix();
            egui::Grid::new("matrix").striped(true).show(ui, |ui| {
                for row in 0..4 {
                    for col in 0..4 {
                        ui.monospace(format!("{:+.3}", m.col(col)[row]));
                    }
                    ui.end_row();
                }
            });
        });

        ui.separator();
        super::inspector::switch(ui, inspector.0, inspector.1.is_some());

        ui.separator();
        ui.strong("Resolution");
        let label = match view.resolution {
            super::Resolution::WindowScale(_) => "scale of the window".to_string(),
            super::Resolution::Fixed(w, h) => format!("{w}x{h}"),
        };
        egui::ComboBox::from_id_salt("resolution")
            .selected_text(label)
            .show_ui(ui, |ui| {
                let scale = match view.resolution {
                    super::Resolution::WindowScale(s) => s,
                    _ => 1.0,
                };
                ui.selectable_value(
                    &mut view.resolution,
                    super::Resolution::WindowScale(scale),
                    "scale of the window",
                );
                for (w, h) in PRESETS {
                    ui.selectable_value(
                        &mut view.resolution,
                        super::Resolution::Fixed(w, h),
                        format!("{w}x{h}"),
                    );
                }
            });
        if let super::Resolution::WindowScale(s) = &mut view.resolution {
            let response = ui.add(typing.slider(&mut *s, 0.1..=1.0).text("scale"));
            actions.note(typing.said_as_edit_ends(ui, &response, "scale", *s));
        }
        ui.collapsing("preview while moving", |ui| {
            ui.checkbox(&mut view.adaptive, "adaptive (holds a frame time)");
            let (value, range, name) = match view.adaptive {
                true => (&mut view.target_ms, 4.0..=100.0, "target ms"),
                false => (&mut view.preview_scale, 0.1..=1.0, "preview scale"),
            };
            let response = ui.add(typing.slider(&mut *value, range).text(name));
            actions.note(typing.said_as_edit_ends(ui, &response, name, *value));
        });

        ui.separator();
        ui.strong("Sampling and intersection");
        for control in CONTROLS.iter().filter(|c| c.heading.is_none()) {
            let code = (control.name == "method")
                .then_some(info.code_name)
                .flatten()
                .map(|name| (name, &mut view.yours));
            let said = control_widget(ui, control, &mut view.controls, code, &typing);
            actions.note(said);
            let (asked, n) = (view.controls.spp, info.samples_shown);
            if control.name == "spp" && n < asked {
                let note = format!("{asked}x{asked} asked, {n}x{n} shown");
                ui.label(egui::RichText::new(note).color(egui::Color32::YELLOW))
                    .on_hover_text(format!(
                        "the window renders at most {} M samples a frame; F5 and copy as \
                         command keep {asked}x{asked}",
                        super::bounds::MAX_SHOWN_SAMPLES >> 20
                    ));
            }
        }
        if let Some(legend) = &info.cracks {
            actions.crack = super::cracks::legend(ui, legend);
        }

        ui.separator();
        ui.horizontal(|ui| {
            ui.strong("Light");
            for (c, name) in view.light.iter_mut().zip(["light x", "light y", "light z"]) {
                let response = ui.add(coordinate(&mut *c, 0.01 * camera.scene_size, &typing));
                actions.note(typing.said_as_edit_ends(ui, &response, name, *c));
            }
        });

        ui.separator();
        ui.horizontal(|ui| {
            let load = egui::Button::new("Load");
            // (In a narrow window the panel shows less than its rows' width: the field takes
            // what is in view, so Load stays in it.)
            let in_view = ui.clip_rect().right() - ui.cursor().min.x;
            let room = ui.available_width().min(in_view) - 50.0;
            let field = egui::TextEdit::singleline(obj_path)
                .hint_text(".scene, .obj or .view path")
                .desired_width(room);
            let typed = ui.add(field);
            super::fields::escape_restores(ui, &typed, obj_path);
            // Enter in the field loads as the button does.
            let entered = typed.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
            let clicked = ui
                .add_enabled(!info.loading, load)
                .on_hover_text("a .scene, .obj or .view file (or drop one on the window)")
                .clicked();
            if clicked || (entered && !info.loading) {
                actions.load = Some(obj_path.clone());
            }
        });
        ui.horizontal(|ui| {
            ui.label("OBJ axes");
            for (frame, name, tip) in [
                (
                    ObjFrame::YUp,
                    "y up",
                    "the usual: y and z negated into the lab's y-down world",
                ),
                (
                    ObjFrame::Lab,
                    "as is",
                    "the lab's own frame, as cornell_lab.obj is written",
                ),
            ] {
                let chosen = ui.selectable_label(info.obj_frame == frame, name);
                if chosen.on_hover_text(tip).clicked() && info.obj_frame != frame {
                    actions.obj_frame = Some(frame);
                }
            }
        });
    });
    ui.advance_cursor_after_rect(rows.min_rect());
    actions.fit = (scrolled.content_size.y, scrolled.inner_rect.height());
    actions.bar_room = (rows.min_rect().width() - scrolled.content_size.x).max(0.0);
    actions
}

/// A field for a camera or light coordinate, kept within the range raylab renders from
/// (±[`raylab::math::MAX_VIEW_COORDINATE`], what `raylab render` accepts), a typed `nan` or
/// `inf` not taken: copy as command and Save view write what the window shows.
fn coordinate<'a, N: egui::emath::Numeric + std::fmt::Display>(
    value: &'a mut N,
    speed: f64,
    typing: &'a Typing,
) -> egui::DragValue<'a> {
    let max = raylab::math::MAX_VIEW_COORDINATE;
    let field = egui::DragValue::new(value).speed(speed).max_decimals(3);
    typing.drag(field, N::from_f64(-max)..=N::from_f64(max))
}

/// egui's solid scroll bar, drawn alike, but taking its room at once: as a floating bar
/// whose room is the solid bar's and that is drawn at its full width all the time.
fn solid_bar() -> egui::style::ScrollStyle {
    let solid = egui::style::ScrollStyle::solid();
    egui::style::ScrollStyle {
        floating: true,
        floating_allocated_width: solid.allocated_width(),
        floating_width: solid.bar_width,
        dormant_background_opacity: solid.active_background_opacity,
        dormant_handle_opacity: solid.active_handle_opacity,
        ..solid
    }
}

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
    let info = PanelInfo {
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
    // (Its edge dragged no further than leaves the image MIN_IMAGE_WIDTH; its rows still
    // widen it to what they take.)
    let most = ui.available_rect_before_wrap().width() - MIN_IMAGE_WIDTH;
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
                ui.add(egui::Label::new(note).wrap());
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
        (*status_whole, *figures_whole) =
            super::notices::status_line(ui, status, (shown, progress), full_size, threads);
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

/// What the linked code's option in the method selector does.
const CODE_HELP: &str = "the linked lab code answers every ray (camera rays, nearest hits, shadow rays); with show cracks on, its leaks are magenta, false hits yellow and wrong primitives cyan";

/// The widget of `control`, one control of the image's table ([`CONTROLS`]): a choice as radio
/// buttons under its own heading or a drop-down, a toggle as a check box, a count as a slider;
/// `code` offers linked code (its name, and whether it is chosen) as one more option of a
/// drop-down choice (the method's). What the slider's box could not read of typed text, said.
fn control_widget(
    ui: &mut egui::Ui,
    control: &Control,
    settings: &mut RenderSettings,
    code: Option<(&str, &mut bool)>,
    typing: &Typing,
) -> Option<Said> {
    match control.kind {
        Kind::Choice { options, get, set } => {
            let (options, mut chosen) = (options(), get(settings));
            match control.heading {
                Some(title) => {
                    ui.strong(title);
                    for (i, o) in options.iter().enumerate() {
                        ui.radio_value(&mut chosen, i, o.label)
                            .on_hover_text(o.help);
                    }
                    ui.small(options[chosen].help);
                }
                None => {
                    // The linked code, as the option past the table's (chosen while set).
                    let (name, mut yours) = code.unzip();
                    let yours_index = options.len();
                    if yours.as_deref() == Some(&true) {
                        chosen = yours_index;
                    }
                    let selected = name.filter(|_| chosen == yours_index);
                    egui::ComboBox::from_label(control.label)
                        .selected_text(selected.unwrap_or_else(|| options[chosen].label))
                        .show_ui(ui, |ui| {
                            for (i, o) in options.iter().enumerate() {
                                ui.selectable_value(&mut chosen, i, o.label)
                                    .on_hover_text(o.help);
                            }
                            if let Some(name) = name {
                                ui.selectable_value(&mut chosen, yours_index, name)
                                    .on_hover_text(CODE_HELP);
                            }
                        })
                        .response
                        .on_hover_text(control.help);
                    if let Some(yours) = yours.as_mut() {
                        **yours = chosen == yours_index;
                    }
                    if chosen == yours_index {
                        return None;
                    }
                }
            }
            if chosen != get(settings) {
                set(settings, chosen);
            }
        }
        Kind::Toggle { get, set } => {
            let mut on = get(settings);
            if ui
                .checkbox(&mut on, control.label)
                .on_hover_text(control.help)
                .changed()
            {
                set(settings, on);
            }
        }
        Kind::Count { min, max, get, set } => {
            let mut n = get(settings);
            let slider = typing.slider(&mut n, min..=max).text(control.label);
            let response = ui.add(slider).on_hover_text(control.help);
            if response.changed() {
                set(settings, n);
            }
            return typing.said_as_edit_ends(ui, &response, control.label, n);
        }
    }
    None
}
