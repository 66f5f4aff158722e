//! Answers lined up with the exact ones, ray by ray: where a program's answers are the exact
//! ones a line off from some answer on (each the next or the last ray's: a line printed too
//! many or left out), or where answers more or fewer than the rays stop lining up. Either
//! made every hint below describe geometry that was not wrong.

use raylab::check::grade::{Answer, Judged, Verdict};
use raylab::math::Real;

/// Whether two t's are one, within 10⁻⁶ (relative).
fn same_t<T: Real>(s: T, t: T) -> bool {
    let (s, t) = (s.f64(), t.f64());
    (s - t).abs() <= 1e-6 * s.abs().max(t.abs())
}

/// Whether two answers are one: both misses, or hits of one primitive at one t. (By the
/// primitive alone, rays side by side meeting one wall lined answers a line late up with their
/// own rays.)
fn same<T: Real>(a: &Answer<T>, b: &Answer<T>) -> bool {
    match (a, b) {
        (Answer::Miss, Answer::Miss) => true,
        (Answer::Hit { prim: p, t: s }, Answer::Hit { prim: q, t }) => p == q && same_t(*s, *t),
        _ => false,
    }
}

/// Whether answer `a` may answer the ray whose exact answer is `b`, t aside: both misses, or
/// hits of one primitive, or at one t (a tie's another primitive).
fn may_answer<T: Real>(a: &Answer<T>, b: &Answer<T>) -> bool {
    match (a, b) {
        (Answer::Miss, Answer::Miss) => true,
        (Answer::Hit { prim: p, t: s }, Answer::Hit { prim: q, t }) => p == q || same_t(*s, *t),
        _ => false,
    }
}

/// Whether nine in ten of `pairs` (at least `least`) hold.
fn nine_in_ten(pairs: impl Iterator<Item = bool>, least: usize) -> bool {
    let (held, all) = pairs.fold((0, 0), |(h, a), p| (h + p as usize, a + 1));
    all >= least && 10 * held >= 9 * all
}

/// The answer from which, and the shift (+1 or −1) by which, a program's answers, as many as
/// the rays, are the exact ones a line off: from the first that is not right (`right`, each
/// ray's: right or a tie), answer K is the exact answer of ray K + shift for nine in ten of
/// its hits (at least 3), and half or fewer of those hits are right where they stand. Not
/// where half or more are their own rays' t on the primitive an index away (an index off by
/// one: its own hint says so).
pub(super) fn shift<T: Real>(
    given: &[Answer<T>],
    exact: &[Answer<T>],
    right: &[bool],
) -> Option<(usize, isize)> {
    let from = right.iter().position(|r| !r)?;
    let hits = || (from..given.len()).filter(|&k| matches!(given[k], Answer::Hit { .. }));
    let in_place = hits().filter(|&k| right[k]).count();
    // (Rays each aimed at the next primitive at t 1: an index off by one reads as a shift.)
    let index_off = |k: usize| match (given[k], exact[k]) {
        (Answer::Hit { t: s, prim: p }, Answer::Hit { t, prim: q }) => {
            same_t(s, t) && p.abs_diff(q) == 1
        }
        _ => false,
    };
    let (indices_off, all) = (hits().filter(|&k| index_off(k)).count(), hits().count());
    if 2 * in_place > all || 2 * indices_off > all {
        return None;
    }
    // (The last ray has no next: the pairs are those with a ray there.)
    let lined = |s: isize| {
        hits().filter_map(move |k| Some(same(&given[k], exact.get(k.checked_add_signed(s)?)?)))
    };
    [1, -1]
        .into_iter()
        .find(|&s| nine_in_ten(lined(s), 3))
        .map(|s| (from, s))
}

/// What `check` and `grade` say of graded answers a line off ([`shift`]), where some are
/// wrong.
pub(super) fn off_by_a_line<T: Real>(
    judged: &[Judged<T>],
    answers: &[(usize, Answer<T>)],
) -> Option<String> {
    let right: Vec<bool> = (judged.iter())
        .map(|j| matches!(j.graded.verdict, Verdict::Right | Verdict::Tie))
        .collect();
    let given: Vec<Answer<T>> = answers.iter().map(|(_, a)| *a).collect();
    let stood: Vec<Answer<T>> = judged.iter().map(|j| j.exact).collect();
    let (from, shift) = shift(&given, &stood, &right)?;
    let (which, why) = match (shift > 0, from) {
        (true, 0) => (
            "K + 1",
            "the first ray's answer left out, one more at the end?",
        ),
        (true, _) => ("K + 1", "its own answer left out, one more at the end?"),
        (false, 0) => (
            "K − 1",
            "a line printed before the first answer, the last left out?",
        ),
        (false, _) => (
            "K − 1",
            "a line printed before it, the last answer left out?",
        ),
    };
    let whence = match from {
        0 => "its answers are".to_string(),
        k => format!("from answer {} on, its answers are", k + 1),
    };
    Some(format!(
        "{whence} the exact ones a line off: answer K is the exact answer of ray {which} \
         ({why}); look at the order the answers are printed in"
    ))
}

