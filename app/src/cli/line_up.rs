//! Answers lined up with the exact ones, ray by ray: where a program's answers are the exact
//! ones a line off from some answer on (each the next or the last ray's: a line printed too
//! many or left out), or where answers more or fewer than the rays part from them. Either made
//! every hint below describe geometry that was not wrong.
//!
//! Both fit one model: the answers are in place up to some answer, and from it on each is the
//! exact answer of the ray `shift` later; the split that makes the most answers agree is
//! taken, and a claim made only where nine in ten agree from it on, and many more than in
//! place.

use raylab::check::grade::{Answer, Judged};
use raylab::math::Real;

/// Whether two answers are one: both misses, or hits of one primitive at t's within 10⁻⁴ of
/// each other (relative: a t printed with 6 digits still lines up). (By the primitive alone,
/// rays side by side meeting one wall lined answers a line late up with their own rays.)
fn same<T: Real>(a: &Answer<T>, b: &Answer<T>) -> bool {
    match (a, b) {
        (Answer::Miss, Answer::Miss) => true,
        (Answer::Hit { prim: p, t: s }, Answer::Hit { prim: q, t }) => p == q && same_t(*s, *t),
        _ => false,
    }
}

/// Whether two t's are one to 10⁻⁴ (relative), as [`same`] takes them.
fn same_t<T: Real>(s: T, t: T) -> bool {
    let (s, t) = (s.f64(), t.f64());
    (s - t).abs() <= 1e-4 * s.abs().max(t.abs())
}

/// The best split of answers `0..n`: in place before it (`before(k)`), shifted from it
/// (`after(k)`, `None` where answer k has no ray to shift to). Returns the first and last
/// splits that make the most answers agree. (Two passes, nothing held a ray: `check --image`
/// holds at most 160 bytes a ray.)
fn best_split(
    n: usize,
    before: impl Fn(usize) -> bool,
    after: impl Fn(usize) -> Option<bool>,
) -> (usize, usize) {
    let agrees = |k: usize| after(k) == Some(true);
    let all_after = (0..n).filter(|&k| agrees(k)).count();
    let (mut best, mut first, mut last) = (0, 0, 0);
    let (mut in_place, mut after_passed) = (0, 0);
    for p in 0..=n {
        let score = in_place + all_after - after_passed;
        if score > best || p == 0 {
            (best, first) = (score, p);
        }
        if score == best {
            last = p;
        }
        if p < n {
            in_place += before(p) as usize;
            after_passed += agrees(p) as usize;
        }
    }
    (first, last)
}

/// How many of answers `from..n` agree shifted (`after`), and how many were compared.
fn held_from(from: usize, n: usize, after: impl Fn(usize) -> Option<bool>) -> (usize, usize) {
    (from..n)
        .filter_map(after)
        .fold((0, 0), |(held, compared), a| {
            (held + a as usize, compared + 1)
        })
}

/// The answer from which, and the shift (+1 or −1) by which, `n` answers (`given(k)`), as
/// many as the rays (`exact(k)`, `None` past the last), are the exact ones a line off: the
/// best split ([`best_split`]) for a shift, where nine in ten of at least 3 agree from it on,
/// and at least half of those more than in place (`right(k)`: right or a tie, t within the
/// tolerance). Not where nine in ten of the answers from it that are wrong are their own
/// ray's t on the primitive an index away (an index off by one: its own hint says so).
pub(super) fn shift<T: Real>(
    n: usize,
    given: impl Fn(usize) -> Answer<T>,
    exact: impl Fn(usize) -> Option<Answer<T>>,
    right: impl Fn(usize) -> bool,
) -> Option<(usize, isize)> {
    let candidate = |s: isize| {
        let after = |k: usize| Some(same(&given(k), &exact(k.checked_add_signed(s)?)?));
        // (The last best split: the first takes in a stray line, one answer against nine.)
        let (_, from) = best_split(n, &right, after);
        let (held, compared) = held_from(from, n, after);
        let in_place = (from..n).filter(|&k| right(k)).count();
        let agreed = compared >= 3 && 10 * held >= 9 * compared;
        (agreed && 2 * held.saturating_sub(in_place) >= compared).then_some((from, s, held))
    };
    let (from, s, _) = [candidate(1), candidate(-1)]
        .into_iter()
        .flatten()
        .max_by_key(|c| c.2)?;
    // (Rays each aimed at the next primitive at t 1: an index off by one reads as a shift.)
    let index_off = |k: usize| match (given(k), exact(k)) {
        (Answer::Hit { t: a, prim: p }, Some(Answer::Hit { t: b, prim: q })) => {
            same_t(a, b) && p.abs_diff(q) == 1
        }
        _ => false,
    };
    let wrong = (from..n).filter(|&k| !right(k)).count();
    let off = (from..n).filter(|&k| !right(k) && index_off(k)).count();
    (wrong == 0 || 10 * off < 9 * wrong).then_some((from, s))
}

