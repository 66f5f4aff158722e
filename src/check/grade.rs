//! Grading answers that are not raylab's against the exact ones: an answer file read as
//! `raylab trace` writes it, each ray's verdict, and the counts `raylab check` prints.

use crate::accel::{Accel, AccelChoice};
use crate::geometry::{adaptive, Method, Shape};
use crate::math::Real;
use crate::render::shade::Rgb;
use crate::render::CRACK;
use crate::scene::Scene;
use crate::tracefile::{TraceError, TraceRay};
use rayon::prelude::*;

/// One ray's answer to the nearest-hit question, as `raylab trace` prints it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Answer<T: Real> {
    /// `miss`: nothing is met with tmin < t < tmax.
    Miss,
    /// `hit <t> <index>`: the nearest primitive met and its t.
    Hit { t: T, prim: u32 },
}

impl<T: Real> Answer<T> {
    /// The answer as a line of an answer file (t as `raylab trace` prints it).
    pub fn text(&self) -> String {
        match self {
            Answer::Miss => "miss".into(),
            Answer::Hit { t, prim } => format!("hit {t} {prim}"),
        }
    }
}

/// Parses an answer file: one line per ray, `hit <t> <index>` or `miss` (blank lines and `#`
/// comments are skipped). t may be any number the precision reads, `nan` and `inf` included
/// (they are graded as t errors); an index must name one of the scene's `primitives`.
/// Returns each answer with its line.
pub fn parse_answers<T: Real>(
    file: &str,
    text: &str,
    primitives: usize,
) -> Result<Vec<(usize, Answer<T>)>, TraceError> {
    let at = |line: usize, message: String| TraceError {
        file: file.to_string(),
        line,
        message,
    };
    let mut answers = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line_no = i + 1;
        let words: Vec<&str> = line.split_whitespace().take(4).collect();
        let answer = match words.as_slice() {
            [] => continue,
            [w, ..] if w.starts_with('#') => continue,
            ["miss"] => Answer::Miss,
            ["hit", t, index] => {
                let t = t
                    .parse::<T>()
                    .map_err(|_| at(line_no, format!("t '{t}' is not a number")))?;
                let prim = index
                    .parse::<u32>()
                    .ok()
                    .filter(|&p| (p as usize) < primitives)
                    .ok_or_else(|| {
                        at(
                            line_no,
                            format!(
                                "'{index}' is not a primitive index (the scene has {primitives}: 0 to {})",
                                primitives.saturating_sub(1)
                            ),
                        )
                    })?;
                Answer::Hit { t, prim }
            }
            _ => {
                let start: String = line.trim().chars().take(60).collect();
                return Err(at(
                    line_no,
                    format!("expected 'hit <t> <index>' or 'miss', found '{start}'"),
                ));
            }
        };
        answers.push((line_no, answer));
    }
    Ok(answers)
}

/// The exact answers in f32 through the renderer's structures (the same on every path): t is
/// the exact t correctly rounded to f32.
pub fn exact_answers_f32(scene: &Scene, rays: &[TraceRay<f32>]) -> Vec<Answer<f32>> {
    let structure = Accel::for_scene(scene, AccelChoice::Auto);
    (rays.par_iter())
        .map(
            |r| match structure.closest_hit(&r.ray, Method::Adaptive, r.tmin, r.tmax) {
                None => Answer::Miss,
                Some(h) => Answer::Hit {
                    t: adaptive::rounded_t(&scene.shape(h.prim), &r.ray, r.tmin, r.tmax)
                        .unwrap_or(h.t),
                    prim: h.prim,
                },
            },
        )
        .collect()
}

