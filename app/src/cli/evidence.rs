//! What a run's answers say of the program as a whole, for the hints beside its wrong ones: a
//! hint that names a bug (an index from 1, a t printed short, an epsilon on the determinant,
//! back faces culled) holds only where the program's other answers bear it out. A correct
//! program that rounds a hit on a tiny cube's edge away was told of an epsilon it did not
//! have, and one printing `%.9g` to print 9 digits.

use super::hint_geometry::{clearly_inside, determinant, faces_back, meets_back, near};
use super::hint_geometry::{near_an_end, past_tmin, surface_ts};
use raylab::check::grade::{Answer, Exact, Judged, Verdict};
use raylab::geometry::Shape;
use raylab::math::Real;

/// The run's evidence ([`Evidence::of`]).
pub(super) struct Evidence {
    /// The index every primitive given at the exact hit's t is off by, where that is 1 or −1
    /// for all of them (two or more): a program's index shifted, not a slip (where most are
    /// right, no shift is claimed).
    pub shift: Option<i64>,
    /// The most significant digits of any t as the program wrote it ([`printed_digits`]):
    /// the digits it prints (`%g`: 6, `%.9g`: 9), where it prints a fixed count.
    pub printed_digits: usize,
    /// Whether the t's were written with different counts of significant digits (`%.4f`'s
    /// 0.7658 and 1.2345: a fixed count of decimals, not of digits).
    pub digits_vary: bool,
    /// The decimals every t was written with, where all have the same count and no
    /// exponent, two or more of them (`%.4f`: 4) ([`printed_decimals`]).
    pub printed_decimals: Option<usize>,
    /// The smallest |determinant| (in f64) of a triangle the program met where it answered
    /// right: an epsilon on the determinant above it would have lost that hit.
    pub smallest_determinant_met: f64,
    /// Whether the program met a triangle's back where it answered right: it does not cull.
    pub meets_backs: bool,
    /// The smallest |determinant| of a triangle the program missed (a leak, or a farther
    /// primitive given) where the ray meets it clearly inside ([`clearly_inside`]) and not
    /// within rounding of tmin or tmax ([`near_an_end`]): a bug's miss, not rounding's; met
    /// from its front, and from its back.
    pub smallest_determinant_missed: [f64; 2],
    /// Whether such a miss was of a triangle met from its back.
    pub misses_backs: bool,
    /// Whether such a miss of a back was a leak not near tmin, where an epsilon in tmin's
    /// place loses backs and fronts alike (a program with one was told that both sides count).
    pub misses_backs_past_tmin: bool,
    /// Whether such a miss of a back, not near tmin, was a pass over it for a farther hit: a
    /// last-hit program's answer as much as a culling one's, so it bears culling out only
    /// beside [`Evidence::keeps_nearest`] (a last-hit program's ray alone was told that both
    /// sides count).
    pub passes_backs_past_tmin: bool,
    /// Whether the program gave the exact hit where the ray meets another primitive farther
    /// on: it keeps the nearest hit, not the last. Looked for only where a pass needs it, in
    /// the first [`NEAREST_LOOKS`] rays answered right.
    pub keeps_nearest: bool,
    /// The smallest t − tmin of an exact hit the program answered right: an epsilon in
    /// tmin's place above it would have lost that hit.
    pub smallest_gap_met: f64,
    /// The smallest t − tmin of a hit the program missed (a leak) clearly inside its primitive
    /// and not within rounding of tmin, near enough to tmin for an epsilon in its place to
    /// lose it ([`past_tmin`]); on a sphere or a triangle's front, and on a triangle's back.
    pub smallest_gap_missed: [f64; 2],
    /// The same of a hit passed over for a farther one: an epsilon's as much as a last hit's,
    /// so it bears out an epsilon only beside [`Evidence::keeps_nearest`].
    pub smallest_gap_passed: [f64; 2],
    /// Whether the program gave a farther primitive where the exact hit is clearly inside its
    /// primitive ([`clearly_inside`], not within rounding of tmin or tmax), not near tmin, and
    /// not a back passed over for a front (culling's): it passes over nearer hits, not only
    /// rounds them away or loses them to an epsilon.
    pub passes_nearer: bool,
}

