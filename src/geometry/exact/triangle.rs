//! The exact questions about a triangle: which side of an edge the line passes in
//! rationals ([`orient_rational`]), which side of its plane a point lies ([`plane_side`]),
//! and the line's t at its plane, exact ([`plane_t`]) or correctly rounded
//! ([`plane_t_rounded`]).

use super::expansion::{orient, sum_of_products_sign, two_sum};
use super::rational::{cross, dot, q, qv, round_ratio, sign, sub, ExactT, Q, QV};
use crate::geometry::adaptive::levels::{note, Event};
use crate::math::Real;
use num_bigint::BigInt;
use num_traits::{One, Zero};
use std::cmp::Ordering;

/// Which side of the plane of triangle `v` point `x` lies on: the exact sign of
/// det[v₁ − v₀, v₂ − v₀, x − v₀]; `None` where the expansions cannot be used (differences
/// not exact in f64).
pub fn plane_side(v: &[[f32; 3]; 3], x: [f64; 3]) -> Option<Ordering> {
    plane_side_f64(&v.map(|p| p.map(f64::from)), x)
}

/// [`plane_side`] for a triangle given in f64.
pub fn plane_side_f64(v: &[[f64; 3]; 3], x: [f64; 3]) -> Option<Ordering> {
    let mut d = [0.0; 3];
    for k in 0..3 {
        let (diff, err) = two_sum(v[1][k], -v[0][k]);
        if err != 0.0 {
            return None;
        }
        d[k] = diff;
    }
    orient(d, v[0], v[2], x)
}

/// Whether `x` lies exactly on the plane of triangle `v` (`None`: cannot tell, which callers
/// treat as "not known to be coplanar").
pub fn on_plane(v: &[[f32; 3]; 3], x: [f64; 3]) -> Option<bool> {
    plane_side(v, x).map(|s| s == Ordering::Equal)
}

/// The exact sign of det[d, a − o, b − o] in rationals (any finite inputs).
pub fn orient_rational(d: [f64; 3], o: [f64; 3], a: [f64; 3], b: [f64; 3]) -> Ordering {
    let o = qv(o);
    let (pa, pb) = (sub(&qv(a), &o), sub(&qv(b), &o));
    sign(&dot(&qv(d), &cross(&pa, &pb)))
}

/// det[d, a − o, b − o] in rationals, rounded to f64: the size of an orientation whose f64
/// value is lost in its rounding (for showing: a weight of 1.2e-17 came out 0 and -0).
pub fn orient_value(d: [f64; 3], o: [f64; 3], a: [f64; 3], b: [f64; 3]) -> f64 {
    use num_traits::ToPrimitive;
    let o = qv(o);
    let (pa, pb) = (sub(&qv(a), &o), sub(&qv(b), &o));
    dot(&qv(d), &cross(&pa, &pb)).to_f64().unwrap_or(f64::NAN)
}

/// The exact t of the line o + t·d at the plane of triangle v (`None` if parallel).
pub fn plane_t(o: [f64; 3], d: [f64; 3], v: &[[f64; 3]; 3]) -> Option<ExactT> {
    let o = qv(o);
    let p: [QV; 3] = [0, 1, 2].map(|i| sub(&qv(v[i]), &o));
    let n = cross(&sub(&p[1], &p[0]), &sub(&p[2], &p[0]));
    let den = dot(&qv(d), &n);
    if den.is_zero() {
        return None;
    }
    Some(ExactT::rational(dot(&p[0], &n) / den))
}

/// The filter's bound on the rounding of a·d − b·c computed in f64 from coordinate
/// differences a, b, c, d that are themselves rounded, relative to |a·d| + |b·c| as computed:
/// 4ε (ε = 2⁻⁵³), a power of two over Shewchuk's (3 + 16ε)ε (orient2d's `ccwerrboundA`).
const ZERO_AREA_BOUND: f64 = 2.0 * f64::EPSILON;

/// The least |a·d| + |b·c| the filter decides from: from it up, the margin of
/// [`ZERO_AREA_BOUND`] over Shewchuk's bound, at least (ε − 16ε²)·10⁻²⁸⁰ ≈ 10⁻²⁹⁶, covers the
/// few 2⁻¹⁰⁷⁵ that underflow can add (a product below 2⁻¹⁰²²; a subnormal difference is
/// exact), and the bound, a power of two times a normal number, is computed exactly.
const ZERO_AREA_FLOOR: f64 = 1e-280;

