//! What the viewer writes: F12's screenshots, F5's views, and C's command, each of the view
//! the window shows (uncropped by the inspector's panel).

use super::*;

/// How the status line begins that says what C copied.
const COPIED: &str = "copied to the clipboard: ";

/// How the status line begins that says where F5 saved the view, and the command that renders
/// it.
const SAVED_VIEW: &str = "saved view ";

/// The command a status line names, after C ([`COPIED`]) or F5 ([`SAVED_VIEW`]): what a click
/// on it copies, rather than the message.
pub fn command_in_status(status: &str) -> Option<&str> {
    if let Some(command) = status.strip_prefix(COPIED) {
        return Some(command);
    }
    let (_, command) = status.strip_prefix(SAVED_VIEW)?.rsplit_once(" (")?;
    command
        .strip_suffix(')')
        .filter(|c| c.starts_with("raylab render --view "))
}

impl Viewer {
    /// F12: renders what the window shows fully refined (the window may be showing a
    /// preview): its render size and supersampling, both within the window's bounds
    /// ([`super::bounds`]), so its work is a refined frame's; on a thread of its own so the
    /// window keeps going ([`AppEvent::ScreenshotSaved`] when done).
    pub fn screenshot(&mut self) {
        self.screenshot_to(PathBuf::from(format!("raylab-{}.png", timestamp())));
    }

    /// Renders what the window shows, fully refined, to the PNG file `path`.
    pub fn screenshot_to(&mut self, path: PathBuf) {
        if let Err(e) = raylab::input::check_output(&path) {
            return self.report_error(format!("cannot save the image: {e}"));
        }
        // The wheel or mouse moved since the last frame takes effect first: the file shows
        // the view they made, not the one before them.
        self.update_camera();
        let (w, h) = self.full_size();
        let n = self.spp_shown();
        let settings = self.settings((w, h), n);
        let (stage, camera, proxy) = (self.stage.clone(), self.camera(w), self.proxy.clone());
        self.screenshots_pending += 1;
        self.set_status(format!(
            "saving {} ({w}x{h} at {n}x{n} samples)...",
            path.display()
        ));
        std::thread::spawn(move || {
            let result = render::render_image(&stage, &camera, &settings)
                .map_err(|e| e.to_string())
                .and_then(|(rgba, _)| {
                    render::write_png(&path, w, h, &rgba)
                        .map_err(|e| format!("{}: {e}", path.display()))
                })
                .map(|()| std::fs::canonicalize(&path).unwrap_or(path));
            let _ = proxy.send_event(AppEvent::ScreenshotSaved(result));
        });
    }

    /// The size of the view as F5 and copy as command write it, and its focal length: a
    /// fixed size is the view's own, even where the window shows it smaller; a window-scaled
    /// one is the render's without the inspector's panel, whose crop of the image's sides is
    /// the window's, not the view's (the focal length stays as it crops).
    fn view_size_and_focal(&self) -> ((u32, u32), f64) {
        match self.view.resolution {
            Resolution::Fixed(w, h) => ((w, h), self.focal(w)),
            Resolution::WindowScale(_) => (self.uncropped_size(), self.focal(self.full_size().0)),
        }
    }

    /// The view as a [`raylab::view::View`]: what `raylab render --view` needs to render
    /// what the window shows at full quality (and uncropped by the inspector's panel).
    pub fn view(&self) -> raylab::view::View {
        let c = &self.controller;
        let source = self.watched.source.lock().expect("not poisoned").clone();
        let ((width, height), focal) = self.view_size_and_focal();
        raylab::view::View {
            scene: source.map_or("cornell".into(), |p| p.display().to_string()),
            obj_frame: self.obj_frame,
            camera: Some(raylab::scene::SceneCamera {
                position: c.position.to_array(),
                yaw: values::degrees(c.yaw),
                pitch: values::degrees(c.pitch),
                fov: None,
            }),
            light: Some(self.view.light),
            focal: Some(focal),
            settings: RenderSettings {
                width,
                height,
                ..self.settings((width, height), self.view.controls.spp)
            },
        }
    }

    /// C or the panel's button: the `raylab render` command of the current view goes to the
    /// clipboard (in the next UI pass) and the status line shows it.
    pub fn copy_command(&mut self) {
        // (A key released since the last frame moves the camera first, as for F12 and F5:
        // the command renders the view the next frame shows.)
        self.update_camera();
        let mut view = self.view();
        view.scene = crate::window::files::scene_from_anywhere(&view.scene);
        let command = view.to_command("raylab.png");
        self.set_status(format!("{COPIED}{command}"));
        self.copy_request = Some(command);
    }

    /// A click on the status line copied `text` (its message, or the command it names): the
    /// status says so, as after C (a click said nothing: had it copied?).
    pub fn say_copied(&mut self, text: &str) {
        if !self.status.starts_with(COPIED) {
            self.set_status(format!("{COPIED}{text}"));
        }
    }

    /// F5: writes the view to `raylab-view-<time>.view` (see [`raylab::view`]).
    pub fn save_view(&mut self) {
        self.save_view_to(PathBuf::from(format!("raylab-view-{}.view", timestamp())));
    }

    /// Carries out what the File menu's dialog picked.
    pub fn apply_picked(&mut self, picked: crate::window::files::Picked) {
        use crate::window::files::Picked;
        match picked {
            Picked::Open(path) => self.load(path),
            Picked::SaveImage(path) => self.screenshot_to(path),
            Picked::SaveView(path) => self.save_view_to(path),
        }
    }

    /// Writes the view to the `.view` file `path`.
    pub fn save_view_to(&mut self, path: PathBuf) {
        self.update_camera();
        let mut view = self.view();
        view.scene = crate::window::files::scene_seen_from(&view.scene, &path);
        let text = view.to_text();
        let written = raylab::input::write_file(&path, text.as_bytes()).map_err(|e| e.to_string());
        match written {
            Ok(()) => {
                let shown = std::fs::canonicalize(&path)
                    .unwrap_or(path)
                    .display()
                    .to_string();
                let word = raylab::view::shell_quote(&shown);
                self.set_status(format!(
                    "{SAVED_VIEW}{shown} (raylab render --view {word} -o out.png)"
                ));
            }
            Err(e) => self.report_error(format!("could not save the view: {e}")),
        }
    }

    /// An F12 screenshot finished.
    pub fn screenshot_saved(&mut self, result: Result<PathBuf, String>) {
        self.screenshots_pending -= 1;
        match result {
            Ok(path) => self.set_status(format!("saved {}", path.display())),
            Err(e) => self.report_error(format!("screenshot failed: {e}")),
        }
    }
}

/// Seconds since the Unix epoch with milliseconds, for screenshot names that sort in time.
fn timestamp() -> String {
    let t = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .unwrap_or_default();
    format!("{}-{:03}", t.as_secs(), t.subsec_millis())
}
