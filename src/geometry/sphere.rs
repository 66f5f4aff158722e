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

use super::adaptive::estimate::{Approx, Estimate};
use super::exact::{dot as qdot, q, qv, sub as qsub, ExactT, Q};
use crate::math::interval::{idot, idot_x4, isub, iv3, Interval, IntervalX4};
use crate::math::real::{dot, scale, sub, V3};
use crate::math::Real;
use num_bigint::BigInt;
use num_traits::{Signed, Zero};
use std::cmp::Ordering;
use wide::f64x4;

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

/// What [`interval_x4`] found per lane: masks (all bits set in a lane where true) of the
/// lanes certainly hitting with tmin < t < tmax, t in [`lo`, `hi`], and of the lanes
/// certainly missing in that range; the rest are undecided.
///
/// [`lo`]: LanesX4::lo
/// [`hi`]: LanesX4::hi
#[derive(Clone, Copy, Debug)]
pub struct LanesX4 {
    pub hit: f64x4,
    pub miss: f64x4,
    pub lo: f64x4,
    pub hi: f64x4,
}

/// The sphere seen from a ray origin o, what [`interval_x4`] needs of it: f = o − c and
/// k = f·f − r² as intervals, computed once for every ray from o.
#[derive(Clone, Copy, Debug)]
pub struct FromOrigin {
    f: [Interval; 3],
    k: Interval,
}

impl FromOrigin {
    pub fn new(o: [f64; 3], centre: [f64; 3], radius: f64) -> Self {
        let f = isub(iv3(o), iv3(centre));
        Self {
            f,
            k: idot(f, f) - Interval::point(radius).square(),
        }
    }
}

/// [`interval`] for four rays from one origin at once (directions `d`, lanes): the same
/// steps in [`IntervalX4`] arithmetic, whose ends are a little wider, so a lane it decides
/// [`interval`] decides the same way (both enclose the exact roots). For f32 inputs (every
/// magnitude within 2^±150, so nothing over- or underflows in f64); lanes with non-finite
/// ends come out undecided.
#[inline(always)]
pub fn interval_x4(sphere: &FromOrigin, d: &[f64x4; 3], tmin: f64, tmax: f64) -> LanesX4 {
    let f = sphere.f.map(IntervalX4::splat);
    let k = IntervalX4::splat(sphere.k);
    let point = |x: f64x4| IntervalX4::point(x);
    let a = point(d[0]).square() + point(d[1]).square() + point(d[2]).square();
    let b = idot_x4(&f, d);
    let disc = b.square() - a * k;
    let zero = f64x4::ZERO;
    let finite = d[0].is_finite() & d[1].is_finite() & d[2].is_finite();
    let miss_line = finite & disc.hi.simd_lt(zero);
    let crosses = finite & disc.lo.simd_gt(zero) & a.lo.simd_gt(zero);
    let root = disc.sqrt();
    let t0 = (-b - root).div_positive(a);
    let t1 = (-b + root).div_positive(a);
    let (tmin, tmax) = (f64x4::splat(tmin), f64x4::splat(tmax));
    let ok = crosses & t0.finite() & t1.finite();
    // As `interval`: the near root unless it is certainly at or before tmin.
    let near_before = t0.hi.simd_le(tmin);
    let inside = |t: IntervalX4| t.lo.simd_gt(tmin) & t.hi.simd_lt(tmax);
    let hit0 = !near_before & inside(t0);
    let hit1 = near_before & inside(t1);
    let miss = (!near_before & t0.lo.simd_ge(tmax))
        | (near_before & (t1.hi.simd_le(tmin) | t1.lo.simd_ge(tmax)));
    LanesX4 {
        hit: ok & (hit0 | hit1),
        miss: miss_line | (ok & miss),
        lo: near_before.bitselect(t1.lo, t0.lo),
        hi: near_before.bitselect(t1.hi, t0.hi),
    }
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

#[cfg(test)]
mod tests {
    use std::cmp::Ordering;

    #[test]
    fn sphere_roots_with_origin_on_the_surface_and_tangent_rays() {
        let c = [0.0, 0.0, 5.0];
        // From the surface point (0,0,4) inward: t = 0 is not > 0, the far root t = 2 is.
        let hit = crate::geometry::sphere::exact(
            [0.0, 0.0, 4.0],
            [0.0, 0.0, 1.0],
            c,
            1.0,
            0.0,
            f64::INFINITY,
        )
        .unwrap();
        assert_eq!(hit.cmp_f(2.0), Ordering::Equal);
        // Tangent: touches at t = 5.
        let tan = crate::geometry::sphere::exact(
            [1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0],
            c,
            1.0,
            0.0,
            f64::INFINITY,
        )
        .unwrap();
        assert_eq!(tan.cmp_f(5.0), Ordering::Equal);
        assert!(crate::geometry::sphere::exact(
            [1.0f64.next_up(), 0.0, 0.0],
            [0.0, 0.0, 1.0],
            c,
            1.0,
            0.0,
            f64::INFINITY
        )
        .is_none());
    }
}
