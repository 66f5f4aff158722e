//! raylab's window: a winit event loop, an egui panel and a `pixels` framebuffer over the raylab
//! library ([`window::run`]). The `raylab` binary (src/main.rs, with the command line in
//! src/cli/) opens it when given no subcommand; a program of its own can open it too.
#![forbid(unsafe_code)]

pub mod window;

/// An error and its causes as one line, each said once: an error whose message already ends
/// with its cause's (`path: No such file or directory (os error 2)`, where the cause is the OS
/// error) is not followed by that cause again.
pub fn error_text(e: &anyhow::Error) -> String {
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

#[cfg(test)]
mod tests {
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
