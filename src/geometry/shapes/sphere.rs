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
//! The sphere's levels of the adaptive method are here too ([`interval`], [`exact`]), its
//! surface point ([`SurfacePoint::on_sphere`]) and the rest of what a shape is asked
//! ([`Sphere`], [`Primitive`]): one shape, one place. Its four-lane interval test for the
//! packets ([`interval_x4`], [`FromOrigin`]) is a module of this file, `sphere/lanes.rs`.

use super::{Primitive, SceneFrame, Shape, ShapeTerms, WordedTerms};
use crate::geometry::adaptive::{self, round_down, Approx, Decided, Estimate, Feature};
use crate::geometry::exact::{dot as qdot, q, qv, sub as qsub, two_sum, ExactT, Q};
use crate::geometry::offset::{normalize, UNDERFLOW};
use crate::geometry::{Method, Ray, SurfacePoint};
use crate::math::interval::{idot, isub, iv3, Interval};
use crate::math::lanes::f64x4;
use crate::math::real::{abs, add, dot, scale, sub, V3};
use crate::math::Real;
use num_bigint::BigInt;
use num_traits::{Signed, Zero};
use std::cmp::Ordering;
use std::fmt;

pub(crate) mod lanes;
pub use lanes::{
    interval_x4, interval_x4_gathered, interval_x4_of, DirectionLanes, DirectionsX4, FromOrigin,
    LanesX4,
};

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

