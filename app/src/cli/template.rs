//! The command a program is run by: `--program`'s template with `{scene}` and `{rays}`
//! replaced by the files' paths, each one shell word whatever its bytes.

use anyhow::{bail, Result};
use std::ffi::OsString;
use std::os::unix::ffi::{OsStrExt, OsStringExt};
use std::path::Path;

/// A --program template must say where the files' paths go.
pub(super) fn check_template(cmd: &str) -> Result<()> {
    if !(cmd.contains("{scene}") && cmd.contains("{rays}")) {
        bail!("--program '{cmd}' must name {{scene}} and {{rays}}, where the files' paths go");
    }
    Ok(())
}

/// The command with `{scene}` and `{rays}` replaced by the paths, for messages (a path that is
/// not UTF-8 shows U+FFFD here; [`command_line`] is the one to run).
pub fn command_for(template: &str, scene: &Path, rays: &Path) -> String {
    command_line(template, scene, rays)
        .to_string_lossy()
        .into_owned()
}

/// The command with `{scene}` and `{rays}` replaced by the paths, made absolute (a program
/// that changes directory first still finds them, as under `grade`), each one shell word with
/// its bytes intact, whether the template writes the placeholder bare, in single or in double
/// quotes (`"{scene}"`, as students write by habit): the path is quoted for the place it
/// goes. One pass over the template: a path that holds `{rays}` itself is never substituted
/// into (that would end its quotes early and run the rest as code).
pub fn command_line(template: &str, scene: &Path, rays: &Path) -> OsString {
    let absolute = |p: &Path| std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf());
    let (scene, rays) = (absolute(scene), absolute(rays));
    let (scene, rays) = (scene.as_os_str().as_bytes(), rays.as_os_str().as_bytes());
    let t = template.as_bytes();
    let mut out = Vec::with_capacity(t.len() + 2 * (scene.len() + rays.len()));
    let mut quote = Quote::None;
    let mut i = 0;
    while i < t.len() {
        let placeholders = [(&b"{scene}"[..], scene), (&b"{rays}"[..], rays)];
        if let Some((name, path)) = placeholders
            .into_iter()
            .find(|(n, _)| t[i..].starts_with(n))
        {
            quote.write(path, &mut out);
            i += name.len();
            continue;
        }
        let b = t[i];
        out.push(b);
        i += 1;
        // A backslash outside single quotes keeps the next byte as it is.
        if b == b'\\' && quote != Quote::Single && i < t.len() {
            out.push(t[i]);
            i += 1;
            continue;
        }
        quote = match (quote, b) {
            (Quote::None, b'\'') => Quote::Single,
            (Quote::None, b'"') => Quote::Double,
            (Quote::Single, b'\'') | (Quote::Double, b'"') => Quote::None,
            (q, _) => q,
        };
    }
    OsString::from_vec(out)
}

/// Where the shell is in the template: outside quotes, or inside single or double ones.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Quote {
    None,
    Single,
    Double,
}

impl Quote {
    /// `path` as one word of literal bytes here: in single quotes outside any (a quote
    /// within written `'\''`); inside single quotes the same, without the outer ones; inside
    /// double quotes with `"`, `\`, `$` and `` ` `` escaped. The shell expands nothing in it.
    fn write(self, path: &[u8], out: &mut Vec<u8>) {
        let bare = self == Quote::None;
        if bare {
            out.push(b'\'');
        }
        for &b in path {
            match (self, b) {
                (Quote::None | Quote::Single, b'\'') => out.extend_from_slice(br"'\''"),
                (Quote::Double, b'"' | b'\\' | b'$' | b'`') => out.extend_from_slice(&[b'\\', b]),
                _ => out.push(b),
            }
        }
        if bare {
            out.push(b'\'');
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Runs `template` with sh, the placeholders standing for `scene` and `rays`; what
    /// `printf '%s|'` printed of its arguments.
    fn args_seen(template: &str, scene: &str, rays: &str) -> String {
        let command = command_line(template, Path::new(scene), Path::new(rays));
        let out = std::process::Command::new("sh")
            .arg("-c")
            .arg(command)
            .output()
            .unwrap();
        String::from_utf8(out.stdout).unwrap()
    }

    #[test]
    fn a_path_is_one_word_bare_or_in_either_quotes() {
        let nasty = "/my suite/it's \"$(x)\" `y` \\ {rays}/scene.txt";
        let rays = "/r s/rays.txt";
        let want = format!("{nasty}|{rays}|");
        for template in [
            "printf '%s|' {scene} {rays}",
            "printf '%s|' \"{scene}\" \"{rays}\"",
            "printf '%s|' '{scene}' '{rays}'",
            "printf '%s|' \"{scene}\" '{rays}'",
        ] {
            assert_eq!(args_seen(template, nasty, rays), want, "{template}");
        }
        // Quotes and escapes around them are followed: an escaped quote opens none.
        let template = "printf '%s|' \\\" {scene} \"a'b\" {rays}";
        assert_eq!(
            args_seen(template, nasty, rays),
            format!("\"|{nasty}|a'b|{rays}|"),
        );
        // Inside a word: the path joins it.
        assert_eq!(
            args_seen("printf '%s|' --in=\"{scene}\" x{rays}", "/a b", "/c d"),
            "--in=/a b|x/c d|"
        );
    }

    /// A relative path goes in made absolute, from where raylab runs.
    #[test]
    fn a_relative_path_goes_in_absolute() {
        let here = std::env::current_dir().unwrap();
        let want = format!(
            "{}|{}|",
            here.join("s p/scene.txt").display(),
            here.join("rays.txt").display()
        );
        assert_eq!(
            args_seen("printf '%s|' {scene} {rays}", "s p/scene.txt", "rays.txt"),
            want
        );
    }
}
