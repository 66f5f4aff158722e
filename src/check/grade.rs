//! Grading answers that are not raylab's against the exact ones: an answer file read as
//! `raylab trace` writes it, the exact answers ([`Exact`]: the reference loop over every
//! primitive accuses), each ray's verdict and t error ([`grade`], [`t_error`]), and the
//! counts `raylab check` prints.

use crate::accel::{Accel, AccelChoice};
use crate::geometry::{adaptive, exact, triangle, Method, Shape};
use crate::math::Real;
use crate::render::shade::Rgb;
use crate::render::CRACK;
use crate::scene::Scene;
use crate::tracefile::{TraceError, TraceRay};
use rayon::prelude::*;
use std::sync::Arc;
use std::time::{Duration, Instant};

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
            // (NaN as a program prints it, `nan`: the echo of "hit nan 0" read "hit NaN 0".)
            Answer::Hit { t, prim } if t.is_nan() => format!("hit nan {prim}"),
            // (Far from 1 with an exponent, as a program prints it: `hit 4.44e-17 64` read
            // "hit 0.00000000000000004440019649484151 64", not a thing to look for.)
            Answer::Hit { t, prim } if t.is_finite() && *t != T::zero() && far_from_1(*t) => {
                format!("hit {t:e} {prim}")
            }
            Answer::Hit { t, prim } => format!("hit {t} {prim}"),
        }
    }
}

/// Whether `t` prints shorter with an exponent: below 10⁻⁵ or from 10¹⁶ in magnitude.
fn far_from_1<T: Real>(t: T) -> bool {
    let a = t.f64().abs();
    !(1e-5..1e16).contains(&a)
}

/// The byte-order mark some editors and runtimes put before a file's first line.
const BOM: char = '\u{feff}';

/// Parses an answer file: one line per ray, `hit <t> <index>` or `miss` (blank lines and `#`
/// comments are skipped, and a byte-order mark before the first line). t may be any number
/// the precision reads, `nan` and `inf` included (graded as t's: `inf` is right only where the
/// exact t rounds to infinity); an index must name one of the scene's `primitives`. Returns
/// each answer with its line.
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
    for (i, line) in text.strip_prefix(BOM).unwrap_or(text).lines().enumerate() {
        let line_no = i + 1;
        if line.starts_with(BOM) {
            return Err(at(
                line_no,
                "starts with a byte-order mark (U+FEFF), which only the first line may".into(),
            ));
        }
        let words: Vec<&str> = line.split_whitespace().take(4).collect();
        let answer = match words.as_slice() {
            [] => continue,
            [w, ..] if w.starts_with('#') => continue,
            ["miss"] => Answer::Miss,
            ["hit", t, index] => {
                let t = t.parse::<T>().map_err(|_| at(line_no, not_a_t(t)))?;
                // (An index past the last primitive is an answer, graded wrong for its ray
                // with the ray shown: refused, it failed the family's whole run.)
                // (`-0` is 0, as `+0` and `00` are.)
                let unsigned = index
                    .strip_prefix('-')
                    .filter(|z| z.bytes().all(|b| b == b'0'));
                let prim = unsigned.unwrap_or(index).parse::<u32>().map_err(|_| {
                    let last = primitives.saturating_sub(1);
                    let why = match index.bytes().all(|b| b.is_ascii_digit()) {
                        true => format!(
                            "index {index} is past any scene's last primitive (indices up to \
                             {}; this scene's last is {last})",
                            u32::MAX
                        ),
                        false => format!(
                            "'{index}' is not a primitive index, a whole number 0 to {last}"
                        ),
                    };
                    at(line_no, why)
                })?;
                Answer::Hit { t, prim }
            }
            _ => {
                // (Cut short with an ellipsis: a path cut at 60 characters read as the
                // program's own.)
                let mut start: String = line.trim().chars().take(60).collect();
                if start.len() < line.trim().len() {
                    start.push('…');
                }
                return Err(at(
                    line_no,
                    format!(
                        "expected 'hit <t> <index>' or 'miss', found '{start}' (other lines \
                         go to stderr, or start with #)"
                    ),
                ));
            }
        };
        answers.push((line_no, answer));
    }
    Ok(answers)
}

/// The default of `--t-tolerance`: how far a right hit's point may lie from the exact one,
/// relative to the size of the coordinates that give it ([`t_error`]).
pub const DEFAULT_T_TOLERANCE: f64 = 1e-6;