/// a = d·d, b = f·d and the discriminant b² − a·c (c = f·f − r², f = o − centre) of
/// |o + t·d − centre|² = r², a·t² + 2b·t + c = 0, in rationals.
fn exact_quadratic(o: [f64; 3], d: [f64; 3], centre: [f64; 3], radius: f64) -> (Q, Q, Q) {
    let d = qv(d);
    let f = qsub(&qv(o), &qv(centre));
    let r = q(radius);
    let a = qdot(&d, &d);
    let b = qdot(&f, &d);
    let c = qdot(&f, &f) - &r * &r;
    let disc = &b * &b - &a * &c;
    (a, b, disc)
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
    let (a, b, disc) = exact_quadratic(o, d, centre, radius);
    if a.is_zero() || disc.is_negative() {
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

/// A sphere (closed: a tangent ray touches it): the shape of [`Shape::Sphere`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere<T: Real = f32> {
    /// Centre.
    pub centre: V3<T>,
    /// Radius (> 0).
    pub radius: T,
}

impl<T: Real> Sphere<T> {
    /// Centre and radius in f64 (exact).
    #[inline]
    fn wide(&self) -> ([f64; 3], f64) {
        (self.centre.map(Real::f64), self.radius.f64())
    }
}

impl<T: Real> Primitive<T> for Sphere<T> {
    const KEYWORD: &'static str = "sphere";
    const KIND: u8 = 1;

    /// Four numbers: the centre and the radius (> 0), under a scale the same along every
    /// axis (another would make an ellipsoid).
    fn read(words: &[&str], frame: &impl SceneFrame<T>) -> Result<Self, String> {
        let x = frame.numbers(words, 4, Self::KEYWORD)?;
        if x[3] <= 0.0 {
            return Err(format!("sphere radius {} must be > 0", words[3]));
        }
        let radius = frame.length(words[3]).ok_or(
            "a sphere under a non-uniform scale would be an ellipsoid (scale all three axes \
             alike, or push/pop around the non-uniform scale)",
        )?;
        if !(radius.is_finite() && radius > T::zero()) {
            return Err(format!(
                "sphere radius {} is {radius} in the world (it must be > 0 and finite)",
                words[3]
            ));
        }
        let centre = frame.point(words)?;
        Ok(Sphere { centre, radius })
    }

    /// Centre, then radius.
    fn numbers(&self) -> impl Iterator<Item = T> {
        self.centre.into_iter().chain([self.radius])
    }

    fn extent(&self) -> f64 {
        let centre = (self.centre.iter()).fold(0.0f64, |m, x| m.max(x.f64().abs()));
        centre + self.radius.f64().abs()
    }

    fn bounds(&self) -> (V3<T>, V3<T>) {
        let (c, r) = (self.centre, self.radius);
        (
            [c[0] - r, c[1] - r, c[2] - r],
            [c[0] + r, c[1] + r, c[2] + r],
        )
    }

    /// c ± r rounded outwards, by an exact difference.
    fn box_f32(&self) -> ([f32; 3], [f32; 3]) {
        let (c, r) = self.wide();
        (c.map(|x| lower(x, r)), c.map(|x| -lower(-x, r)))
    }

    fn triangle(&self) -> Option<&[V3<T>; 3]> {
        None
    }

    fn seen_from(&self, o: [f64; 3]) -> Option<FromOrigin> {
        let (c, r) = self.wide();
        Some(FromOrigin::for_packets(o, c, r))
    }

    fn is_degenerate(&self) -> bool {
        false
    }

    /// The cancellation-free test ([`intersect`]) whatever the method.
    #[inline]
    fn intersect(&self, ray: &Ray<T>, _method: Method, tmin: T, tmax: T) -> Option<(T, T, T)> {
        intersect(ray.o, ray.d, self.centre, self.radius, tmin, tmax)
            .map(|t| (t, T::zero(), T::zero()))
    }

    /// p − c.
    fn normal_at(&self, ray: &Ray<T>, t: T) -> [f64; 3] {
        let c = self.centre;
        [0, 1, 2].map(|k| ray.o[k].f64() + t.f64() * ray.d[k].f64() - c[k].f64())
    }

    /// Decided within 10⁻⁹ relative of the surface.
    fn outside(&self, p: V3<T>) -> Option<bool> {
        let rel = [0, 1, 2].map(|k| p[k].f64() - self.centre[k].f64());
        let d2 = rel[0] * rel[0] + rel[1] * rel[1] + rel[2] * rel[2];
        let r2 = self.radius.f64() * self.radius.f64();
        if d2 > r2 * (1.0 + 1e-9) {
            Some(true)
        } else if d2 < r2 * (1.0 - 1e-9) {
            Some(false)
        } else {
            None
        }
    }

    /// Where the light is certainly on the side the segment ends on (from inside with the
    /// light outside, the segment must cross the sphere, which then blocks it).
    fn shadow_clear_of_itself(&self, light: V3<T>, end_outside: bool) -> bool {
        self.outside(light) == Some(end_outside)
    }

    /// The f64 interval root's midpoint ([`interval_x4`], t_error its half-width and t's
    /// rounding to f32), or where the interval cannot decide, the exact t correctly rounded
    /// ([`adaptive::rounded_t`], within 2⁻²⁴·|t| + 2⁻¹⁴⁹), re-projected onto the sphere by
    /// [`SurfacePoint::on_sphere`]: the same for every path, whichever level of the search
    /// found the hit.
    fn surface_point(&self, ray: &Ray<f32>) -> SurfacePoint {
        let (c, r) = self.wide();
        let (centre, radius) = (c.map(|x| x as f32), r as f32);
        let (o, d) = (ray.o.map(f64::from), ray.d.map(f64::from));
        let from = FromOrigin::new(o, c, r);
        let root = interval_x4(&from, &d.map(f64x4::splat), 0.0, f64::INFINITY);
        let (t, t_error) = match root.hit.to_bitmask() & 1 {
            1 => {
                let (lo, hi) = (root.lo.to_array()[0], root.hi.to_array()[0]);
                let t = (0.5 * lo + 0.5 * hi) as f32;
                let off = (f64::from(t) - lo).max(hi - f64::from(t));
                (t, (off * (1.0 + 1e-6)) as f32 + f32::from_bits(1))
            }
            _ => {
                let shape = Shape::sphere(centre, radius);
                let t = adaptive::rounded_t(&shape, ray, 0.0, f32::INFINITY);
                let t = t.unwrap_or(f32::NAN);
                (t, t.abs() * f32::EPSILON / 2.0 + f32::from_bits(1))
            }
        };
        SurfacePoint::on_sphere(centre, radius, ray, t, t_error)
    }

    fn terms(&self, ray: &Ray<T>) -> ShapeTerms {
        let o = ray.o.map(Real::f64);
        let d = ray.d.map(Real::f64);
        let (centre, r) = self.wide();
        let oc = [0, 1, 2].map(|k| o[k] - centre[k]);
        let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        let (a, b, c) = (dot(d, d), 2.0 * dot(d, oc), dot(oc, oc) - r * r);
        ShapeTerms::Sphere(Terms {
            a,
            b,
            c,
            discriminant: b * b - 4.0 * a * c,
        })
    }

    fn locate(&self, ray: &Ray<T>) -> super::Location {
        let (centre, radius) = self.wide();
        let (o, d) = (ray.o.map(Real::f64), ray.d.map(Real::f64));
        super::Location::Sphere(locate(centre, radius, o, d))
    }

    fn widen(&self) -> Shape<f64> {
        let (centre, radius) = self.wide();
        Shape::Sphere(Sphere { centre, radius })
    }

    /// None: a sphere starts at f64 intervals.
    fn f32_filter(&self, _o: [f32; 3], _d: [f32; 3]) -> Option<Estimate> {
        None
    }

    /// The nearest root within tmin < t < tmax in f64 intervals ([`interval`]).
    fn f64_intervals(&self, o: [f64; 3], d: [f64; 3], tmin: f64, tmax: f64) -> Estimate {
        let (c, r) = self.wide();
        interval(o, d, c, r, tmin, tmax)
    }

    /// The exact nearest root within tmin < t < tmax ([`exact`]).
    fn decide_exactly(&self, o: [f64; 3], d: [f64; 3], tmin: f64, tmax: f64) -> Option<Decided> {
        let t = self.exact_t(o, d, tmin, tmax)?;
        Some(Decided {
            t: None,
            point: Feature::Root,
            exact: Some(t),
            b1: 0.0,
            b2: 0.0,
        })
    }

    fn exact_t(&self, o: [f64; 3], d: [f64; 3], tmin: f64, tmax: f64) -> Option<ExactT> {
        let (c, r) = self.wide();
        exact(o, d, c, r, tmin, tmax)
    }

    /// Never known without the exact roots.
    fn same_t(&self, _other: &Shape<T>) -> bool {
        false
    }

    /// The nearest root's f64 interval, where [`interval`] decides the hit.
    fn t_in_f64(&self, o: [f64; 3], d: [f64; 3], tmin: f64, tmax: f64) -> Option<(f64, f64)> {
        match self.f64_intervals(o, d, tmin, tmax) {
            Estimate::Hit(a) => Some((a.lo, a.hi)),
            Estimate::Miss | Estimate::Unsure => None,
        }
    }

    fn t_rounded<R: Real>(&self, o: [f64; 3], d: [f64; 3], tmin: f64, tmax: f64) -> Option<R> {
        Some(self.exact_t(o, d, tmin, tmax)?.rounded())
    }
}

impl SurfacePoint {
    /// The hit point of `ray` on the sphere (`centre`, `radius`) from t with |t − exact t| ≤
    /// `t_error`: o + t·d re-projected onto the sphere, which keeps it on the surface within
    /// γ₆·(|c| + |p − c|) + 8·2⁻¹⁴⁹ (the roundings below f32's normal range) whatever t's
    /// error.
    ///
    /// `hit_error`: o + t·d is within εₖ = γ₂·(|oₖ| + |t·dₖ|) + t_error·|dₖ| of the exact hit
    /// x, and q = fl(o + t·d − c) within εₖ + u·|qₖ| of x − c (whose length is r); scaling q
    /// to length r moves it by ||q| − r| ≤ ‖ε‖₂ per axis, so r·q/|q| is within ‖ε‖₂ + εₖ of
    /// x − c; the normalisation and the sum with c round by at most γ₁₀·(|cₖ| + |pₖ − cₖ|).
    pub fn on_sphere(centre: V3<f32>, radius: f32, ray: &Ray<f32>, t: f32, t_error: f32) -> Self {
        let raw = ray.at(t);
        let rel = sub(raw, centre);
        let len = dot(rel, rel).sqrt();
        let n = if len > 0.0 {
            normalize(rel)
        } else {
            [0.0, 0.0, 1.0]
        };
        let p = add(centre, scale(n, radius));
        let p_error = scale(add(abs(centre), abs(sub(p, centre))), f32::error_gamma(6))
            .map(|e| e + UNDERFLOW);
        // The bound in f64 (no rounding of its own worth a term), rounded up by a margin.
        let u = f64::from(f32::EPSILON) / 2.0;
        let gamma = |n: f64| n * u / (1.0 - n * u);
        let eps = [0, 1, 2].map(|k| {
            let (o, d, t) = (ray.o[k] as f64, ray.d[k] as f64, t as f64);
            gamma(2.0) * (o.abs() + (t * d).abs())
                + t_error as f64 * d.abs()
                + u * rel[k].abs() as f64
                + 8.0 * f64::from(UNDERFLOW)
        });
        let norm = (eps[0] * eps[0] + eps[1] * eps[1] + eps[2] * eps[2]).sqrt();
        let hit_error = [0, 1, 2].map(|k| {
            let round = gamma(10.0) * (centre[k].abs() as f64 + (p[k] - centre[k]).abs() as f64)
                + 8.0 * f64::from(UNDERFLOW);
            let bound = ((norm + eps[k]) * (1.0 + 1e-6) + round) * (1.0 + 1e-6);
            if len > 0.0 && bound.is_finite() {
                bound as f32
            } else {
                f32::INFINITY
            }
        });
        Self {
            p,
            p_error,
            hit_error,
            n,
        }
    }
}

/// |o + t·d − c|² = r² as a·t² + b·t + c = 0 with a = d·d, b = 2·d·(o − c), c = |o − c|² − r²,
/// and its discriminant b² − 4ac.
#[derive(Clone, Debug, PartialEq)]
pub struct Terms {
    pub a: f64,
    pub b: f64,
    pub c: f64,
    pub discriminant: f64,
}

impl WordedTerms for Terms {
    fn lines(&self) -> Vec<String> {
        let Terms { a, b, c, .. } = self;
        vec![
            "shape: sphere".to_string(),
            format!("quadratic_abc: {a} {b} {c}"),
            format!("discriminant: {}", self.discriminant),
        ]
    }

    fn rows(&self, v3: &dyn Fn([f64; 3]) -> String) -> Vec<(&'static str, String)> {
        let Terms { a, b, c, .. } = self;
        vec![
            // (As the vectors are written: one line of the inspector's width.)
            ("a, b, c: a t^2+b t+c", v3([*a, *b, *c])),
            ("b^2 - 4ac", format!("{:.6}", self.discriminant)),
        ]
    }
}

/// Where a ray's line meets a sphere ([`Primitive::locate`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Location {
    /// Through it (two points).
    Through,
    /// Tangent to it (the exact discriminant is zero: one point).
    Tangent,
    /// Outside it.
    Misses,
}

