//! Loading what the viewer shows: a `.scene`, OBJ or `.view` file on a thread of its own, a
//! load asked for while one runs, and the file watched for changes (reloaded as it was).

use super::*;

/// What a load does once its file is read.
#[derive(Clone, Debug)]
pub enum LoadKind {
    /// A file opened (dropped, the File menu, the path field): a new camera for it.
    Open,
    /// The file shown changed on disk: the camera, light and settings stay.
    Reload,
    /// A saved view's scene (the view file's path beside it): the view's camera, light and
    /// settings apply once its own scene has loaded.
    View(Box<raylab::view::View>, PathBuf),
}

/// A load asked for: the file and what to do with it.
#[derive(Clone, Debug)]
pub struct LoadRequest {
    pub path: PathBuf,
    pub kind: LoadKind,
}

impl LoadRequest {
    fn is_reload(&self) -> bool {
        matches!(self.kind, LoadKind::Reload)
    }
}

/// How often the scene's file is checked for changes.
const WATCH_EVERY: Duration = Duration::from_millis(250);

/// The most mesh files of a scene watched beside it (the first it names): a scene of a
/// million meshes is not looked at a million times a quarter second.
const WATCH_MOST: usize = 1024;

/// The files the window watches: the scene shown (`source`) and the mesh files it names
/// (`meshes`), and a file whose opening failed (`failed`), which loads once it changes.
#[derive(Clone)]
pub(super) struct Watched {
    pub source: Arc<Mutex<Option<PathBuf>>>,
    pub meshes: Arc<Mutex<Vec<PathBuf>>>,
    pub failed: Arc<Mutex<Option<PathBuf>>>,
}

/// Watches the files of `watched` (whichever they are now) and sends
/// [`AppEvent::SourceChanged`] with the source (or the failed file) when the modification
/// time or size of one of its files changes; ends with the event loop. (An OBJ a scene places
/// was not watched: an edit of it left the window showing the old mesh, where the same OBJ
/// opened alone reloaded; nor a file that failed to open, fixed on disk.)
pub(super) fn watch(watched: Watched, proxy: EventLoopProxy<AppEvent>) {
    /// A file's modification time and size, as far as they can be had.
    type Stamp = Option<(Option<std::time::SystemTime>, u64)>;
    let stamp = |p: &PathBuf| -> Stamp {
        std::fs::metadata(p)
            .ok()
            .map(|m| (m.modified().ok(), m.len()))
    };
    let mut last: [Option<(Vec<PathBuf>, Vec<Stamp>)>; 2] = [None, None];
    loop {
        std::thread::sleep(WATCH_EVERY);
        let source = watched.source.lock().expect("not poisoned").clone();
        let failed = watched.failed.lock().expect("not poisoned").clone();
        for (k, path) in [source, failed].into_iter().enumerate() {
            let Some(path) = path else {
                last[k] = None;
                continue;
            };
            let mut files = vec![path.clone()];
            if k == 0 {
                let meshes = watched.meshes.lock().expect("not poisoned");
                files.extend(meshes.iter().take(WATCH_MOST).cloned());
            }
            let now: Vec<Stamp> = files.iter().map(stamp).collect();
            let changed = matches!(&last[k], Some((f, s)) if *f == files && *s != now);
            last[k] = Some((files, now));
            if changed && proxy.send_event(AppEvent::SourceChanged(path)).is_err() {
                return;
            }
        }
    }
}

