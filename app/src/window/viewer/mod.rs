//! The viewer's state: the scene, the camera controller, the panel's settings, the held
//! input, and the render worker with its refinement (preview while things change, then full
//! resolution, then full supersampling: levels 0, 1, 2). It knows nothing of egui-winit or
//! the GPU: the app hands it finished frames and asks it what to show.

use super::bounds::{fit_shown, samples_shown};
use super::input::InputState;
use super::values;
use super::worker::{self, Worker};
use super::AppEvent;
use raylab::accel::AccelChoice;
use raylab::check::code::CodeInspection;
use raylab::check::LabCode;
use raylab::controller::CameraController;
use raylab::render::inspect::Inspection;
use raylab::render::{self, LabStep, RenderSettings, RenderStats, Stage, MAX_SIDE};
use raylab::scene::ObjFrame;
use raylab::{Camera, Scene};
use std::path::PathBuf;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};
use winit::event_loop::EventLoopProxy;

mod loading;
mod outputs;

pub use outputs::command_in_status;

use loading::watch;

pub use loading::LoadRequest;

/// How long a refinement renders before the status line says how far it has come.
const SAY_PROGRESS_AFTER: Duration = Duration::from_secs(1);
/// How often the status line's progress is drawn again.
const PROGRESS_EVERY: Duration = Duration::from_millis(250);

/// The render resolution: a fraction of the image area, or fixed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Resolution {
    /// This fraction of the image area's physical pixels.
    WindowScale(f32),
    /// A fixed size.
    Fixed(u32, u32),
}

/// Everything on the panel that changes the image (besides the camera).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViewSettings {
    /// The image's controls ([`raylab::render::CONTROLS`]); the size in it is unused (each
    /// render's own size comes from `resolution`).
    pub controls: RenderSettings,
    pub resolution: Resolution,
    pub adaptive: bool,
    pub target_ms: f32,
    pub preview_scale: f32,
    pub light: [f32; 3],
    /// "your code" chosen in the method selector: the linked code answers the rays.
    pub yours: bool,
}

/// How long after the last change the viewer keeps previewing before it refines.
pub const SETTLE: Duration = Duration::from_millis(120);

/// What the status line says after R; it goes once the camera moves.
const CAMERA_RESET: &str = "camera back at its start (R)";

/// The image on screen.
pub struct Shown {
    pub generation: u64,
    pub level: u8,
    pub size: (u32, u32),
    /// Its supersampling, n per axis.
    pub spp: u32,
    pub stats: RenderStats,
    /// Its camera's focal length (pixels).
    pub focal: f64,
}

/// A rendered frame for the window to show.
pub struct NewFrame {
    pub width: u32,
    pub height: u32,
    pub rgba: Vec<u8>,
}

