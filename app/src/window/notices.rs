//! What the window tells the user outside the panel's controls: the status line under the
//! image (the last action's message and the frame's figures), the red banner over the image
//! for an error, and the scene's warnings (a count and the first few in the panel, all of them
//! in a window of their own, laid out only as far as they are scrolled into view).

use super::worker::Progress;
use raylab::render::RenderStats;

/// Warnings the panel lists under their count; the rest are a click away.
pub const FIRST_WARNINGS: usize = 3;

/// The red of the error banner and of an error in the status line.
const ERROR_RED: egui::Color32 = egui::Color32::from_rgb(190, 30, 30);

/// The image on screen, for the status line: its size, refinement level, supersampling (n
/// per axis) and render figures.
pub type ShownFigures = (u32, u32, u8, u32, RenderStats);

/// The status line: the last message on the left (red for an error), the image's figures on
/// the right. The message has the room first, but the figures keep theirs up to half the
/// line: a long message (a copied command) is cut short (the whole of it on hover; a click
/// copies it), the frame's figures stay in view. Returns whether the whole message and the
/// whole figures are shown, and what a click copied. A refinement under way long enough to be
/// said ([`Progress`]) is said after the figures, with how far it has come.
pub fn status_line(
    ui: &mut egui::Ui,
    (status, is_error): (&str, bool),
    (shown, progress): (Option<ShownFigures>, Option<Progress>),
    full_size: (u32, u32),
    threads: usize,
) -> StatusShown {
    let mut figures = match shown {
        Some((w, h, level, spp, stats)) => {
            let what = match level {
                0 => format!("preview of {}x{}", full_size.0, full_size.1),
                1 => "full".to_string(),
                _ => format!("{spp}x{spp} samples"),
            };
            format!(
                "{w}x{h} {what} · {:.1} ms · {:.2} Mrays/s · {threads} threads",
                stats.elapsed.as_secs_f64() * 1e3,
                stats.mrays_per_s(),
            )
        }
        None => "rendering...".to_string(),
    };
    if let Some(p) = progress {
        let what = match p.level {
            1 => "full resolution".to_string(),
            _ => format!("{0}x{0} samples", p.spp),
        };
        figures += &format!(
            " · rendering {what}: {:.0}% begun, {:.0} s",
            100.0 * p.begun,
            p.since.elapsed().as_secs_f64()
        );
    }
    let font = egui::TextStyle::Body.resolve(ui.style());
    let width_of = |text: &str| {
        let galley =
            ui.painter()
                .layout_no_wrap(text.to_owned(), font.clone(), egui::Color32::WHITE);
        galley.size().x
    };
    // (The separator and the spacing either side of it; a little slack for strong text.)
    let gap = 3.0 * ui.spacing().item_spacing.x + 4.0;
    let total = ui.available_width();
    let wanted = width_of(status) * 1.05 + 2.0;
    let figures_wanted = width_of(&figures) * 1.05 + 2.0;
    let figures_room = figures_wanted.min((total - gap - wanted).max(0.5 * total));
    let message_room = wanted.min((total - gap - figures_room).max(0.0));
    let whole = wanted <= message_room;
    let figures_whole = figures_wanted <= total - gap - message_room;
    let height = ui.spacing().interact_size.y;
    let mut copied = None;
    ui.horizontal(|ui| {
        let size = egui::vec2(message_room, height);
        let left = egui::Layout::left_to_right(egui::Align::Center);
        let message = ui.allocate_ui_with_layout(size, left, |ui| {
            let mut text = egui::RichText::new(status);
            if is_error {
                text = text.color(egui::Color32::from_rgb(255, 110, 110)).strong();
            }
            // (Its own tooltip below: egui's for a cut text would be a second one.)
            ui.add(
                egui::Label::new(text)
                    .truncate()
                    .show_tooltip_when_elided(false)
                    .sense(egui::Sense::click()),
            )
        });
        let response = message.inner;
        let response = match status.is_empty() {
            true => response,
            false => response.on_hover_text(format!("{status}\n(click to copy)")),
        };
        if response.clicked() && !status.is_empty() {
            // (What C copied, or F5's command, rather than the message that names it.)
            let text = super::viewer::command_in_status(status).unwrap_or(status);
            ui.ctx().copy_text(text.to_owned());
            log::info!("the status message was copied to the clipboard");
            copied = Some(text.to_owned());
        }
        // (No separator seen before an empty message: it stood alone at the line's start. Laid
        // out still, so that the figures' automatic id stays when a message comes or goes
        // between egui's passes: egui warned of a widget that changed its id.)
        ui.add_visible(!status.is_empty(), egui::Separator::default());
        ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
            ui.add(egui::Label::new(figures).truncate());
        });
    });
    StatusShown {
        whole,
        figures_whole,
        copied,
    }
}

