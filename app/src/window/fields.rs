//! The panel's number fields as typed into. egui keeps a field's number where the text typed
//! is not one (`1,5`, `abc`, `nan`) and drops the text without a word, takes a number past the
//! field's range at its end without a word, and takes each number on the way as it is typed
//! (`1` of `1,5`): these fields take the text once the edit ends (Return, Tab or a click
//! elsewhere; Esc drops it) and the status line says what they did with it where that is not
//! what was typed.

use egui::emath::Numeric;
use std::cell::RefCell;
use std::fmt::Display;
use std::ops::RangeInclusive;

/// What a field did with the text typed into it, kept for the panel to say once that field's
/// edit ends. One for a whole panel pass: each field reads its text as its edit ends, inside
/// its `add`.
#[derive(Default)]
pub struct Typing(RefCell<Option<Read>>);

/// Typed text as a field read it.
#[derive(Clone, Debug, PartialEq)]
enum Read {
    /// A number within the field's range, and that number in the field's type (an f32
    /// field's 0.333333333 is 0.33333334).
    Number { text: String, as_typed: String },
    /// A number outside it (the field takes the nearest end).
    Outside { text: String, range: String },
    /// Not a finite number (the field keeps its value).
    NotANumber(String),
}

/// What the status line says once a field's edit ended.
#[derive(Clone, Debug, PartialEq)]
pub enum Said {
    /// The field holds the number typed: clears what a field said before.
    Taken(String),
    /// The field holds another value than typed (its range's end, a whole number), or kept
    /// its own: in red.
    Slip(String),
}

/// A field's range as its bounds (as the status line writes them, [`text`]) and as that text,
/// and how the field's type holds a number.
#[derive(Clone)]
struct Bounds {
    lo: f64,
    hi: f64,
    text: String,
    /// A number as the field's type holds it, written as [`text`] writes it.
    in_type: fn(f64) -> String,
}

impl Bounds {
    fn of<N: Numeric + Display>(range: &RangeInclusive<N>) -> Self {
        let (lo, hi) = (text(*range.start()), text(*range.end()));
        Self {
            lo: lo.parse().unwrap_or(f64::NAN),
            hi: hi.parse().unwrap_or(f64::NAN),
            text: format!("{lo} … {hi}"),
            in_type: |x| text(N::from_f64(x)),
        }
    }
}

impl Typing {
    /// `field`, kept within `range`, reading typed text ([`Typing::read`]) once its edit ends.
    pub fn drag<'a, N: Numeric + Display>(
        &'a self,
        field: egui::DragValue<'a>,
        range: RangeInclusive<N>,
    ) -> egui::DragValue<'a> {
        let bounds = Bounds::of(&range);
        field
            .range(range)
            .custom_parser(move |text| self.read(text, &bounds))
            .update_while_editing(false)
    }

    /// A slider of `value` over `range` whose number box reads typed text so.
    pub fn slider<'a, N: Numeric + Display>(
        &'a self,
        value: &'a mut N,
        range: RangeInclusive<N>,
    ) -> egui::Slider<'a> {
        let bounds = Bounds::of(&range);
        egui::Slider::new(value, range)
            .custom_parser(move |text| self.read(text, &bounds))
            .update_while_editing(false)
    }

    /// Typed text as a number (spaces dropped, U+2212 a minus), where it is finite: egui's
    /// own parser takes `nan` and `inf`, which a clamped field turned into its lower or upper
    /// end. What it read is kept for [`Typing::said_as_edit_ends`].
    fn read(&self, text: &str, bounds: &Bounds) -> Option<f64> {
        let text: String = text.chars().filter(|c| !c.is_whitespace()).collect();
        let text = text.replace('−', "-");
        let number = text.parse::<f64>().ok().filter(|v| v.is_finite());
        *self.0.borrow_mut() = Some(match number {
            None => Read::NotANumber(text),
            Some(x) if x < bounds.lo || x > bounds.hi => Read::Outside {
                text,
                range: bounds.text.clone(),
            },
            Some(number) => Read::Number {
                text,
                as_typed: (bounds.in_type)(number),
            },
        });
        number
    }

    /// After the field called `name`, which now holds `value`, was added: what the status
    /// line says where its edit ended. Where Esc ended it, the text is dropped: egui reads it
    /// again in the next frame, whose keys hold no Esc, and would take it. (egui reads the
    /// text of an edit ended by Return, Tab or a click twice, in that frame and the next: the
    /// same words twice, which the viewer says once.)
    pub fn said_as_edit_ends<N: Numeric + Display>(
        &self,
        ui: &egui::Ui,
        response: &egui::Response,
        name: &str,
        value: N,
    ) -> Option<Said> {
        if response.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Escape)) {
            ui.data_mut(|data| data.remove_temp::<String>(response.id));
        }
        let read = self.0.borrow_mut().take()?;
        response.lost_focus().then(|| message(name, read, value))
    }
}

