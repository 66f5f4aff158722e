//! raylab's window: a winit event loop, an egui panel and a framebuffer texture over the raylab
//! library ([`window::run`]). The `raylab` binary (src/main.rs, with the command line in
//! src/cli/) opens it when given no subcommand; a program of its own can open it too.
#![forbid(unsafe_code)]

pub mod window;

/// Logs to stderr at `RUST_LOG`'s levels, warnings where it is not set. egui-wgpu's warning
/// that the window draws to an sRGB surface is left out then: the surface is sRGB on purpose
/// (egui's colours blended in linear light, the image shown as rendered), and a student would
/// read it as something to fix.
pub fn init_logging() {
    let env = env_logger::Env::default().default_filter_or("warn,egui_wgpu::renderer=error");
    env_logger::Builder::from_env(env).init();
}

/// An error and its causes as one line, each said once: an error whose message already ends
/// with its cause's (`path: No such file or directory (os error 2)`, where the cause is the OS
/// error) is not followed by that cause again. Control characters other than line breaks
/// (a NUL, an escape sequence quoted from a file) are shown escaped (`\u{1b}`), so that an
/// error never drives the terminal.
pub fn error_text(e: &anyhow::Error) -> String {
    escape_controls(said_once(e))
}

/// [`error_text`] before its control characters are escaped.
fn said_once(e: &anyhow::Error) -> String {
    let mut text = String::new();
    for cause in e.chain() {
        let said = cause.to_string();
        if !text.ends_with(&said) {
            if !text.is_empty() {
                text += ": ";
            }
            text += &said;
        }
    }
    text
}

/// `text` with every control character but a line break, and every mark that turns the
/// text's direction or breaks its line, written as its escape: a program's output quoted in
/// a message drives no terminal.
pub fn escape_controls(text: String) -> String {
    escape_where(text, |c| drives_a_terminal(c) && c != '\n')
}

/// `text` with every control character, a line break too, and every mark that turns the
/// text's direction or breaks its line, written as its escape: a name shown on one line of
/// a table, driving no terminal.
pub fn one_line(text: &str) -> String {
    escape_where(text.to_string(), drives_a_terminal)
}

/// A control character, a mark that turns the text's direction (a right-to-left override in
/// a name reversed the rest of its row in the table) or a line or paragraph separator.
fn drives_a_terminal(c: char) -> bool {
    let direction = matches!(
        c,
        '\u{61c}' | '\u{200e}' | '\u{200f}' | '\u{202a}'..='\u{202e}'
    );
    let isolate_or_break = matches!(c, '\u{2066}'..='\u{2069}' | '\u{2028}' | '\u{2029}');
    c.is_control() || direction || isolate_or_break
}

/// `text` with the characters `hidden` picks written as their escapes (`\u{1b}`, `\n`).
fn escape_where(text: String, hidden: impl Fn(char) -> bool) -> String {
    if !text.contains(&hidden) {
        return text;
    }
    let mut out = String::with_capacity(text.len() + 8);
    for c in text.chars() {
        match hidden(c) {
            true => out.extend(c.escape_default()),
            false => out.push(c),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    #[test]
    fn control_characters_are_shown_escaped() {
        let e = anyhow::anyhow!("x.scene:2: unknown statement '\u{1b}[31mred\0'");
        assert_eq!(
            super::error_text(&e),
            "x.scene:2: unknown statement '\\u{1b}[31mred\\u{0}'"
        );
    }

    #[test]
    fn a_cause_already_in_the_message_is_said_once() {
        let os = std::io::Error::from(std::io::ErrorKind::NotFound);
        let e = anyhow::Error::new(raylab::input::InputError::Io {
            path: "nope".into(),
            source: os,
        });
        assert_eq!(super::error_text(&e), "nope: entity not found");
        let e = e.context("loading scene 'nope'");
        assert_eq!(
            super::error_text(&e),
            "loading scene 'nope': nope: entity not found"
        );
    }
}
