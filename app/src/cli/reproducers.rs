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
            "t failure: o + t·d off by {:.1e} of |o| + |t·d| + extent",
            j.graded.relative
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
