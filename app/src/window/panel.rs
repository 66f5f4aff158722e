//! The egui side panel's controls (the window's layout around it: layout.rs; the shortcuts
//! overlay: shortcuts.rs).

use super::fields::{Said, Typing};
use super::viewer::ViewSettings;
use raylab::controller::{CameraController, Mode, FOCAL_RATIO_RANGE};
use raylab::render::inspect::Inspection;
use raylab::render::settings::{Control, Kind};
use raylab::render::{RenderSettings, CONTROLS};
use raylab::scene::file::Level;
use raylab::scene::ObjFrame;

/// Preset render resolutions offered besides "a scale of the window".
pub const PRESETS: [(u32, u32); 4] = [(320, 240), (640, 480), (1280, 720), (1920, 1080)];

/// The fixed sizes the resolution list offers: the presets, and every other fixed size the
/// panel has shown (a loaded view's, while the panel was drawn), so that one chosen away from
/// can be chosen again; smallest first.
fn sizes_offered(ui: &egui::Ui, resolution: super::Resolution) -> Vec<(u32, u32)> {
    let id = egui::Id::new("sizes offered");
    let mut sizes: Vec<(u32, u32)> = ui.data(|d| d.get_temp(id)).unwrap_or(PRESETS.to_vec());
    if let super::Resolution::Fixed(w, h) = resolution {
        if !sizes.contains(&(w, h)) {
            sizes.push((w, h));
            sizes.sort_by_key(|&(w, h)| (u64::from(w) * u64::from(h), w));
            ui.data_mut(|d| d.insert_temp(id, sizes.clone()));
        }
    }
    sizes
}

/// What the panel shows but does not edit.
pub struct PanelInfo<'a> {
    /// The widest the panel may be (points): what leaves the image its least width.
    pub widest: f32,
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
    /// What a click on the status line copied (it says so).
    pub status_copied: Option<String>,
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
        // (Short words where the widest panel the window allows cannot hold the row: "Copy as
        // command (C)" was cut to "Copy as con" in a narrow window.)
        let words = match row_fits(ui, &CAMERA_BUTTONS, info.widest) {
            true => CAMERA_BUTTONS,
            false => ["Reset (R)", "Save (F5)", "Copy (C)"],
        };
        ui.horizontal(|ui| {
            if ui.button(words[0]).clicked() {
                actions.reset_camera = true;
            }
            if ui
                .button(words[1])
                .on_hover_text(
                    "camera, light and settings to a file `raylab render --view` renders",
                )
                .clicked()
            {
                actions.save_view = true;
            }
            if ui
                .button(words[2])
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
        let label = |resolution| match resolution {
            super::Resolution::WindowScale(_) => "scale of the window".to_string(),
            super::Resolution::Fixed(w, h) => format!("{w}x{h}"),
        };
        let sizes = sizes_offered(ui, view.resolution);
        egui::ComboBox::from_id_salt("resolution")
            .selected_text(label(view.resolution))
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
                for &(w, h) in &sizes {
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
            // (The field takes what is in view, so Load stays in it.)
            let room = width_in_view(ui) - 50.0;
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

/// The panel's width beside its rows' (points): its margins and scroll bar, with room to
/// spare.
const PANEL_CHROME: f32 = 40.0;

/// The camera's buttons, as a wide enough panel shows them.
const CAMERA_BUTTONS: [&str; 3] = ["Reset camera (R)", "Save view (F5)", "Copy as command (C)"];

/// Whether a row of buttons with `words` fits a panel at most `widest` points wide, its
/// margins and scroll bar taken off. (Not the width the panel has now: its rows widen it, and
/// a row of short words kept it narrow.)
fn row_fits(ui: &egui::Ui, words: &[&str], widest: f32) -> bool {
    let font = egui::TextStyle::Button.resolve(ui.style());
    let spacing = ui.spacing();
    let width: f32 = (words.iter())
        .map(|w| {
            let galley =
                ui.painter()
                    .layout_no_wrap(w.to_string(), font.clone(), egui::Color32::WHITE);
            galley.size().x + 2.0 * spacing.button_padding.x + spacing.item_spacing.x
        })
        .sum();
    // (Margins and bar: the panel was 368 points wide for a row of 342.)
    width - spacing.item_spacing.x + PANEL_CHROME <= widest
}

/// The width left in `ui` that is in view: in a narrow window the panel shows less than its
/// rows' width, and a row laid out to its end is cut.
pub fn width_in_view(ui: &egui::Ui) -> f32 {
    let in_view = ui.clip_rect().right() - ui.cursor().min.x;
    ui.available_width().min(in_view)
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