/// The exact answer of the reference loop over `count` primitives: t is the exact t correctly
/// rounded to `T`.
fn reference_answer<T: Real>(
    count: usize,
    shape_of: impl Fn(u32) -> Shape<T> + Copy,
    r: &TraceRay<T>,
) -> Answer<T> {
    match adaptive::closest_hit_reference_by(count, shape_of, &r.ray, r.tmin, r.tmax) {
        None => Answer::Miss,
        Some(h) => Answer::Hit {
            t: adaptive::rounded_t(&shape_of(h.prim), &r.ray, r.tmin, r.tmax).unwrap_or(T::of(h.t)),
            prim: h.prim,
        },
    }
}

/// The exact answers by the reference loop over every primitive, in any precision: t is the
/// exact t correctly rounded to `T`.
pub fn exact_answers<T: Real>(shapes: &[Shape<T>], rays: &[TraceRay<T>]) -> Vec<Answer<T>> {
    (rays.par_iter())
        .map(|r| reference_answer(shapes.len(), |p| shapes[p as usize], r))
        .collect()
}

/// A shape by its index, shared by the threads that grade.
type ShapeOf<T> = Arc<dyn Fn(u32) -> Shape<T> + Send + Sync>;

/// A scene's rays and their exact answers, read once and used to grade any number of answer
/// files. Where the answers came from the renderer's structures (to save time on a large
/// scene), every one that an answer disagrees with is answered again by the reference loop
/// over every primitive before that answer is graded: what accuses an answer is always the
/// reference.
pub struct Exact<T: Real> {
    /// The scene's primitives.
    pub primitives: usize,
    /// The rays, each with its line in the rays file.
    pub rays: Vec<(usize, TraceRay<T>)>,
    /// The exact answers, one per ray.
    pub answers: Vec<Answer<T>>,
    /// How long the exact answers took.
    pub elapsed: Duration,
    shape_of: ShapeOf<T>,
    /// Whether `answers` came from the renderer's structures (confirmed where disputed).
    fast: bool,
}

/// One ray graded against the exact answer that stands (the reference's, where disputed).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Judged<T: Real> {
    pub graded: Graded,
    pub exact: Answer<T>,
}

impl Exact<f32> {
    /// A scene as the renderer holds it (instances placed), answered through its structure
    /// in f32, each disputed answer confirmed by the reference loop.
    pub fn of_scene(scene: Arc<Scene>, rays: Vec<(usize, TraceRay<f32>)>) -> Self {
        let start = Instant::now();
        let structure = Accel::for_scene(&scene, AccelChoice::Auto);
        let answers = (rays.par_iter())
            .map(
                |(_, r)| match structure.closest_hit(&r.ray, Method::Adaptive, r.tmin, r.tmax) {
                    None => Answer::Miss,
                    Some(h) => Answer::Hit {
                        t: adaptive::rounded_t(&scene.shape(h.prim), &r.ray, r.tmin, r.tmax)
                            .unwrap_or(h.t),
                        prim: h.prim,
                    },
                },
            )
            .collect();
        Self {
            primitives: scene.len(),
            rays,
            answers,
            elapsed: start.elapsed(),
            shape_of: Arc::new(move |p| scene.shape(p)),
            fast: true,
        }
    }
}

impl<T: Real> Exact<T> {
    /// Primitives in any precision, answered by the reference loop.
    pub fn of_shapes(shapes: Vec<Shape<T>>, rays: Vec<(usize, TraceRay<T>)>) -> Self {
        let start = Instant::now();
        let shape_of = |p: u32| shapes[p as usize];
        let answers = (rays.par_iter())
            .map(|(_, r)| reference_answer(shapes.len(), shape_of, r))
            .collect();
        let primitives = shapes.len();
        Self {
            primitives,
            rays,
            answers,
            elapsed: start.elapsed(),
            shape_of: Arc::new(move |p| shapes[p as usize]),
            fast: false,
        }
    }

    /// Primitive `p`.
    pub fn shape(&self, p: u32) -> Shape<T> {
        (self.shape_of)(p)
    }

    /// Grades one answer per ray (in the rays' order), t against `tolerance`
    /// ([`t_error`]); an answer the fast path disputes is graded against the reference's.
    pub fn judge(&self, answers: &[Answer<T>], tolerance: f64) -> Vec<Judged<T>> {
        let shape_of = |p: u32| (self.shape_of)(p);
        (0..self.rays.len().min(answers.len()))
            .into_par_iter()
            .map(|i| {
                let ray = &self.rays[i].1;
                let graded = |exact| match answers[i] {
                    Answer::Hit { prim, .. } if prim as usize >= self.primitives => {
                        past_the_last(exact)
                    }
                    answer => grade(shape_of, ray, exact, answer, tolerance),
                };
                let (exact, first) = (self.answers[i], graded(self.answers[i]));
                if !self.fast || first.stands() {
                    return Judged {
                        graded: first,
                        exact,
                    };
                }
                let exact = reference_answer(self.primitives, shape_of, ray);
                Judged {
                    graded: graded(exact),
                    exact,
                }
            })
            .collect()
    }
}