/// The coordinate planes (i, j) whose orientations a_i·b_j − a_j·b_i are the components of
/// a × b.
const PLANES: [(usize, usize); 3] = [(1, 2), (2, 0), (0, 1)];

/// Whether triangle `v` has zero area (its vertices on one line, or coincident), exactly:
/// every component of (v₁ − v₀) × (v₂ − v₀) is 0. Each component is the orientation of the
/// triangle projected on a coordinate plane, and a plain f64 filter proves it nonzero where
/// it clears its rounding ([`ZERO_AREA_BOUND`]; the differences' rounding included, so any
/// coordinates, 0.1 as well as 0.5): a triangle with area is decided so in a few dozen flops.
/// Only where no component clears its bound (zero area, or nearly) is each decided exactly:
/// multiplied out as six products of coordinates, summed as an expansion; for coordinates
/// past the expansions' range (beyond 10¹²⁰ or under 10⁻¹²⁰ in magnitude, never an f32's), in
/// rationals. Both are counted ([`Event::ZeroAreaExact`], [`Event::ZeroAreaRational`]).
pub fn zero_area(v: &[[f64; 3]; 3]) -> bool {
    let surely_nonzero = |(i, j): (usize, usize)| {
        let (ai, aj) = (v[1][i] - v[0][i], v[1][j] - v[0][j]);
        let (bi, bj) = (v[2][i] - v[0][i], v[2][j] - v[0][j]);
        let (l, r) = (ai * bj, aj * bi);
        let sum = l.abs() + r.abs();
        // (Not finite: an overflow, which decides nothing.)
        sum.is_finite() && sum >= ZERO_AREA_FLOOR && (l - r).abs() > ZERO_AREA_BOUND * sum
    };
    if PLANES.into_iter().any(surely_nonzero) {
        return false;
    }
    note(Event::ZeroAreaExact);
    let safe = |x: &f64| *x == 0.0 || (1e-120..=1e120).contains(&x.abs());
    if !v.iter().flatten().all(safe) {
        note(Event::ZeroAreaRational);
        return zero_area_rational(v);
    }
    PLANES.into_iter().all(|(i, j)| {
        let [(x0, y0), (x1, y1), (x2, y2)] = v.map(|p| (p[i], p[j]));
        // (x₁ − x₀)(y₂ − y₀) − (y₁ − y₀)(x₂ − x₀) multiplied out (the x₀·y₀ terms cancel).
        let terms = [
            (x1, y2),
            (-x1, y0),
            (-x0, y2),
            (-y1, x2),
            (y1, x0),
            (y0, x2),
        ];
        sum_of_products_sign(&terms) == Ordering::Equal
    })
}

/// [`zero_area`] in rationals (any finite inputs).
fn zero_area_rational(v: &[[f64; 3]; 3]) -> bool {
    let p = v.map(qv);
    let n = cross(&sub(&p[1], &p[0]), &sub(&p[2], &p[0]));
    n.iter().all(Zero::is_zero)
}

