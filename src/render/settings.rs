//! Everything a render needs besides the scene and camera, in one struct
//! ([`RenderSettings`]), and the image's controls listed once ([`CONTROLS`]): every setting
//! besides the scene, the camera, the light and the size that changes the image, each row
//! naming its field and how its value is written. Everything that reads or writes settings
//! goes through the table: the `.view` file (`NAME VALUE`), copy-as-command and the `raylab
//! render` flags (`--NAME=VALUE`, a toggle as a bare `--NAME`), the window's panel (one
//! widget per row) and a scripted run's `set NAME VALUE`.
//!
//! A new control is a field of [`RenderSettings`] with its default and a row in
//! [`CONTROLS`], here, and the code that uses it.

use crate::geometry::Method;
use std::fmt;
use std::str::FromStr;

/// Largest accepted image side in pixels.
pub const MAX_SIDE: u32 = crate::limits::MAX_IMAGE_SIDE;
/// Largest accepted image area in pixels (a 16k × 8k image: 512 MiB of RGBA8).
pub const MAX_PIXELS: u64 = 1 << 27;
/// Largest supersampling factor per axis (16 × 16 = 256 rays per pixel).
pub const MAX_SPP: u32 = 16;

/// The lab's shading steps (the camera step is the camera itself, not a shading step).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum LabStep {
    /// Step 1: the colour of the closest surface, no light.
    #[default]
    Flat,
    /// Step 3: direct light from the point light, ρ·P·max(n·r̂, 0)/(4πr²).
    Direct,
    /// Step 4: direct light blocked by a shadow ray.
    Shadows,
    /// Step 5: shadows plus the lab's constant indirect term, ρ·(D + N).
    Indirect,
}

impl LabStep {
    /// All steps in lab order.
    pub const ALL: [LabStep; 4] = [
        LabStep::Flat,
        LabStep::Direct,
        LabStep::Shadows,
        LabStep::Indirect,
    ];

    /// The CLI / UI name.
    pub fn name(self) -> &'static str {
        match self {
            LabStep::Flat => "flat",
            LabStep::Direct => "direct",
            LabStep::Shadows => "shadows",
            LabStep::Indirect => "indirect",
        }
    }

    /// The lab's number for the step: 1, 3, 4, 5 (step 2 is moving the camera, which every
    /// step does; it has no shading of its own).
    pub fn number(self) -> u32 {
        match self {
            LabStep::Flat => 1,
            LabStep::Direct => 3,
            LabStep::Shadows => 4,
            LabStep::Indirect => 5,
        }
    }

    /// The panel's label: the lab's number and the name (`3 direct`).
    pub fn label(self) -> &'static str {
        match self {
            LabStep::Flat => "1 flat",
            LabStep::Direct => "3 direct",
            LabStep::Shadows => "4 shadows",
            LabStep::Indirect => "5 indirect",
        }
    }

    /// Whether the step's colour holds the direct light D (ρ·D from step 3 on).
    pub fn uses_direct(self) -> bool {
        self != LabStep::Flat
    }

    /// Whether the step's colour holds the lab's constant indirect light N (ρ·(D + N)).
    pub fn uses_indirect(self) -> bool {
        self == LabStep::Indirect
    }

    /// The terms the step's colour is made of, as the inspector names them (`rho D N`).
    pub fn colour_terms(self) -> &'static str {
        match (self.uses_direct(), self.uses_indirect()) {
            (false, _) => "rho",
            (true, false) => "rho D",
            (true, true) => "rho D N",
        }
    }

    /// Whether the step casts shadow rays.
    pub fn casts_shadows(self) -> bool {
        matches!(self, LabStep::Shadows | LabStep::Indirect)
    }

    /// One line for the UI and `--help`.
    pub fn explanation(self) -> &'static str {
        match self {
            LabStep::Flat => "colour of the closest surface, no light",
            LabStep::Direct => "point light: colour * P max(n . r/|r|, 0) / (4 pi |r|^2)",
            LabStep::Shadows => "direct light, blocked where a shadow ray hits something",
            LabStep::Indirect => "shadows plus the lab's constant indirect light N",
        }
    }
}

