//! The panel's number fields as typed into. egui keeps a field's number where the text typed
//! is not one (`1,5`, `abc`, `nan`) and drops the text without a word, and it takes each
//! number on the way as it is typed (`1` of `1,5`): these fields take the text once the edit
//! ends (Return, Tab or a click elsewhere; Esc drops it) and name what they could not read in
//! the status line.

use std::cell::RefCell;
use std::ops::RangeInclusive;

/// What a field did with the text typed into it, kept for the panel to say once that field's
/// edit ends. One for a whole panel pass: each field reads its text as its edit ends, inside
/// its `add`.
#[derive(Default)]
pub struct Typing(RefCell<Option<Read>>);

/// Typed text as a field read it.
#[derive(Clone, Debug, PartialEq)]
enum Read {
    /// A number within the field's range.
    Number,
    /// A number outside it (the field takes the nearest end).
    Outside { text: String, range: (f64, f64) },
    /// Not a finite number (the field keeps its value).
    NotANumber(String),
}

/// What the status line says once a field's edit ended.
#[derive(Clone, Debug, PartialEq)]
pub enum Said {
    /// The field took the text as typed: clears what a field said before.
    Taken(String),
    /// The field took another value than typed, or none: in red.
    Slip(String),
}

impl Typing {
    /// `field`, kept within `range`, reading typed text as [`super::values::finite_number`]
    /// once its edit ends.
    pub fn drag<'a>(
        &'a self,
        field: egui::DragValue<'a>,
        range: RangeInclusive<f64>,
    ) -> egui::DragValue<'a> {
        let bounds = (*range.start(), *range.end());
        field
            .range(range)
            .custom_parser(move |text| self.read(text, bounds))
            .update_while_editing(false)
    }

    /// A slider over `range` whose number box reads typed text so.
    pub fn slider<'a>(
        &'a self,
        slider: egui::Slider<'a>,
        range: RangeInclusive<f64>,
    ) -> egui::Slider<'a> {
        let bounds = (*range.start(), *range.end());
        slider
            .custom_parser(move |text| self.read(text, bounds))
            .update_while_editing(false)
    }

    fn read(&self, text: &str, (lo, hi): (f64, f64)) -> Option<f64> {
        let number = super::values::finite_number(text);
        let text = text.trim().to_string();
        *self.0.borrow_mut() = Some(match number {
            None => Read::NotANumber(text),
            Some(x) if x < lo || x > hi => Read::Outside {
                text,
                range: (lo, hi),
            },
            Some(_) => Read::Number,
        });
        number
    }

    /// After the field called `name`, which now holds `value`, was added: what the status
    /// line says where its edit ended. Where Esc ended it, the text is dropped: egui reads it
    /// again in the next frame, whose keys hold no Esc, and would take it.
    pub fn said(
        &self,
        ui: &egui::Ui,
        response: &egui::Response,
        name: &str,
        value: f64,
    ) -> Option<Said> {
        if response.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Escape)) {
            ui.data_mut(|data| data.remove_temp::<String>(response.id));
        }
        let read = self.0.borrow_mut().take()?;
        response.lost_focus().then(|| said(name, read, value))
    }
}

/// What the status line says of a field called `name`, now holding `value`, that read `read`.
fn said(name: &str, read: Read, value: f64) -> Said {
    let value = shown(value);
    match read {
        Read::Number => Said::Taken(format!("{name} set to {value}")),
        Read::Outside { text, range } => Said::Slip(format!(
            "{name}: {text} lies outside {} … {}; it took {value}",
            shown(range.0),
            shown(range.1)
        )),
        Read::NotANumber(text) => Said::Slip(not_a_number(name, &text)),
    }
}

/// A field's value or bound as the status line writes it: the short decimal it was set as
/// ([`super::values::clean`]).
fn shown(x: f64) -> String {
    super::values::clean(x).to_string()
}

/// What the status line says of `text` typed into the field `name`.
fn not_a_number(name: &str, text: &str) -> String {
    let what = match text.parse::<f64>() {
        Ok(_) => "is not a finite number",
        Err(_) => "is not a number",
    };
    let hint = match text.contains(',') {
        true => " (decimals take a point: 1.5)",
        false => "",
    };
    format!("{name}: {text:?} {what}{hint}; the field keeps its value")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_status_names_the_field_the_text_and_what_was_taken() {
        let typing = Typing::default();
        let read = |text: &str| {
            typing.read(text, (-2.0, 2.0));
            typing.0.borrow_mut().take().unwrap()
        };
        assert_eq!(
            said("camera x", read("1,5"), 0.0),
            Said::Slip(
                "camera x: \"1,5\" is not a number (decimals take a point: 1.5); the field \
                 keeps its value"
                    .into()
            )
        );
        assert_eq!(
            said("yaw", read(" nan "), 0.0),
            Said::Slip("yaw: \"nan\" is not a finite number; the field keeps its value".into())
        );
        assert_eq!(
            said("light z", read("abc"), 0.0),
            Said::Slip("light z: \"abc\" is not a number; the field keeps its value".into())
        );
        assert_eq!(
            said("light z", read(" 1e30"), 2.0),
            Said::Slip("light z: 1e30 lies outside -2 … 2; it took 2".into())
        );
        assert_eq!(
            said("light z", read("−0.25"), -0.25),
            Said::Taken("light z set to -0.25".into())
        );
        // The value the field holds after, as its short decimal.
        assert_eq!(
            said("focal length", read("1.1"), 1.1 * 3.0 / 3.0),
            Said::Taken("focal length set to 1.1".into())
        );
    }
}