/// The line o + t·d against the sphere, from the exact sign of the discriminant
/// ([`exact_quadratic`]); a zero d meets nothing.
fn locate(centre: [f64; 3], radius: f64, o: [f64; 3], d: [f64; 3]) -> Location {
    let (a, _, disc) = exact_quadratic(o, d, centre, radius);
    match (a.is_zero(), disc.is_zero(), disc.is_negative()) {
        (true, _, _) | (_, _, true) => Location::Misses,
        (false, true, _) => Location::Tangent,
        (false, false, false) => Location::Through,
    }
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str(match self {
            Location::Through => "on the sphere",
            Location::Tangent => "tangent to the sphere (discriminant exactly 0)",
            Location::Misses => "outside the sphere",
        })
    }
}

/// The largest f32 at or below `a − b`, exactly: the difference's rounding error is found by
/// two-sum (s + e = a − b exactly); where s is an f32 and e < 0, one f32 below it.
fn lower(a: f64, b: f64) -> f32 {
    let (s, e) = two_sum(a, -b);
    let r = round_down(s);
    match e < 0.0 && f64::from(r) == s {
        true => r.next_down(),
        false => r,
    }
}

#[cfg(feature = "unit-tests")]
#[deny(dead_code)]
pub(crate) mod tests {
    use super::{Primitive, Sphere};
    use num_rational::BigRational;
    use std::cmp::Ordering;

