//! The image's controls, listed once: every setting besides the scene, the camera, the light
//! and the size that changes the image. Each row names its field of [`RenderSettings`] and
//! how its value is written; everything that reads or writes settings goes through the table:
//! the `.view` file (`NAME VALUE`), copy-as-command and the `raylab render` flags
//! (`--NAME=VALUE`, a toggle as a bare `--NAME`), the window's panel (one widget per row) and
//! a scripted run's `set NAME VALUE`.
//!
//! A new control is a field of [`RenderSettings`] with its default, a row in [`CONTROLS`],
//! and the code that uses it.

use super::{LabStep, RenderSettings};
use crate::geometry::Method;

/// One value of a [`Kind::Choice`], with its one-line explanation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Choice {
    pub name: &'static str,
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
        heading: Some("Lab step"),
        kind: Kind::Choice {
            options: || {
                LabStep::ALL
                    .map(|s| Choice {
                        name: s.name(),
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
            max: super::MAX_SPP,
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

/// "a, b or c": the names of every control, for messages.
pub fn names() -> String {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
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

    #[test]
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
        assert_eq!(names(), "step, spp, method or cracks");
    }

    #[test]
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
}
