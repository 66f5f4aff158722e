//! `raylab grade`'s families: each family of an exported suite with its exact answers computed
//! once, to grade any number of programs' outputs ([`Case`]).

use super::check::{
    answers_for, check_tolerance, exact_f32, exact_generic, judge_all, max_output, ray_place,
    tally_of,
};
use super::reproducers::{first_shown, reproducers, Written};
use super::rounding::rounding_fails;
use super::run_words::stalled;
use super::suite_dir::{family_name, suite_families};
use super::Precision;
use anyhow::Result;
use raylab::check::grade::{Exact, Tally};
use raylab::math::Real;
use std::path::{Path, PathBuf};

/// One family of an exported suite with its exact answers, computed once, to grade any
/// number of programs' outputs (`raylab grade`).
pub(super) struct Case {
    /// The family's directory name (`01-cube-from-inside`).
    pub name: String,
    pub scene: PathBuf,
    pub rays: PathBuf,
    pub ray_count: usize,
    /// Whether rounding fails some correct programs of the grading's precision on it
    /// (`None`: not a family of this raylab's suite).
    pub rounding: Option<bool>,
    /// The most a program may print for this family.
    pub max_output: usize,
    grader: Grader,
    /// Each ray's place (`rays.txt:LINE (ray N)`), for a run stopped for its time.
    places: Vec<String>,
}

/// Grades a program's standard output: the tally, its first mistake and that ray's line in
/// the rays file, or why it is not one answer per ray.
type Grader = Box<dyn Fn(&str) -> std::result::Result<Graded, String> + Send + Sync>;

/// A program's answers graded: the tally and, where it did not pass, its first mistake as
/// `check` shows it (the ray's place, the ray, the exact answer and the given one) and the
/// line of that ray in the rays file.
pub struct Graded {
    pub tally: Tally,
    pub first_mistake: String,
    pub first_line: Option<usize>,
}

impl Case {
    /// Grades a program's standard output ([`Graded`]), or says why it is not one answer per
    /// ray.
    pub fn grade(&self, stdout: &str) -> std::result::Result<Graded, String> {
        (self.grader)(stdout)
    }

    /// `why` a run was stopped for its time, with how far its answers came ([`stalled`]).
    pub fn stalled(&self, why: String, printed: &[u8]) -> String {
        stalled(why, printed, self.ray_count, |i| self.places[i].clone())
    }

    /// [`super::run_words::crashed`] for this family's rays.
    pub fn crashed(&self, why: String, printed: &[u8]) -> String {
        let place = |i: usize| self.places[i].clone();
        let graded = || {
            self.grade(&String::from_utf8_lossy(printed))
                .map(|g| g.tally)
        };
        super::run_words::crashed(why, printed, self.ray_count, place, graded)
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
        .map(|path| {
            let (scene, rays) = (path.join("scene.txt"), path.join("rays.txt"));
            let rounding = rounding_fails(&path, precision == Precision::F64);
            match precision {
                Precision::F32 => case_of(&path, exact_f32(&scene, &rays)?, tolerance, rounding),
                Precision::F64 => {
                    let exact = exact_generic::<f64>(&scene, &rays)?;
                    case_of(&path, exact, tolerance, rounding)
                }
            }
        })
        .collect()
}

fn case_of<T: Real>(
    path: &Path,
    exact: Exact<T>,
    tolerance: f64,
    rounding: Option<bool>,
) -> Result<Case> {
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
        rounding,
        max_output: max_output(ray_count),
        grader: Box::new(move |stdout| {
            let answers = answers_for("its output", stdout, &exact, &rays_file)
                .map_err(|e| format!("{e:#}"))?;
            let judged = judge_all(&exact, &answers, tolerance);
            let place = |i: usize| ray_place(&rays_file, &exact, i);
            // (The first line heads the list; the second is the first mistake.)
            let written = Written {
                name: "its output",
                text: stdout,
            };
            let lines = reproducers(&judged, &exact, &answers, &place, written, 1);
            Ok(Graded {
                tally: tally_of(&judged),
                first_mistake: {
                    let first = lines.get(1).map_or("", |l| l.trim()).to_string();
                    match super::line_up::off_by_a_line(&judged, &answers) {
                        Some(off) => format!("{first}\n{off}"),
                        None => first,
                    }
                },
                first_line: first_shown(&judged).map(|i| exact.rays[i].0),
            })
        }),
    })
}