/// Everything the window shows besides egui and the GPU.
pub struct Viewer {
    proxy: EventLoopProxy<AppEvent>,
    pub stage: Stage,
    obj_frame: ObjFrame,
    /// The structure every scene opened is built with (`--accel`).
    accel: AccelChoice,
    pub controller: CameraController,
    pub view: ViewSettings,
    /// The light the scene shown came with (the panel's light is the view's), which a view
    /// naming no light takes.
    scene_light: [f32; 3],
    /// The model the window opened with is framed once the image's size is known (its
    /// first layout), as a model opened later is: `new` knows no size.
    frame_when_sized: bool,
    pub input: InputState,
    worker: Worker,
    /// Bumped by every change; the worker drops stale frames.
    pub generation: u64,
    last_change: Instant,
    last_update: Instant,
    pub shown: Option<Shown>,
    last_full_ms: Option<f64>,
    /// The image area beside the panel, in physical pixels.
    pub image_area: (u32, u32),
    /// The width of the area beside the side panel (physical pixels): the image area's, and
    /// the inspector's panel's where it is shown.
    pub beside_width: u32,
    /// The largest texture side of the graphics device: no render is larger.
    pub max_side: u32,
    /// A generation whose render failed: not submitted again (it would fail again).
    failed_generation: Option<u64>,
    pub show_help: bool,
    /// P hid the side panel (and its menu bar): the image takes the window.
    pub panel_hidden: bool,
    pub status: String,
    /// Whether the status is an error (drawn red).
    pub status_is_error: bool,
    /// Whether the status tells of the inspected pixel (an inspection, a crack stepped to):
    /// it then follows the pixel as the inspector does.
    pub status_follows_pixel: bool,
    /// Whether the status tells of a number field ([`Viewer::field_slip`],
    /// [`Viewer::field_taken`]).
    status_from_field: bool,
    /// Whether the status tells of the frame shown (N found no crack in it): the next change
    /// of the view clears it, as it would no longer be true.
    pub status_of_frame: bool,
    /// Whether the status line showed the whole message in the last UI pass.
    pub status_whole: bool,
    /// Whether it showed the frame's figures whole beside it.
    pub figures_whole: bool,
    /// The next render to finish fails (the script's `fail-render`).
    pub fail_next_render: bool,
    /// How often the event loop woke to refine (for the scripted run's final line).
    pub refine_wakes: u64,
    /// An error shown in red over the image until dismissed (a click on it, or Esc) or a
    /// scene loads.
    pub banner: Option<String>,
    /// The window listing every scene warning is open.
    pub show_all_warnings: bool,
    /// The panel's OBJ path field.
    pub obj_path: String,
    pub loading: bool,
    /// The load under way: its file (the scene shown after it, if it loads).
    running_load: Option<PathBuf>,
    /// A load asked for while another was under way, started as it was asked for when that
    /// one ends: the newest explicit load (open, a view) wins over everything asked for
    /// before it; a reload is kept only of the file that will be shown (an edit saved during
    /// a reload is loaded too).
    queued_load: Option<LoadRequest>,
    pub screenshots_pending: usize,
    /// Rendered frames that arrived while a key held the camera moving (the preview works).
    pub frames_while_moving: u64,
    /// Rendering paused (the window is minimised).
    pub paused: bool,
    /// The files watched for changes, shared with the watcher's thread: the one the scene
    /// came from (a reload keeps the camera), the meshes it names, a file that failed to open.
    watched: loading::Watched,
    /// The push level of a `.scene` file selected in the panel: its primitives are tinted.
    pub selected_level: Option<usize>,
    /// Whether a left click on the image inspects the pixel under it (I toggles).
    pub inspector_on: bool,
    /// Where the inspected pixel lay off the image when the status line last said so (the
    /// pixel chosen, off the view or only cropped, on the left): said once, not each frame.
    pub off_image_said: Option<((u32, u32), bool, bool)>,
    /// The inspected pixel's ray, in the world, as last answered ([`super::follow`]).
    pub inspection: Option<Inspection>,
    /// Linked code that is not raylab's ([`super::ViewerOptions::code`]).
    pub code: Option<Arc<dyn LabCode>>,
    /// The linked code's answer for the inspected pixel, beside the exact one.
    pub code_inspection: Option<CodeInspection>,
    /// The pixel the inspector follows ([`super::follow`]), and its crack.
    pub inspected: Option<super::inspected::Inspected>,
    pub crack: Option<super::inspected::Detail>,
    /// Whether the inspector's panel was drawn in the last UI pass.
    pub inspector_shown: bool,
    /// Whether it was drawn in a window of its own (over the side panel at first), the
    /// window too narrow for its panel.
    pub inspector_over: bool,
    /// The cracks of the frames shown, counted ([`super::cracks`]).
    pub cracks: super::cracks::Counter,
    /// Text to put on the clipboard in the next UI pass (copy as command).
    pub copy_request: Option<String>,
    /// The File menu and its dialog.
    pub files: super::files::FileMenu,
}

/// The colour selected primitives are tinted towards (linear RGB).
const HIGHLIGHT: [f32; 3] = [1.0, 0.45, 0.0];

