//! The File menu: open a scene or model, save the image, save the view, through a file dialog
//! drawn by egui itself (egui-file-dialog), so it works wherever the window does.

use egui_file_dialog::{DialogState, FileDialog};
use std::path::PathBuf;

/// What the open dialog was asked for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Purpose {
    Open,
    SaveImage,
    SaveView,
}

/// A file picked in the dialog, and what to do with it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Picked {
    Open(PathBuf),
    SaveImage(PathBuf),
    SaveView(PathBuf),
}

/// The menu's dialog and what it is for.
pub struct FileMenu {
    dialog: FileDialog,
    purpose: Option<Purpose>,
}

impl Default for FileMenu {
    fn default() -> Self {
        Self {
            dialog: FileDialog::new(),
            purpose: None,
        }
    }
}

impl FileMenu {
    /// The menu bar's File menu (inside a menu bar `ui`).
    pub fn menu(&mut self, ui: &mut egui::Ui) {
        ui.menu_button("File", |ui| {
            let items = [
                ("Open scene or OBJ…", Purpose::Open),
                ("Save image…", Purpose::SaveImage),
                ("Save view…", Purpose::SaveView),
            ];
            for (label, purpose) in items {
                if ui.button(label).clicked() {
                    self.open(purpose);
                    ui.close();
                }
            }
        });
    }

    fn open(&mut self, purpose: Purpose) {
        let (title, name) = match purpose {
            Purpose::Open => ("Open a .scene or .obj file", ""),
            Purpose::SaveImage => ("Save the image (PNG, full quality)", "raylab.png"),
            Purpose::SaveView => ("Save the view (raylab render --view)", "raylab.view"),
        };
        let mut dialog = FileDialog::new().title(title).default_file_name(name);
        if purpose == Purpose::Open {
            dialog = dialog
                .add_file_filter_extensions("scenes and models", vec!["scene", "obj", "view"])
                .default_file_filter("scenes and models");
        }
        self.dialog = match std::env::current_dir() {
            Ok(dir) => dialog.initial_directory(dir),
            Err(_) => dialog,
        };
        match purpose {
            Purpose::Open => self.dialog.pick_file(),
            _ => self.dialog.save_file(),
        }
        self.purpose = Some(purpose);
    }

    /// Whether the dialog is shown: Esc then closes it rather than being the app's.
    pub fn is_open(&self) -> bool {
        *self.dialog.state() == DialogState::Open
    }

    /// Shows the dialog while it is open; what was picked, once.
    pub fn update(&mut self, ctx: &egui::Context) -> Option<Picked> {
        self.dialog.update(ctx);
        let path = self.dialog.take_picked()?;
        Some(match self.purpose.take()? {
            Purpose::Open => Picked::Open(path),
            Purpose::SaveImage => Picked::SaveImage(with_extension(path, "png")),
            Purpose::SaveView => Picked::SaveView(with_extension(path, "view")),
        })
    }
}

/// `path`, with `.ext` added where it has no extension.
fn with_extension(path: PathBuf, ext: &str) -> PathBuf {
    match path.extension() {
        Some(_) => path,
        None => path.with_extension(ext),
    }
}
