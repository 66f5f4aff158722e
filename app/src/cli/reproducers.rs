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
    answers_file: &str,
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
            lines.push(reproducer(i, j, exact, answers, place, answers_file));
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
    answers_file: &str,
) -> String {
    let ray = exact.rays[i].1;
    let what = match j.graded.verdict {
        // What the tolerance judges: the point's distance, not t's own relative error (t 4x
        // too small can put the point 0.27 of the scale off).
        Verdict::Right | Verdict::Tie => format!(
            "t failure: o + t·d off by {:.2e} of |o| + |t·d| + extent{}",
            j.graded.relative,
            (short_print(&j.exact, &answers[i].1)).map_or(String::new(), |digits| format!(
                "; t is the exact one to {digits} significant digits: print {0} (%.{0}g)",
                round_trip_digits::<T>()
            ))
        ),
        v => v.name().to_string(),
    };
    format!(
        "  {}: {}  exact: {}  given ({answers_file}:{}): {}  [{what}]",
        place(i),
        ray.line(),
        j.exact.text(),
        answers[i].0,
        answers[i].1.text()
    )
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