/// A hit on an index past the last primitive (a count from 1, say): another primitive than
/// the exact one, or a hit where nothing is met.
fn past_the_last<T: Real>(exact: Answer<T>) -> Graded {
    let verdict = match exact {
        Answer::Hit { .. } => Verdict::Wrong,
        Answer::Miss => Verdict::FalseHit,
    };
    Graded {
        verdict,
        t_error: None,
        relative: 0.0,
    }
}

/// How an answer compares with the exact one.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Verdict {
    /// The exact primitive, or a miss where the exact ray meets nothing.
    Right,
    /// Another primitive met at exactly the same t as the exact one (or at a t rounding to
    /// the same value in the precision graded), or a triangle of zero area met no farther
    /// (accepted).
    Tie,
    /// A miss where the exact ray meets a primitive.
    Leak,
    /// A hit where the exact ray meets nothing.
    FalseHit,
    /// Another primitive, not met at the same t (nor at one rounding alike).
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
    /// At most one ulp of the precision away (or exactly the exact t where that is 0 or ±∞).
    WithinUlp,
    /// More than an ulp, within the tolerance ([`t_error`]).
    WithinTolerance,
    /// Beyond the tolerance, or not a number: a failure.
    Beyond,
}

/// One ray graded: its verdict and, for a right or tied hit, its t error.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Graded {
    pub verdict: Verdict,
    /// `Some` for a right or tied hit.
    pub t_error: Option<TError>,
    /// For a right or tied hit, the distance between the answer's point and the exact one,
    /// relative to the size of the coordinates ([`t_error`]).
    pub relative: f64,
}

impl Graded {
    /// Right or a tie, with t within the tolerance: the answer stands.
    pub fn stands(&self) -> bool {
        matches!(self.verdict, Verdict::Right | Verdict::Tie)
            && self.t_error != Some(TError::Beyond)
    }
}

/// How far `t` is from the exact `exact_t` along `ray`, on a primitive whose largest
/// coordinate is `extent` in magnitude: within an ulp of the precision; else the distance
/// between the points o + t·d and o + exact_t·d relative to the size of the coordinates that
/// give them, |t − exact_t|·|d| / (|o| + |exact_t|·|d| + extent), within `tolerance` or beyond
/// it (a correct program loses digits of o − c or o − v₀ in proportion to them). An exact t of
/// ±∞ (a t past the precision's range) is right only as itself. Also the relative distance.
pub fn t_error<T: Real>(
    ray: &TraceRay<T>,
    exact_t: T,
    t: T,
    extent: f64,
    tolerance: f64,
) -> (TError, f64) {
    let (te, tf) = (exact_t.f64(), t.f64());
    if tf == te {
        return (TError::WithinUlp, 0.0);
    }
    if !te.is_finite() || !tf.is_finite() {
        return (TError::Beyond, f64::INFINITY);
    }
    // Scaled by the largest component first: no square overflows or underflows.
    let norm = |v: [T; 3]| {
        let m = v.iter().fold(0.0f64, |m, c| m.max(c.f64().abs()));
        match m > 0.0 {
            true => m * v.iter().map(|c| (c.f64() / m).powi(2)).sum::<f64>().sqrt(),
            false => 0.0,
        }
    };
    let len = norm(ray.ray.d);
    let scale = norm(ray.ray.o) + te.abs() * len + extent;
    let relative = match scale > 0.0 {
        true => (tf - te).abs() * len / scale,
        false => f64::INFINITY,
    };
    // (Keys of opposite signs far apart differ by more than i64 holds.)
    let grade = if t.key().abs_diff(exact_t.key()) <= 1 {
        TError::WithinUlp
    } else if relative <= tolerance {
        TError::WithinTolerance
    } else {
        TError::Beyond
    };
    (grade, relative)
}