impl Evidence {
    /// The evidence of `answers` (`written`: their text, as the program wrote them; `meets`:
    /// whether ray i meets primitive p at about t).
    pub fn of<T: Real>(
        judged: &[Judged<T>],
        exact: &Exact<T>,
        answers: &[(usize, Answer<T>)],
        written: &str,
        meets: impl Fn(usize, u32, f64) -> bool,
    ) -> Self {
        let (printed_digits, digits_vary) = printed_digits(written);
        let mut evidence = Evidence {
            shift: index_shift(judged, exact.primitives, answers, &meets),
            printed_digits,
            digits_vary,
            printed_decimals: printed_decimals(written),
            smallest_determinant_met: f64::INFINITY,
            meets_backs: false,
            smallest_determinant_missed: [f64::INFINITY; 2],
            misses_backs: false,
            misses_backs_past_tmin: false,
            passes_backs_past_tmin: false,
            keeps_nearest: false,
            smallest_gap_met: f64::INFINITY,
            smallest_gap_missed: [f64::INFINITY; 2],
            smallest_gap_passed: [f64::INFINITY; 2],
            passes_nearer: false,
        };
        for (i, (j, (_, given))) in judged.iter().zip(answers).enumerate() {
            let farther = match (j.exact, *given) {
                (Answer::Hit { t: te, .. }, Answer::Hit { t, .. }) => {
                    j.graded.verdict == Verdict::Wrong && t > te && !near(t.f64(), te.f64())
                }
                _ => false,
            };
            let missed = farther || j.graded.verdict == Verdict::Leak;
            if let (true, Answer::Hit { t: te, prim }) = (missed, j.exact) {
                let inside =
                    !near_an_end(exact, i, prim, te.f64()) && clearly_inside(exact, i, prim);
                let triangle = match exact.shape(prim) {
                    Shape::Triangle(tri) => Some(tri),
                    Shape::Sphere(_) => None,
                };
                let back = meets_back(exact, i, prim);
                // (Not over a back for a front: a culling program passes over those, and was
                // told that the nearest hit wins. It gives no back.)
                let given_back = match *given {
                    Answer::Hit { prim: g, .. } => meets_back(exact, i, g),
                    Answer::Miss => false,
                };
                // (A hit near tmin passed over is an epsilon's as much as a last hit's: a
                // last-hit program was told of an epsilon in tmin's place, beside a hit given
                // 100 times farther than any epsilon reaches.)
                let near_tmin = past_tmin(exact, i, te.f64()).filter(|&(_, near)| near);
                let passes = farther && inside && (!back || given_back);
                evidence.passes_nearer |= passes && near_tmin.is_none();
                if let (true, Some((gap, _))) = (inside, near_tmin) {
                    let gaps = match farther {
                        true => &mut evidence.smallest_gap_passed,
                        false => &mut evidence.smallest_gap_missed,
                    };
                    gaps[back as usize] = gaps[back as usize].min(gap);
                }
                if let (true, Some(tri)) = (inside, triangle) {
                    let det = determinant(exact, i, &tri).abs();
                    let smallest = &mut evidence.smallest_determinant_missed[back as usize];
                    *smallest = smallest.min(det);
                    evidence.misses_backs |= back;
                    let past = back && near_tmin.is_none();
                    evidence.misses_backs_past_tmin |= past && !farther;
                    evidence.passes_backs_past_tmin |= past && farther;
                }
            }
            // (Met at its t: a sphere's hit past tmin skipped for its other root is the
            // right primitive, and bore out that no epsilon was in tmin's place.)
            let met = j.graded.verdict == Verdict::Right && j.graded.stands();
            if let (true, Answer::Hit { t, .. }) = (met, j.exact) {
                let gap = t.f64() - exact.rays[i].1.tmin.f64();
                evidence.smallest_gap_met = evidence.smallest_gap_met.min(gap);
            }
            // (The primitive the program met: a tie's is not the exact answer's, and a culling
            // program's tie on a front face beside a back one was taken to meet backs.)
            let right = matches!(j.graded.verdict, Verdict::Right | Verdict::Tie);
            let (true, Answer::Hit { prim, .. }) = (right, *given) else {
                continue;
            };
            if let Shape::Triangle(tri) = exact.shape(prim) {
                let det = determinant(exact, i, &tri).abs();
                evidence.smallest_determinant_met = evidence.smallest_determinant_met.min(det);
                evidence.meets_backs |= faces_back(exact, i, &tri);
            }
        }
        let passes = evidence.passes_backs_past_tmin
            || evidence.smallest_gap_passed.iter().any(|g| g.is_finite());
        // (The first rays answered right, each tested against every primitive: a last-hit
        // program, which never keeps the nearest, costs those many rays' worth.)
        if passes {
            let right = (judged.iter().enumerate()).filter_map(|(i, j)| match j.exact {
                Answer::Hit { t, prim } if j.graded.verdict == Verdict::Right => Some((i, t, prim)),
                _ => None,
            });
            evidence.keeps_nearest = (right.take(NEAREST_LOOKS))
                .any(|(i, t, prim)| meets_farther(exact, i, prim, t.f64(), &meets));
        }
        evidence
    }