impl Viewer {
    pub fn new(
        stage: Stage,
        scene_path: Option<&PathBuf>,
        (obj_frame, accel): (ObjFrame, AccelChoice),
        code: Option<Arc<dyn LabCode>>,
        proxy: EventLoopProxy<AppEvent>,
    ) -> Self {
        let wake = proxy.clone();
        let controller = CameraController::starting(stage.scene(), scene_path.is_none(), 4, 3);
        let watched = loading::Watched {
            source: Arc::new(Mutex::new(scene_path.cloned())),
            meshes: Arc::new(Mutex::new(stage.scene().mesh_files.clone())),
            failed: Arc::new(Mutex::new(None)),
        };
        let (shared, watcher) = (watched.clone(), proxy.clone());
        std::thread::spawn(move || watch(shared, watcher));
        let light = stage.scene().light.position;
        let cracks = super::cracks::Counter::new(proxy.clone());
        let frame_when_sized = scene_path.is_some() && stage.scene().camera.is_none();
        Self {
            proxy,
            stage,
            obj_frame,
            accel,
            controller,
            scene_light: light,
            frame_when_sized,
            view: ViewSettings {
                controls: RenderSettings {
                    step: LabStep::Indirect,
                    spp: 2,
                    ..Default::default()
                },
                resolution: Resolution::WindowScale(1.0),
                adaptive: true,
                target_ms: 16.0,
                preview_scale: 0.5,
                light,
                yours: code.is_some(),
            },
            input: InputState::default(),
            worker: Worker::new(move || {
                let _ = wake.send_event(AppEvent::FrameReady);
            }),
            generation: 0,
            last_change: Instant::now(),
            last_update: Instant::now(),
            shown: None,
            last_full_ms: None,
            image_area: (640, 480),
            beside_width: 640,
            max_side: MAX_SIDE,
            failed_generation: None,
            show_help: false,
            panel_hidden: false,
            status_from_field: false,
            status_of_frame: false,
            status: String::new(),
            status_is_error: false,
            status_follows_pixel: false,
            status_whole: true,
            figures_whole: true,
            fail_next_render: false,
            refine_wakes: 0,
            banner: None,
            show_all_warnings: false,
            obj_path: scene_path
                .map(|p| p.display().to_string())
                .unwrap_or_default(),
            loading: false,
            running_load: None,
            queued_load: None,
            screenshots_pending: 0,
            frames_while_moving: 0,
            paused: false,
            watched,
            selected_level: None,
            inspector_on: true,
            off_image_said: None,
            inspection: None,
            code,
            code_inspection: None,
            inspected: None,
            crack: None,
            inspector_shown: false,
            inspector_over: false,
            cracks,
            copy_request: None,
            files: Default::default(),
        }
    }

    /// Selects a push level of the scene tree (its primitives are tinted), or none.
    pub fn select_level(&mut self, level: Option<usize>) {
        let level = level.filter(|l| *l < self.stage.scene().levels.len());
        if level != self.selected_level {
            self.selected_level = level;
            self.changed();
        }
    }

    /// The stage as `raylab render` and `inspect` take it: the scene with the panel's light.
    pub(super) fn stage_lit(&mut self) -> Stage {
        let light = self.view.light;
        if self.stage.scene().light.position != light {
            self.stage.restyle(|scene| scene.light.position = light);
        }
        self.stage.clone()
    }

    /// The stage as rendered: [`Viewer::stage_lit`], the primitives the selected level
    /// places tinted, its nested levels' too (the same structure: neither moves a primitive).
    pub(super) fn stage_to_render(&mut self) -> Stage {
        let mut tinted = self.stage_lit();
        let levels = &self.stage.scene().levels;
        let Some(chosen) = self.selected_level.filter(|&l| l < levels.len()) else {
            return tinted;
        };
        // (The levels after it that are deeper, up to the next at its depth or above.)
        let depth = levels[chosen].depth;
        let nested = levels[chosen + 1..].iter().take_while(|l| l.depth > depth);
        let placed: Vec<_> = std::iter::once(&levels[chosen])
            .chain(nested)
            .flat_map(|l| l.primitives.iter().cloned())
            .collect();
        let mix = |c: [f32; 3]| [0, 1, 2].map(|k| 0.35 * c[k] + 0.65 * HIGHLIGHT[k]);
        tinted.restyle(|scene| {
            for range in &placed {
                match scene.instances().is_empty() {
                    true => {
                        for c in &mut scene.colors_mut()[range.start as usize..range.end as usize] {
                            *c = mix(*c);
                        }
                    }
                    // An instance is tinted as a whole (its mesh's colours are shared).
                    false => scene.tint(range.clone(), mix(raylab::scene::file::DEFAULT_COLOR)),
                }
            }
        });
        tinted
    }