impl fmt::Display for LabStep {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for LabStep {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        LabStep::ALL
            .into_iter()
            .find(|m| m.name() == s)
            .ok_or_else(|| {
                format!("unknown step '{s}' (expected flat, direct, shadows or indirect)")
            })
    }
}

/// Render parameters.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RenderSettings {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Lab step (shading).
    pub step: LabStep,
    /// Supersampling: n × n stratified samples per pixel.
    pub spp: u32,
    /// Ray/triangle method.
    pub method: Method,
    /// Trace camera rays of small scenes against only the triangles whose screen bounds meet
    /// each 16×16 tile (same image, faster); off only to measure what it saves.
    pub tile_culling: bool,
    /// The "cracks" view: paint magenta every camera ray that `method` lets through where the
    /// exact adaptive method hits (or the reverse), so the lecture's method can be seen
    /// leaking at shared edges ([`crate::render::is_crack`]).
    pub cracks: bool,
}

impl Default for RenderSettings {
    fn default() -> Self {
        Self {
            width: 640,
            height: 480,
            step: LabStep::Flat,
            spp: 1,
            method: Method::Adaptive,
            tile_culling: true,
            cracks: false,
        }
    }
}

/// A setting out of range.
#[derive(Debug, thiserror::Error, PartialEq, Eq)]
pub enum SettingsError {
    /// Width or height 0 or too large.
    #[error("image size {0}x{1} is out of range (each side 1..={MAX_SIDE}, at most {MAX_PIXELS} pixels)")]
    Size(u32, u32),
    /// Supersampling out of range.
    #[error("supersampling {0} is out of range (1..={MAX_SPP} samples per axis)")]
    Spp(u32),
    /// The pixel buffer does not fit the image.
    #[error("pixel buffer holds {0} bytes, the {1}x{2} RGBA8 image needs {3}")]
    Buffer(usize, u32, u32, usize),
    /// A pixel outside the image.
    #[error("pixel ({0}, {1}) is outside the {2}x{3} image")]
    Pixel(u32, u32, u32, u32),
}

impl RenderSettings {
    /// Checks sizes and sampling.
    pub fn validate(&self) -> Result<(), SettingsError> {
        let (w, h) = (self.width, self.height);
        if w == 0 || h == 0 || w > MAX_SIDE || h > MAX_SIDE || w as u64 * h as u64 > MAX_PIXELS {
            return Err(SettingsError::Size(w, h));
        }
        if self.spp == 0 || self.spp > MAX_SPP {
            return Err(SettingsError::Spp(self.spp));
        }
        Ok(())
    }

    /// Bytes of the RGBA8 image.
    pub fn buffer_len(&self) -> usize {
        self.width as usize * self.height as usize * 4
    }
}

// The image's controls (see the module doc).

/// One value of a [`Kind::Choice`], with its one-line explanation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Choice {
    /// How files, flags and scripts write it.
    pub name: &'static str,
    /// What the panel shows (the lab step's number and name; otherwise the name).
    pub label: &'static str,
    pub help: &'static str,
}

/// How a control holds its value, with the field's accessors.
#[derive(Clone, Copy)]
pub enum Kind {
    /// One of a list of named values (written by name).
    Choice {
        options: fn() -> Vec<Choice>,
        get: fn(&RenderSettings) -> usize,
        set: fn(&mut RenderSettings, usize),
    },
    /// On or off (written `on` or `off`).
    Toggle {
        get: fn(&RenderSettings) -> bool,
        set: fn(&mut RenderSettings, bool),
    },
    /// A whole number, in `min..=max` where [`RenderSettings::validate`] checks it (so an
    /// out-of-range value gets the same message wherever it comes from).
    Count {
        min: u32,
        max: u32,
        get: fn(&RenderSettings) -> u32,
        set: fn(&mut RenderSettings, u32),
    },
}