/// Grades `answer` to `ray` against the exact answer `exact`, t against `tolerance`
/// ([`t_error`]); `shape_of` gives a primitive by its index (to decide an exact tie). A hit
/// on a triangle of zero area is a tie where the ray meets it ([`zero_area_tie`]).
pub fn grade<T: Real>(
    shape_of: impl Fn(u32) -> Shape<T>,
    ray: &TraceRay<T>,
    exact: Answer<T>,
    answer: Answer<T>,
    tolerance: f64,
) -> Graded {
    if let Some(graded) = zero_area_tie(&shape_of, ray, exact, answer, tolerance) {
        return graded;
    }
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
            // Or met at a t that rounds to the exact nearest t: in the precision the answers
            // are written in the two hits lie at the same t, and no answer can say which of
            // them is nearer (a correct double program gets either).
            let same_rounded = || {
                let alone =
                    (adaptive::closest_hit_reference(&pair[..1], &ray.ray, ray.tmin, ray.tmax))
                        .is_some();
                let at = adaptive::rounded_t(&pair[0], &ray.ray, ray.tmin, ray.tmax);
                alone && at.is_some_and(|at| at.f64() == te.f64())
            };
            match first {
                Some(h) if h.prim == 0 => (Verdict::Tie, Some(te), Some(t)),
                _ if same_rounded() => (Verdict::Tie, Some(te), Some(t)),
                _ => (Verdict::Wrong, None, None),
            }
        }
    };
    let (t_error, relative) = match (exact_t, t, exact) {
        (Some(te), Some(t), Answer::Hit { prim, .. }) => {
            let extent = shape_of(prim).extent();
            let (grade, relative) = t_error(ray, te, t, extent, tolerance);
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

/// A hit on a triangle of zero area (vertices on one line), which raylab never hits, graded
/// as a tie where the ray exactly meets the segment or point its vertices span, with
/// tmin < t < tmax and t no farther than the exact answer's (rounded alike): a program that
/// takes such a triangle as closed is not wrong there. Its t is graded against where the ray
/// meets it. `None` for any other answer (graded as usual: a false hit or wrong primitive
/// where the ray passes it by).
fn zero_area_tie<T: Real>(
    shape_of: &impl Fn(u32) -> Shape<T>,
    ray: &TraceRay<T>,
    exact: Answer<T>,
    answer: Answer<T>,
    tolerance: f64,
) -> Option<Graded> {
    let Answer::Hit { t, prim } = answer else {
        return None;
    };
    if matches!(exact, Answer::Hit { prim: p, .. } if p == prim) {
        return None;
    }
    let shape = shape_of(prim);
    let v = shape.triangle().filter(|v| triangle::zero_area(v))?;
    let wide = |p: [T; 3]| p.map(Real::f64);
    let (o, d) = (wide(ray.ray.o), wide(ray.ray.d));
    let (tmin, tmax) = (ray.tmin.f64(), ray.tmax.f64());
    let contact = exact::zero_area_contact(o, d, &v.map(wide), tmin, tmax)?;
    let at: T = contact.rounded();
    if matches!(exact, Answer::Hit { t: te, .. } if at.f64() > te.f64()) {
        return None;
    }
    let (t_error, relative) = t_error(ray, at, t, shape.extent(), tolerance);
    Some(Graded {
        verdict: Verdict::Tie,
        t_error: Some(t_error),
        relative,
    })
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
    /// … more than an ulp but within the tolerance.
    pub t_within_tolerance: usize,
    /// … beyond the tolerance (or not a number): t failures.
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
        "t fail",
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
            Some(TError::WithinTolerance) => self.t_within_tolerance += 1,
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
        self.t_within_tolerance += other.t_within_tolerance;
        self.t_beyond += other.t_beyond;
    }

    /// No leak, no false hit, no wrong primitive and no t beyond the tolerance.
    pub fn passed(&self) -> bool {
        self.leaks + self.false_hits + self.wrong + self.t_beyond == 0
    }

    /// The machine-readable line `raylab check` ends with.
    pub fn line(&self) -> String {
        format!(
            "check: rays {} right {} leaks {} false_hits {} wrong {} ties {} t_failures {}",
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

/// Why an answer's t did not parse, naming the two forms a right program prints by its
/// language's defaults: C's `%a` hexadecimal, and a locale's decimal comma (Java's
/// `String.format` follows the locale LANG names).
fn not_a_t(t: &str) -> String {
    let digits = t.trim_start_matches(['-', '+']);
    let comma = t.contains(',') && t.replacen(',', ".", 1).parse::<f64>().is_ok();
    if digits.starts_with("0x") || digits.starts_with("0X") {
        format!(
            "t '{t}' is hexadecimal (C's %a): print it in decimal, `%.9g` in f32, `%.17g` in f64"
        )
    } else if comma {
        format!(
            "t '{t}' has a decimal comma, as a locale writes it: print a decimal point (in Java \
             `String.format(Locale.ROOT, ...)`)"
        )
    } else {
        format!("t '{t}' is not a number")
    }
}