    /// A message for the panel (and the log, so scripted runs can be checked).
    pub fn set_status(&mut self, message: impl Into<String>) {
        self.status = message.into();
        (self.status_is_error, self.status_follows_pixel) = (false, false);
        (self.status_from_field, self.status_of_frame) = (false, false);
        log::info!("{}", self.status);
    }

    /// Says in the status whether the ray inspector is on, as I or its check box left it.
    pub fn say_inspector(&mut self) {
        let state = ["off", "on"][self.inspector_on as usize];
        self.set_status(format!("ray inspector {state}"));
    }

    /// A number field's slip (text that is not a number, a number past its range) in red
    /// in the status line, once: the eye is on the field, no banner over the image.
    pub fn field_slip(&mut self, message: String) {
        if !(self.status_is_error && self.status == message) {
            self.status = message;
            (self.status_is_error, self.status_follows_pixel) = (true, false);
            self.status_from_field = true;
            log::warn!("{}", self.status);
        }
    }

    /// The view changed by other means than a field (R, the wheel, the panel's other rows):
    /// a field's slip on the status line ("focal length: 1e12 ... it took 39700") no longer
    /// describes the field, and goes.
    pub fn field_slip_outdated(&mut self) {
        if self.status_from_field && self.status_is_error {
            self.status.clear();
            (self.status_is_error, self.status_from_field) = (false, false);
        }
    }

    /// A number field took what was typed: the status line says what was set. (It said so
    /// only over an earlier field's words: a student typing a pitch or a light's x saw
    /// nothing, where a value typed after a slip was confirmed.)
    pub fn field_taken(&mut self, message: String) {
        if self.status != message {
            self.set_status(message);
            self.status_from_field = true;
        }
    }

    /// An error: in the status line and in the banner over the image, where the eye is.
    pub fn report_error(&mut self, message: impl Into<String>) {
        self.status = message.into();
        (self.status_is_error, self.status_follows_pixel) = (true, false);
        self.status_from_field = false;
        self.banner = Some(self.status.clone());
        log::warn!("{}", self.status);
    }

    /// Something that changes the image changed: start over from a preview.
    pub fn changed(&mut self) {
        self.generation += 1;
        self.last_change = Instant::now();
        self.worker.set_generation(self.generation);
        self.cracks.cancel();
        if std::mem::take(&mut self.status_of_frame) {
            self.status.clear();
        }
    }

    /// Frames the model the window opened with for the image's size, once it is known.
    pub fn frame_for_image(&mut self) {
        if !std::mem::take(&mut self.frame_when_sized) {
            return;
        }
        if let Some(bounds) = self.stage.scene().bounds() {
            let (w, h) = self.uncropped_size();
            self.controller = CameraController::framing(bounds, w, h);
            self.changed();
        }
    }

    /// Moves the camera by the keys held since the last call (each for as long as it was
    /// held: a press and release a slow frame took together still moves), and by the mouse
    /// and wheel.
    pub fn update_camera(&mut self) {
        let now = Instant::now();
        let since = now.duration_since(self.last_update).as_secs_f64();
        let step = since.min(CameraController::LONGEST_STEP);
        self.last_update = now;
        let control = self.input.take(now, step);
        if self.controller.update(&control, step) {
            self.camera_moved();
            self.changed();
        }
    }

    /// The camera moved (keys, mouse, wheel, a field dragged): R's "camera back at its start"
    /// no longer describes it, and goes.
    pub fn camera_moved(&mut self) {
        if self.status == CAMERA_RESET {
            self.status.clear();
        }
    }

    /// R or the panel's button: back to the starting pose, where motion not yet taken (a key
    /// released since the last frame) is spent first rather than moving it from there.
    pub fn reset_camera(&mut self) {
        self.update_camera();
        self.controller.reset();
        // (A field's "camera y set to 5" stayed up under the camera it no longer described.)
        self.set_status(CAMERA_RESET);
    }

