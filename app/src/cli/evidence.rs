//! What a run's answers say of the program as a whole, for the hints beside its wrong ones: a
//! hint that names a bug (an index from 1, a t printed short, an epsilon on the determinant,
//! back faces culled) holds only where the program's other answers bear it out. A correct
//! program that rounds a hit on a tiny cube's edge away was told of an epsilon it did not
//! have, and one printing `%.9g` to print 9 digits.

use super::hint_geometry::{determinant, faces_back, near};
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
    /// The smallest |determinant| (in f64) of a triangle the program met where it answered
    /// right: an epsilon on the determinant above it would have lost that hit.
    pub smallest_determinant_met: f64,
    /// Whether the program met a triangle's back where it answered right: it does not cull.
    pub meets_backs: bool,
    /// The smallest t − tmin of an exact hit the program answered right: an epsilon in
    /// tmin's place above it would have lost that hit.
    pub smallest_gap_met: f64,
    /// Whether the program gave a farther primitive where the exact hit is well inside its
    /// primitive (not on a triangle's edge or vertex, nor a sphere's rim): it passes over
    /// nearer hits, not only rounds them away.
    pub passes_nearer: bool,
}

impl Evidence {
    /// The evidence of `answers` (`written`: their text, as the program wrote them).
    pub fn of<T: Real>(
        judged: &[Judged<T>],
        exact: &Exact<T>,
        answers: &[(usize, Answer<T>)],
        written: &str,
    ) -> Self {
        let mut evidence = Evidence {
            shift: index_shift(judged, answers),
            printed_digits: printed_digits(written),
            smallest_determinant_met: f64::INFINITY,
            meets_backs: false,
            smallest_gap_met: f64::INFINITY,
            passes_nearer: false,
        };
        for (i, (j, (_, given))) in judged.iter().zip(answers).enumerate() {
            if let (Answer::Hit { t: te, prim }, Answer::Hit { t, .. }) = (j.exact, *given) {
                let farther =
                    j.graded.verdict == Verdict::Wrong && t > te && !near(t.f64(), te.f64());
                // (Decided exactly: once is enough.)
                if farther && !evidence.passes_nearer {
                    evidence.passes_nearer = well_inside(exact, i, prim);
                }
            }
            if let (Verdict::Right, Answer::Hit { t, .. }) = (j.graded.verdict, j.exact) {
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
        evidence
    }
}

/// Whether ray `i` meets primitive `prim` well inside it, decided exactly: inside a triangle
/// (not on an edge or vertex), through a sphere (not a tangent).
fn well_inside<T: Real>(exact: &Exact<T>, i: usize, prim: u32) -> bool {
    use raylab::geometry::{sphere, triangle, Location};
    matches!(
        exact.shape(prim).locate(&exact.rays[i].1.ray),
        Location::Triangle(triangle::Location::Inside { .. })
            | Location::Sphere(sphere::Location::Through)
    )
}

/// The most significant digits of a t in `written`'s `hit <t> <index>` lines, as written
/// (`0.10000000000000001`: 17; `1.5`: 2; trailing zeros count, leading ones do not). (By the
/// value's shortest decimal, 0.1, a `%.17g` program was taken to print 1.)
fn printed_digits(written: &str) -> usize {
    (written.lines())
        .filter_map(|l| {
            let mut words = l.split_whitespace();
            (words.next() == Some("hit"))
                .then(|| words.next())
                .flatten()
        })
        .map(|t| {
            let mantissa = t.split(['e', 'E']).next().unwrap_or_default();
            let digits: String = mantissa.chars().filter(char::is_ascii_digit).collect();
            digits.trim_start_matches('0').len()
        })
        .max()
        .unwrap_or(0)
}

fn index_shift<T: Real>(judged: &[Judged<T>], answers: &[(usize, Answer<T>)]) -> Option<i64> {
    let shifts: Vec<i64> = (judged.iter().zip(answers))
        .filter_map(|(j, (_, given))| match (j.exact, *given) {
            (Answer::Hit { t: te, prim: q }, Answer::Hit { t, prim: p })
                if near(te.f64(), t.f64()) =>
            {
                Some(i64::from(p) - i64::from(q))
            }
            _ => None,
        })
        .collect();
    let first = *shifts.first()?;
    (shifts.len() >= 2 && first.abs() == 1 && shifts.iter().all(|&k| k == first)).then_some(first)
}
