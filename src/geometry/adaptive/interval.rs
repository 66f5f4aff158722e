//! Level 2 for a triangle: its edge signs and t in plain f64 with a proved bound
//! ([`triangle_f64`]), then where that leaves them open in f64 interval arithmetic
//! ([`triangle_interval`]); and t as an interval for a hit decided exactly.

use super::estimate::{Approx, Estimate};
use crate::geometry::exact::plane_side_f64;
use crate::math::interval::{icross, idot, isub, iv3, Interval};
use crate::math::real::{abs, cross, cross_size, dot, sub};
use std::cmp::Ordering;

/// Level 2 for a triangle: [`triangle_f64`], and [`triangle_interval`] where it cannot tell;
/// between them, an origin exactly in the triangle's plane, told by one orientation: the line
/// meets the plane at t = 0 only (or lies in it), so outside tmin < 0 < tmax it is a miss for
/// the query (a camera on a floor: every level was unsure, and rational t's cost ~40 µs a ray).
pub fn triangle_level2(
    o: [f64; 3],
    d: [f64; 3],
    v: &[[f64; 3]; 3],
    (tmin, tmax): (f64, f64),
) -> Estimate {
    match triangle_f64(o, d, v) {
        Estimate::Unsure => {}
        decided => return decided,
    }
    let zero_in_range = tmin < 0.0 && 0.0 < tmax;
    if !zero_in_range && plane_side_f64(v, o) == Some(Ordering::Equal) {
        return Estimate::Miss;
    }
    if misses_box(o, d, v, (tmin, tmax)) {
        return Estimate::Miss;
    }
    triangle_interval(o, d, v)
}

/// Whether the ray certainly misses the triangle's bounding box for tmin < t < tmax (slabs in
/// outward-rounded intervals). Where the triangle is small beside its distance from the
/// origin, its vertices less the origin agree in nearly every bit, and every edge sign is
/// within its rounding at level 2: a ray passing a unit from a triangle 10⁻²⁰ across went to
/// exact rationals (~100 µs a test), where its box is plainly missed.
fn misses_box(o: [f64; 3], d: [f64; 3], v: &[[f64; 3]; 3], (tmin, tmax): (f64, f64)) -> bool {
    let (mut enter, mut leave) = (tmin, tmax);
    for k in 0..3 {
        let lo = v[0][k].min(v[1][k]).min(v[2][k]);
        let hi = v[0][k].max(v[1][k]).max(v[2][k]);
        if d[k] == 0.0 {
            if o[k] < lo || o[k] > hi {
                return true;
            }
            continue;
        }
        // The t's where the line crosses the slab's two planes, each enclosed.
        let at = |x: f64| (Interval::point(x) - Interval::point(o[k])).checked_div(d[k].into());
        let (Some(a), Some(b)) = (at(lo), at(hi)) else {
            return false;
        };
        let (near, far) = match d[k] > 0.0 {
            true => (a, b),
            false => (b, a),
        };
        enter = enter.max(near.lo);
        leave = leave.min(far.hi);
    }
    // (A hit needs tmin < t < tmax with t within every slab: none where the enclosures part.)
    enter > leave || enter >= tmax || leave <= tmin
}

/// The predicates of [`triangle_interval`] in round-to-nearest f64 with a static bound on
/// their rounding: a fraction of the intervals' cost (their outward roundings step every
/// operation's ends one ulp out), and the test that rays from far away need for every
/// triangle near them (from 10⁶ scene sizes, the f32 levels decide none). `Unsure` where a
/// sign is within the bound, or a magnitude outside 10⁻⁹⁰…10⁹⁰ (no product of three then
/// underflows or overflows).
///
/// With u = 2⁻⁵³: each pᵢ = vᵢ − o is within u·|p̃ᵢ| of exact per component, so each of the six
/// terms of eₖ = d·(pᵢ × pⱼ) meets at most 7 roundings (two of the p's, the product and the
/// difference of the cross product, the product and two sums of the dot product): |ẽₖ − eₖ|
/// ≤ γ₇·(1 + u)²·P with P = |d|·(|p̃ᵢ| × |p̃ⱼ|) (the sizes of the terms; [`cross_size`]),
/// and P computed with 5 roundings more: 8u·P̃ bounds it. The numerator p₀·(p₁ × p₂) meets 8:
/// 9u·P̃. The denominator's sum adds 2u·Σ|ẽₖ|. t = num / den is then bracketed by the four
/// quotients of num ± its bound and den ± its bound (den's sign certain), widened by 4u
/// and an ulp.
pub fn triangle_f64(o: [f64; 3], d: [f64; 3], v: &[[f64; 3]; 3]) -> Estimate {
    const U: f64 = f64::EPSILON / 2.0;
    let tame = |x: f64| x == 0.0 || (1e-90..=1e90).contains(&x.abs());
    let p = v.map(|vi| sub(vi, o));
    if !(d.iter().chain(p.iter().flatten())).all(|&x| tame(x)) {
        return Estimate::Unsure;
    }
    let edge =
        |a: [f64; 3], b: [f64; 3]| (dot(d, cross(a, b)), 8.0 * U * dot(abs(d), cross_size(a, b)));
    let e = [edge(p[1], p[2]), edge(p[2], p[0]), edge(p[0], p[1])];
    let (mut pos, mut neg) = (0, 0);
    for (value, bound) in e {
        pos += (value > bound) as u32;
        neg += (value < -bound) as u32;
    }
    if pos > 0 && neg > 0 {
        return Estimate::Miss;
    }
    if pos != 3 && neg != 3 {
        return Estimate::Unsure;
    }
    let den = e[0].0 + e[1].0 + e[2].0;
    let den_bound = (e[0].1 + e[1].1 + e[2].1) * (1.0 + 4.0 * U) + 3.0 * U * den.abs();
    let num = dot(p[0], cross(p[1], p[2]));
    let num_bound = 9.0 * U * dot(abs(p[0]), cross_size(p[1], p[2])) * (1.0 + 4.0 * U);
    // (False for a NaN anywhere.)
    let den_certain = den_bound < 0.25 * den.abs();
    if !den_certain {
        return Estimate::Unsure;
    }
    let (n_lo, n_hi) = (num - num_bound, num + num_bound);
    let (d_lo, d_hi) = (den - den_bound, den + den_bound);
    let q = [n_lo / d_lo, n_lo / d_hi, n_hi / d_lo, n_hi / d_hi];
    let lo = q.iter().fold(f64::INFINITY, |m, &x| m.min(x));
    let hi = q.iter().fold(f64::NEG_INFINITY, |m, &x| m.max(x));
    // Out by 4u and an ulp: the quotients' rounding and the bounds' sums' (3u at most).
    let (lo, hi) = (
        (lo - lo.abs() * 4.0 * U).next_down(),
        (hi + hi.abs() * 4.0 * U).next_up(),
    );
    if !(lo.is_finite() && hi.is_finite()) {
        return Estimate::Unsure;
    }
    Estimate::Hit(Approx {
        t: num / den,
        lo,
        hi,
        b1: e[1].0 / den,
        b2: e[2].0 / den,
        level: 2,
    })
}

/// Level 2 for a triangle in f64 intervals: the signs of det[d, pᵢ, pⱼ] and t.
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
