//! The File menu: open a scene or model, save the image, save the view (its scene named so
//! that it renders from any directory), through a file dialog drawn by egui itself
//! (egui-file-dialog), so it works wherever the window does.

use egui_file_dialog::{DialogState, FileDialog};
use std::path::{Path, PathBuf};

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
    /// The folder of the last file picked, where the next dialog starts (the working
    /// directory until then).
    last_folder: Option<PathBuf>,
}

impl Default for FileMenu {
    fn default() -> Self {
        Self {
            dialog: FileDialog::new(),
            purpose: None,
            last_folder: None,
        }
    }
}

impl FileMenu {
    /// The menu bar's File menu (inside a menu bar `ui`).
    pub fn menu(&mut self, ui: &mut egui::Ui) {
        ui.menu_button("File", |ui| {
            let items = [
                ("Open scene, OBJ or view…", Purpose::Open),
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
            Purpose::Open => ("Open a .scene, .obj or .view file", ""),
            Purpose::SaveImage => ("Save the image (PNG, full quality)", "raylab.png"),
            Purpose::SaveView => ("Save the view (raylab render --view)", "raylab.view"),
        };
        // (Each lists the files of its kind: the view's save listed the images.)
        let (filter, extensions) = match purpose {
            Purpose::Open => ("scenes and models", vec!["scene", "obj", "view"]),
            Purpose::SaveImage => ("PNG images", vec!["png"]),
            Purpose::SaveView => ("views", vec!["view"]),
        };
        let dialog = (FileDialog::new().title(title).default_file_name(name))
            .add_file_filter_extensions(filter, extensions)
            .default_file_filter(filter);
        let folder = (self.last_folder.clone().filter(|f| f.is_dir()))
            .or_else(|| std::env::current_dir().ok());
        self.dialog = match folder {
            Some(dir) => dialog.initial_directory(dir),
            None => dialog,
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
        self.last_folder = path.parent().map(Path::to_path_buf);
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

/// The scene `scene` (a path from the window's working directory, or `cornell`) as a view
/// file at `view_file` names it, so that the view renders from any directory: relative to
/// the view file's directory where the scene lies under it, else the absolute path. (Written
/// as opened, a relative path rendered only from the window's working directory.)
pub fn scene_seen_from(scene: &str, view_file: &Path) -> String {
    let scene_path = scene_from_anywhere(scene);
    let dir = view_file.parent().filter(|d| !d.as_os_str().is_empty());
    match absolute(dir.unwrap_or(Path::new("."))) {
        Ok(dir) if scene != raylab::scene::CORNELL => {
            match Path::new(&scene_path).strip_prefix(dir) {
                Ok(relative) => relative.display().to_string(),
                Err(_) => scene_path,
            }
        }
        _ => scene_path,
    }
}

/// The scene `scene` (a path from the window's working directory, or `cornell`) as a command
/// copied from the window names it: by its absolute path, so that it runs from any directory
/// (as typed, a relative path ran only from the window's).
pub fn scene_from_anywhere(scene: &str) -> String {
    match scene == raylab::scene::CORNELL {
        true => scene.to_string(),
        false => absolute(Path::new(scene)).map_or(scene.to_string(), |p| p.display().to_string()),
    }
}

/// `p` as an absolute path, its links and `..` resolved where it exists.
fn absolute(p: &Path) -> std::io::Result<PathBuf> {
    std::fs::canonicalize(p).or_else(|_| std::path::absolute(p))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_saved_views_scene_is_named_as_seen_from_the_view_file() {
        // A scene under the view file's directory is named relative to it; one elsewhere by
        // its absolute path; `cornell` as it is. (The path as opened, relative to the
        // window's working directory, rendered from nowhere else.)
        let dir = tempfile::tempdir().unwrap();
        let root = std::fs::canonicalize(dir.path()).unwrap();
        std::fs::create_dir_all(root.join("scenes/deep")).unwrap();
        std::fs::create_dir_all(root.join("views")).unwrap();
        let scene = root.join("scenes/deep/s.scene");
        std::fs::write(&scene, "cornell\n").unwrap();
        let spec = scene.to_str().unwrap();
        assert_eq!(
            scene_seen_from(spec, &root.join("scenes/v.view")),
            "deep/s.scene"
        );
        assert_eq!(scene_seen_from(spec, &root.join("views/v.view")), spec);
        // Through `..` from the views' directory: the absolute path, with no `..` in it.
        let roundabout = root.join("views/../scenes/deep/s.scene");
        let seen = scene_seen_from(roundabout.to_str().unwrap(), &root.join("views/v.view"));
        assert_eq!(seen, spec);
        assert_eq!(scene_seen_from("cornell", &root.join("v.view")), "cornell");
        // A command copied names it absolutely (it runs in any directory).
        assert_eq!(scene_from_anywhere(roundabout.to_str().unwrap()), spec);
        assert_eq!(scene_from_anywhere("cornell"), "cornell");
        let relative = scene_from_anywhere("Cargo.toml");
        assert!(Path::new(&relative).is_absolute() && relative.ends_with("/Cargo.toml"));
        // The view's own rule finds it from another directory.
        let view = raylab::view::View::parse("v.view", "scene deep/s.scene\n").unwrap();
        let found = view.scene_path(&root.join("scenes/v.view"));
        assert_eq!(std::fs::canonicalize(found).unwrap(), scene);
    }
}