/// The exact answers in any precision by the reference loop over every primitive: t is the
/// exact t correctly rounded to `T`.
pub fn exact_answers<T: Real>(shapes: &[Shape<T>], rays: &[TraceRay<T>]) -> Vec<Answer<T>> {
    (rays.par_iter())
        .map(
            |r| match adaptive::closest_hit_reference(shapes, &r.ray, r.tmin, r.tmax) {
                None => Answer::Miss,
                Some(h) => Answer::Hit {
                    t: adaptive::rounded_t(&shapes[h.prim as usize], &r.ray, r.tmin, r.tmax)
                        .unwrap_or(T::of(h.t)),
                    prim: h.prim,
                },
            },
        )
        .collect()
}

/// How an answer compares with the exact one.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Verdict {
    /// The exact primitive, or a miss where the exact ray meets nothing.
    Right,
    /// Another primitive met at exactly the same t as the exact one (accepted).
    Tie,
    /// A miss where the exact ray meets a primitive.
    Leak,
    /// A hit where the exact ray meets nothing.
    FalseHit,
    /// Another primitive, not met at exactly the same t.
    Wrong,
}

/// The colour of a wrong primitive in a picture of answers (linear cyan); a leak is
/// [`crate::render::CRACK`] magenta, as in the cracks view.
pub const WRONG: Rgb = [0.0, 1.0, 1.0];
/// The colour of a false hit (linear yellow).
pub const FALSE_HIT: Rgb = [1.0, 1.0, 0.0];

impl Verdict {
    /// The colour a picture of answers marks this verdict with (`raylab check --image`, the
    /// window's cracks view of code that is not raylab's); `None` where the answer stands
    /// (right, or an exact tie).
    pub fn mark(self) -> Option<Rgb> {
        match self {
            Verdict::Right | Verdict::Tie => None,
            Verdict::Leak => Some(CRACK),
            Verdict::Wrong => Some(WRONG),
            Verdict::FalseHit => Some(FALSE_HIT),
        }
    }

    /// The verdict in a word or two.
    pub fn name(self) -> &'static str {
        match self {
            Verdict::Right => "right",
            Verdict::Tie => "tie",
            Verdict::Leak => "leak",
            Verdict::FalseHit => "false hit",
            Verdict::Wrong => "wrong primitive",
        }
    }
}

/// How far a right or tied hit's t is from the exact t correctly rounded.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TError {
    /// At most one ulp of the precision away.
    WithinUlp,
    /// More than an ulp, at most 10⁻⁶ relative.
    WithinMicro,
    /// More than 10⁻⁶ relative, or not a finite number.
    Beyond,
}

/// One ray graded: its verdict and, for a right or tied hit, its t error.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Graded {
    pub verdict: Verdict,
    /// `Some` for a right or tied hit.
    pub t_error: Option<TError>,
    /// |t − exact t| / exact t, for a right or tied hit.
    pub relative: f64,
}

/// Grades `answer` to `ray` against the exact answer `exact`; `shape_of` gives a primitive by
/// its index (to decide an exact tie).
pub fn grade<T: Real>(
    shape_of: impl Fn(u32) -> Shape<T>,
    ray: &TraceRay<T>,
    exact: Answer<T>,
    answer: Answer<T>,
) -> Graded {
    let (verdict, exact_t, t) = match (exact, answer) {
        (Answer::Miss, Answer::Miss) => (Verdict::Right, None, None),
        (Answer::Hit { .. }, Answer::Miss) => (Verdict::Leak, None, None),
        (Answer::Miss, Answer::Hit { .. }) => (Verdict::FalseHit, None, None),
        (Answer::Hit { t: te, prim: pe }, Answer::Hit { t, prim }) if prim == pe => {
            (Verdict::Right, Some(te), Some(t))
        }
        (Answer::Hit { t: te, prim: pe }, Answer::Hit { t, prim }) => {
            // Listed first, the answer's primitive wins the exact search (ties go to the
            // lower index) only if it is met at exactly the exact nearest t.
            let pair = [shape_of(prim), shape_of(pe)];
            let first = adaptive::closest_hit_reference(&pair, &ray.ray, ray.tmin, ray.tmax);
            match first {
                Some(h) if h.prim == 0 => (Verdict::Tie, Some(te), Some(t)),
                _ => (Verdict::Wrong, None, None),
            }
        }
    };
    let (t_error, relative) = match (exact_t, t) {
        (Some(te), Some(t)) => {
            let relative = ((t.f64() - te.f64()) / te.f64()).abs();
            let grade = if !t.is_finite() {
                TError::Beyond
            } else if (t.key() - te.key()).abs() <= 1 {
                TError::WithinUlp
            } else if relative <= 1e-6 {
                TError::WithinMicro
            } else {
                TError::Beyond
            };
            (Some(grade), relative)
        }
        _ => (None, 0.0),
    };
    Graded {
        verdict,
        t_error,
        relative,
    }
}