/// One row of the table.
#[derive(Clone, Copy)]
pub struct Control {
    /// The `.view` statement, the `--flag` and the script's `set` name.
    pub name: &'static str,
    /// The panel's label.
    pub label: &'static str,
    /// `--help` and the panel's hover text.
    pub help: &'static str,
    /// `Some(title)`: the panel gives the control a section of its own under this title, its
    /// choices as radio buttons (the lab step); `None`: a row of the sampling section.
    pub heading: Option<&'static str>,
    pub kind: Kind,
}

/// Every control, in the order the file, the command and the panel list them.
pub const CONTROLS: [Control; 4] = [
    Control {
        name: "step",
        label: "lab step",
        help: "Lab step (shading).",
        heading: Some("Lab step (2 is the camera, below)"),
        kind: Kind::Choice {
            options: || {
                LabStep::ALL
                    .map(|s| Choice {
                        name: s.name(),
                        label: s.label(),
                        help: s.explanation(),
                    })
                    .to_vec()
            },
            get: |s| index_of(&LabStep::ALL, s.step),
            set: |s, i| s.step = LabStep::ALL[i],
        },
    },
    Control {
        name: "spp",
        label: "supersampling (n x n)",
        help: "Supersampling: N×N stratified rays per pixel (1..=16).",
        heading: None,
        kind: Kind::Count {
            min: 1,
            max: MAX_SPP,
            get: |s| s.spp,
            set: |s, n| s.spp = n,
        },
    },
    Control {
        name: "method",
        label: "ray/triangle",
        help: "Ray/triangle intersection method.",
        heading: None,
        kind: Kind::Choice {
            options: || {
                Method::ALL
                    .map(|m| Choice {
                        name: m.name(),
                        label: m.name(),
                        help: m.explanation(),
                    })
                    .to_vec()
            },
            get: |s| index_of(&Method::ALL, s.method),
            set: |s, i| s.method = Method::ALL[i],
        },
    },
    Control {
        name: "cracks",
        label: "show cracks",
        help: "The cracks view: paint magenta where the method lets a ray through that the \
               exact adaptive method hits, or the reverse (where the lecture's method leaks).",
        heading: None,
        kind: Kind::Toggle {
            get: |s| s.cracks,
            set: |s, on| s.cracks = on,
        },
    },
];

fn index_of<T: PartialEq>(all: &[T], value: T) -> usize {
    all.iter()
        .position(|x| *x == value)
        .expect("every value is listed")
}

/// The control named `name`.
pub fn control(name: &str) -> Option<&'static Control> {
    CONTROLS.iter().find(|c| c.name == name)
}

/// `step=flat spp=1 method=adaptive cracks=off`: every control's value in `settings`, for
/// reports.
pub fn controls_text(settings: &RenderSettings) -> String {
    CONTROLS
        .map(|c| format!("{}={}", c.name, c.text(settings)))
        .join(" ")
}

/// "a, b or c": the names of every control, for messages.
pub fn control_names() -> String {
    or_list(&CONTROLS.map(|c| c.name))
}

fn or_list(words: &[&str]) -> String {
    match words {
        [] => String::new(),
        [one] => one.to_string(),
        [rest @ .., last] => format!("{} or {last}", rest.join(", ")),
    }
}

impl Control {
    /// The value in `settings` as the file and the command write it.
    pub fn text(&self, settings: &RenderSettings) -> String {
        match self.kind {
            Kind::Choice { options, get, .. } => options()[get(settings)].name.to_string(),
            Kind::Toggle { get, .. } => if get(settings) { "on" } else { "off" }.to_string(),
            Kind::Count { get, .. } => get(settings).to_string(),
        }
    }

    /// Sets the value from its text; the error says what was expected.
    pub fn set_text(&self, settings: &mut RenderSettings, value: &str) -> Result<(), String> {
        match self.kind {
            Kind::Choice { options, set, .. } => {
                let options = options();
                let i = options
                    .iter()
                    .position(|o| o.name == value)
                    .ok_or_else(|| {
                        let names: Vec<&str> = options.iter().map(|o| o.name).collect();
                        format!(
                            "unknown {} '{value}' (expected {})",
                            self.name,
                            or_list(&names)
                        )
                    })?;
                set(settings, i);
            }
            Kind::Toggle { set, .. } => match value {
                "on" => set(settings, true),
                "off" => set(settings, false),
                other => return Err(format!("{} is on or off, not '{other}'", self.name)),
            },
            Kind::Count { set, .. } => {
                let n = value
                    .parse()
                    .map_err(|_| format!("'{value}' is not a whole number"))?;
                set(settings, n);
            }
        }
        Ok(())
    }

