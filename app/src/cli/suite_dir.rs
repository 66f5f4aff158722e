//! An exported suite on disk: its family directories in order, its manifest checked
//! (`raylab check --suite` and `raylab grade`'s [`super::cases`]).

use super::read_text;
use anyhow::{anyhow, bail, Result};
use raylab::check::export;
use std::path::{Path, PathBuf};

/// A family directory's name.
pub(super) fn family_name(dir: &Path) -> String {
    dir.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default()
}

/// The family directories of an exported suite, in order (only `only`, by its directory name
/// or its number, if given). Every directory in the suite must hold a regular scene.txt and
/// rays.txt: one that does not is named, not skipped.
pub(super) fn suite_families(dir: &Path, only: Option<&str>) -> Result<Vec<PathBuf>> {
    let entries = std::fs::read_dir(dir).map_err(|e| anyhow!("{}: {e}", dir.display()))?;
    let mut families: Vec<PathBuf> = Vec::new();
    for entry in entries {
        let entry = entry.map_err(|e| anyhow!("{}: {e}", dir.display()))?;
        let path = entry.path();
        if !entry.file_type().is_ok_and(|t| t.is_dir()) {
            continue;
        }
        for file in ["scene.txt", "rays.txt"] {
            let f = path.join(file);
            let meta = std::fs::metadata(&f);
            if !meta.as_ref().is_ok_and(|m| m.is_file()) {
                let why = match meta {
                    Err(e) => e.to_string(),
                    Ok(_) => "not a regular file".to_string(),
                };
                bail!(
                    "{}: a family of the suite without its {file} ({why}); if {} is a suite, export it again with `raylab suite export`",
                    f.display(),
                    dir.display()
                );
            }
        }
        families.push(path);
    }
    families.sort();
    check_manifest(dir, &families, only)?;
    if families.is_empty() && dir.join("scene.txt").is_file() && dir.join("rays.txt").is_file() {
        let parent = dir.parent().unwrap_or(Path::new("."));
        bail!(
            "{}: a family, not a suite; check it with `--suite {} --family {}`",
            dir.display(),
            parent.display(),
            family_name(dir)
        );
    }
    if families.is_empty() {
        bail!(
            "{}: no family directories (DIR/<family>/scene.txt and rays.txt); write a suite with `raylab suite export {}`",
            dir.display(),
            dir.display()
        );
    }
    if let Some(only) = only {
        families.retain(|p| is_family(&family_name(p), Some(only)));
        if families.is_empty() {
            bail!(
                "{}: no family '{only}' (a directory name such as 01-cube-from-inside, or its number)",
                dir.display()
            );
        }
    }
    Ok(families)
}

/// Whether family directory `name` is the one `only` names (its directory name, or its number),
/// or any family where `only` is `None`.
fn is_family(name: &str, only: Option<&str>) -> bool {
    let Some(only) = only else { return true };
    let number = only.parse::<usize>().ok().map(|n| format!("{n:02}-"));
    name == only || number.is_some_and(|n| name.starts_with(n.as_str()))
}

/// Checks the families found in `dir` (those `only` names) against the suite's manifest
/// ([`export::MANIFEST`], written last by `raylab suite export`): a family it lists that is
/// missing or has another number of rays fails the run, named. Without a manifest (a suite
/// made by hand, or an export cut short) that is said on stderr, and what is there is graded.
fn check_manifest(dir: &Path, families: &[PathBuf], only: Option<&str>) -> Result<()> {
    let path = dir.join(export::MANIFEST);
    if std::fs::symlink_metadata(&path).is_err() {
        // (No families at all is said as such.)
        if families.is_empty() {
            return Ok(());
        }
        eprintln!(
            "warning: {}: no {} (written last by `raylab suite export`): not an exported suite, \
             or an export cut short; grading what it holds ({} family directories)",
            dir.display(),
            export::MANIFEST,
            families.len()
        );
        return Ok(());
    }
    let listed =
        export::read_manifest(&read_text(&path)?).map_err(|e| anyhow!("{}:{e}", path.display()))?;
    let mut wrong = Vec::new();
    for (name, count) in listed.iter().filter(|(n, _)| is_family(n, only)) {
        let Some(family) = families.iter().find(|p| family_name(p) == *name) else {
            wrong.push(format!("{name} is missing"));
            continue;
        };
        let rays = read_text(&family.join("rays.txt"))?;
        let found = rays
            .lines()
            .filter(|l| {
                l.split_whitespace()
                    .next()
                    .is_some_and(|w| !w.starts_with('#'))
            })
            .count();
        if found != *count {
            wrong.push(format!("{name} has {found} rays, not {count}"));
        }
    }
    // (A family directory the manifest does not list is graded, and said: an empty manifest
    // graded a folder of them without a word.)
    let unlisted: Vec<String> = (families.iter().map(|p| family_name(p)))
        .filter(|name| is_family(name, only) && !listed.iter().any(|(n, _)| n == name))
        .collect();
    if !unlisted.is_empty() {
        eprintln!(
            "warning: {}: {} not listed in its {}, graded as found: {}",
            dir.display(),
            raylab::words::count(unlisted.len(), "family directory", "family directories"),
            export::MANIFEST,
            unlisted.join(", ")
        );
    }
    if !wrong.is_empty() {
        bail!(
            "{}: not the suite its {} lists: {}; export it again with `raylab suite export {}`",
            dir.display(),
            export::MANIFEST,
            wrong.join(", "),
            dir.display()
        );
    }
    Ok(())
}
