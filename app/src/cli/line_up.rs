//! Answers lined up with the exact ones, ray by ray: where a program's answers are
//! right but a line off (each the next or the last ray's), or where, fewer than the rays, they
//! stop lining up (an answer left out there). Either made every hint below describe geometry
//! that was not wrong, and a ray checked alone passed.

use raylab::check::grade::{Answer, Judged, Verdict};
use raylab::math::Real;

/// Whether two answers agree: both misses, or hits of one primitive (`with_t`: at t's within
/// 10⁻⁶ of each other, relative). (Rays side by side meet one wall: by the primitive alone,
/// answers a line late lined up with their own rays.)
fn alike<T: Real>(a: &Answer<T>, b: &Answer<T>, with_t: bool) -> bool {
    match (a, b) {
        (Answer::Miss, Answer::Miss) => true,
        (Answer::Hit { prim: p, t: s }, Answer::Hit { prim: q, t }) => {
            let (s, t) = (s.f64(), t.f64());
            p == q && (!with_t || (s - t).abs() <= 1e-6 * s.abs().max(t.abs()))
        }
        _ => false,
    }
}

/// How many of `given`'s answers that are hits agree with `exact`'s `shift` rays later (K
/// against K + shift), and how many hits were compared.
fn hits_alike<T: Real>(given: &[Answer<T>], exact: &[Answer<T>], shift: isize) -> (usize, usize) {
    let pairs = (0..given.len()).filter_map(|k| {
        let e = exact.get(k.checked_add_signed(shift)?)?;
        let g = &given[k];
        matches!(g, Answer::Hit { .. }).then_some(alike(g, e, true))
    });
    pairs.fold((0, 0), |(same, all), a| (same + a as usize, all + 1))
}

/// The shift (+1 or −1) by which a program's answers, as many as the rays, are the exact ones
/// a line off: answer K is the exact answer of ray K + shift for nine in ten of its hits (at
/// least 3), and half or fewer of them are its own ray's.
pub(super) fn shift<T: Real>(given: &[Answer<T>], exact: &[Answer<T>]) -> Option<isize> {
    if given.len() != exact.len() {
        return None;
    }
    let (in_place, all) = hits_alike(given, exact, 0);
    if all < 3 || 2 * in_place > all {
        return None;
    }
    [1, -1].into_iter().find(|&s| {
        let (same, all) = hits_alike(given, exact, s);
        all >= 3 && 10 * same >= 9 * all
    })
}

/// What `check` and `grade` say of graded answers a line off ([`shift`]), where some are
/// wrong.
pub(super) fn off_by_a_line<T: Real>(
    judged: &[Judged<T>],
    answers: &[(usize, Answer<T>)],
) -> Option<String> {
    let right = |j: &Judged<T>| matches!(j.graded.verdict, Verdict::Right | Verdict::Tie);
    if judged.iter().all(right) {
        return None;
    }
    let given: Vec<Answer<T>> = answers.iter().map(|(_, a)| *a).collect();
    let stood: Vec<Answer<T>> = judged.iter().map(|j| j.exact).collect();
    shift(&given, &stood).map(shift_said)
}

/// What is said of answers a line off by `shift`.
fn shift_said(shift: isize) -> String {
    let (which, why) = match shift > 0 {
        true => (
            "K + 1",
            "the first ray's answer left out, and one more at the end?",
        ),
        false => (
            "K − 1",
            "a line printed before the first ray's answer, and the last one left out?",
        ),
    };
    format!(
        "its answers are the exact ones a line off: answer K is the exact answer of ray {which} \
         ({why}); a ray checked alone passes: look at the order the answers are printed in"
    )
}

/// Where answers fewer than the rays stop lining up with the exact ones: the first ray whose
/// answer is unlike its exact one, t aside (an answer left out there, or before it where its neighbours
/// are alike), or the first ray past the last answer.
pub(super) fn first_unlike<T: Real>(given: &[Answer<T>], exact: &[Answer<T>]) -> usize {
    (given.iter().zip(exact))
        .position(|(g, e)| !alike(g, e, false))
        .unwrap_or(given.len())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hit(prim: u32) -> Answer<f64> {
        Answer::Hit { t: 1.0, prim }
    }

    /// A program one line late (a stale answer first) is found; right answers, or ones a line
    /// off on rays that all meet the same primitive, are not.
    #[test]
    fn answers_a_line_off_are_found() {
        let exact: Vec<Answer<f64>> = [3, 1, 4, 1, 5, 9, 2, 6].map(hit).to_vec();
        let mut late = vec![Answer::Miss];
        late.extend_from_slice(&exact[..7]);
        assert_eq!(shift(&late, &exact), Some(-1));
        let early: Vec<Answer<f64>> = exact[1..].iter().copied().chain([hit(0)]).collect();
        assert_eq!(shift(&early, &exact), Some(1));
        assert_eq!(shift(&exact, &exact), None);
        let same = vec![hit(7); 8];
        assert_eq!(shift(&same, &same), None);
        assert_eq!(first_unlike(&late[..7], &exact), 0);
        let skipped: Vec<Answer<f64>> = [3, 1, 4, 5, 9].map(hit).to_vec();
        assert_eq!(first_unlike(&skipped, &exact), 3);
        assert_eq!(first_unlike(&exact[..5], &exact), 5);
    }
}