    /// The status line's word for the lab step shown (a key or the panel's radio buttons).
    pub fn say_step(&mut self) {
        self.set_status(format!("lab step {}", self.view.controls.step.label()));
    }

    /// The status line's word for a drop-down or check box of the panel that changed the
    /// image (the method, the cracks view, a resolution chosen from the list): the status
    /// kept the message before ("supersampling set to 2" over a method chosen).
    pub fn say_setting(&mut self, was: &ViewSettings) {
        let (now, was) = (&self.view, was);
        let chosen = |r: Resolution| matches!(r, Resolution::Fixed(..));
        let said = if (now.controls.method, now.yours) != (was.controls.method, was.yours) {
            let name = match (&self.code, now.yours) {
                (Some(code), true) => code.name().to_string(),
                _ => now.controls.method.name().to_string(),
            };
            format!("ray/triangle method: {name}")
        } else if now.controls.cracks != was.controls.cracks {
            format!(
                "show cracks {}",
                ["off", "on"][now.controls.cracks as usize]
            )
        } else if now.resolution != was.resolution
            && (chosen(now.resolution) || chosen(was.resolution))
        {
            match now.resolution {
                Resolution::Fixed(w, h) => format!("resolution {w}x{h}"),
                Resolution::WindowScale(_) => "resolution: the scale of the window".into(),
            }
        } else {
            return;
        };
        self.set_status(said);
    }

    /// What the panel can change, to tell afterwards whether it did.
    pub fn panel_state(&self) -> (ViewSettings, CameraController, (u32, u32), u32) {
        let size = self.full_size();
        (self.view, self.controller, size, self.focal_width())
    }

    /// The full render size for the current image area and resolution setting. Where the
    /// inspector's panel crops the image's sides, the crop is even (one column less where it
    /// would be odd): each pixel shown is then the pixel [`Viewer::view_offset`] further right
    /// of the view F5 and copy as command write, the same ray.
    pub fn full_size(&self) -> (u32, u32) {
        self.shown_in_view().0
    }

    /// How many columns of the view F5 and copy as command write lie left of the image shown:
    /// half the inspector's panel's crop (0 uncropped or at a fixed size). A pixel the
    /// inspector names is the view's, as `raylab inspect --pixel` with that view names it.
    pub fn view_offset(&self) -> u32 {
        self.shown_in_view().1
    }

    /// The full render size shown ([`Viewer::full_size`]) and its offset in the view
    /// ([`Viewer::view_offset`]). (At a fixed size the view is the size shown: no crop.)
    fn shown_in_view(&self) -> ((u32, u32), u32) {
        let (w, h) = self.size_for(self.image_area);
        let (view_w, view_h) = self.uncropped_size();
        if view_h != h || view_w <= w {
            return ((w, h), 0);
        }
        let w = match (view_w - w) % 2 == 1 && w > 1 {
            true => w - 1,
            false => w,
        };
        ((w, h), (view_w - w) / 2)
    }

    /// The full render size for an image area of `area` physical pixels.
    fn size_for(&self, area: (u32, u32)) -> (u32, u32) {
        let clamp = |x: f32| (x.round() as u32).clamp(1, MAX_SIDE);
        match self.view.resolution {
            Resolution::WindowScale(s) => {
                let s = s.clamp(0.05, 1.0);
                let (w, h) = (area.0 as f32 * s, area.1 as f32 * s);
                fit_shown((clamp(w), clamp(h)), self.max_side)
            }
            Resolution::Fixed(w, h) => fit_shown((w, h), self.max_side),
        }
    }

    /// The width the focal length is a fraction of ([`CameraController::focal_ratio`]): the
    /// full render width the image would have without the inspector's panel. That panel
    /// opening narrows the image and crops the view's sides; the focal length stays.
    pub fn focal_width(&self) -> u32 {
        self.uncropped_size().0
    }

    /// The full render size the image would have without the inspector's panel.
    fn uncropped_size(&self) -> (u32, u32) {
        let beside = self.beside_width.max(self.image_area.0);
        self.size_for((beside, self.image_area.1))
    }

