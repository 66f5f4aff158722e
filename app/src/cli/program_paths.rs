//! The files a `grade --program` command names outside the submissions: a teacher's wrapper
//! named by a path relative to where raylab runs (the command runs in each submission's copy,
//! where it is not), or one the programs cannot read (they run as other users). Either made
//! every submission crash with a shell's "not found" or "Permission denied", the grading run
//! through, so both are refused before any program runs.

use anyhow::{bail, Result};
use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};

/// Refuses a `--program` that names a file the submissions' runs cannot reach: a relative
/// path to a file here that no submission holds, or (`as_others`: the programs run as other
/// users, `who` says which) an absolute one those users cannot read.
pub(super) fn check_program_paths(
    template: &str,
    submissions: &[PathBuf],
    as_others: Option<&str>,
) -> Result<()> {
    for (k, word) in path_words(template).enumerate() {
        let path = Path::new(word);
        let here = path.is_file();
        if path.is_relative() && here && !submissions.iter().any(|s| s.join(path).exists()) {
            let absolute = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
            bail!(
                "--program: {word} is a file here, but the command runs in each submission's \
                 copy, and no submission holds it: name it by its absolute path, {}",
                absolute.display()
            );
        }
        let Some(who) = as_others else { continue };
        if path.is_absolute() && here {
            // (The command's first word is run: a script needs x as well as r.)
            let needs = if k == 0 { 0o005 } else { 0o004 };
            let mode = std::fs::metadata(path).map_or(0, |m| m.permissions().mode());
            let dir = path.parent().unwrap_or(Path::new("/"));
            if !super::access::open_to_others(dir) || mode & needs != needs {
                bail!(
                    "--program: {word}: the programs run as {who}, other users to it, who \
                     cannot {} it: `chmod o+{}` it and `o+x` the directories above it (or \
                     --as-root)",
                    if k == 0 { "run" } else { "read" },
                    if k == 0 { "rx" } else { "r" }
                );
            }
        }
    }
    Ok(())
}

/// The template's words that name a path (a `/` in them) and nothing the shell expands, its
/// quotes taken off: `'/opt/lab/run.sh'` is /opt/lab/run.sh; `{scene}`, `$HOME/x` and `*/x`
/// are left out.
fn path_words(template: &str) -> impl Iterator<Item = &str> {
    template
        .split_whitespace()
        .map(|w| w.trim_matches(|c| c == '\'' || c == '"'))
        .filter(|w| w.contains('/'))
        .filter(|w| !w.contains(['{', '$', '`', '*', '?', '[', '~', '\\', '\'', '"', ';', '&']))
}
