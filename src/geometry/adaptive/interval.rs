//! Level 2 for a triangle: its edge signs and t in f64 interval arithmetic
//! ([`triangle_interval`]), and t as an interval for a hit decided exactly.

use super::estimate::{Approx, Estimate};
use crate::math::interval::{icross, idot, isub, iv3, Interval};
use std::cmp::Ordering;

/// Level 2 for a triangle: the signs of det[d, pᵢ, pⱼ] and t in f64 intervals.
pub fn triangle_interval(o: [f64; 3], d: [f64; 3], v: &[[f64; 3]; 3]) -> Estimate {
    let (o, d) = (iv3(o), iv3(d));
    let p = v.map(|vi| isub(iv3(vi), o));
    let e = [(1, 2), (2, 0), (0, 1)].map(|(i, j)| idot(d, icross(p[i], p[j])));
    let s = e.map(Interval::sign);
    if s.contains(&Some(Ordering::Less)) && s.contains(&Some(Ordering::Greater)) {
        return Estimate::Miss;
    }
    if s.contains(&None) {
        return Estimate::Unsure;
    }
    if s.iter().all(|x| *x == Some(Ordering::Equal)) {
        return Estimate::Miss; // the line lies in the triangle's plane
    }
    let den = e[0] + e[1] + e[2];
    let num = idot(p[0], icross(p[1], p[2]));
    let Some(t) = num.checked_div(den) else {
        return Estimate::Unsure;
    };
    if !t.is_finite() {
        return Estimate::Unsure;
    }
    let dm = den.mid();
    Estimate::Hit(Approx {
        t: t.mid(),
        lo: t.lo,
        hi: t.hi,
        b1: e[1].mid() / dm,
        b2: e[2].mid() / dm,
        level: 2,
    })
}

/// t = det[p₀, p₁, p₂] / d·n as an interval (if d·n is certainly non-zero), with estimates
/// of the barycentrics.
pub(crate) fn triangle_t_interval(
    o: [f64; 3],
    d: [f64; 3],
    v: &[[f64; 3]; 3],
) -> (Option<Interval>, f64, f64) {
    let (o, d) = (iv3(o), iv3(d));
    let p = v.map(|vi| isub(iv3(vi), o));
    let e = [(1, 2), (2, 0), (0, 1)].map(|(i, j)| idot(d, icross(p[i], p[j])));
    let den = e[0] + e[1] + e[2];
    let num = idot(p[0], icross(p[1], p[2]));
    let t = num.checked_div(den).filter(|t| t.is_finite());
    let dm = den.mid();
    (
        t,
        (e[1].mid() / dm).clamp(0.0, 1.0),
        (e[2].mid() / dm).clamp(0.0, 1.0),
    )
}
