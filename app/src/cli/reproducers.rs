//! `raylab check`'s reproducers: the first wrong answers and t failures, each a line with
//! where its ray is, the ray, the exact answer and the answer given.

use raylab::check::grade::{self, Answer, Exact, Judged, Verdict};
use raylab::math::Real;

/// The first `most` wrong answers and the first `most` t failures, each under a heading, as
/// one-line reproducers.
pub(super) fn reproducers<T: Real>(
    judged: &[Judged<T>],
    exact: &Exact<T>,
    answers: &[(usize, Answer<T>)],
    place: &dyn Fn(usize) -> String,
    written: Written,
    most: usize,
) -> Vec<String> {
    let mut lines = Vec::new();
    let wrong = |j: &Judged<T>| !matches!(j.graded.verdict, Verdict::Right | Verdict::Tie);
    let t_failed = |j: &Judged<T>| j.graded.t_error == Some(grade::TError::Beyond);
    for (heading, wanted) in [
        ("wrong answers", &wrong as &dyn Fn(&Judged<T>) -> bool),
        ("hits whose t is beyond the tolerance", &t_failed),
    ] {
        let count = judged.iter().filter(|j| wanted(j)).count();
        if count == 0 || most == 0 {
            continue;
        }
        lines.push(format!(
            "the first of the {count} {heading} (ray, exact answer, the answer given):"
        ));
        let shown = (judged.iter().enumerate()).filter(|(_, j)| wanted(j));
        for (i, j) in shown.take(most) {
            lines.push(reproducer(i, j, exact, answers, place, written));
        }
    }
    lines
}

/// One graded ray as a line: where the ray is, the ray, the exact answer and the one given.
fn reproducer<T: Real>(
    i: usize,
    j: &Judged<T>,
    exact: &Exact<T>,
    answers: &[(usize, Answer<T>)],
    place: &dyn Fn(usize) -> String,
    written: Written,
) -> String {
    let ray = exact.rays[i].1;
    let given_t = match answers[i].1 {
        Answer::Hit { t, .. } => Some(t.f64()),
        Answer::Miss => None,
    };
    let outside = outside_interval(exact, i, &answers[i].1);
    let what = match j.graded.verdict {
        // (Not "off by inf": no point is off by a t that is no number or infinite.)
        Verdict::Right | Verdict::Tie if given_t.is_some_and(f64::is_nan) => {
            "t failure: t is not a number".to_string()
        }
        Verdict::Right | Verdict::Tie if given_t.is_some_and(f64::is_infinite) => {
            "t failure: t is infinite, where the exact t is not".to_string()
        }
        // What the tolerance judges: the point's distance, not t's own relative error (t 4x
        // too small can put the point 0.27 of the scale off).
        Verdict::Right | Verdict::Tie => format!(
            "t failure: o + t·d off by {:.2e} of |o| + |t·d| + extent{}",
            j.graded.relative,
            match (
                outside.as_deref(),
                short_print(&j.exact, &answers[i].1),
                other_root(exact, i, &j.exact, &answers[i].1),
                times_length(exact, i, &j.exact, &answers[i].1),
            ) {
                (Some(hint), ..) => format!("; {hint}"),
                (None, Some(digits), _, _) => format!(
                    "; t is the exact one to {digits} significant digits: print {0} (%.{0}g)",
                    round_trip_digits::<T>()
                ),
                (None, None, Some(_), _) => {
                    "; t is the ray's other meeting with the sphere: the nearest root above \
                     tmin wins"
                        .to_string()
                }
                (None, None, None, Some(length)) => format!(
                    "; t is the exact one times |d| = {}: t is in units of d, not normalised",
                    match (1e-3..1e6).contains(&length) {
                        true => format!("{length:.6}"),
                        false => format!("{length:.3e}"),
                    }
                ),
                (None, None, None, None) => String::new(),
            }
        ),
        v => match answers[i].1 {
            Answer::Hit { prim, .. } if prim as usize >= exact.primitives => {
                let last = exact.primitives.saturating_sub(1);
                let from_1 = match prim as usize == exact.primitives {
                    true => " (indices count from 0)",
                    false => "",
                };
                format!(
                    "{}: index {prim} is past the last primitive, {last}{from_1}",
                    v.name()
                )
            }
            _ => match &outside {
                Some(hint) => format!("{}: {hint}", v.name()),
                None => v.name().to_string(),
            },
        },
    };
    let line = answers[i].0;
    format!(
        "  {}: {}  exact: {}  given ({}:{line}): {}  [{what}]",
        place(i),
        ray.line(),
        j.exact.text(),
        written.name,
        written.line(line).unwrap_or_else(|| answers[i].1.text())
    )
}

/// Where the answers were read: the name of their file (`its output` for a program's) and
/// its text, so that an answer is shown as written (`hit 1e39 0` was shown as `hit inf 0`,
/// `hit 1.50 3` as `hit 1.5 3`).
#[derive(Clone, Copy)]
pub(super) struct Written<'a> {
    pub name: &'a str,
    pub text: &'a str,
}

