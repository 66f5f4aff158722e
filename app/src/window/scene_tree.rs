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
            let nested = nested_primitives(levels);
            for (i, level) in levels.iter().enumerate() {
                let title = title(level);
                let count = own_primitives(level);
                ui.horizontal(|ui| {
                    ui.add_space(12.0 * level.depth as f32);
                    let label = format!("{title}: {}", raylab::words::primitives(count));
                    if ui.selectable_label(selected == Some(i), label).clicked() {
                        clicked = Some((selected != Some(i)).then_some(i));
                    }
                });
                // (With its nested levels' too, which a click tints: "12 primitives" stood
                // beside 13 tinted. On a line of its own: beside the row it widened the
                // panel, narrowing the image for good.)
                if nested[i] > 0 {
                    ui.horizontal(|ui| {
                        ui.add_space(12.0 * level.depth as f32 + 16.0);
                        ui.small(format!("{} with its nested levels", count + nested[i]));
                    });
                }
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

/// The primitives a level adds itself.
fn own_primitives(level: &Level) -> usize {
    level
        .primitives
        .iter()
        .map(|r| (r.end - r.start) as usize)
        .sum()
}

/// The primitives each level's nested levels add (the levels after it that are deeper, up to
/// the next at its depth or above), in one pass: prefix sums over each level's run.
fn nested_primitives(levels: &[Level]) -> Vec<usize> {
    let mut prefix = vec![0];
    for level in levels {
        prefix.push(prefix.last().unwrap_or(&0) + own_primitives(level));
    }
    // (Where each level's nested run ends: the next level no deeper than it.)
    let (mut end, mut open) = (vec![levels.len(); levels.len()], Vec::<usize>::new());
    for (i, level) in levels.iter().enumerate() {
        while open.last().is_some_and(|&o| levels[o].depth >= level.depth) {
            end[open.pop().unwrap_or_default()] = i;
        }
        open.push(i);
    }
    (0..levels.len())
        .map(|i| prefix[end[i]] - prefix[i + 1])
        .collect()
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A level at `depth` adding the primitives of each `(first, end)` run.
    fn level(depth: usize, runs: &[(u32, u32)]) -> Level {
        Level {
            line: depth,
            depth,
            statements: Vec::new(),
            world_from_object: [[0.0; 4]; 4],
            primitives: runs.iter().map(|&(first, end)| first..end).collect(),
        }
    }

    /// A level's nested levels are the deeper ones after it, up to the next at its depth or
    /// above: the file's top level holds them all, a leaf none.
    #[test]
    fn nested_primitives_count_the_deeper_levels_that_follow() {
        let levels = [
            level(0, &[(0, 2), (9, 10)]),
            level(1, &[(2, 4)]),
            level(2, &[(4, 7)]),
            level(1, &[(7, 8)]),
            level(2, &[(8, 9)]),
        ];
        assert_eq!(nested_primitives(&levels), [7, 3, 0, 1, 0]);
        assert_eq!(own_primitives(&levels[0]), 3);
    }
}