/// What `check` and `grade` say of graded answers a line off ([`shift`]), where some are
/// wrong.
pub(super) fn off_by_a_line<T: Real>(
    judged: &[Judged<T>],
    answers: &[(usize, Answer<T>)],
) -> Option<String> {
    let right = |k: usize| judged[k].graded.stands();
    let n = judged.len().min(answers.len());
    if (0..n).all(right) {
        return None;
    }
    let (given, stood) = (
        |k: usize| answers[k].1,
        |k: usize| judged.get(k).map(|j| j.exact),
    );
    let (from, shift) = shift(n, given, stood, right)?;
    // (Shifted a line late, the first answer is never compared: the split is 1 or more.)
    let (which, why) = match (shift > 0, from) {
        (true, 0) => (
            "K + 1",
            "the first ray's answer left out, one more at the end?",
        ),
        (true, _) => ("K + 1", "its own answer left out, one more at the end?"),
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

/// Where answers more or fewer than the rays (`given`; `exact`, the rays' exact answers) part
/// from the exact ones, in words after "N answers for the M rays of FILE" (`place(k)`: where
/// ray k is): where the best split ([`best_split`]) lines nine in ten up, the answer left out
/// or the line printed too many there (or the range of them the answers cannot tell apart);
/// else where the first answer unlike its own ray's is.
pub(super) fn where_they_part<T: Real>(
    given: &[Answer<T>],
    exact: &[Answer<T>],
    place: impl Fn(usize) -> String,
) -> String {
    let n = given.len();
    if n == 0 || n == exact.len() {
        return String::new();
    }
    let fewer = n < exact.len();
    let d = n.abs_diff(exact.len());
    let before = |k: usize| exact.get(k).is_some_and(|e| same(&given[k], e));
    let after = |k: usize| {
        let e = match fewer {
            true => k + d,
            false => k.checked_sub(d)?,
        };
        Some(exact.get(e).is_some_and(|e| same(&given[k], e)))
    };
    let (first, last) = best_split(n, before, after);
    let agreed = (0..first).filter(|&k| before(k)).count()
        + (first..n).filter(|&k| after(k).unwrap_or(false)).count();
    // (More answers than rays, every ray's in place: the rest are lines too many.)
    let in_place = (0..n).position(|k| !before(k)).unwrap_or(n);
    if !fewer && in_place >= exact.len() {
        return format!(
            "they are the exact answers, and the {d} after the last ray's lines too many"
        );
    }
    // (Of the answers that can: lines too many agree with no ray.)
    let can = if fewer { n } else { n - d };
    if 10 * agreed < 9 * can {
        return match Some(in_place).filter(|&k| k < n) {
            Some(k) => format!(
                "they line up with the rays neither in place nor {d} off; the first unlike its \
                 own ray's exact answer is answer {} ({})",
                k + 1,
                place(k)
            ),
            None => String::new(),
        };
    }
    // (A split p: the answers of rays p.. left out, fewer; answers p.. printed too many, more,
    // where the d + 1 splits around lines too many, unlike their neighbours' rays, tie.)
    let last = match fewer {
        true => last,
        false => last.saturating_sub(d).max(first).min(n - 1),
    };
    let (f, l) = (first, last);
    let lines = |(one, many): (&str, &str), end: usize| match (d, f == l) {
        (1, true) => format!("{one} {}", f + 1),
        (_, true) => format!("{many} {} to {}", f + 1, f + d),
        (1, false) => format!("one of {many} {} to {end}", f + 1),
        (_, false) => format!("{d} of {many} {} to {end}", f + 1),
    };
    match fewer {
        // (Every split alike: the answers cannot tell where.)
        true if f == 0 && l >= n => String::new(),
        false if f == 0 && l + 1 >= n => String::new(),
        true if f == n => format!(
            "they are the exact answers up to {}, and stop",
            place(n - 1)
        ),
        true if d == 1 && f == l => format!(
            "they line up with the exact answers, but for the answer of {} left out? (each \
             answer after it the exact answer of the ray 1 later)",
            place(f)
        ),
        true => format!(
            "they line up with the exact answers, but for {} left out? (each answer after \
             them the exact answer of the ray {d} later)",
            lines(
                ("the answer of ray", "the answers of rays"),
                (l + d).min(exact.len())
            )
        ),
        false => format!(
            "they line up with the exact answers, but for {} printed too many? (each answer \
             after them the exact answer of the ray {d} before)",
            lines(("answer", "answers"), (l + d).min(n))
        ),
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

    /// [`shift`] of slices.
    fn shift_of(
        given: &[Answer<f64>],
        exact: &[Answer<f64>],
        right: &[bool],
    ) -> Option<(usize, isize)> {
        shift(
            given.len(),
            |k| given[k],
            |k| exact.get(k).copied(),
            |k| right[k],
        )
    }

    /// A program one line late (a stale answer first, or from some answer on) is found, and
    /// from where, past an early wrong answer of its own; right answers, or an index off by
    /// one at the same t, are not.
    #[test]
    fn answers_a_line_off_are_found() {
        let exact: Vec<Answer<f64>> = [3, 1, 4, 1, 5, 9, 2, 6, 5, 3].map(hit).to_vec();
        let late: Vec<Answer<f64>> = [Answer::Miss].iter().chain(&exact[..9]).copied().collect();
        assert_eq!(
            shift_of(&late, &exact, &right(&late, &exact)),
            Some((1, -1))
        );
        let early: Vec<Answer<f64>> = exact[1..].iter().copied().chain([hit(0)]).collect();
        assert_eq!(
            shift_of(&early, &exact, &right(&early, &exact)),
            Some((0, 1))
        );
        let mut mid: Vec<Answer<f64>> =
            (exact[..4].iter().chain(&[Answer::Miss]).chain(&exact[4..9]))
                .copied()
                .collect();
        assert_eq!(shift_of(&mid, &exact, &right(&mid, &exact)), Some((5, -1)));
        mid[2] = Answer::Miss;
        assert_eq!(shift_of(&mid, &exact, &right(&mid, &exact)), Some((5, -1)));
        assert_eq!(shift_of(&exact, &exact, &right(&exact, &exact)), None);
        let t1 = |p: u32| Answer::Hit { t: 1.0, prim: p };
        let exact_t1: Vec<Answer<f64>> = (0..8).map(t1).collect();
        let index_plus_1: Vec<Answer<f64>> = (1..9).map(t1).collect();
        let wrong = right(&index_plus_1, &exact_t1);
        assert_eq!(shift_of(&index_plus_1, &exact_t1, &wrong), None);
    }

    /// Answers fewer or more than the rays: the answer left out or the line too many, a range
    /// where the answers cannot tell, or the first unlike its own where nothing lines up.
    #[test]
    fn answers_short_or_long_say_where_they_part() {
        let exact: Vec<Answer<f64>> = [3, 1, 4, 1, 5, 9, 2, 6, 5, 3].map(hit).to_vec();
        let place = |k: usize| format!("ray {}", k + 1);
        let part = |given: &[Answer<f64>]| where_they_part(given, &exact, place);
        let skipped: Vec<Answer<f64>> = (exact[..3].iter().chain(&exact[4..])).copied().collect();
        assert!(part(&skipped).contains("but for the answer of ray 4 left out?"));
        assert!(part(&exact[1..]).contains("but for the answer of ray 1 left out?"));
        assert!(part(&exact[1..])
            .contains("(each answer after it the exact answer of the ray 1 later)"));
        assert!(part(&exact[..9]).starts_with("they are the exact answers up to ray 9, and stop"));
        let extra: Vec<Answer<f64>> = (exact[..2].iter().chain(&[Answer::Miss]).chain(&exact[2..]))
            .copied()
            .collect();
        assert!(
            part(&extra).contains("but for answer 3 printed too many?"),
            "{}",
            part(&extra)
        );
        let walls = vec![hit(7); 10];
        assert_eq!(where_they_part(&walls[..9], &walls, place), "");
        let twin: Vec<Answer<f64>> = [3, 1, 1, 1, 5].map(hit).to_vec();
        let said = where_they_part(&[3, 1, 1, 5].map(hit), &twin, place);
        assert!(
            said.contains("one of the answers of rays 2 to 4 left out?"),
            "{said}"
        );
        let scrambled: Vec<Answer<f64>> = [9, 9, 9, 9, 9, 9, 9, 9, 9].map(hit).to_vec();
        assert!(
            part(&scrambled).contains("the first unlike its own ray's exact answer is answer 1")
        );
        assert_eq!(part(&[]), "");
        let two_out: Vec<Answer<f64>> = (exact[..3].iter().chain(&exact[5..])).copied().collect();
        assert!(part(&two_out).contains("but for the answers of rays 4 to 5 left out?"));
        let two_more: Vec<Answer<f64>> = (exact[..3]
            .iter()
            .chain(&[Answer::Miss, Answer::Miss])
            .chain(&exact[3..]))
        .copied()
        .collect();
        let said = part(&two_more);
        assert!(
            said.contains("but for answers 4 to 5 printed too many?"),
            "{said}"
        );
        let first_out = where_they_part(&[hit(2)], &[hit(1), hit(2)], place);
        assert!(
            first_out.contains("but for the answer of ray 1 left out?"),
            "{first_out}"
        );
        let one_more = where_they_part(&[hit(3), Answer::Miss], &[hit(3)], place);
        assert_eq!(
            one_more,
            "they are the exact answers, and the 1 after the last ray's lines too many"
        );
    }

    /// Every pairing of up to 4 answers with up to 4 rays, each a miss or one of two hits,
    /// is lined up without a panic (a ray's place past the last ray was asked for).
    #[test]
    fn every_small_pairing_lines_up_without_a_panic() {
        let kinds = [Answer::Miss, hit(1), hit(2)];
        let all = |len: usize| -> Vec<Vec<Answer<f64>>> {
            (0..3usize.pow(len as u32))
                .map(|mut code| {
                    (0..len)
                        .map(|_| {
                            let a = kinds[code % 3];
                            code /= 3;
                            a
                        })
                        .collect()
                })
                .collect()
        };
        for (n, m) in (0..=4).flat_map(|n| (1..=4).map(move |m| (n, m))) {
            // (A place past the last ray panics where the command line looks it up.)
            let place = |k: usize| {
                assert!(k < m, "ray {k} of {m}");
                format!("ray {}", k + 1)
            };
            for given in all(n) {
                for exact in all(m) {
                    where_they_part(&given, &exact, place);
                    if n == m {
                        shift_of(&given, &exact, &right(&given, &exact));
                    }
                }
            }
        }
    }
}