    fn exact(x: f32) -> BigRational {
        BigRational::from_float(x).expect("finite")
    }

    fn box_sides_are_the_nearest_f32_outside_the_exact_sphere() {
        // Centres and radii from 2⁻⁴⁰ to 2⁴⁰, of both signs, equal, and 2³⁰ apart (where the
        // f64 difference itself rounds): each side is at or beyond c ∓ r exactly, and the next
        // f32 inwards is not.
        let mut x = 0x2545_f491_4f6c_dd1du64;
        let mut next = move || crate::math::xorshift(&mut x);
        for i in 0..20_000 {
            let value = |bits: u64| {
                let e = (bits % 81) as i32 - 40;
                let m = 1.0 + (bits >> 8) as f64 / (1u64 << 56) as f64;
                (m * 2f64.powi(e)) as f32
            };
            let c = value(next()) * if next() % 2 == 0 { 1.0 } else { -1.0 };
            let r = match i % 4 {
                0 => c.abs(),
                1 => c.abs() * 2f32.powi(-30),
                _ => value(next()),
            };
            let sphere = Sphere {
                centre: [c, -c, 0.5],
                radius: r,
            };
            let (low, high) = sphere.box_f32();
            let (lo, hi) = (low[0], high[0]);
            assert_eq!((-hi, -lo), (low[1], high[1]));
            let (want_lo, want_hi) = (exact(c) - exact(r), exact(c) + exact(r));
            assert!(
                exact(lo) <= want_lo && exact(lo.next_up()) > want_lo,
                "{c} - {r}: {lo}"
            );
            assert!(
                exact(hi) >= want_hi && exact(hi.next_down()) < want_hi,
                "{c} + {r}: {hi}"
            );
        }
    }

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

    /// This module's tests, for tests/unit.rs to run.
    pub(crate) const TESTS: &[(&str, fn())] = &[
        (
            "box_sides_are_the_nearest_f32_outside_the_exact_sphere",
            box_sides_are_the_nearest_f32_outside_the_exact_sphere,
        ),
        (
            "sphere_roots_with_origin_on_the_surface_and_tangent_rays",
            sphere_roots_with_origin_on_the_surface_and_tangent_rays,
        ),
    ];
}
