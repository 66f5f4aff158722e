//! A view that leaves the window: the scene, the camera and the render settings in a small
//! text file (`.view`), which `raylab render --view FILE` renders headless and the window
//! loads back. One statement per line, `#` comments:
//! ```text
//! scene cornell | PATH             the built-in box, or a .scene / OBJ file
//! obj-frame yup|lab                how an OBJ's coordinates are read
//! camera x y z yaw DEG pitch DEG [fov DEG]
//! focal F                          the focal length in pixels at the view's width (else the
//!                                  camera's fov; not both)
//! light x y z                      the point light's position
//! size W H                         the image in pixels
//! step flat|direct|shadows|indirect
//! spp N                            N×N samples per pixel
//! method adaptive|watertight|moller|cramer
//! cracks on|off
//! ```
//! Without `camera` the scene is seen from where it starts (a `.scene` file's camera, the lab's
//! for the box, else one framing the model), without `light` by its own light: as
//! `raylab render --scene` renders it.
//! `step` onwards are the image's controls, one `NAME VALUE` line per row of
//! [`crate::render::CONTROLS`]: the file reads and writes them through that table, as the
//! command line's flags and the window's panel do.
//! A path with spaces, `#` or quotes is written in double quotes (`crate::words`), so any file
//! name round-trips. Numbers are written in Rust's shortest round-trip form, so a saved view
//! reads back to the same f64 values; the window writes the focal length itself (a field of
//! view gave it back only within an ulp: 499.9999999999999 for 500).

use crate::render::settings::Kind;
use crate::render::{RenderSettings, CONTROLS};
use crate::scene::file::{FileError, SceneCamera};
use crate::scene::ObjFrame;

/// Everything a window view holds that a render needs.
#[derive(Clone, Debug, PartialEq)]
pub struct View {
    /// `cornell` or a file path.
    pub scene: String,
    pub obj_frame: ObjFrame,
    /// `None`: the scene's starting camera.
    pub camera: Option<SceneCamera>,
    /// `None`: the scene's light.
    pub light: Option<[f32; 3]>,
    /// The focal length in pixels at the view's width (`None`: the camera's field of view).
    pub focal: Option<f64>,
    pub settings: RenderSettings,
}

impl View {
    /// The scene this view names, as a name [`crate::scene::Scene::open`] takes: `cornell`,
    /// or the path as written where it exists from here, else the same path beside the view
    /// file at `view_file` (the rule for the command line and the window alike).
    pub fn scene_path(&self, view_file: &std::path::Path) -> String {
        let spec = &self.scene;
        let beside = view_file
            .parent()
            .unwrap_or(std::path::Path::new(""))
            .join(spec);
        match spec != crate::scene::CORNELL
            && !std::path::Path::new(spec).exists()
            && beside.exists()
        {
            true => beside.display().to_string(),
            false => spec.clone(),
        }
    }

    /// The file text.
    pub fn to_text(&self) -> String {
        let s = &self.settings;
        let mut out =
            String::from("# raylab view: `raylab render --view FILE -o out.png` renders it\n");
        out += &format!("scene {}\n", crate::words::quoted(&self.scene));
        let frame = match self.obj_frame {
            ObjFrame::YUp => "yup",
            ObjFrame::Lab => "lab",
        };
        out += &format!("obj-frame {frame}\n");
        if let Some(c) = &self.camera {
            let p = c.position;
            out += &format!(
                "camera {} {} {} yaw {} pitch {}",
                p[0], p[1], p[2], c.yaw, c.pitch
            );
            if let Some(fov) = c.fov {
                out += &format!(" fov {fov}");
            }
            out += "\n";
        }
        if let Some(f) = self.focal {
            out += &format!("focal {f}\n");
        }
        if let Some(l) = self.light {
            out += &format!("light {} {} {}\n", l[0], l[1], l[2]);
        }
        out += &format!("size {} {}\n", s.width, s.height);
        for control in &CONTROLS {
            out += &format!("{} {}\n", control.name, control.text(s));
        }
        out
    }

    /// The `raylab render` command that renders this view to `out` (the window's "copy as
    /// command"): every setting as a flag, numbers in shortest round-trip form, paths quoted
    /// for a POSIX shell where they need it. A view without a camera gives no camera flags.
    pub fn to_command(&self, out: &str) -> String {
        let width = self.settings.width as f64;
        let camera = self.camera.map_or(width, |c| c.focal_ratio() * width);
        let focal = self.focal.unwrap_or(camera);
        let s = &self.settings;
        let mut args = vec!["raylab".to_string(), "render".into()];
        // (`--name=value`: a negative number is then never taken for a flag.)
        // (A toggle is a bare `--name`, given when on.)
        let mut flag = |name: &str, value: Option<String>| {
            args.push(match value {
                Some(value) => format!("--{name}={value}"),
                None => format!("--{name}"),
            })
        };
        flag("scene", Some(shell_quote(&self.scene)));
        if self.obj_frame == ObjFrame::Lab {
            flag("obj-frame", Some("lab".into()));
        }
        if let Some(c) = &self.camera {
            let p = c.position;
            flag("camera", Some(format!("{},{},{}", p[0], p[1], p[2])));
            flag("yaw", Some(c.yaw.to_string()));
            flag("pitch", Some(c.pitch.to_string()));
        }
        if self.camera.is_some() || self.focal.is_some() {
            flag("focal", Some(focal.to_string()));
        }
        if let Some(l) = self.light {
            flag("light", Some(format!("{},{},{}", l[0], l[1], l[2])));
        }
        flag("width", Some(s.width.to_string()));
        flag("height", Some(s.height.to_string()));
        for control in &CONTROLS {
            match control.kind {
                Kind::Toggle { get, .. } if !get(s) => {}
                Kind::Toggle { .. } => flag(control.name, None),
                _ => flag(control.name, Some(control.text(s))),
            }
        }
        args.push("-o".into());
        args.push(shell_quote(out));
        args.join(" ")
    }

