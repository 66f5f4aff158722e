//! The command a program is run by: `--program`'s template with `{scene}` and `{rays}`
//! replaced by the files' paths, each one shell word whatever its bytes.

use anyhow::{bail, Result};
use std::ffi::{OsStr, OsString};
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

/// The command with `{scene}` and `{rays}` replaced by the paths, each one quoted shell word
/// with its bytes intact. One pass over the template: a path that holds `{rays}` itself is
/// never substituted into (that would end its quotes early and run the rest as code).
pub fn command_line(template: &str, scene: &Path, rays: &Path) -> OsString {
    let (scene, rays) = (shell_word(scene.as_os_str()), shell_word(rays.as_os_str()));
    let t = template.as_bytes();
    let mut out = Vec::with_capacity(t.len() + scene.len() + rays.len());
    let mut i = 0;
    while i < t.len() {
        if t[i..].starts_with(b"{scene}") {
            out.extend_from_slice(&scene);
            i += "{scene}".len();
        } else if t[i..].starts_with(b"{rays}") {
            out.extend_from_slice(&rays);
            i += "{rays}".len();
        } else {
            out.push(t[i]);
            i += 1;
        }
    }
    OsString::from_vec(out)
}

/// `word` in single quotes, a quote within written `'\''`: the shell expands nothing in it.
fn shell_word(word: &OsStr) -> Vec<u8> {
    let mut out = vec![b'\''];
    for &b in word.as_bytes() {
        match b {
            b'\'' => out.extend_from_slice(br"'\''"),
            _ => out.push(b),
        }
    }
    out.push(b'\'');
    out
}