    /// Whether the run bears out culled back faces, so that the rule may be said: it may
    /// cull ([`Evidence::may_cull`]), and missed a back not near tmin. (A program with an
    /// epsilon in tmin's place, run on one ray, was told that both sides count.)
    pub fn culls_backs(&self) -> bool {
        let passes = self.passes_backs_past_tmin && self.keeps_nearest;
        self.may_cull() && (self.misses_backs_past_tmin || passes)
    }

    /// Whether culled back faces explain the run's misses of backs, so that they bear out
    /// no epsilon: the program met no triangle's back right, and missed one met clearly
    /// inside, but no front met so. (A correct program that rounded away a hit inside an
    /// edge of a back face, alone in its run, was told it culled; a program giving the last
    /// hit, which missed fronts and backs alike, too.)
    fn may_cull(&self) -> bool {
        let misses_fronts = self.smallest_determinant_missed[0] < f64::INFINITY;
        !self.meets_backs && self.misses_backs && !misses_fronts
    }

    /// Below which t − tmin the run bears out an epsilon in tmin's place: the smallest gap
    /// the program met right, where it missed a hit with a smaller one (clearly inside, not
    /// within rounding of tmin; passed over for a farther one only where the program keeps
    /// the nearest hit); else 0. (A run of one ray named it beside nothing.)
    pub fn tmin_epsilon_below(&self) -> f64 {
        let passed = match self.keeps_nearest && !self.passes_nearer {
            true => self.smallest_gap_passed,
            false => [f64::INFINITY; 2],
        };
        let missed = [0, 1].map(|k| self.smallest_gap_missed[k].min(passed[k]));
        match self.unculled(missed) < self.smallest_gap_met {
            true => self.smallest_gap_met,
            false => 0.0,
        }
    }

    /// Below which |determinant| the run bears out an epsilon on it: the smallest the
    /// program met right, where it missed a triangle met clearly inside with a smaller one
    /// (not a back it is shown to cull); else 0. (A run of one ray, with nothing met right,
    /// named an epsilon for a hit rounded away beside an edge.)
    pub fn epsilon_below(&self) -> f64 {
        match self.unculled(self.smallest_determinant_missed) < self.smallest_determinant_met {
            true => self.smallest_determinant_met,
            false => 0.0,
        }
    }

    /// The smaller of a front face's and a back face's `[front, back]`, or the front's where
    /// the run bears out culled backs: those misses are culling's. (A culling program was
    /// told of an epsilon on back faces met near tmin, and not of the back.)
    fn unculled(&self, [front, back]: [f64; 2]) -> f64 {
        match self.may_cull() {
            true => front,
            false => front.min(back),
        }
    }
}

/// The decimals of every t in `written`'s `hit <t> <index>` lines written without an
/// exponent where they all have the same count after a point, and there are two or more: a
/// fixed count printed (`%.4f`). (Its 0.9980 for 0.99797 had a bare t failure.) A t with an
/// exponent, or not finite, is no evidence either way: JavaScript's `toFixed(4)` writes
/// 1.2e28 so, and a family of such t's named no decimals.
fn printed_decimals(written: &str) -> Option<usize> {
    let decimals = hit_ts(written).filter_map(|t| {
        let digits = t.trim_start_matches(['-', '+']);
        if t.contains(['e', 'E']) || !digits.starts_with(|c: char| c.is_ascii_digit()) {
            return None;
        }
        let after = t.split_once('.').map(|(_, after)| after);
        Some(
            after
                .filter(|a| a.bytes().all(|b| b.is_ascii_digit()))
                .map(str::len),
        )
    });
    let mut count = 0;
    let mut all = None;
    for n in decimals {
        let n = n?;
        if all.is_some_and(|a| a != n) {
            return None;
        }
        all = Some(n);
        count += 1;
    }
    all.filter(|_| count >= 2)
}