impl Viewer {
    /// Loads a `.scene`, OBJ or `.view` file (a `.scene` or OBJ on a thread of its own,
    /// [`AppEvent::SceneLoaded`] when done).
    pub fn load(&mut self, path: PathBuf) {
        // The panel's path field names the file opened however it was opened (a drop, the
        // File menu): its Load button loaded the one typed before.
        self.obj_path = path.display().to_string();
        let is_view = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("view"));
        match is_view {
            true => self.load_view(&path),
            false => self.request_load(LoadRequest {
                path,
                kind: LoadKind::Open,
            }),
        }
    }

    /// How OBJ files are read.
    pub fn obj_frame(&self) -> ObjFrame {
        self.obj_frame
    }

    /// Reads OBJ files with `frame` from now on (the panel's OBJ axes), and the one shown
    /// again (opened anew: framed by the camera), so that a model seen from behind or upside
    /// down is set right where it is seen.
    pub fn set_obj_frame(&mut self, frame: ObjFrame) {
        self.obj_frame = frame;
        let shown = self.watched.source.lock().expect("not poisoned").clone();
        let read = match frame {
            ObjFrame::YUp => "y up (y and z negated)",
            ObjFrame::Lab => "as they are (the lab's frame)",
        };
        match shown.filter(|p| Scene::reads_as_obj(p)) {
            Some(path) => self.load(path),
            None => self.set_status(format!("OBJ files are now read {read}")),
        }
    }

    /// Opens a saved view (F5): its scene first (unless it is the one shown), then its
    /// camera, light and settings.
    fn load_view(&mut self, path: &std::path::Path) {
        let view = raylab::input::read_text(path, raylab::input::max_input_bytes())
            .map_err(|e| e.to_string())
            .and_then(|text| {
                raylab::view::View::parse(&path.display().to_string(), &text)
                    .map_err(|e| e.to_string())
            });
        match view {
            Ok(view) => self.request_load(LoadRequest {
                path: PathBuf::from(view.scene_path(path)),
                kind: LoadKind::View(Box::new(view), path.to_path_buf()),
            }),
            Err(e) => self.report_error(format!("could not load the view: {e}")),
        }
    }

    /// Applies a view's camera, light and settings to the scene shown (its own).
    fn apply_view(&mut self, view: &raylab::view::View, path: &std::path::Path) {
        let s = view.settings;
        self.view.controls = s;
        self.view.resolution = Resolution::Fixed(s.width, s.height);
        // (Without a camera or light, the scene's own, as `raylab render --view` takes them.)
        let cornell = self.watched.source.lock().expect("not poisoned").is_none();
        let scene = self.stage.scene();
        self.controller = match &view.camera {
            Some(c) => CameraController::from_scene_camera(c, scene.size()),
            None => CameraController::starting(scene, cornell, s.width, s.height),
        };
        if let Some(focal) = view.focal {
            self.controller.set_focal(focal, s.width);
        }
        self.view.light = view.light.unwrap_or(self.scene_light);
        self.obj_frame = view.obj_frame;
        let shown = fit_shown((s.width, s.height), self.max_side);
        let mut message = format!("loaded view {}", path.display());
        if shown != (s.width, s.height) {
            message += &format!(
                ": its {}x{} shown at {}x{} (F5 and copy as command keep {}x{})",
                s.width, s.height, shown.0, shown.1, s.width, s.height
            );
        }
        let n = samples_shown(s.spp, shown);
        if n != s.spp {
            message += &format!(", its {0}x{0} samples at {n}x{n}", s.spp);
        }
        let width = f64::from(s.width.max(1));
        let asked = match (view.focal, &view.camera) {
            (Some(focal), _) => Some(focal / width),
            (None, Some(camera)) => Some(camera.focal_ratio()),
            (None, None) => None,
        };
        if let Some(asked) = asked {
            message += &fov_note(asked, &self.controller);
        }
        self.set_status(message);
        self.changed();
    }

    /// Shows the built-in lab Cornell box (`cornell`, wherever a scene is named).
    fn show_cornell(&mut self, kind: &LoadKind) {
        *self.watched.source.lock().expect("not poisoned") = None;
        *self.watched.failed.lock().expect("not poisoned") = None;
        self.watched.meshes.lock().expect("not poisoned").clear();
        self.stage = Stage::new(Scene::cornell(), self.accel);
        self.selected_level = None;
        self.banner = None;
        self.scene_light = self.stage.scene().light.position;
        // (As an opened file's: the lab's camera and light, not the last scene's.)
        if let LoadKind::Open = kind {
            self.controller = CameraController::cornell();
            self.view.light = self.scene_light;
        }
        self.set_status(format!(
            "loaded {} ({})",
            raylab::scene::CORNELL,
            raylab::words::primitives(self.stage.scene().len())
        ));
        self.changed();
    }

    /// The scene's file changed on disk: reloads it (keeping the camera) if it is the file
    /// shown, or the one a load under way will show.
    pub fn reload(&mut self, path: PathBuf) {
        // (A file that failed to open, changed: opened again, as it was asked for.)
        if self.watched.failed.lock().expect("not poisoned").as_ref() == Some(&path) {
            log::info!("{} changed: opened again", path.display());
            return self.request_load(LoadRequest {
                path,
                kind: LoadKind::Open,
            });
        }
        let request = LoadRequest {
            path,
            kind: LoadKind::Reload,
        };
        if self.loading {
            self.queue_load(request);
        } else if self.watched.source.lock().expect("not poisoned").as_ref() == Some(&request.path)
        {
            self.start_load(request);
        }
    }

    /// Starts a load, or queues it behind the one under way.
    fn request_load(&mut self, request: LoadRequest) {
        match self.loading {
            true => self.queue_load(request),
            false => self.start_load(request),
        }
    }

    /// Keeps a load for when the one under way ends: an explicit load (open, a view) replaces
    /// whatever was queued; a reload is kept only where no explicit load is queued and its
    /// file is the one the load under way will show.
    fn queue_load(&mut self, request: LoadRequest) {
        let path = request.path.display().to_string();
        if request.is_reload() {
            let explicit_queued = self.queued_load.as_ref().is_some_and(|q| !q.is_reload());
            if explicit_queued || self.running_load.as_ref() != Some(&request.path) {
                log::info!("{path} changed, but another file is shown next: not reloaded");
                return;
            }
        }
        let message =
            format!("{path} asked for while a load is under way: loaded once that one ends");
        match request.is_reload() {
            true => log::info!("{message}"),
            false => self.set_status(message),
        }
        self.queued_load = Some(request);
    }

    /// Starts a load now: the Cornell box and a view of the scene shown at once, a file on
    /// a thread of its own.
    fn start_load(&mut self, request: LoadRequest) {
        let cornell = request.path.as_os_str() == raylab::scene::CORNELL;
        let shown = self.watched.source.lock().expect("not poisoned").clone();
        if let LoadKind::View(view, file) = &request.kind {
            if (cornell && shown.is_none()) || shown.as_ref() == Some(&request.path) {
                return self.apply_view(view, file);
            }
        }
        if cornell {
            self.show_cornell(&request.kind);
            if let LoadKind::View(view, file) = &request.kind {
                self.apply_view(view, file);
            }
            return;
        }
        self.loading = true;
        self.running_load = Some(request.path.clone());
        let verb = match request.kind {
            LoadKind::Reload => "reloading",
            _ => "loading",
        };
        self.set_status(format!("{verb} {}...", request.path.display()));
        let proxy = self.proxy.clone();
        let frame = match &request.kind {
            LoadKind::View(view, _) => view.obj_frame,
            _ => self.obj_frame,
        };
        let accel = self.accel;
        std::thread::spawn(move || {
            let result = load_stage(&request.path, frame, accel);
            let _ = proxy.send_event(AppEvent::SceneLoaded(request, Box::new(result)));
        });
    }

    /// A load ended: its scene is shown ([`Viewer::show_loaded`]), then a load asked for
    /// meanwhile starts as it was asked for. Returns the new scene's name for the window
    /// title.
    pub fn scene_loaded(
        &mut self,
        request: LoadRequest,
        result: Result<Stage, String>,
    ) -> Option<String> {
        self.loading = false;
        self.running_load = None;
        let failed = result.is_err();
        let name = self.show_loaded(&request, result);
        if let Some(next) = self.queued_load.take() {
            // A file that failed and changed meanwhile (fixed, perhaps) is loaded again as
            // it was asked for.
            let again = failed && next.is_reload() && next.path == request.path;
            self.start_load(if again { request } else { next });
        }
        name
    }

    /// A loaded scene replaces the shown one (with a new camera for an opened file, the
    /// view's for a view's scene, the same for a reload); a failed load keeps it and says
    /// why.
    fn show_loaded(
        &mut self,
        request: &LoadRequest,
        result: Result<Stage, String>,
    ) -> Option<String> {
        let path = &request.path;
        let reload = request.is_reload();
        let stage = match result {
            Ok(stage) => stage,
            Err(e) if reload => {
                self.report_error(format!("could not reload (the last good scene stays): {e}"));
                return None;
            }
            Err(e) => {
                // (A view's scene is named with the view, as `raylab render --view` names it:
                // "missing.scene: No such file" alone did not say which file asked for it.)
                let of_view = match &request.kind {
                    LoadKind::View(view, file) => {
                        format!(" scene '{}' of view '{}':", view.scene, file.display())
                    }
                    _ => String::new(),
                };
                self.report_error(format!("could not load:{of_view} {e}"));
                // (Not the file shown: its change reloads it, keeping the camera.)
                let shown = self.watched.source.lock().expect("not poisoned").clone();
                if matches!(request.kind, LoadKind::Open) && shown.as_ref() != Some(path) {
                    *self.watched.failed.lock().expect("not poisoned") = Some(path.clone());
                }
                return None;
            }
        };
        *self.watched.source.lock().expect("not poisoned") = Some(path.clone());
        *self.watched.meshes.lock().expect("not poisoned") = stage.scene().mesh_files.clone();
        *self.watched.failed.lock().expect("not poisoned") = None;
        // (The error of an earlier load no longer describes the scene shown.)
        self.banner = None;
        let scene = stage.scene();
        let old = &self.stage.scene().levels;
        self.selected_level = (self.selected_level)
            .filter(|_| reload)
            .and_then(|l| same_level(old, &scene.levels, l));
        // (Framed for the whole view, not the part the inspector's panel leaves shown: the
        // camera does not depend on whether that panel is open.)
        let (w, h) = self.uncropped_size();
        self.frame_when_sized = false;
        let mut note = String::new();
        match (&request.kind, scene.camera, scene.bounds()) {
            (LoadKind::Open, Some(c), _) => {
                self.controller = CameraController::from_scene_camera(&c, scene.size());
                note = fov_note(c.focal_ratio(), &self.controller);
            }
            (LoadKind::Open, None, Some(bounds)) => {
                self.controller = CameraController::framing(bounds, w, h)
            }
            // (A reload keeps the camera, but moves scale with the scene as it is now.)
            _ => self.controller.set_scene_size(scene.size()),
        }
        // (A light moved in the panel is kept by a reload, as the camera is.)
        let keep_light = reload && self.view.light != self.scene_light;
        if !keep_light {
            self.view.light = scene.light.position;
        }
        self.scene_light = scene.light.position;
        if keep_light {
            note += ", the light kept where the panel put it";
        }
        let verb = if reload { "reloaded" } else { "loaded" };
        self.set_status(format!(
            "{verb} {} ({}){note}",
            path.display(),
            raylab::words::primitives(scene.len())
        ));
        let name = scene.name.clone();
        self.stage = stage;
        if let LoadKind::View(view, file) = &request.kind {
            self.apply_view(view, file);
        }
        self.changed();
        Some(name)
    }
}

