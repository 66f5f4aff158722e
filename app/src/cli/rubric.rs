//! `raylab grade --rubric`: points per passed family, as a teacher writes them; and a
//! submission's name as the rubric and the table write it.

use anyhow::{anyhow, bail, Result};
use std::collections::HashMap;
use std::path::Path;

/// Points per passed family.
pub(super) struct Rubric {
    named: HashMap<String, f64>,
    rest: f64,
}

impl Rubric {
    /// Reads a rubric; every family it names must be one of the suite's.
    pub(super) fn read(file: &Path, suite: &Path) -> Result<Rubric> {
        let text = super::read_text(file)?;
        let families: Vec<String> = std::fs::read_dir(suite)
            .map_err(|e| anyhow!("{}: {e}", suite.display()))?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.is_dir())
            .map(|p| name_of(&p))
            .collect();
        let (mut named, mut rest) = (HashMap::new(), None);
        for (n, line) in text.lines().enumerate() {
            let at = || format!("{}:{}", file.display(), n + 1);
            let words: Vec<&str> = line
                .split('#')
                .next()
                .unwrap_or("")
                .split_whitespace()
                .collect();
            let (key, points) = match words[..] {
                [] => continue,
                [key, points] => (key, points),
                _ => bail!(
                    "{}: expected `<family name or number> <points>` or `* <points>`",
                    at()
                ),
            };
            let points: f64 = match points.parse() {
                Ok(p) if (0.0..=1e9).contains(&p) => p,
                _ => bail!("{}: '{points}' is not a number of points (0 to 1e9)", at()),
            };
            let name = match key {
                "*" => {
                    if rest.replace(points).is_some() {
                        bail!("{}: a second `*` line", at());
                    }
                    continue;
                }
                _ => families.iter().find(|f| family_is(f, key)).cloned(),
            };
            let Some(name) = name else {
                bail!(
                    "{}: no family '{key}' in the suite {}",
                    at(),
                    suite.display()
                );
            };
            if named.insert(name.clone(), points).is_some() {
                bail!("{}: {name} has points already", at());
            }
        }
        if named.is_empty() && rest.is_none() {
            bail!(
                "{}: no points (lines `<family name or number> <points>`, `* <points>`)",
                file.display()
            );
        }
        let unnamed = families.len().saturating_sub(named.len());
        if rest.is_none() && unnamed > 0 {
            // (Likely a forgotten `* <points>` line.)
            eprintln!(
                "warning: {}: no `*` line: the families it does not name ({unnamed}) are worth \
                 0 points",
                file.display()
            );
        }
        Ok(Rubric {
            named,
            rest: rest.unwrap_or(0.0),
        })
    }

    pub(super) fn points(&self, family: &str) -> f64 {
        self.named.get(family).copied().unwrap_or(self.rest)
    }
}

/// Whether `key` names the family `name`: the name itself, or its number (`7` or `07`).
fn family_is(name: &str, key: &str) -> bool {
    name == key
        || key
            .parse::<usize>()
            .is_ok_and(|n| name.starts_with(&format!("{n:02}-")))
}

/// Points as a person writes them: `3`, `2.5`, `0.33` (sums of decimals rounded to 0.01).
pub(super) fn points_text(points: f64) -> String {
    let text = format!("{points:.2}");
    text.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// A submission's name: its directory's, a byte that is not UTF-8 written as `\xNN` (two
/// folders `caf\xe9` and `caf\xe8` both showed as `caf�`).
pub(super) fn name_of(dir: &Path) -> String {
    use std::os::unix::ffi::OsStrExt;
    let bytes = dir.file_name().map_or(&[][..], |n| n.as_bytes());
    let mut name = String::with_capacity(bytes.len());
    for chunk in bytes.utf8_chunks() {
        name.push_str(chunk.valid());
        for b in chunk.invalid() {
            name.push_str(&format!("\\x{b:02x}"));
        }
    }
    name
}