/// Where answers more or fewer than the rays (`given`, `exact` the rays' exact answers) stop
/// lining up with the exact ones, t aside, in words after "N answers for the M rays of FILE"
/// (`place(k)`: where ray k is): the first answer unlike its own ray's, and where from there
/// the rest line up with the rays the difference later (fewer) or earlier (more), the answer
/// left out there or the line printed too many.
pub(super) fn where_they_part<T: Real>(
    given: &[Answer<T>],
    exact: &[Answer<T>],
    place: impl Fn(usize) -> String,
) -> String {
    if given.is_empty() {
        return String::new();
    }
    let n = given.len().min(exact.len());
    let from = (0..n)
        .position(|k| !may_answer(&given[k], &exact[k]))
        .unwrap_or(n);
    let fewer = given.len() < exact.len();
    let d = given.len().abs_diff(exact.len());
    let up_to = match from {
        0 => "the first is unlike its ray's".to_string(),
        k => format!(
            "they line up with the exact answers (t aside) up to {}",
            place(k - 1)
        ),
    };
    if from == n {
        return match fewer {
            true => format!("{up_to}, and stop there"),
            false => format!("{up_to}; the {d} after the last ray's are lines too many"),
        };
    }
    let (g, e) = match fewer {
        true => (&given[from..], &exact[from + d..]),
        false => (&given[from + d..], &exact[from..]),
    };
    let rest = g.iter().zip(e).map(|(a, b)| may_answer(a, b));
    match (nine_in_ten(rest, 1), fewer) {
        (true, true) => format!(
            "{up_to}, and from there with the rays {d} later: the answer of {} left out?",
            place(from)
        ),
        (true, false) => format!(
            "{up_to}, and answers {} on are the exact answers of the rays {d} before them: \
             answer {} printed too many?",
            from + d + 1,
            from + 1
        ),
        (false, _) if from == 0 => format!("the first is unlike the exact answer of {}", place(0)),
        (false, _) => format!("{up_to}; the next, {}'s, is not", place(from)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hit(prim: u32) -> Answer<f64> {
        Answer::Hit {
            t: 1.0 + prim as f64,
            prim,
        }
    }

    fn right(given: &[Answer<f64>], exact: &[Answer<f64>]) -> Vec<bool> {
        given.iter().zip(exact).map(|(g, e)| same(g, e)).collect()
    }

    /// A program one line late (a stale answer first, or from some answer on) is found; right
    /// answers, an index off by one at the same t, or ones a line off on rays that all meet
    /// one primitive at one t, are not.
    #[test]
    fn answers_a_line_off_are_found() {
        let exact: Vec<Answer<f64>> = [3, 1, 4, 1, 5, 9, 2, 6].map(hit).to_vec();
        let late: Vec<Answer<f64>> = [Answer::Miss].iter().chain(&exact[..7]).copied().collect();
        assert_eq!(shift(&late, &exact, &right(&late, &exact)), Some((0, -1)));
        let early: Vec<Answer<f64>> = exact[1..].iter().copied().chain([hit(0)]).collect();
        assert_eq!(shift(&early, &exact, &right(&early, &exact)), Some((0, 1)));
        let mid: Vec<Answer<f64>> = (exact[..3].iter().chain(&[Answer::Miss]).chain(&exact[3..7]))
            .copied()
            .collect();
        assert_eq!(shift(&mid, &exact, &right(&mid, &exact)), Some((3, -1)));
        assert_eq!(shift(&exact, &exact, &right(&exact, &exact)), None);
        let same_t = |p: u32| Answer::Hit { t: 1.0, prim: p };
        let exact_t1: Vec<Answer<f64>> = (0..8).map(same_t).collect();
        let index_plus_1: Vec<Answer<f64>> = (1..9).map(same_t).collect();
        let wrong = right(&index_plus_1, &exact_t1);
        assert_eq!(shift(&index_plus_1, &exact_t1, &wrong), None);
    }

    /// Answers fewer or more than the rays: where they part, and the answer left out or the
    /// line too many where the rest line up.
    #[test]
    fn answers_short_or_long_say_where_they_part() {
        let exact: Vec<Answer<f64>> = [3, 1, 4, 1, 5, 9, 2, 6].map(hit).to_vec();
        let place = |k: usize| format!("ray {}", k + 1);
        let skipped: Vec<Answer<f64>> = [3, 1, 4, 5, 9, 2, 6].map(hit).to_vec();
        let said = where_they_part(&skipped, &exact, place);
        assert!(
            said.ends_with("rays 1 later: the answer of ray 4 left out?"),
            "{said}"
        );
        let cut = &exact[..5];
        assert!(where_they_part(cut, &exact, place).ends_with("up to ray 5, and stop there"));
        let extra: Vec<Answer<f64>> = (exact[..2].iter().chain(&[Answer::Miss]).chain(&exact[2..]))
            .copied()
            .collect();
        let said = where_they_part(&extra, &exact, place);
        assert!(said.ends_with("answers 4 on are the exact answers of the rays 1 before them: answer 3 printed too many?"), "{said}");
        let one_wrong: Vec<Answer<f64>> =
            (exact[..2].iter().chain(&[Answer::Miss]).chain(&exact[3..6]))
                .copied()
                .collect();
        let said = where_they_part(&one_wrong, &exact, place);
        assert!(
            said.ends_with("up to ray 2; the next, ray 3's, is not"),
            "{said}"
        );
        assert_eq!(where_they_part(&[], &exact, place), "");
    }
}