/// What the status adds where the window shows a camera whose focal length is `asked` times
/// the image width at another field of view: the window keeps the focal length within
/// [`FOCAL_RATIO_RANGE`](raylab::controller::FOCAL_RATIO_RANGE) of the image width (168.6° to
/// 1.1°), where `raylab render` takes any from 0.001 pixels.
fn fov_note(asked: f64, controller: &CameraController) -> String {
    let shown = controller.focal_ratio;
    if shown == asked {
        return String::new();
    }
    let fov = |ratio: f64| raylab::camera::fov_of_focal(ratio, 1.0).to_degrees();
    let end = if shown > asked { "widest" } else { "narrowest" };
    format!(
        "; its field of view {:.1}° shown at {:.1}°, the window's {end} (F5 and copy as \
         command write that)",
        fov(asked),
        fov(shown)
    )
}

/// The level of `new` (a reloaded file's) that is level `l` of `old`: the same place where
/// the file has as many levels (an edit of a statement, its lines shifted), else the level
/// nearest it with the same depth and statements (an edit that added or removed a level:
/// the tint had moved to the level after a removed one), or none.
fn same_level(
    old: &[raylab::scene::file::Level],
    new: &[raylab::scene::file::Level],
    l: usize,
) -> Option<usize> {
    let was = old.get(l)?;
    if old.len() == new.len() {
        return new.get(l).filter(|n| n.depth == was.depth).map(|_| l);
    }
    let texts = |v: &raylab::scene::file::Level| -> Vec<String> {
        v.statements.iter().map(|(_, t)| t.clone()).collect()
    };
    let wanted = texts(was);
    (new.iter().enumerate())
        .filter(|(_, n)| n.depth == was.depth && texts(n) == wanted)
        .min_by_key(|(j, _)| j.abs_diff(l))
        .map(|(j, _)| j)
}

