//! The shortcuts overlay (H or F1): every keyboard and mouse control, as the README lists them.

/// The shortcuts overlay.
pub fn help_window(ctx: &egui::Context, open: &mut bool) {
    // (In a short window its last rows, Esc's among them, fell below the window: they
    // scroll instead.)
    let room = ctx.content_rect().height() - 2.0 * 12.0;
    egui::Window::new("Shortcuts")
        .open(open)
        .collapsible(false)
        .resizable(false)
        .anchor(egui::Align2::RIGHT_TOP, [-12.0, 12.0])
        .max_height(room)
        .show(ctx, |ui| {
            // (As tall as the window has room for: egui's default cut a 720-pixel window's
            // list at some 400, hiding H, P and Esc below the fold.)
            let list = room - 56.0;
            let scroll = egui::ScrollArea::vertical()
                .max_height(list)
                .min_scrolled_height(list);
            scroll.show(ui, |ui| {
                egui::Grid::new("keys").striped(true).show(ui, |ui| {
                    for (k, what) in SHORTCUTS {
                        ui.monospace(*k);
                        ui.label(*what);
                        ui.end_row();
                    }
                });
            });
        });
}

/// The keyboard and mouse controls, as shown in the overlay and the README.
const SHORTCUTS: &[(&str, &str)] = &[
    ("W / S", "move forward / back"),
    ("A / D", "move left / right"),
    ("Q / E", "move down / up"),
    ("arrows", "turn (yaw and pitch)"),
    ("Shift / Ctrl", "4x faster / 4x slower"),
    ("+ / -", "moving speed up / down"),
    ("Tab", "fly / orbit mode"),
    ("left drag (orbit)", "turn around the target"),
    ("right or middle drag (orbit)", "pan"),
    ("right drag (fly)", "look around"),
    ("wheel", "fly: focal length (up zooms in); orbit: dolly"),
    ("R", "reset the camera"),
    ("1 / 3 / 4 / 5", "lab step: flat, direct, shadows, indirect"),
    ("C", "copy the `raylab render` command of this view"),
    (
        "left click / I",
        "ray inspector: one pixel's ray as the lecture writes it / on or off",
    ),
    (
        "N / Shift+N",
        "next / previous crack (show cracks on) in the ray inspector",
    ),
    ("F12", "save a screenshot (PNG)"),
    (
        "F5",
        "save the view (camera, light, settings) for `raylab render --view`",
    ),
    ("H / F1", "this overlay"),
    ("P", "hide / show the side panel"),
    (
        "Esc",
        "release the mouse; close this overlay; dismiss an error; again to quit",
    ),
];
