//! The transform-stack inspector of the side panel.

use raylab::scene::file::Level;

/// The transform-stack inspector: the `.scene` file's push levels as a tree, each with its
/// statements and its `world_from_object` matrix; clicking a level selects it (its primitives
/// are tinted in the image), clicking it again clears the selection. What is unfolded is
/// kept per scene (`scene`: its name), not carried to the same rows of another.
pub fn scene_tree(
    ui: &mut egui::Ui,
    levels: &[Level],
    selected: Option<usize>,
    scene: &str,
) -> Option<Option<usize>> {
    let mut clicked = None;
    let title = |level: &Level| match level.line {
        0 => "file (top level)".to_string(),
        line => format!("push (line {line})"),
    };
    // (The tinted level named on the header too: folded, the tint had no word in the panel.)
    let header = match selected.and_then(|i| levels.get(i)) {
        Some(level) => format!("Transform stack: {} tinted", title(level)),
        None => "Transform stack".to_string(),
    };
    egui::CollapsingHeader::new(header)
        .id_salt(("transform stack", scene))
        .default_open(false)
        .show(ui, |ui| {
            ui.small("M = T*R*S per level, times its parent's; click a level to highlight it");
            for (i, level) in levels.iter().enumerate() {
                let title = title(level);
                let count: u32 = level.primitives.iter().map(|r| r.end - r.start).sum();
                ui.horizontal(|ui| {
                    ui.add_space(12.0 * level.depth as f32);
                    let label = format!("{title}: {}", raylab::words::primitives(count as usize));
                    if ui.selectable_label(selected == Some(i), label).clicked() {
                        clicked = Some((selected != Some(i)).then_some(i));
                    }
                });
                // (Indented as its level's row: the details of nested levels had all lined
                // up under the top one. The header's arrow takes the indent's width, so
                // that is set back inside: a wider one had moved the label off its arrow.)
                let indent = ui.spacing().indent;
                ui.scope(|ui| {
                    ui.spacing_mut().indent = indent + 12.0 * level.depth as f32;
                    ui.indent(("level", i), |ui| {
                        ui.spacing_mut().indent = indent;
                        details(ui, level, (scene, i));
                    });
                });
            }
        });
    clicked
}

/// A level's statements (with their lines) and its `world_from_object` matrix, folded;
/// `id`: the scene and the level.
fn details(ui: &mut egui::Ui, level: &Level, id: (&str, usize)) {
    egui::CollapsingHeader::new("statements and world_from_object")
        .id_salt(("level-details", id))
        .default_open(false)
        .show(ui, |ui| {
            // (Scrolled sideways within the panel: a long statement or a deep level's matrix
            // had widened the panel, narrowing the image and its view for good.)
            egui::ScrollArea::horizontal()
                .id_salt(("level-scroll", id))
                .show(ui, |ui| {
                    for (line, text) in &level.statements {
                        ui.monospace(format!("{line:>4}  {text}"));
                    }
                    egui::Grid::new(("matrix", id)).show(ui, |ui| {
                        for row in &level.world_from_object {
                            for x in row {
                                ui.monospace(format!("{x:>8.4}"));
                            }
                            ui.end_row();
                        }
                    });
                });
        });
}
