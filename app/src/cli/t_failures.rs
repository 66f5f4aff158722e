//! What a hint says of a t the grader failed: the exact t printed short (fewer digits or a
//! fixed count of decimals), the ray's other meeting with a sphere, t times |d|, and the
//! exact t as the hints estimate it in f64.

use super::evidence::Evidence;
use super::hint_geometry::{length, near, o_and_d, plane_t, quadratic};
use raylab::check::grade::{Answer, Exact};
use raylab::math::Real;

/// Where the given hit is on a sphere and its t is, to 10⁻⁶ relative, the root of the ray's
/// quadratic that is not the exact answer's (the far root, or the one behind tmin): that root,
/// in f64. A hint beside the verdict, which the exact grading gave (a program that tried only
/// the far root was told its t was off by 0.47, and no more).
pub(super) fn other_root<T: Real>(
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
    let (roots, _, disc) = quadratic(exact, i, &s);
    let exact_t = t_of(standing)?;
    if disc < 0.0 || roots.iter().any(|r| !r.is_finite()) {
        return None;
    }
    let other = match near(roots[0], exact_t) {
        true => roots[1],
        false => roots[0],
    };
    (near(t.f64(), other) && !near(t.f64(), exact_t)).then_some(other)
}

/// The exact hit's t on `prim` (`te`, rounded to the precision graded) as an f64 estimate
/// where that rounds back to `te`, else `te`: the triangle's plane t or the sphere's nearer
/// root. (A gap past tmin of 8.9e-8 was shown as 1.2e-7, from t rounded to f32.)
pub(super) fn fine_t<T: Real>(exact: &Exact<T>, i: usize, prim: u32, te: T) -> f64 {
    use raylab::geometry::Shape;
    let estimate = match exact.shape(prim) {
        Shape::Triangle(tri) => plane_t(exact, i, &tri),
        Shape::Sphere(s) => {
            let (roots, _, _) = quadratic(exact, i, &s);
            let off = |r: f64| (r - te.f64()).abs();
            match off(roots[0]) <= off(roots[1]) {
                true => roots[0],
                false => roots[1],
            }
        }
    };
    match T::of(estimate) == te {
        true => estimate,
        false => te.f64(),
    }
}

/// The t of a hit, in f64.
pub(super) fn t_of<T: Real>(answer: &Answer<T>) -> Option<f64> {
    match *answer {
        Answer::Hit { t, .. } => Some(t.f64()),
        Answer::Miss => None,
    }
}

/// Where the given t is, to 10⁻⁶ relative, the exact t times |d| (the ray's direction
/// normalised, its t in units of length) and |d| is not 1: |d|. A hint beside the t failure.
pub(super) fn times_length<T: Real>(
    exact: &Exact<T>,
    i: usize,
    standing: &Answer<T>,
    given: &Answer<T>,
) -> Option<f64> {
    let (Answer::Hit { t: te, .. }, Answer::Hit { t, .. }) = (standing, given) else {
        return None;
    };
    let length = length(o_and_d(exact, i).1);
    let (want, got) = (te.f64() * length, t.f64());
    let near = (want - got).abs() <= 1e-6 * want.abs().max(got.abs());
    ((length - 1.0).abs() > 1e-6 && near && got.is_finite()).then_some(length)
}

/// The significant digits that print every value of `T` so that it reads back the same: 9
/// for f32, 17 for f64.
pub(super) fn round_trip_digits<T: Real>() -> usize {
    if T::PRECISION <= 24 {
        9
    } else {
        17
    }
}

/// Where the program prints fewer significant digits than `T` needs (the most of any t it
/// gave: a C `%g` prints 6), or a fixed count of decimals (`%.4f`: every t with 4), and the
/// given t is the exact t rounded so: how it was rounded ("to 6 significant digits", "to 4
/// decimals (%.4f)"). The t failure is the printing's, not the arithmetic's. (By the given
/// t's own digits, a `%.9g` program's t of 1 for 0.99998 was told to print 9; a `%.4f` one
/// got a bare t failure, or the sphere's roots as if its arithmetic were wrong.)
pub(super) fn short_print<T: Real>(
    exact: &Exact<T>,
    i: usize,
    standing: &Answer<T>,
    given: &Answer<T>,
    evidence: &Evidence,
) -> Option<String> {
    let (Answer::Hit { t: te, prim }, Answer::Hit { t: given, .. }) = (standing, given) else {
        return None;
    };
    if !given.is_finite() {
        return None;
    }
    // (The exact t so rounded from its f64 estimate, or from t rounded to `T` first, as a
    // program that prints its f32 t does: 10321.649924 is 10321.6 to 6 digits, 10321.7
    // from f32's 10321.650390625, and either was said as the exact t to 6 digits.)
    let fine = fine_t(exact, i, *prim, *te);
    let in_t = match T::PRECISION < 53 && te.f64() != fine {
        true => format!("in f32 ({}) ", raylab::math::real::exact_decimal(te.f64())),
        false => String::new(),
    };
    let rounded = |text: &dyn Fn(f64) -> String| {
        let rounds_to = |t: f64| text(t).parse::<T>().ok() == Some(*given);
        match (rounds_to(fine), rounds_to(te.f64())) {
            (true, _) => Some(""),
            (false, true) => Some(in_t.as_str()),
            (false, false) => None,
        }
    };
    // (Decimals where the t's significant digits vary, as `%.4f`'s do (0.7658 is 0.7657972
    // to 5 digits too); else digits first: t's between 1 and 10 at `%.6g` have 5 decimals
    // each.)
    let decimals = (evidence.printed_decimals).and_then(|n| {
        let as_is = rounded(&|t| format!("{t:.n$}"))?;
        Some(format!("{as_is}to {n} decimals (%.{n}f)"))
    });
    // (A t of 0 has no significant digits: `%.4f`'s 0.0000 for 1.4e-5 its decimals alone.)
    if (evidence.digits_vary && decimals.is_some()) || *given == T::zero() {
        return decimals;
    }
    let printed = evidence.printed_digits;
    let short = (1..round_trip_digits::<T>()).contains(&printed);
    let digits = short
        .then(|| rounded(&|t| format!("{:.*e}", printed - 1, t)))
        .flatten();
    match digits {
        Some(as_is) => Some(format!(
            "{as_is}to {}",
            raylab::words::count(printed, "significant digit", "significant digits")
        )),
        None => decimals,
    }
}