/// The t of each `hit <t> <index>` line of `written`, as written.
pub(super) fn hit_ts(written: &str) -> impl Iterator<Item = &str> {
    written.lines().filter_map(|l| {
        let mut words = l.split_whitespace();
        (words.next() == Some("hit"))
            .then(|| words.next())
            .flatten()
    })
}

/// The most significant digits of a t in `written`'s `hit <t> <index>` lines, as written
/// ([`significant_digits`]), where two t's or more have them, else 0 (one t is no evidence: a `%.9g` program's lone t of 1
/// for 0.9999839 was told to print 9); and whether the t's have different counts. (By the
/// value's shortest decimal, 0.1, a `%.17g` program was taken to print 1.)
fn printed_digits(written: &str) -> (usize, bool) {
    let digits: Vec<usize> = hit_ts(written).map(significant_digits).collect();
    let most = digits.iter().copied().max().unwrap_or(0);
    let twice = digits.iter().filter(|&&n| n == most).count() >= 2;
    let vary = digits.iter().any(|&n| n != most);
    (if twice { most } else { 0 }, vary)
}

/// The significant digits of a t as written (`0.10000000000000001`: 17; `1.5`: 2; trailing
/// zeros count, leading ones do not).
pub(super) fn significant_digits(t: &str) -> usize {
    let mantissa = t.split(['e', 'E']).next().unwrap_or_default();
    let digits: String = mantissa.chars().filter(char::is_ascii_digit).collect();
    digits.trim_start_matches('0').len()
}

/// The index every primitive given at the exact hit's t is off by, 1 or −1: each such
/// primitive less that is one the ray meets at that t (the exact one, or one tied with it:
/// where hits tie, the program's own choice shifted is not the exact one's), two or more
/// of them, one at least the exact one shifted. (Where ties were many, a program counting
/// from 1 was told of the inside-outside test.)
fn index_shift<T: Real>(
    judged: &[Judged<T>],
    primitives: usize,
    answers: &[(usize, Answer<T>)],
    meets: impl Fn(usize, u32, f64) -> bool,
) -> Option<i64> {
    let at_exact_t: Vec<(usize, u32, u32, f64)> = (judged.iter().zip(answers).enumerate())
        .filter_map(|(i, (j, (_, given)))| match (j.exact, *given) {
            (Answer::Hit { t: te, prim: q }, Answer::Hit { t, prim: p })
                if near(te.f64(), t.f64()) =>
            {
                Some((i, p, q, te.f64()))
            }
            _ => None,
        })
        .collect();
    let shifted_by = |k: i64| {
        let unshifted = |p: u32| {
            let r = i64::from(p) - k;
            (0..primitives as i64).contains(&r).then_some(r as u32)
        };
        let exact_one = at_exact_t
            .iter()
            .any(|&(_, p, q, _)| unshifted(p) == Some(q));
        let all_met = (at_exact_t.iter())
            .all(|&(i, p, q, t)| unshifted(p).is_some_and(|r| r == q || meets(i, r, t)));
        at_exact_t.len() >= 2 && exact_one && all_met
    };
    [1, -1].into_iter().find(|&k| shifted_by(k))
}

/// The rays answered right that [`Evidence::keeps_nearest`] looks at, at most.
const NEAREST_LOOKS: usize = 256;

/// Whether ray `i`, whose exact hit is on `prim` at `te`, meets another primitive farther on,
/// before tmax (`meets`: whether ray i meets primitive p at about t).
fn meets_farther<T: Real>(
    exact: &Exact<T>,
    i: usize,
    prim: u32,
    te: f64,
    meets: &impl Fn(usize, u32, f64) -> bool,
) -> bool {
    let tmax = exact.rays[i].1.tmax.f64();
    (0..exact.primitives as u32)
        .filter(|&q| q != prim)
        .any(|q| {
            (surface_ts(exact, i, q).into_iter())
                .any(|t| t > te && !near(t, te) && t < tmax && meets(i, q, t))
        })
}