impl Written<'_> {
    /// Line `n` (from 1) as written, its spaces trimmed, control characters escaped and a
    /// long one cut.
    fn line(&self, n: usize) -> Option<String> {
        let text = self.text.strip_prefix('\u{feff}').unwrap_or(self.text);
        let line = text.lines().nth(n.checked_sub(1)?)?.trim();
        Some(raylab_app::one_line(&raylab::words::shown(line)))
    }
}

/// Where a given hit's t is not inside the ray's open interval (tmin, tmax): which end it
/// passes. A hint beside the verdict (a hit behind the origin showed as a wrong primitive and
/// no more; on a sphere, as its other root).
fn outside_interval<T: Real>(exact: &Exact<T>, i: usize, given: &Answer<T>) -> Option<String> {
    let Answer::Hit { t, .. } = *given else {
        return None;
    };
    let ray = &exact.rays[i].1;
    let (tmin, tmax) = (ray.tmin, ray.tmax);
    if t.is_nan() {
        None
    } else if t <= tmin {
        let behind = match tmin == T::zero() && t < tmin {
            true => " (it is behind the origin)",
            false => "",
        };
        Some(format!(
            "t {t} is not above tmin {tmin}{behind}: only tmin < t < tmax counts"
        ))
    } else if t >= tmax {
        Some(format!(
            "t {t} is not below tmax {tmax}: only tmin < t < tmax counts, both ends open"
        ))
    } else {
        None
    }
}

/// Where the given hit is on a sphere and its t is, to 10⁻⁶ relative, the root of the ray's
/// quadratic that is not the exact answer's (the far root, or the one behind tmin): that root,
/// in f64. A hint beside the verdict, which the exact grading gave (a program that tried only
/// the far root was told its t was off by 0.47, and no more).
fn other_root<T: Real>(
    exact: &Exact<T>,
    i: usize,
    standing: &Answer<T>,
    given: &Answer<T>,
) -> Option<f64> {
    let Answer::Hit { t, prim } = *given else {
        return None;
    };
    let raylab::geometry::Shape::Sphere(s) = exact.shape(prim) else {
        return None;
    };
    let ray = &exact.rays[i].1.ray;
    let (o, d) = (ray.o.map(|c| c.f64()), ray.d.map(|c| c.f64()));
    let oc: Vec<f64> = (0..3).map(|k| o[k] - s.centre[k].f64()).collect();
    let a: f64 = d.iter().map(|c| c * c).sum();
    let b: f64 = (0..3).map(|k| d[k] * oc[k]).sum();
    let c: f64 = oc.iter().map(|c| c * c).sum::<f64>() - s.radius.f64().powi(2);
    let disc = b * b - a * c;
    if disc < 0.0 || a == 0.0 {
        return None;
    }
    let roots = [(-b - disc.sqrt()) / a, (-b + disc.sqrt()) / a];
    let exact_t = match *standing {
        Answer::Hit { t, .. } => t.f64(),
        Answer::Miss => return None,
    };
    let near = |x: f64, y: f64| (x - y).abs() <= 1e-6 * x.abs().max(y.abs()).max(1e-30);
    let other = match near(roots[0], exact_t) {
        true => roots[1],
        false => roots[0],
    };
    (near(t.f64(), other) && !near(t.f64(), exact_t)).then_some(other)
}

/// Where the given t is, to 10⁻⁶ relative, the exact t times |d| (the ray's direction
/// normalised, its t in units of length) and |d| is not 1: |d|. A hint beside the t failure.
fn times_length<T: Real>(
    exact: &Exact<T>,
    i: usize,
    standing: &Answer<T>,
    given: &Answer<T>,
) -> Option<f64> {
    let (Answer::Hit { t: te, .. }, Answer::Hit { t, .. }) = (standing, given) else {
        return None;
    };
    let d = exact.rays[i].1.ray.d.map(|c| c.f64());
    let length = d.iter().map(|c| c * c).sum::<f64>().sqrt();
    let (want, got) = (te.f64() * length, t.f64());
    let near = (want - got).abs() <= 1e-6 * want.abs().max(got.abs());
    ((length - 1.0).abs() > 1e-6 && near && got.is_finite()).then_some(length)
}

/// The significant digits that print every value of `T` so that it reads back the same: 9
/// for f32, 17 for f64.
fn round_trip_digits<T: Real>() -> usize {
    if T::PRECISION <= 24 {
        9
    } else {
        17
    }
}

/// Where the given t is the exact t rounded to fewer significant digits than `T` needs (a
/// C `%g` prints 6), how many: the t failure is the printing's, not the arithmetic's.
fn short_print<T: Real>(exact: &Answer<T>, given: &Answer<T>) -> Option<usize> {
    let (Answer::Hit { t: exact, .. }, Answer::Hit { t: given, .. }) = (exact, given) else {
        return None;
    };
    if !given.is_finite() || *given == T::zero() {
        return None;
    }
    // The shortest decimal that reads back as the given t, its significant digits only.
    let shortest = given.to_string();
    let digits = shortest.trim_start_matches('-').replace('.', "");
    let digits = digits
        .trim_start_matches('0')
        .trim_end_matches('0')
        .len()
        .max(1);
    let rounded = format!("{:.*e}", digits - 1, exact.f64())
        .parse::<T>()
        .ok()?;
    (digits < round_trip_digits::<T>() && rounded == *given).then_some(digits)
}