/// A text field's Esc, as a number field's: `text` goes back to what it held when the edit
/// began (egui's Esc only leaves the field, keeping what was typed).
pub fn escape_restores(ui: &egui::Ui, response: &egui::Response, text: &mut String) {
    let before_edit = response.id.with("before edit");
    if response.gained_focus() {
        ui.data_mut(|data| data.insert_temp(before_edit, text.clone()));
    }
    if response.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Escape)) {
        if let Some(before) = ui.data(|data| data.get_temp::<String>(before_edit)) {
            *text = before;
        }
    }
}

fn message<N: Numeric + Display>(name: &str, read: Read, value: N) -> Said {
    let value = text(value);
    match read {
        Read::Number { as_typed, .. } if as_typed == value => {
            Said::Taken(format!("{name} set to {value}"))
        }
        Read::Number { text, .. } => Said::Slip(format!("{name}: {text} taken as {value}")),
        Read::Outside { text, range } => Said::Slip(format!(
            "{name}: {text} lies outside {range}; it took {value}"
        )),
        Read::NotANumber(text) => Said::Slip(not_a_number(name, &text)),
    }
}

/// A field's value or bound as the status line writes it: a whole number whole (2⁴⁰ in f32 as
/// 1099511627776, not 1099511600000), else the shortest digits its type reads back (an f32 0.1
/// as 0.1, not 0.10000000149011612).
fn text<N: Numeric + Display>(value: N) -> String {
    let x = value.to_f64();
    match x.fract() == 0.0 && x.abs() < 2f64.powi(53) {
        true => format!("{x:.0}"),
        false => value.to_string(),
    }
}

/// What the status line says of `text` typed into the field `name`.
fn not_a_number(name: &str, text: &str) -> String {
    let what = match text.parse::<f64>() {
        Ok(_) => "is not a finite number",
        Err(_) => "is not a number",
    };
    let hint = match text.contains(',') {
        true => format!(" (decimals take a point: {})", text.replace(',', ".")),
        false => String::new(),
    };
    format!("{name}: {text:?} {what}{hint}; the field keeps its value")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_status_names_the_field_the_text_and_what_was_taken() {
        let typing = Typing::default();
        let read = |text: &str, range: RangeInclusive<f32>| {
            typing.read(text, &Bounds::of(&range));
            typing.0.borrow_mut().take().unwrap()
        };
        let wide = -2.0..=2.0;
        assert_eq!(
            message("camera x", read("1,5", wide.clone()), 0.0),
            Said::Slip(
                "camera x: \"1,5\" is not a number (decimals take a point: 1.5); the field \
                 keeps its value"
                    .into()
            )
        );
        assert_eq!(
            message("yaw", read(" nan ", wide.clone()), 0.0),
            Said::Slip("yaw: \"nan\" is not a finite number; the field keeps its value".into())
        );
        assert_eq!(
            message("yaw", read("−inf", wide.clone()), 0.0),
            Said::Slip("yaw: \"-inf\" is not a finite number; the field keeps its value".into())
        );
        assert_eq!(
            message("light z", read("abc", wide.clone()), 0.0),
            Said::Slip("light z: \"abc\" is not a number; the field keeps its value".into())
        );
        assert_eq!(
            message("light z", read(" 1e30", wide.clone()), 2.0f32),
            Said::Slip("light z: 1e30 lies outside -2 … 2; it took 2".into())
        );
        assert_eq!(
            message("light z", read("−0.25", wide.clone()), -0.25f32),
            Said::Taken("light z set to -0.25".into())
        );
        // An f32 field's 0.1 at its f32 bound 0.1 is within it, and taken as typed.
        assert_eq!(
            message("preview scale", read("0.1", 0.1..=1.0), 0.1f32),
            Said::Taken("preview scale set to 0.1".into())
        );
        // An f32 field's bound 2⁴⁰ written whole, and taken where typed exactly.
        let far = 2f32.powi(40);
        assert_eq!(
            message("light x", read("-1e30", -far..=far), -far),
            Said::Slip(
                "light x: -1e30 lies outside -1099511627776 … 1099511627776; it took \
                 -1099511627776"
                    .into()
            )
        );
        assert_eq!(
            message("light x", read("1099511627776", -far..=far), far),
            Said::Taken("light x set to 1099511627776".into())
        );
        // An f32 field holds 0.333333333 as 0.33333334: taken, as its type writes it.
        assert_eq!(
            message("light x", read("0.333333333", wide), 0.333_333_34_f32),
            Said::Taken("light x set to 0.33333334".into())
        );
        // A whole-number field holds 3 for 2.5: said.
        let typing = Typing::default();
        typing.read("2.5", &Bounds::of(&(1u32..=16)));
        let read = typing.0.borrow_mut().take().unwrap();
        assert_eq!(
            message("supersampling", read, 3u32),
            Said::Slip("supersampling: 2.5 taken as 3".into())
        );
    }
}