    /// The focal length (pixels) of a render `width` pixels wide of the view as now set up
    /// (the full render's, scaled), as the short decimal it was set as ([`values::clean`]).
    pub fn focal(&self, width: u32) -> f64 {
        let full = self.full_size().0;
        let f = self.controller.focal(self.focal_width());
        values::clean(match width == full {
            true => f,
            false => f * width as f64 / full as f64,
        })
    }

    /// Sets the focal length (pixels of the full render) as the panel's slider does.
    pub fn set_focal(&mut self, focal: f64) {
        let width = self.focal_width();
        self.controller.set_focal(focal, width);
    }

    /// The camera of a render `width` pixels wide of the view as now set up.
    pub fn camera(&self, width: u32) -> Camera {
        self.camera_with_focal(self.focal(width))
    }

    /// The camera as now posed, with focal length `focal` (pixels).
    pub fn camera_with_focal(&self, focal: f64) -> Camera {
        // (The controller's camera at width 1: `focal_ratio` × 1 is `focal` exactly.)
        let mut c = self.controller;
        c.focal_ratio = focal;
        c.camera(1)
    }

    /// The supersampling the window renders at its full size ([`super::bounds`]).
    pub fn spp_shown(&self) -> u32 {
        samples_shown(self.view.controls.spp, self.full_size())
    }

    /// The last refinement level: full supersampling where there is some to do.
    pub fn max_level(&self) -> u8 {
        if self.spp_shown() > 1 {
            2
        } else {
            1
        }
    }

    /// Whether the frame shown has the shape of the image area as laid out now, so a click
    /// on it can be mapped to a pixel of the full-size image: not in the frame or two after
    /// the inspector's panel opens or closes (or the window is resized), which draw the last
    /// frame squeezed into the new area. (A preview is a scaled frame: the same shape within
    /// a pixel.) Where the render failed no other frame comes, and the one shown is taken.
    pub fn shown_fits_layout(&self) -> bool {
        let (fw, fh) = self.full_size();
        let fits = |s: &Shown| {
            let (sw, sh) = (s.size.0 as u64, s.size.1 as u64);
            (sw * fh as u64).abs_diff(sh * fw as u64) <= fw.max(fh) as u64
        };
        let failed = self.failed_generation == Some(self.generation);
        failed || self.shown.as_ref().is_some_and(fits)
    }

    /// Whether the frame shown is of the full size laid out now (not a preview): where a click
    /// kept for a fitting frame ([`Viewer::shown_fits_layout`]) is mapped to its pixel, the
    /// pixel drawn under the pointer to the pixel. (As there, a failed render is taken.)
    pub fn shown_full_size(&self) -> bool {
        let failed = self.failed_generation == Some(self.generation);
        failed
            || self
                .shown
                .as_ref()
                .is_some_and(|s| s.size == self.full_size())
    }

    /// Whether the newest generation is shown fully refined.
    pub fn is_refined(&self) -> bool {
        self.shown
            .as_ref()
            .is_some_and(|s| s.generation == self.generation && s.level >= self.max_level())
    }

    /// Whether no render is running.
    pub fn is_idle(&self) -> bool {
        self.worker.is_idle()
    }

    /// How far the refinement being rendered has come, once it has taken long enough to
    /// say ([`SAY_PROGRESS_AFTER`]).
    pub fn progress(&self) -> Option<worker::Progress> {
        (self.worker.progress()).filter(|p| p.since.elapsed() >= SAY_PROGRESS_AFTER)
    }

    /// When to draw again for the status line's progress of a long refinement, the last
    /// frame drawn at `drawn`.
    pub fn progress_redraw_at(&self, drawn: Instant) -> Option<Instant> {
        let since = self.worker.progress()?.since;
        Some((drawn + PROGRESS_EVERY).max(since + SAY_PROGRESS_AFTER))
    }

    /// When to wake to start refining (the preview has settled), if anything is left to do.
    pub fn refine_at(&self) -> Option<Instant> {
        // (Not while paused: nothing renders then, and waking for it would spin.)
        // (Nor after this generation's render failed: it is not submitted again until
        // something changes, and waking for it would redraw without end.)
        let idle = self.worker.is_idle() && !self.paused;
        let failed = self.failed_generation == Some(self.generation);
        (!self.is_refined() && idle && !failed).then_some(self.last_change + SETTLE)
    }

