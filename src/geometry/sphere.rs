//! Ray/sphere intersection without catastrophic cancellation (Haines et al., "Precision
//! Improvements for Ray/Sphere Intersection", Ray Tracing Gems ch. 7).
//!
//! With f = o − c, a = d·d and b = f·d, the roots of a t² + 2 b t + (f·f − r²) = 0 have the
//! discriminant b² − a(f·f − r²) (for unit d: (d·(o−c))² − ((o−c)·(o−c) − r²)). Computed that
//! way it cancels catastrophically for small, far spheres. Instead, with l = f − (b/a)·d (the
//! offset from the centre to the ray's closest point), b² − a(f·f − r²) = a(r² − l·l), and we
//! evaluate r² − l·l as (r − |l|)(r + |l|). The far root comes from q = −b − sign(b)·√disc as
//! q/a and the near one as c/q, which avoids subtracting nearly equal numbers, with
//! c = f·f − r² evaluated as (|f| − r)(|f| + r) so that an origin on the sphere gives c ≈ 0.
//!
//! The sphere's levels of the adaptive method are here too ([`interval`], [`exact`]): one
//! shape, one place. (Its surface point and offset are in `geometry::offset`, with the
//! triangle's.)

use super::adaptive::{Approx, Estimate};
use super::exact::{dot as qdot, q, qv, sub as qsub, ExactT, Q};
use crate::math::interval::{idot, isub, iv3, Interval};
use crate::math::real::{dot, scale, sub, V3};
use crate::math::Real;
use num_bigint::BigInt;
use num_traits::{Signed, Zero};
use std::cmp::Ordering;

/// Nearest root t of the ray o + t·d on the sphere (centre, radius) with tmin < t < tmax.
#[inline]
pub fn intersect<T: Real>(
    o: V3<T>,
    d: V3<T>,
    centre: V3<T>,
    radius: T,
    tmin: T,
    tmax: T,
) -> Option<T> {
    let f = sub(o, centre);
    let a = dot(d, d);
    if a == T::zero() {
        return None;
    }
    let b = dot(f, d);
    let l = sub(f, scale(d, b / a));
    let l_len = dot(l, l).sqrt();
    let disc = a * ((radius - l_len) * (radius + l_len));
    if disc < T::zero() {
        return None;
    }
    let f_len = dot(f, f).sqrt();
    let c = (f_len - radius) * (f_len + radius);
    let sign_b = if b >= T::zero() { T::one() } else { -T::one() };
    let q = -b - sign_b * disc.sqrt();
    let (mut t0, mut t1) = if q == T::zero() {
        // b = 0 and disc = 0: the ray's closest point touches the sphere at t = 0.
        (T::zero(), T::zero())
    } else {
        (c / q, q / a)
    };
    if t0 > t1 {
        std::mem::swap(&mut t0, &mut t1);
    }
    if t0 > tmin && t0 < tmax {
        Some(t0)
    } else if t1 > tmin && t1 < tmax {
        Some(t1)
    } else {
        None
    }
}

/// The textbook form, b² − a·c with c = f·f − r², kept for the speed-versus-error report.
#[inline]
pub fn intersect_naive<T: Real>(
    o: V3<T>,
    d: V3<T>,
    centre: V3<T>,
    radius: T,
    tmin: T,
    tmax: T,
) -> Option<T> {
    let f = sub(o, centre);
    let a = dot(d, d);
    if a == T::zero() {
        return None;
    }
    let b = dot(f, d);
    let c = dot(f, f) - radius * radius;
    let disc = b * b - a * c;
    if disc < T::zero() {
        return None;
    }
    let s = disc.sqrt();
    let t0 = (-b - s) / a;
    let t1 = (-b + s) / a;
    if t0 > tmin && t0 < tmax {
        Some(t0)
    } else if t1 > tmin && t1 < tmax {
        Some(t1)
    } else {
        None
    }
}

/// Level 2 for a sphere: the nearest root with tmin < t < tmax in f64 intervals.
pub fn interval(
    o: [f64; 3],
    d: [f64; 3],
    centre: [f64; 3],
    radius: f64,
    tmin: f64,
    tmax: f64,
) -> Estimate {
    let d = iv3(d);
    let f = isub(iv3(o), iv3(centre));
    let a = idot(d, d);
    let b = idot(f, d);
    let k = idot(f, f) - Interval::point(radius).square();
    let disc = b.square() - a * k;
    match disc.sign() {
        Some(Ordering::Less) => return Estimate::Miss,
        Some(Ordering::Greater) => {}
        _ => return Estimate::Unsure,
    }
    let Some(root) = disc.sqrt() else {
        return Estimate::Unsure;
    };
    for t in [(-b - root).checked_div(a), (-b + root).checked_div(a)] {
        let Some(t) = t.filter(|t| t.is_finite()) else {
            return Estimate::Unsure;
        };
        if t.hi <= tmin {
            continue;
        }
        if t.lo >= tmax {
            return Estimate::Miss;
        }
        if t.lo > tmin && t.hi < tmax {
            return Estimate::Hit(Approx {
                t: t.mid(),
                lo: t.lo,
                hi: t.hi,
                b1: 0.0,
                b2: 0.0,
                level: 2,
            });
        }
        return Estimate::Unsure;
    }
    Estimate::Miss
}

/// The exact nearest root of o + t·d on the closed sphere with tmin < t < tmax (a tangent
/// ray touches it at one point, which counts).
pub fn exact(
    o: [f64; 3],
    d: [f64; 3],
    centre: [f64; 3],
    radius: f64,
    tmin: f64,
    tmax: f64,
) -> Option<ExactT> {
    let d = qv(d);
    let f = qsub(&qv(o), &qv(centre));
    let r = q(radius);
    let a = qdot(&d, &d);
    if a.is_zero() {
        return None;
    }
    let b = qdot(&f, &d);
    let c = qdot(&f, &f) - &r * &r;
    let disc = &b * &b - &a * &c;
    if disc.is_negative() {
        return None;
    }
    let centre_t = -(&b / &a);
    let half = Q::from_integer(BigInt::from(1)) / &a;
    [-half.clone(), half]
        .into_iter()
        .map(|b| ExactT {
            a: centre_t.clone(),
            b,
            s: disc.clone(),
        })
        .find(|t| t.cmp_f(tmin) == Ordering::Greater && t.cmp_f(tmax) == Ordering::Less)
}
