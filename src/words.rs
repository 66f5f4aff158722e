//! The words of one line of raylab's text formats (`.scene`, `.view`): separated by
//! whitespace, `#` starts a comment, and a word in double quotes may hold anything a path can
//! (spaces, `#`, quotes as `\"`, backslashes as `\\`, a newline as `\n`), so every file name
//! round-trips. Outside quotes every character but whitespace and `#` is itself, except a
//! byte-order mark (U+FEFF), which is refused by name rather than read as part of a word.

use std::borrow::Cow;

/// The byte-order mark, which no unquoted word may hold.
const BOM: char = '\u{feff}';

/// The words of `line` before its comment, quoted words unquoted.
pub fn words(line: &str) -> Result<Vec<String>, String> {
    let max = crate::limits::MAX_LINE_BYTES;
    if line.len() > max {
        return Err(format!(
            "the line is {} bytes long, more than the {max} a line may have",
            line.len()
        ));
    }
    let mut out = Vec::new();
    let mut chars = line.chars().peekable();
    loop {
        while chars.next_if(|c| c.is_whitespace()).is_some() {}
        match chars.peek() {
            None | Some('#') => return Ok(out),
            Some('"') => {
                chars.next();
                let mut word = String::new();
                loop {
                    match chars.next() {
                        None => {
                            let start: String = line.chars().take(60).collect();
                            let more = if start.len() < line.len() { "…" } else { "" };
                            return Err(format!(
                                "a quoted word has no closing quote: {start}{more}"
                            ));
                        }
                        Some('"') => break,
                        Some('\\') => match chars.next() {
                            Some('"') => word.push('"'),
                            Some('\\') => word.push('\\'),
                            Some('n') => word.push('\n'),
                            other => {
                                let e =
                                    other.map_or("the line's end".into(), |c| format!("'\\{c}'"));
                                return Err(format!(
                                    "{e} in a quoted word (only \\\", \\\\ and \\n are escapes)"
                                ));
                            }
                        },
                        Some(c) => word.push(c),
                    }
                }
                match chars.peek() {
                    Some(c) if !c.is_whitespace() && *c != '#' => {
                        return Err(format!("a quoted word runs into '{c}'"))
                    }
                    _ => out.push(word),
                }
            }
            Some(_) => {
                let mut word = String::new();
                while let Some(c) = chars.next_if(|c| !c.is_whitespace() && *c != '#') {
                    word.push(c);
                }
                // Invisible when quoted: named instead (a file's first line has it skipped).
                if word.contains(BOM) {
                    return Err(match (out.is_empty(), word.starts_with(BOM)) {
                        (true, true) => "the line starts with a byte-order mark (U+FEFF), \
                                         which only a file's first line may (files joined \
                                         together?)"
                            .to_string(),
                        _ => format!(
                            "'{}' holds a byte-order mark (U+FEFF)",
                            word.replace(BOM, "")
                        ),
                    });
                }
                out.push(word);
            }
        }
    }
}

/// The most characters of a word an error message quotes.
const SHOWN_CHARS: usize = 40;

/// `word` as an error message quotes it: whole up to 40 characters, else its start, an
/// ellipsis and its length (a line of a million zeros was quoted whole, a megabyte of error).
pub fn shown(word: &str) -> Cow<'_, str> {
    let word = visible(word);
    match word.chars().nth(SHOWN_CHARS) {
        None => word,
        Some(_) => {
            let start: String = word.chars().take(SHOWN_CHARS).collect();
            let n = word.chars().count();
            Cow::Owned(format!("{start}… ({n} characters)"))
        }
    }
}

/// `word` with the characters a terminal shows as nothing (controls, a byte-order mark, zero
/// widths, direction marks) written as escapes (`\u{feff}`): `'0' is not a number` named a
/// word whose byte-order mark could not be seen.
fn visible(word: &str) -> Cow<'_, str> {
    let hidden = |c: char| {
        c.is_control()
            || matches!(c, '\u{ad}' | '\u{200b}'..='\u{200f}' | '\u{202a}'..='\u{202e}')
            || matches!(c, '\u{2060}'..='\u{2064}' | '\u{feff}')
    };
    match word.contains(hidden) {
        false => Cow::Borrowed(word),
        true => Cow::Owned(
            word.chars()
                .map(|c| match hidden(c) {
                    true => c.escape_unicode().to_string(),
                    false => c.to_string(),
                })
                .collect(),
        ),
    }
}

/// `word` as [`words`] reads it back: as it is where it can be, else in double quotes.
pub fn quoted(word: &str) -> Cow<'_, str> {
    let plain = !word.is_empty()
        && !word.starts_with('"')
        && !word.chars().any(|c| c.is_whitespace() || c == '#');
    if plain {
        return Cow::Borrowed(word);
    }
    let mut out = String::from('"');
    for c in word.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            c => out.push(c),
        }
    }
    out.push('"');
    Cow::Owned(out)
}

#[cfg(feature = "unit-tests")]
#[deny(dead_code)]
pub(crate) mod tests {
    use super::*;

    fn words_split_on_whitespace_and_stop_at_a_comment() {
        assert_eq!(
            words("  tri 0\t1  2 # note").unwrap(),
            ["tri", "0", "1", "2"]
        );
        assert_eq!(words("#only").unwrap(), Vec::<String>::new());
        assert_eq!(
            words(r#"mesh a\b"c.obj lab"#).unwrap(),
            ["mesh", r#"a\b"c.obj"#, "lab"]
        );
    }

    fn every_name_round_trips_through_quotes() {
        for name in [
            "plain.obj",
            "two  spaces.scene",
            "x#y.scene",
            " lead and trail ",
            "\"quoted\"",
            "back\\slash\\\"",
            "new\nline",
            "",
            "tab\there",
            "ünï ©ode",
        ] {
            let line = format!("scene {} # comment", quoted(name));
            assert_eq!(words(&line).unwrap(), ["scene", name], "{line}");
        }
        assert!(matches!(quoted("plain.obj"), Cow::Borrowed(_)));
    }

    fn broken_quotes_are_errors() {
        for bad in [
            r#"scene "open"#,
            r#"scene "a"b"#,
            r#"scene "a\t""#,
            r#"scene "a\"#,
        ] {
            assert!(words(bad).is_err(), "{bad}");
        }
    }

    /// This module's tests, for tests/unit.rs to run.
    pub(crate) const TESTS: &[(&str, fn())] = &[
        (
            "words_split_on_whitespace_and_stop_at_a_comment",
            words_split_on_whitespace_and_stop_at_a_comment,
        ),
        (
            "every_name_round_trips_through_quotes",
            every_name_round_trips_through_quotes,
        ),
        ("broken_quotes_are_errors", broken_quotes_are_errors),
    ];
}

/// `n` things in words, `one` after a count of 1 and `many` after any other: "1 family",
/// "2 families"; a verb can come along ("1 sphere repeats", "2 spheres repeat").
pub fn count(n: usize, one: &str, many: &str) -> String {
    match n {
        1 => format!("1 {one}"),
        n => format!("{n} {many}"),
    }
}

/// `n` primitives, in words: "1 primitive", "2 primitives".
pub fn primitives(n: usize) -> String {
    count(n, "primitive", "primitives")
}