/// Where the line o + t·d meets the zero-area triangle `v` (its vertices' hull: a segment or
/// a point) with tmin < t < tmax: the nearest such t, exact. Where the line runs along the
/// segment and enters it at or before tmin, there is no nearest: `tmin` itself is given.
/// `None` where it does not meet it there (or `v` has area). A tmin of −∞ is no lower bound
/// and a tmax of +∞ no upper one; a tmin of +∞ or a tmax of −∞ (or NaN) leaves nothing.
pub fn zero_area_contact(
    o: [f64; 3],
    d: [f64; 3],
    v: &[[f64; 3]; 3],
    tmin: f64,
    tmax: f64,
) -> Option<ExactT> {
    // The bounds in rationals: `None` for no bound (an infinite one on its own side).
    let lower = match tmin {
        t if t.is_finite() => Some(q(t)),
        f64::NEG_INFINITY => None,
        _ => return None,
    };
    let upper = match tmax {
        t if t.is_finite() => Some(q(t)),
        f64::INFINITY => None,
        _ => return None,
    };
    let zero = |x: &QV| x.iter().all(Zero::is_zero);
    let p = v.map(qv);
    if !zero(&cross(&sub(&p[1], &p[0]), &sub(&p[2], &p[0]))) {
        return None;
    }
    // The hull: the two vertices farthest apart.
    let len2 = |a: &QV, b: &QV| {
        let e = sub(b, a);
        dot(&e, &e)
    };
    let (a, b) = [(0, 1), (1, 2), (0, 2)]
        .into_iter()
        .max_by(|x, y| len2(&p[x.0], &p[x.1]).cmp(&len2(&p[y.0], &p[y.1])))
        .map(|(i, j)| (p[i].clone(), p[j].clone()))
        .expect("three pairs");
    let (o, d) = (qv(o), qv(d));
    let (e, w) = (sub(&b, &a), sub(&a, &o));
    let n = cross(&d, &e);
    let above = |t: &Q| lower.as_ref().is_none_or(|l| t > l);
    let below = |t: &Q| upper.as_ref().is_none_or(|u| t < u);
    let within = |t: &Q| above(t) && below(t);
    if !zero(&n) {
        // The lines cross where o + t·d = a + s·e, if they are coplanar; 0 ≤ s ≤ 1 on it.
        if !dot(&w, &n).is_zero() {
            return None;
        }
        let nn = dot(&n, &n);
        let t = dot(&cross(&w, &e), &n) / &nn;
        let s = dot(&cross(&w, &d), &n) / &nn;
        let on = s >= Q::zero() && s <= Q::one();
        return (on && within(&t)).then(|| ExactT::rational(t));
    }
    // Parallel: on the line only if a is; then met over [ta, tb].
    if !zero(&cross(&w, &d)) {
        return None;
    }
    let dd = dot(&d, &d);
    let ta = dot(&w, &d) / &dd;
    let tb = dot(&sub(&b, &o), &d) / &dd;
    let (lo, hi) = match ta <= tb {
        true => (ta, tb),
        false => (tb, ta),
    };
    if within(&lo) {
        return Some(ExactT::rational(lo));
    }
    // (Entered at or before a finite tmin: tmin, if the interval is not empty there.)
    let tmin_q = lower?;
    (lo <= tmin_q && hi > tmin_q && below(&tmin_q)).then(|| ExactT::rational(tmin_q))
}

/// An f64 as m·2^e with an integer m (0 as 0·2^0).
fn integer_and_exponent(x: f64) -> (BigInt, i64) {
    let bits = x.to_bits();
    let (exp, frac) = (((bits >> 52) & 0x7ff) as i64, bits & ((1u64 << 52) - 1));
    let (m, e) = match exp {
        0 => (frac, -1074),
        _ => (frac | (1u64 << 52), exp - 1075),
    };
    let m = BigInt::from(m);
    (if x < 0.0 { -m } else { m }, e)
}

/// The exact t of the line o + t·d at the plane of triangle v correctly rounded to T
/// (`None` if parallel), in integers: every input is m·2^e, so with E the least exponent
/// they are all integers times 2^E, and t = p₀·n / d·n is a ratio of integers (both carry
/// 2^3E, which cancels), rounded by one division. No gcds: some 20× cheaper than
/// [`plane_t`] and [`ExactT::rounded`].
pub fn plane_t_rounded<T: Real>(o: [f64; 3], d: [f64; 3], v: &[[f64; 3]; 3]) -> Option<T> {
    let inputs = [o, d, v[0], v[1], v[2]].map(|p| p.map(integer_and_exponent));
    let least = inputs
        .iter()
        .flatten()
        .filter(|(m, _)| !m.is_zero())
        .map(|(_, e)| *e)
        .min()
        .unwrap_or(0);
    let [o, d, a, b, c] = inputs.map(|p| p.map(|(m, e)| m << (e - least) as u64));
    let sub = |x: &[BigInt; 3], y: &[BigInt; 3]| [0, 1, 2].map(|k| &x[k] - &y[k]);
    let dot = |x: &[BigInt; 3], y: &[BigInt; 3]| &x[0] * &y[0] + &x[1] * &y[1] + &x[2] * &y[2];
    let (p0, p1, p2) = (sub(&a, &o), sub(&b, &o), sub(&c, &o));
    let (e1, e2) = (sub(&p1, &p0), sub(&p2, &p0));
    let n = [
        &e1[1] * &e2[2] - &e1[2] * &e2[1],
        &e1[2] * &e2[0] - &e1[0] * &e2[2],
        &e1[0] * &e2[1] - &e1[1] * &e2[0],
    ];
    let den = dot(&d, &n);
    if den.is_zero() {
        return None;
    }
    let num = dot(&p0, &n);
    Some(match den < BigInt::zero() {
        true => round_ratio(&-num, &-den),
        false => round_ratio(&num, &den),
    })
}