    /// The preview size: a fixed fraction, or (adaptive) what the last full frame's time says
    /// will hold the target frame time.
    fn preview_size(&self) -> (u32, u32) {
        let (w, h) = self.full_size();
        let scale = if self.view.adaptive {
            match self.last_full_ms {
                Some(ms) if ms > 0.0 => {
                    ((self.view.target_ms as f64 / ms).sqrt() as f32).clamp(0.1, 1.0)
                }
                _ => 0.5,
            }
        } else {
            self.view.preview_scale.clamp(0.05, 1.0)
        };
        (
            ((w as f32 * scale) as u32).max(1),
            ((h as f32 * scale) as u32).max(1),
        )
    }

    /// The render settings at size `(w, h)` with `spp` samples per axis.
    pub(super) fn settings(&self, (width, height): (u32, u32), spp: u32) -> RenderSettings {
        RenderSettings {
            width,
            height,
            spp,
            ..self.view.controls
        }
    }

    /// Submits the next render if the worker is free and something is left to do.
    pub fn pump(&mut self) {
        let failed = self.failed_generation == Some(self.generation);
        if !self.worker.is_idle() || self.paused || failed {
            return;
        }
        log::trace!("pump: generation {}", self.generation);
        let settling = self.last_change.elapsed() < SETTLE || self.input.is_moving();
        let level = match &self.shown {
            Some(s) if s.generation == self.generation => {
                if settling || s.level >= self.max_level() {
                    return;
                }
                s.level + 1
            }
            _ if settling => 0,
            _ => 1,
        };
        let size = match level {
            0 => self.preview_size(),
            _ => self.full_size(),
        };
        let stage = self.stage_to_render();
        let spp = if level == 2 { self.spp_shown() } else { 1 };
        self.worker.submit(worker::Job {
            stage,
            camera: self.camera(size.0),
            settings: self.settings(size, spp),
            code: self.code.clone().filter(|_| self.view.yours),
            generation: self.generation,
            level,
            view_offset: self.view_offset(),
        });
    }

    /// Takes the worker's newest frame: `None` where none finished, `Some(None)` where it
    /// has nothing to show (cancelled, or failed: the status says why).
    pub fn take_frame(&mut self) -> Option<Option<NewFrame>> {
        let mut done = self.worker.take_latest()?;
        if matches!(done.image, Ok(Some(_))) && std::mem::take(&mut self.fail_next_render) {
            done.image = Err("injected by the script".into());
        }
        Some(match done.image {
            Ok(None) => None, // cancelled by a newer change
            Ok(Some((rgba, stats))) => {
                let s = done.job.settings;
                if done.job.level == 1 {
                    self.last_full_ms = Some(stats.elapsed.as_secs_f64() * 1e3);
                }
                if self.input.is_moving() {
                    self.frames_while_moving += 1;
                }
                self.shown = Some(Shown {
                    generation: done.job.generation,
                    level: done.job.level,
                    size: (s.width, s.height),
                    spp: s.spp,
                    stats,
                    focal: done.job.camera.focal,
                });
                // (A preview is not counted: the counts are of the views that settle.)
                if s.cracks && done.job.level > 0 {
                    let last = done.job.level >= self.max_level();
                    self.cracks.submit(done.job.clone(), last);
                }
                Some(NewFrame {
                    width: s.width,
                    height: s.height,
                    rgba,
                })
            }
            Err(e) => {
                self.failed_generation = Some(done.job.generation);
                self.report_error(format!("render failed: {e}"));
                None
            }
        })
    }

    /// A digit key: the lab step of that number (the panel's radio buttons). Step 2 is the
    /// camera, which moves in every step: the status line says so.
    pub fn choose_step(&mut self, number: u32) {
        match LabStep::ALL.into_iter().find(|s| s.number() == number) {
            Some(step) => {
                self.view.controls.step = step;
                self.say_step();
                self.changed();
            }
            None => self.set_status(
                "lab step 2 is the camera: fly it in any step (1, 3, 4, 5 choose the shading)",
            ),
        }
    }
}