/// The scene file at `path` read and made ready to render, on threads of its own: in the
/// pool the frames share, its parallel work queued behind a refinement's tiles and the
/// cracks' count, and a scene that loads in a tenth of a second took three
/// (`benches/window_waits.sh`).
fn load_stage(
    path: &std::path::Path,
    frame: ObjFrame,
    accel: AccelChoice,
) -> Result<Stage, String> {
    let load = || Scene::load(path, frame).map(|scene| Stage::new(scene, accel));
    match rayon::ThreadPoolBuilder::new().build() {
        Ok(pool) => pool.install(load),
        Err(_) => load(),
    }
}

#[cfg(test)]
mod tests {
    use super::{load_stage, same_level};
    use raylab::accel::AccelChoice;
    use raylab::scene::file::Level;
    use raylab::scene::ObjFrame;

    /// A scene placing a mesh (whose bounds are found in parallel) loads while every thread
    /// of the pool the frames share is busy, as while a refinement renders: on that pool
    /// its work waited for them.
    #[test]
    fn a_load_goes_on_while_the_shared_pool_is_busy() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(
            dir.path().join("pyramid.obj"),
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\nf 1 3 4\nf 2 3 4\n",
        )
        .unwrap();
        let scene = dir.path().join("s.scene");
        std::fs::write(&scene, "push\ntranslate 1 0 0\nmesh pyramid.obj\npop\n").unwrap();
        // Every thread of the shared pool held until the load has ended (or given up on).
        let (release, held) = std::sync::mpsc::channel::<()>();
        let held = std::sync::Mutex::new(held);
        let (busy, all_busy) = std::sync::mpsc::channel();
        let threads = rayon::current_num_threads();
        let holder = std::thread::spawn(move || {
            rayon::broadcast(|_| {
                busy.send(()).unwrap();
                let _ = held.lock().unwrap().recv();
            })
        });
        for _ in 0..threads {
            all_busy.recv().unwrap();
        }
        let (done, loaded) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            let stage = load_stage(&scene, ObjFrame::default(), AccelChoice::default());
            let _ = done.send(stage.map(|s| s.scene().len()));
        });
        // (A minute: where the load waited for the pool, it never ended while it was held.)
        let primitives = loaded.recv_timeout(std::time::Duration::from_secs(60));
        drop(release);
        holder.join().unwrap();
        assert_eq!(primitives, Ok(Ok(4)));
    }

    /// Levels at `depths`, each with one statement naming it.
    fn levels(named: &[(usize, &str)]) -> Vec<Level> {
        (named.iter())
            .map(|&(depth, name)| Level {
                line: 0,
                depth,
                statements: vec![(1, name.to_string())],
                world_from_object: [[0.0; 4]; 4],
                primitives: Vec::new(),
            })
            .collect()
    }

    /// A selected level stays itself through a reload: in place where the file keeps its
    /// levels (a statement edited), found by its statements where one was added before it,
    /// and none where it was removed (the tint moved to the next level).
    #[test]
    fn a_selected_level_is_followed_through_an_edit_or_dropped() {
        let old = levels(&[(0, "top"), (1, "a"), (1, "b"), (2, "c")]);
        let edited = levels(&[(0, "top"), (1, "a2"), (1, "b"), (2, "c")]);
        assert_eq!(same_level(&old, &edited, 1), Some(1));
        let added = levels(&[(0, "top"), (1, "new"), (1, "a"), (1, "b"), (2, "c")]);
        assert_eq!(same_level(&old, &added, 2), Some(3));
        let removed = levels(&[(0, "top"), (1, "b"), (2, "c")]);
        assert_eq!(same_level(&old, &removed, 1), None);
        assert_eq!(same_level(&old, &removed, 2), Some(1));
    }
}