    /// Parses view text; errors name the file and line.
    pub fn parse(file: &str, text: &str) -> Result<View, FileError> {
        let mut view = View {
            scene: "cornell".into(),
            obj_frame: ObjFrame::YUp,
            camera: None,
            light: None,
            focal: None,
            settings: RenderSettings::default(),
        };
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        // Each statement's line, for a second one: the last had won unseen (a `.scene` file
        // refuses a second camera too).
        let mut first = std::collections::HashMap::<String, usize>::new();
        for (i, raw) in text.lines().enumerate() {
            let error = |message| FileError {
                file: file.to_string(),
                line: i + 1,
                message,
            };
            let words = crate::words::words(raw).map_err(error)?;
            if words.is_empty() {
                continue;
            }
            let w: Vec<&str> = words.iter().map(String::as_str).collect();
            if let Some(line) = first.insert(w[0].to_string(), i + 1) {
                let said = format!("a second `{}` (the first on line {line}): one each", w[0]);
                return Err(error(said));
            }
            // (Checked after every line, so a size or spp out of range names its own line.)
            let checked = view
                .statement(&w)
                .and_then(|()| (view.settings.validate()).map_err(|e| format!("{}: {e}", w[0])));
            checked.map_err(error)?;
        }
        if let (Some(line), Some(true)) = (first.get("focal"), view.camera.map(|c| c.fov.is_some()))
        {
            return Err(FileError {
                file: file.to_string(),
                line: *line,
                message: "focal and the camera's fov both set the lens: give one".into(),
            });
        }
        // (A file left empty or cut short by a failed save would render the defaults, as if
        // it were the view.)
        if first.is_empty() {
            return Err(FileError {
                file: file.to_string(),
                line: text.lines().count().max(1),
                message: "not one statement: a view names at least one of its scene, camera, \
                          light, size or a control (`scene cornell` is the lab's box)"
                    .into(),
            });
        }
        Ok(view)
    }

    fn statement(&mut self, w: &[&str]) -> Result<(), String> {
        let num = |s: &str| -> Result<f64, String> {
            match s.parse::<f64>() {
                Ok(x) if x.is_finite() => Ok(x),
                _ => Err(format!("'{s}' is not a finite number")),
            }
        };
        let int = |s: &str| {
            s.parse::<u32>()
                .map_err(|_| format!("'{s}' is not a whole number"))
        };
        let want = |n: usize| match w.len() == n {
            true => Ok(()),
            false => Err(format!(
                "{} needs {}, found {}",
                w[0],
                crate::words::count(n - 1, "value", "values"),
                w.len() - 1
            )),
        };
        match w[0] {
            "scene" => {
                if w.len() < 2 {
                    return Err("scene needs `cornell` or a path".into());
                }
                // (Unquoted words joined by one space: what views written before paths were
                // quoted hold for a name with spaces.)
                self.scene = w[1..].join(" ");
            }
            "obj-frame" => {
                want(2)?;
                self.obj_frame = w[1].parse()?;
            }
            "camera" => {
                // The .scene statement's syntax, its words joined again: a quoted word with a
                // space, a `#` or a line break in it would be read as other words.
                let plain = |word: &&str| {
                    !word.is_empty() && !word.contains(|c: char| c.is_whitespace() || c == '#')
                };
                if !w.iter().all(plain) {
                    return Err("camera takes plain numbers and words, none quoted".into());
                }
                let text = w.join(" ");
                let d = crate::scene::file::parse::<f32>(
                    "",
                    &text,
                    std::path::Path::new(""),
                    &|_, _, _| Err("no meshes in a view".to_string()),
                )
                .map_err(|e| e.message)?;
                if let Some(e) = d.beyond_view {
                    return Err(e.message);
                }
                self.camera = Some(d.camera.expect("a camera statement"));
            }
            "focal" => {
                want(2)?;
                let f = num(w[1])?;
                let (lo, hi) = crate::camera::FOCAL_RANGE;
                if !(lo..=hi).contains(&f) {
                    // (As written: 1e-400 reads as 0.)
                    return Err(format!("focal {} px is outside [{lo}, {hi}]", w[1]));
                }
                self.focal = Some(f);
            }
            "light" => {
                want(4)?;
                let l = [num(w[1])?, num(w[2])?, num(w[3])?];
                let max = crate::math::MAX_VIEW_COORDINATE;
                crate::math::check_range("light position", l, max)?;
                self.light = Some(l.map(|x| x as f32));
            }
            "size" => {
                want(3)?;
                (self.settings.width, self.settings.height) = (int(w[1])?, int(w[2])?);
            }
            name => match crate::render::settings::control(name) {
                Some(control) => {
                    want(2)?;
                    control.set_text(&mut self.settings, w[1])?;
                }
                None => {
                    return Err(format!(
                        "unknown view statement '{name}' (expected scene, obj-frame, camera, \
                         focal, light, size, {})",
                        crate::render::settings::control_names()
                    ))
                }
            },
        }
        Ok(())
    }
}

/// `word` as one POSIX shell word: as is when it holds only characters no shell treats
/// specially, else in single quotes (a `'` inside written `'\''`).
pub fn shell_quote(word: &str) -> String {
    let plain = |c: char| c.is_ascii_alphanumeric() || "_-./,:=+@%".contains(c);
    if !word.is_empty() && word.chars().all(plain) {
        word.to_string()
    } else {
        format!("'{}'", word.replace('\'', "'\\''"))
    }
}