/// What [`status_line`] showed, and what a click on it copied.
pub struct StatusShown {
    /// The whole message is in view.
    pub whole: bool,
    /// The whole figures are in view.
    pub figures_whole: bool,
    /// What a click on the message put on the clipboard (the status line is to say so).
    pub copied: Option<String>,
}

/// The error banner across the top of `image`, until clicked (or Esc). Returns where it was
/// drawn and whether it was clicked.
pub fn banner(ui: &mut egui::Ui, image: egui::Rect, text: &str) -> (egui::Rect, bool) {
    let margin = 8.0;
    let width = (image.width() - 2.0 * margin).max(40.0);
    let at = image.left_top() + egui::vec2(margin, margin);
    let area = egui::Rect::from_min_size(at, egui::vec2(width, image.height()));
    let mut child = ui.new_child(egui::UiBuilder::new().max_rect(area));
    let frame = egui::Frame::new()
        .fill(ERROR_RED)
        .stroke(egui::Stroke::new(
            1.0,
            egui::Color32::from_rgb(255, 160, 160),
        ))
        .corner_radius(4.0)
        .inner_margin(10.0)
        .show(&mut child, |ui| {
            ui.set_width(width - 20.0);
            let white = egui::Color32::WHITE;
            ui.add(egui::Label::new(egui::RichText::new(text).color(white).strong()).wrap());
            ui.add(egui::Label::new(
                egui::RichText::new("click here or press Esc to dismiss")
                    .color(white)
                    .small(),
            ));
        });
    let rect = frame.response.rect;
    let clicked = ui
        .interact(rect, egui::Id::new("error banner"), egui::Sense::click())
        .clicked();
    (rect, clicked)
}

/// The scene's warnings in the panel: their count (yellow, open by default) over the first
/// [`FIRST_WARNINGS`], and a button that opens the list of all of them.
pub fn warnings(ui: &mut egui::Ui, warnings: &[String], show_all: &mut bool) {
    let n = warnings.len();
    if n == 0 {
        return;
    }
    let yellow = egui::Color32::YELLOW;
    let title = match n {
        1 => "1 scene warning".to_string(),
        n => format!("{n} scene warnings"),
    };
    egui::CollapsingHeader::new(egui::RichText::new(title).color(yellow))
        .id_salt("scene warnings")
        .default_open(true)
        .show(ui, |ui| {
            for w in warnings.iter().take(FIRST_WARNINGS) {
                ui.add(egui::Label::new(egui::RichText::new(w).color(yellow).small()).wrap());
            }
            if n > FIRST_WARNINGS && ui.button(format!("all {n} warnings…")).clicked() {
                *show_all = true;
            }
        });
}

/// The most warnings the list shows wrapped; past it, one line each, laid out only where
/// seen (a hundred thousand wrapped labels would be laid out every frame).
const WRAPPED_WARNINGS: usize = 1000;

/// The window listing every warning: wrapped to its width, or past [`WRAPPED_WARNINGS`] one
/// line each (scrolled sideways to read a long one), only the rows in view laid out, so a
/// scene of a million warnings costs no more a frame than one of ten.
pub fn all_warnings(ctx: &egui::Context, warnings: &[String], open: &mut bool) {
    if warnings.is_empty() {
        *open = false;
    }
    egui::Window::new(format!("{} scene warnings", warnings.len()))
        .open(open)
        .default_size([640.0, 420.0])
        .show(ctx, |ui| {
            // (Bars drawn whenever there is more to see, sideways too.)
            ui.style_mut().spacing.scroll = egui::style::ScrollStyle::solid();
            if warnings.len() <= WRAPPED_WARNINGS {
                // Wrapped to the window's width: a warning read whole without scrolling.
                egui::ScrollArea::vertical()
                    .auto_shrink(false)
                    .show(ui, |ui| {
                        for w in warnings {
                            ui.add(egui::Label::new(w.as_str()).wrap());
                        }
                    });
                return;
            }
            let row = ui.text_style_height(&egui::TextStyle::Body);
            egui::ScrollArea::both().auto_shrink(false).show_rows(
                ui,
                row,
                warnings.len(),
                |ui, rows| {
                    for w in &warnings[rows] {
                        ui.add(egui::Label::new(w.as_str()).extend());
                    }
                },
            );
        });
}
