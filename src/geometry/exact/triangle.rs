//! The exact questions about a triangle: which side of an edge the line passes in
//! rationals ([`orient_rational`]), which side of its plane a point lies ([`plane_side`]),
//! and the line's t at its plane, exact ([`plane_t`]) or correctly rounded
//! ([`plane_t_rounded`]).

use super::expansion::{orient, two_sum};
use super::rational::{cross, dot, qv, round_ratio, sign, sub, ExactT, QV};
use crate::math::Real;
use num_bigint::BigInt;
use num_traits::Zero;
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