/// The counts of a graded answer file (or of several).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Tally {
    pub rays: usize,
    pub right: usize,
    pub ties: usize,
    pub leaks: usize,
    pub false_hits: usize,
    pub wrong: usize,
    /// Right or tied hits whose t is within an ulp of the exact t.
    pub t_within_ulp: usize,
    /// … more than an ulp but within 10⁻⁶ relative.
    pub t_within_micro: usize,
    /// … beyond 10⁻⁶ relative (or not finite).
    pub t_beyond: usize,
}

/// The header of a suite's table, one [`Tally::row`] per family.
pub fn table_header() -> String {
    format!(
        "{:<46} {:>6} {:>6} {:>5} {:>6} {:>6} {:>6} {:>7} {:>11} {:>10}",
        "family",
        "rays",
        "right",
        "ties",
        "leaks",
        "false",
        "wrong",
        "t>1e-6",
        "program ms",
        "raylab ms"
    )
}

impl Tally {
    /// The counts as a row of a suite's table ([`table_header`]), with the program's and
    /// raylab's times in milliseconds.
    pub fn row(&self, name: &str, (program_ms, raylab_ms): (f64, f64)) -> String {
        format!(
            "{:<46} {:>6} {:>6} {:>5} {:>6} {:>6} {:>6} {:>7} {:>11.1} {:>10.1}",
            name,
            self.rays,
            self.right,
            self.ties,
            self.leaks,
            self.false_hits,
            self.wrong,
            self.t_beyond,
            program_ms,
            raylab_ms
        )
    }

    /// Counts one graded ray.
    pub fn add(&mut self, g: &Graded) {
        self.rays += 1;
        match g.verdict {
            Verdict::Right => self.right += 1,
            Verdict::Tie => self.ties += 1,
            Verdict::Leak => self.leaks += 1,
            Verdict::FalseHit => self.false_hits += 1,
            Verdict::Wrong => self.wrong += 1,
        }
        match g.t_error {
            Some(TError::WithinUlp) => self.t_within_ulp += 1,
            Some(TError::WithinMicro) => self.t_within_micro += 1,
            Some(TError::Beyond) => self.t_beyond += 1,
            None => {}
        }
    }

    /// Adds another tally's counts.
    pub fn merge(&mut self, other: &Tally) {
        self.rays += other.rays;
        self.right += other.right;
        self.ties += other.ties;
        self.leaks += other.leaks;
        self.false_hits += other.false_hits;
        self.wrong += other.wrong;
        self.t_within_ulp += other.t_within_ulp;
        self.t_within_micro += other.t_within_micro;
        self.t_beyond += other.t_beyond;
    }

    /// No leak, no false hit, no wrong primitive (t errors are reported, not failed).
    pub fn passed(&self) -> bool {
        self.leaks + self.false_hits + self.wrong == 0
    }

    /// The machine-readable line `raylab check` ends with.
    pub fn line(&self) -> String {
        format!(
            "check: rays {} right {} leaks {} false_hits {} wrong {} ties {} t_beyond_1e-6 {}",
            self.rays,
            self.right,
            self.leaks,
            self.false_hits,
            self.wrong,
            self.ties,
            self.t_beyond
        )
    }
}
