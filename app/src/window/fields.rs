//! The panel's number fields as typed into. egui keeps a field's number where the text typed
//! is not one (`1,5`, `abc`, `nan`) and drops the text without a word, and it takes each
//! number on the way as it is typed (`1` of `1,5`): these fields take the text once the edit
//! ends (Return, Tab or a click elsewhere; Esc drops it) and name what they could not read in
//! the status line.

use std::cell::RefCell;

/// The text a field last could not read, for the panel to name once that field's edit ends.
/// One for a whole panel pass: each field reads its text as its edit ends, inside its `add`.
#[derive(Default)]
pub struct Unread(RefCell<Option<String>>);

impl Unread {
    /// `field` reading typed text as [`super::values::finite_number`], once its edit ends.
    pub fn drag<'a>(&'a self, field: egui::DragValue<'a>) -> egui::DragValue<'a> {
        field
            .custom_parser(|text| self.read(text))
            .update_while_editing(false)
    }

    /// A slider whose number box reads typed text so.
    pub fn slider<'a>(&'a self, slider: egui::Slider<'a>) -> egui::Slider<'a> {
        slider
            .custom_parser(|text| self.read(text))
            .update_while_editing(false)
    }

    fn read(&self, text: &str) -> Option<f64> {
        let number = super::values::finite_number(text);
        *self.0.borrow_mut() = number.is_none().then(|| text.to_string());
        number
    }

    /// After the field called `name` was added: where its edit ended on text it could not
    /// read, what the status line says. Where Esc ended it, the text is dropped: egui reads
    /// it again in the next frame, whose keys hold no Esc, and would take it.
    pub fn said(&self, ui: &egui::Ui, response: &egui::Response, name: &str) -> Option<String> {
        if response.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Escape)) {
            ui.data_mut(|data| data.remove_temp::<String>(response.id));
        }
        let text = self.0.borrow_mut().take()?;
        response.lost_focus().then(|| not_a_number(name, &text))
    }
}

/// What the status line says of `text` typed into the field `name`.
fn not_a_number(name: &str, text: &str) -> String {
    let text = text.trim();
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
    fn the_message_names_the_field_and_the_text() {
        assert_eq!(
            not_a_number("camera x", "1,5"),
            "camera x: \"1,5\" is not a number (decimals take a point: 1.5); the field keeps \
             its value"
        );
        assert_eq!(
            not_a_number("yaw", " nan "),
            "yaw: \"nan\" is not a finite number; the field keeps its value"
        );
        assert_eq!(
            not_a_number("light z", "abc"),
            "light z: \"abc\" is not a number; the field keeps its value"
        );
    }

    #[test]
    fn a_read_remembers_only_text_that_is_not_a_number() {
        let unread = Unread::default();
        assert_eq!(unread.read("abc"), None);
        assert_eq!(unread.0.borrow().as_deref(), Some("abc"));
        assert_eq!(unread.read("−2.5"), Some(-2.5));
        assert_eq!(*unread.0.borrow(), None);
        assert_eq!(unread.read("inf"), None);
        assert_eq!(unread.0.borrow().as_deref(), Some("inf"));
    }
}
