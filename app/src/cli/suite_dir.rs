//! An exported suite on disk: its family directories in order, its manifest checked, and
//! each family with its exact answers computed once, to grade any number of programs'
//! outputs (`raylab grade`'s [`Case`]).

use super::check::{
    answers_for, check_tolerance, exact_f32, exact_generic, judge_all, max_output, ray_place,
    stalled, tally_of,
};
use super::reproducers::reproducers;
use super::{read_text, Precision};
use anyhow::{anyhow, bail, Result};
use raylab::check::export;
use raylab::check::grade::{Exact, Tally};
use raylab::math::Real;
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
    let listed = export::read_manifest(&read_text(&path)?)
        .map_err(|e| anyhow!("{}: {e}", path.display()))?;
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

/// One family of an exported suite with its exact answers, computed once, to grade any
/// number of programs' outputs (`raylab grade`).
pub(super) struct Case {
    /// The family's directory name (`01-cube-from-inside`).
    pub name: String,
    pub scene: PathBuf,
    pub rays: PathBuf,
    pub ray_count: usize,
    /// The most a program may print for this family.
    pub max_output: usize,
    grader: Grader,
    /// Each ray's place (`rays.txt:LINE (ray N)`), for a run stopped for its time.
    places: Vec<String>,
}

/// Grades a program's standard output: the tally and its first mistake, or why it is not one
/// answer per ray.
type Grader = Box<dyn Fn(&str) -> std::result::Result<(Tally, String), String> + Send + Sync>;

impl Case {
    /// Grades a program's standard output: the tally and, where it did not pass, its first
    /// mistake as `check` shows it (the ray's place, the ray, the exact answer and the given
    /// one), or why it is not one answer per ray.
    pub fn grade(&self, stdout: &str) -> std::result::Result<(Tally, String), String> {
        (self.grader)(stdout)
    }

    /// `why` a run was stopped for its time, with how far its answers came ([`stalled`]).
    pub fn stalled(&self, why: String, printed: &[u8]) -> String {
        stalled(why, printed, self.ray_count, |i| self.places[i].clone())
    }
}

/// The families of an exported suite (only `family` if given: a directory name or its
/// number), each with its exact answers computed once.
pub(super) fn suite_cases(
    dir: &Path,
    family: Option<&str>,
    precision: Precision,
    tolerance: f64,
) -> Result<Vec<Case>> {
    check_tolerance(tolerance)?;
    suite_families(dir, family)?
        .into_iter()
        .map(|path| match precision {
            Precision::F32 => case_of(
                &path,
                exact_f32(&path.join("scene.txt"), &path.join("rays.txt"))?,
                tolerance,
            ),
            Precision::F64 => case_of(
                &path,
                exact_generic::<f64>(&path.join("scene.txt"), &path.join("rays.txt"))?,
                tolerance,
            ),
        })
        .collect()
}

fn case_of<T: Real>(path: &Path, exact: Exact<T>, tolerance: f64) -> Result<Case> {
    let (scene, rays) = (path.join("scene.txt"), path.join("rays.txt"));
    let rays_file = rays.clone();
    let ray_count = exact.rays.len();
    let places = (0..ray_count)
        .map(|i| ray_place(&rays, &exact, i))
        .collect();
    Ok(Case {
        places,
        name: family_name(path),
        scene,
        rays,
        ray_count,
        max_output: max_output(ray_count),
        grader: Box::new(move |stdout| {
            let answers = answers_for("its output", stdout, &exact, &rays_file)
                .map_err(|e| format!("{e:#}"))?;
            let judged = judge_all(&exact, &answers, tolerance);
            let place = |i: usize| ray_place(&rays_file, &exact, i);
            // (The first line heads the list; the second is the first mistake.)
            let lines = reproducers(&judged, &exact, &answers, &place, "its output", 1);
            let first = lines.get(1).map_or("", |l| l.trim()).to_string();
            Ok((tally_of(&judged), first))
        }),
    })
}