    /// Every value the control can be written with (a count's ends only).
    pub fn sample_values(&self) -> Vec<String> {
        match self.kind {
            Kind::Choice { options, .. } => options().iter().map(|o| o.name.into()).collect(),
            Kind::Toggle { .. } => vec!["on".into(), "off".into()],
            Kind::Count { min, max, .. } => vec![min.to_string(), max.to_string()],
        }
    }
}

#[cfg(feature = "unit-tests")]
#[deny(dead_code)]
pub(crate) mod tests {
    use super::*;

    fn the_panel_numbers_the_steps_as_the_lab_does() {
        let labels = LabStep::ALL.map(|s| (s.number(), s.label().to_string()));
        assert_eq!(labels.each_ref().map(|(n, _)| *n), [1, 3, 4, 5]);
        for (step, (n, label)) in LabStep::ALL.iter().zip(labels) {
            assert_eq!(label, format!("{n} {}", step.name()));
        }
    }

    fn every_value_reads_back_as_written_and_changes_only_its_field() {
        for c in &CONTROLS {
            for value in c.sample_values() {
                let mut s = RenderSettings::default();
                c.set_text(&mut s, &value).unwrap();
                assert_eq!(c.text(&s), value, "{}", c.name);
                // Every other control still reads its default.
                let d = RenderSettings::default();
                for other in CONTROLS.iter().filter(|o| o.name != c.name) {
                    assert_eq!(
                        other.text(&s),
                        other.text(&d),
                        "{} moved {}",
                        c.name,
                        other.name
                    );
                }
            }
        }
    }

    fn bad_values_are_refused_with_what_was_expected() {
        let mut s = RenderSettings::default();
        let step = control("step").unwrap();
        assert_eq!(
            step.set_text(&mut s, "glossy").unwrap_err(),
            "unknown step 'glossy' (expected flat, direct, shadows or indirect)"
        );
        let method = control("method").unwrap();
        assert_eq!(
            method.set_text(&mut s, "embree").unwrap_err(),
            "unknown method 'embree' (expected adaptive, watertight, moller or cramer)"
        );
        assert_eq!(
            control("cracks")
                .unwrap()
                .set_text(&mut s, "yes")
                .unwrap_err(),
            "cracks is on or off, not 'yes'"
        );
        assert_eq!(
            control("spp").unwrap().set_text(&mut s, "-1").unwrap_err(),
            "'-1' is not a whole number"
        );
        assert_eq!(
            s,
            RenderSettings::default(),
            "a refused value changes nothing"
        );
        assert_eq!(control_names(), "step, spp, method or cracks");
    }

    fn a_count_s_range_is_the_one_validate_checks() {
        for c in &CONTROLS {
            if let Kind::Count { min, max, set, .. } = c.kind {
                let at = |n| {
                    let mut s = RenderSettings::default();
                    set(&mut s, n);
                    s.validate().is_ok()
                };
                assert!(at(min) && at(max), "{}", c.name);
                assert!(!at(min - 1) && !at(max + 1), "{}", c.name);
            }
        }
    }

    /// This module's tests, for tests/unit.rs to run.
    pub(crate) const TESTS: &[(&str, fn())] = &[
        (
            "the_panel_numbers_the_steps_as_the_lab_does",
            the_panel_numbers_the_steps_as_the_lab_does,
        ),
        (
            "every_value_reads_back_as_written_and_changes_only_its_field",
            every_value_reads_back_as_written_and_changes_only_its_field,
        ),
        (
            "bad_values_are_refused_with_what_was_expected",
            bad_values_are_refused_with_what_was_expected,
        ),
        (
            "a_count_s_range_is_the_one_validate_checks",
            a_count_s_range_is_the_one_validate_checks,
        ),
    ];
}
