//! Ray/triangle intersection: three methods, all closed (edges and vertices belong), two-sided,
//! and free of absolute epsilons (an `|det| < 1e-8` test drops every hit on a 1e-4 triangle).
//!
//! - [`watertight`] (Woop, Benthin & Wald 2013, "Watertight Ray/Triangle Intersection"): the
//!   default. It shears the triangle into the ray's frame so that the three edge functions of
//!   two triangles sharing an edge are computed from the same numbers with opposite signs: a
//!   ray can never pass between them. An edge function that rounds to exactly 0 is recomputed
//!   in f64, as in the paper.
//! - [`moller`] (Möller & Trumbore 1997): barycentrics by Cramer's rule on the edge vectors.
//! - [`cramer`]: the lecture's x = A⁻¹b with A = [−d, e1, e2] and b = o − v0, through an
//!   explicit inverse. It is the baseline of the speed-versus-error report.
//!
//! Each returns `(t, b1, b2)`: the ray parameter and the barycentric weights of v1 and v2
//! (the hit point is (1 − b1 − b2)·v0 + b1·v1 + b2·v2).
//!
//! [`Triangle`] answers the rest of what a shape is asked ([`Primitive`]): the adaptive
//! method's levels (its f32 filter in `adaptive::filter`, its f64 intervals in
//! `adaptive::interval`, its exact level here on the exact predicates of `geometry::exact`),
//! the renderer's shading point (the barycentrics of the triangle prepared for the ray's
//! origin, as the camera packets compute them: `shading_points`, in `triangle/shading.rs`)
//! and the inspector's linear system. That preparation is the accelerator's
//! (`accel::frame::OriginTriangle`): the one thing `geometry` takes from above it, so that
//! every path shades to the same bits.

use super::{sphere, Primitive, SceneFrame, Shape, ShapeTerms, WordedTerms};
use crate::accel::OriginTriangle;
use crate::geometry::adaptive::interval::{triangle_level2, triangle_t_interval};
use crate::geometry::adaptive::rounded::plane_t_f64;
use crate::geometry::adaptive::{precise_f32, round_down, round_up, Decided, Estimate, Feature};
use crate::geometry::exact::{self, ExactT};
use crate::geometry::{Method, Ray, SurfacePoint};
use crate::math::real::{cross, dot, sub, V3};
use crate::math::Real;
use std::cmp::Ordering;

mod shading;
pub(crate) use shading::shading_points;
pub use shading::{surface_point_prepared, unit_normal};

/// Whether the triangle has zero area (its vertices on one line, or coincident), decided
/// exactly ([`exact::zero_area`]). Such a triangle is no surface: no method hits it,
/// whatever its rounding would give (the watertight test's shear can leave it a sliver).
pub fn zero_area<T: Real>(v: &[V3<T>; 3]) -> bool {
    exact::zero_area(&v.map(|p| p.map(Real::f64)))
}

/// A hit: ray parameter t and barycentrics (b1, b2) of vertices 1 and 2.
pub type TriHit<T> = (T, T, T);

#[inline]
fn max_dim<T: Real>(a: V3<T>) -> usize {
    if a[0] > a[1] {
        if a[0] > a[2] {
            0
        } else {
            2
        }
    } else if a[1] > a[2] {
        1
    } else {
        2
    }
}

/// The per-ray part of the watertight test (axis permutation and shear), computed once per
/// ray and shared by every triangle it is tested against.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WatertightRay<T: Real> {
    /// Ray origin.
    pub o: V3<T>,
    /// Ray direction.
    pub d: V3<T>,
    /// Axes permuted so that `kz` is the largest |d| component.
    pub k: [usize; 3],
    /// Shear constants: −dx/dz, −dy/dz, 1/dz in the permuted frame.
    pub s: V3<T>,
}

impl<T: Real> WatertightRay<T> {
    /// Precomputes for o + t·d; `None` for a zero direction.
    #[inline]
    pub fn new(o: V3<T>, d: V3<T>) -> Option<Self> {
        let kz = max_dim([d[0].abs(), d[1].abs(), d[2].abs()]);
        let kx = if kz == 2 { 0 } else { kz + 1 };
        let ky = if kx == 2 { 0 } else { kx + 1 };
        let dz = d[kz];
        if dz == T::zero() {
            return None;
        }
        Some(Self {
            o,
            d,
            k: [kx, ky, kz],
            s: [-d[kx] / dz, -d[ky] / dz, T::one() / dz],
        })
    }
}

/// Woop–Benthin–Wald watertight test. Hits with tmin < t < tmax.
#[inline]
pub fn watertight<T: Real>(
    o: V3<T>,
    d: V3<T>,
    v: &[V3<T>; 3],
    tmin: T,
    tmax: T,
) -> Option<TriHit<T>> {
    watertight_pre(&WatertightRay::new(o, d)?, v, tmin, tmax)
}

/// The watertight test with the per-ray part precomputed.
#[inline]
pub fn watertight_pre<T: Real>(
    r: &WatertightRay<T>,
    v: &[V3<T>; 3],
    tmin: T,
    tmax: T,
) -> Option<TriHit<T>> {
    let (t, b1, b2, bound) = watertight_raw(r, v)?;
    if !(t > tmin && t < tmax && beyond_tmin(r, v, t, bound, tmin)) {
        return None;
    }
    Some((t, b1, b2))
}

/// Whether a hit at computed `t` (rounding error ≤ `bound`) is provably beyond `tmin`. Where
/// the f32 bound cannot tell (t within its error of tmin: a ray leaving this very surface, or a
/// grazing ray whose f32 bound is loose), the test is redone in f64 on the same (exact) inputs,
/// whose bound is about 2²⁹ times tighter.
#[inline]
pub fn beyond_tmin<T: Real>(r: &WatertightRay<T>, v: &[V3<T>; 3], t: T, bound: T, tmin: T) -> bool {
    if t - bound > tmin {
        return true;
    }
    let wide = |p: V3<T>| p.map(Real::f64);
    let Some(r64) = WatertightRay::new(wide(r.o), wide(r.d)) else {
        return false;
    };
    watertight_raw(&r64, &v.map(wide)).is_some_and(|(t64, _, _, b64)| t64 - b64 > tmin.f64())
}

/// The watertight test without the interval: `(t, b1, b2, error bound of t)` if the ray's line
/// meets the closed triangle and the triangle is not seen edge-on.
#[inline]
pub fn watertight_raw<T: Real>(r: &WatertightRay<T>, v: &[V3<T>; 3]) -> Option<(T, T, T, T)> {
    let [kx, ky, kz] = r.k;
    let [sx, sy, sz] = r.s;
    let a = sub(v[0], r.o);
    let b = sub(v[1], r.o);
    let c = sub(v[2], r.o);
    let (ax, ay, az) = (a[kx] + sx * a[kz], a[ky] + sy * a[kz], a[kz]);
    let (bx, by, bz) = (b[kx] + sx * b[kz], b[ky] + sy * b[kz], b[kz]);
    let (cx, cy, cz) = (c[kx] + sx * c[kz], c[ky] + sy * c[kz], c[kz]);
    let (u, vv, w) = edge_functions(ax, ay, bx, by, cx, cy);
    let zero = T::zero();
    if (u < zero || vv < zero || w < zero) && (u > zero || vv > zero || w > zero) {
        return None;
    }
    let det = u + vv + w;
    if det == zero {
        return None; // ray in the triangle's plane, or a degenerate triangle
    }
    let t_scaled = (u * az + vv * bz + w * cz) * sz;
    let rcp = T::one() / det;
    let t = t_scaled * rcp;
    let bound = t_error_bound(
        &[[ax, ay, az], [bx, by, bz], [cx, cy, cz]],
        sz,
        [u, vv, w],
        rcp,
    );
    // u weighs vertex a (v0), vv weighs b (v1), w weighs c (v2).
    Some((t, vv * rcp, w * rcp, bound))
}

/// A conservative bound on the rounding error of the watertight test's t, after pbrt-v4
/// §6.8.5 (Pharr, Jakob & Humphreys), from the sheared vertices (x, y sheared, z not yet
/// scaled by `sz`), the edge functions and 1/det. A hit whose t does not exceed tmin by more
/// than this bound is not counted: it may lie at or before tmin (a shadow ray re-hitting the
/// surface it leaves).
///
/// Unlike pbrt, which bounds the shear term of x′ = x + Sx·z by the *scaled* z (fine for unit
/// directions), this uses the unscaled z (|Sx| ≤ 1 since z is the largest direction axis), so
/// the bound stays right for any |d|: a 1e-5 triangle hit by a 1e-6-long direction.
///
/// pbrt's terms are all relative; where t's products underflow (a hit 1e-55 along a ray from
/// 1e-45 above the triangle) each rounding loses up to half the least subnormal, which they
/// do not cover: t (0) and its bound (0) then left out the exact t. The absolute term
/// U·(1 + |1/det|·(1 + 3|Sz|)), U = [`Real::UNDERFLOW`], covers the three products scaled by
/// Sz/det, the scaling by Sz and the division, 16 times over (and `max_zt` starts at U, for
/// the bound's own products).
#[inline]
pub fn t_error_bound<T: Real>(p: &[[T; 3]; 3], sz: T, e: [T; 3], rcp: T) -> T {
    let max3 = |a: T, b: T, c: T| a.abs().max(b.abs()).max(c.abs());
    let max_z = max3(p[0][2], p[1][2], p[2][2]);
    let max_zt = max_z * sz.abs() + T::UNDERFLOW;
    let max_xt = max3(p[0][0], p[1][0], p[2][0]);
    let max_yt = max3(p[0][1], p[1][1], p[2][1]);
    let delta_z = T::error_gamma(3) * max_zt;
    let delta_x = T::error_gamma(5) * (max_xt + max_z);
    let delta_y = T::error_gamma(5) * (max_yt + max_z);
    let two = T::one() + T::one();
    let three = two + T::one();
    let delta_e = two * (T::error_gamma(2) * max_xt * max_yt + delta_y * max_xt + delta_x * max_yt);
    let max_e = max3(e[0], e[1], e[2]);
    let underflow = T::UNDERFLOW * (T::one() + rcp.abs() * (T::one() + three * sz.abs()));
    three * (T::error_gamma(3) * max_e * max_zt + delta_e * max_zt + delta_z * max_e) * rcp.abs()
        + underflow
}

/// The three edge functions of the sheared triangle. One that rounds to exactly 0 may be a
/// rounding artefact: all three are then decided in double precision, as in the paper (for
/// f64 input this recomputes the same values).
#[inline]
pub fn edge_functions<T: Real>(ax: T, ay: T, bx: T, by: T, cx: T, cy: T) -> (T, T, T) {
    let u = cx * by - cy * bx;
    let w = bx * ay - by * ax;
    let vv = ax * cy - ay * cx;
    if u == T::zero() || vv == T::zero() || w == T::zero() {
        let (ax, ay, bx, by, cx, cy) = (ax.f64(), ay.f64(), bx.f64(), by.f64(), cx.f64(), cy.f64());
        return (
            T::of(cx * by - cy * bx),
            T::of(ax * cy - ay * cx),
            T::of(bx * ay - by * ax),
        );
    }
    (u, vv, w)
}

/// Möller–Trumbore. Hits with tmin < t < tmax.
#[inline]
pub fn moller<T: Real>(o: V3<T>, d: V3<T>, v: &[V3<T>; 3], tmin: T, tmax: T) -> Option<TriHit<T>> {
    let e1 = sub(v[1], v[0]);
    let e2 = sub(v[2], v[0]);
    let p = cross(d, e2);
    let det = dot(e1, p);
    if det == T::zero() {
        return None;
    }
    let inv = T::one() / det;
    let s = sub(o, v[0]);
    let b1 = dot(s, p) * inv;
    if !(b1 >= T::zero() && b1 <= T::one()) {
        return None;
    }
    let q = cross(s, e1);
    let b2 = dot(d, q) * inv;
    if !(b2 >= T::zero() && b1 + b2 <= T::one()) {
        return None;
    }
    let t = dot(e2, q) * inv;
    if !(t > tmin && t < tmax) {
        return None;
    }
    Some((t, b1, b2))
}

/// The lecture's method: solve [−d, e1, e2]·(t, b1, b2)ᵀ = o − v0 through A⁻¹ (adjugate over
/// determinant, as glm::inverse does). Hits with tmin < t < tmax.
#[inline]
pub fn cramer<T: Real>(o: V3<T>, d: V3<T>, v: &[V3<T>; 3], tmin: T, tmax: T) -> Option<TriHit<T>> {
    let e1 = sub(v[1], v[0]);
    let e2 = sub(v[2], v[0]);
    let nd = [-d[0], -d[1], -d[2]];
    // Columns of A: nd, e1, e2. Rows of A⁻¹ are the cross products of column pairs / det.
    let r0 = cross(e1, e2);
    let r1 = cross(e2, nd);
    let r2 = cross(nd, e1);
    let det = dot(nd, r0);
    if det == T::zero() {
        return None;
    }
    let inv = T::one() / det;
    let r0 = [r0[0] * inv, r0[1] * inv, r0[2] * inv];
    let r1 = [r1[0] * inv, r1[1] * inv, r1[2] * inv];
    let r2 = [r2[0] * inv, r2[1] * inv, r2[2] * inv];
    let b = sub(o, v[0]);
    let t = dot(r0, b);
    let b1 = dot(r1, b);
    let b2 = dot(r2, b);
    let zero = T::zero();
    if !(b1 >= zero && b2 >= zero && b1 + b2 <= T::one()) {
        return None;
    }
    if !(t > tmin && t < tmax) {
        return None;
    }
    Some((t, b1, b2))
}

/// A triangle v₀, v₁, v₂ (closed, two-sided): the shape of [`Shape::Triangle`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Triangle<T: Real = f32>(pub [V3<T>; 3]);

impl<T: Real> Triangle<T> {
    /// The vertices in f64 (exact).
    #[inline]
    fn wide(&self) -> [[f64; 3]; 3] {
        self.0.map(|p| p.map(Real::f64))
    }
}

impl<T: Real> Primitive<T> for Triangle<T> {
    const KEYWORD: &'static str = "tri";
    const KIND: u8 = 0;

    /// Nine numbers: the three vertices.
    fn read(words: &[&str], frame: &impl SceneFrame<T>) -> Result<Self, String> {
        // (Checked for their count and finiteness; `point` reads each vertex in `T`.)
        frame.numbers(words, 9, Self::KEYWORD)?;
        let [a, b, c] = [0, 1, 2].map(|i| frame.point(&words[3 * i..]));
        Ok(Triangle([a?, b?, c?]))
    }

    fn numbers(&self) -> impl Iterator<Item = T> {
        self.0.into_iter().flatten()
    }

    fn extent(&self) -> f64 {
        (self.0.iter().flatten()).fold(0.0f64, |m, x| m.max(x.f64().abs()))
    }

    fn bounds(&self) -> (V3<T>, V3<T>) {
        let v = &self.0;
        let mut lo = v[0];
        let mut hi = v[0];
        for p in &v[1..] {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        (lo, hi)
    }

    /// Exact where its numbers are f32.
    fn box_f32(&self) -> ([f32; 3], [f32; 3]) {
        let (lo, hi) = self.bounds();
        (
            lo.map(|x| round_down(x.f64())),
            hi.map(|x| round_up(x.f64())),
        )
    }

    fn triangle(&self) -> Option<&[V3<T>; 3]> {
        Some(&self.0)
    }

    /// None: the packets prepare triangles their own way (`accel::frame::OriginTriangle`).
    fn seen_from(&self, _o: [f64; 3]) -> Option<sphere::FromOrigin> {
        None
    }

    fn is_degenerate(&self) -> bool {
        zero_area(&self.0)
    }

    #[inline]
    fn intersect(&self, ray: &Ray<T>, method: Method, tmin: T, tmax: T) -> Option<(T, T, T)> {
        let v = &self.0;
        let hit = match method {
            Method::Adaptive => unreachable!("Shape::intersect answers the adaptive method"),
            Method::Watertight => watertight(ray.o, ray.d, v, tmin, tmax),
            Method::Moller => moller(ray.o, ray.d, v, tmin, tmax),
            Method::Cramer => cramer(ray.o, ray.d, v, tmin, tmax),
        };
        // A triangle of zero area is never hit (decided only for a hit: rare).
        hit.filter(|_| !zero_area(v))
    }

    /// e₁ × e₂ (wherever the ray meets the plane).
    fn normal_at(&self, _ray: &Ray<T>, _t: T) -> [f64; 3] {
        let v = self.wide();
        let e1 = [0, 1, 2].map(|k| v[1][k] - v[0][k]);
        let e2 = [0, 1, 2].map(|k| v[2][k] - v[0][k]);
        [
            e1[1] * e2[2] - e1[2] * e2[1],
            e1[2] * e2[0] - e1[0] * e2[2],
            e1[0] * e2[1] - e1[1] * e2[0],
        ]
    }

    /// No inside.
    fn outside(&self, _p: V3<T>) -> Option<bool> {
        None
    }

    /// Always: the segment ends on the light's side of the plane, and a plane is crossed once.
    fn shadow_clear_of_itself(&self, _light: V3<T>, _end_outside: bool) -> bool {
        true
    }

    /// The vertices interpolated with the barycentrics b̃ᵢ = ẽᵢ/S̃ of the triangle prepared for
    /// the ray's origin (`OriginTriangle`, what the camera packets compute), clamped into
    /// the triangle (the centroid where they are not finite): `shading_points`, which the
    /// renderer's packets run too, so every path shades a pixel to the same bits. The point
    /// lies on the triangle's plane within γ(7)·Σ|bᵢ·vᵢ| + 8·2⁻¹⁴⁹ (`p_error`) whatever the
    /// bᵢ's own error.
    ///
    /// `hit_error`: with ẽᵢ the edge functions, |ẽᵢ − eᵢ| ≤ Bᵢ by
    /// `OriginTriangle::edge_bounds`, S̃ = fl(ẽ₀ + ẽ₁ + ẽ₂), and the exact barycentrics
    /// bᵢ = eᵢ/S of a ray that hits the triangle (all in [0, 1]),
    /// |ẽᵢ/S̃ − bᵢ| = |(ẽᵢ − eᵢ) + bᵢ·(S − S̃)|/|S̃| ≤ (Bᵢ + B_S)/|S̃| with
    /// B_S = ΣBⱼ + γ₂·Σ|ẽⱼ|, plus γ₂ for the division; clamping b₁ into [0, 1] keeps that
    /// bound (Δ₁), clamping b₂ into [0, 1 − b₁] gives Δ₂ = max(its own, Δ₁ + u) (each Δ at
    /// most 1 + 2u: every weight lies in [0, 1]), and b̃₀ = fl(fl(1 − b̃₁) − b̃₂) =
    /// 1 − b̃₁ − b̃₂ + η, |η| ≤ u. As the exact weights sum to 1 too, Σ(b̃ᵢ − bᵢ)·vᵢ =
    /// (b̃₁ − b₁)·(v₁ − v₀) + (b̃₂ − b₂)·(v₂ − v₀) + η·v₀, so
    /// |pₖ − xₖ| ≤ Δ₁·|v₁ₖ − v₀ₖ| + Δ₂·|v₂ₖ − v₀ₖ| + u·|v₀ₖ| + `p_error`ₖ (the interpolation's
    /// own rounding): the weights' error scales with the triangle's size, not its distance.
    /// Large where the ray grazes the triangle (S small against the Bᵢ): the point is then
    /// still on the plane within `p_error`, but anywhere on the triangle within `hit_error`.
    fn surface_point(&self, ray: &Ray<f32>) -> SurfacePoint {
        let v = self.0.map(|p| p.map(|x| x.f64() as f32));
        // (The primitive's index is no part of the edge functions.)
        let tri = OriginTriangle::new(&v, ray.o, u32::MAX);
        surface_point_prepared(&tri, &v, unit_normal(&v), ray.d)
    }

    fn terms(&self, ray: &Ray<T>) -> ShapeTerms {
        let o = ray.o.map(Real::f64);
        let d = ray.d.map(Real::f64);
        let v = self.wide();
        let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
        let (e1, e2) = (sub(v[1], v[0]), sub(v[2], v[0]));
        let b = sub(o, v[0]);
        let a = [0, 1, 2].map(|r| [-d[r], e1[r], e2[r]]);
        ShapeTerms::Triangle(Terms {
            a,
            b,
            x: solve3(&a, b),
        })
    }

    fn locate(&self, ray: &Ray<T>) -> super::Location {
        let (o, d) = (ray.o.map(Real::f64), ray.d.map(Real::f64));
        super::Location::Triangle(locate(&self.wide(), o, d))
    }

    fn widen(&self) -> Shape<f64> {
        Shape::Triangle(Triangle(self.wide()))
    }

    /// The watertight test in f32 with pbrt's t bound (the inputs f32, the vertices too).
    fn f32_filter(&self, o: [f32; 3], d: [f32; 3]) -> Option<Estimate> {
        let v = self.0.map(|p| p.map(|x| x.f64() as f32));
        Some(precise_f32(o, d, &v))
    }

    /// The signs of det[d, pᵢ, pⱼ] and t in f64 with a proved bound, else in f64 intervals
    /// (t's range is the search's business, but for an origin in the plane: a miss where
    /// t = 0 lies outside the range).
    fn f64_intervals(&self, o: [f64; 3], d: [f64; 3], tmin: f64, tmax: f64) -> Estimate {
        triangle_level2(o, d, &self.wide(), (tmin, tmax))
    }

    /// Exact edge signs (expansions, or rationals where those cannot be used), which edge or
    /// vertex the line passes through, and t as an interval (t's range is the search's
    /// business).
    fn decide_exactly(&self, o: [f64; 3], d: [f64; 3], _tmin: f64, _tmax: f64) -> Option<Decided> {
        const EDGES: [(usize, usize); 3] = [(1, 2), (2, 0), (0, 1)];
        let v = self.wide();
        let s = EDGES.map(|(i, j)| {
            exact::orient(d, o, v[i], v[j])
                .unwrap_or_else(|| exact::orient_rational(d, o, v[i], v[j]))
        });
        let mixed = s.contains(&Ordering::Less) && s.contains(&Ordering::Greater);
        let zeros: Vec<usize> = (0..3).filter(|&k| s[k] == Ordering::Equal).collect();
        if mixed || zeros.len() == 3 {
            return None;
        }
        let point = match zeros[..] {
            [] => Feature::Interior,
            [k] => {
                let (i, j) = EDGES[k];
                let mut e = [v[i], v[j]];
                e.sort_by(|a, b| {
                    a.iter()
                        .zip(b)
                        .fold(Ordering::Equal, |o, (x, y)| o.then(x.total_cmp(y)))
                });
                Feature::Edge(e)
            }
            // Two edges through the line: it passes through the vertex they share (the one
            // opposite the third edge).
            _ => Feature::Vertex(v[3 - zeros[0] - zeros[1]]),
        };
        let (t, b1, b2) = triangle_t_interval(o, d, &v);
        Some(Decided {
            t,
            point,
            exact: None,
            b1,
            b2,
        })
    }

    /// t at the plane, exactly.
    fn exact_t(&self, o: [f64; 3], d: [f64; 3], _tmin: f64, _tmax: f64) -> Option<ExactT> {
        exact::plane_t(o, d, &self.wide())
    }

    /// Two hits on one plane are at the same t (the line crosses it once: a line in the plane
    /// misses). Deciding that from three exact orientations spares the rational t's, which
    /// made a ray through 10⁴ overlapping coplanar faces cost 10⁴ big-number divisions.
    fn same_t(&self, other: &Shape<T>) -> bool {
        other.triangle().is_some_and(|q| {
            let (p, q) = (self.wide(), q.map(|x| x.map(Real::f64)));
            same_vertices(&p, &q) || coplanar(&p, &q)
        })
    }

    /// t at the plane in plain f64 with a proved bound (`plane_t_f64`).
    fn t_in_f64(&self, o: [f64; 3], d: [f64; 3], _tmin: f64, _tmax: f64) -> Option<(f64, f64)> {
        plane_t_f64(o, d, &self.wide()).map(|(t, err)| (t - err, t + err))
    }

    /// t at the plane, correctly rounded ([`exact::plane_t_rounded`]).
    fn t_rounded<R: Real>(&self, o: [f64; 3], d: [f64; 3], _tmin: f64, _tmax: f64) -> Option<R> {
        exact::plane_t_rounded(o, d, &self.wide())
    }
}

/// Whether triangle `q` lies exactly in the plane of triangle `p` (false where the exact test
/// cannot be made with expansions: the caller then compares exact t's).
fn coplanar(p: &[[f64; 3]; 3], q: &[[f64; 3]; 3]) -> bool {
    q.iter()
        .all(|x| exact::plane_side_f64(p, *x) == Some(Ordering::Equal))
}

/// Whether two triangles have the same three vertices (in any order).
fn same_vertices(p: &[[f64; 3]; 3], q: &[[f64; 3]; 3]) -> bool {
    p.iter().all(|a| q.contains(a)) && q.iter().all(|a| p.contains(a))
}

/// x = A⁻¹·b by Cramer's rule in f64 (NaN where A is singular).
fn solve3(a: &[[f64; 3]; 3], b: [f64; 3]) -> [f64; 3] {
    let det = |m: &[[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let d = det(a);
    [0, 1, 2].map(|col| {
        let mut m = *a;
        for (r, row) in m.iter_mut().enumerate() {
            row[col] = b[r];
        }
        det(&m) / d
    })
}

/// A triangle's edges, in the order of [`Location`]'s edge numbers: edge k runs from vertex k
/// to vertex k + 1.
pub const EDGES: [&str; 3] = ["v0–v1", "v1–v2", "v2–v0"];

/// Where a ray's line meets a triangle ([`Primitive::locate`]), from the exact signs of its
/// Plücker products with the three edges ([`exact::orient`]): what the ray inspector says of
/// a crack, where a leak on a shared edge is a ray exactly through the edge or within
/// rounding of it.
#[derive(Clone, Debug, PartialEq)]
pub enum Location {
    /// Strictly inside; `nearest` is the edge it passes closest to, `weight` the barycentric
    /// weight of the vertex opposite it (an f64 estimate, for showing only: the decision is
    /// exact).
    Inside { nearest: usize, weight: f64 },
    /// Exactly on edge k (not at its ends).
    Edge(usize),
    /// Exactly at vertex k.
    Vertex(usize),
    /// Outside: beyond these edges.
    Outside(Vec<usize>),
    /// The ray is parallel to the triangle's plane (edge-on: missed).
    EdgeOn,
}

/// The line o + t·d against the triangle `v`.
fn locate(v: &[[f64; 3]; 3], o: [f64; 3], d: [f64; 3]) -> Location {
    // The exact sign of det[d, a − o, b − o].
    let side =
        |o, a, b| exact::orient(d, o, a, b).unwrap_or_else(|| exact::orient_rational(d, o, a, b));
    // The sign every edge has for a line through the inside: that of d·((v1 − v0) × (v2 − v0))
    // (the three edges' products sum to it).
    let inside = side(v[0], v[1], v[2]);
    if inside == Ordering::Equal {
        return Location::EdgeOn;
    }
    let signs = [0, 1, 2].map(|k| side(o, v[k], v[(k + 1) % 3]));
    let beyond: Vec<usize> = (0..3).filter(|&k| signs[k] == inside.reverse()).collect();
    if !beyond.is_empty() {
        return Location::Outside(beyond);
    }
    let zeros: Vec<usize> = (0..3).filter(|&k| signs[k] == Ordering::Equal).collect();
    match zeros[..] {
        [] => {
            // The same determinants in plain f64, for showing sizes only; in rationals where
            // f64's lies within 2¹⁰ times its rounding (a weight of 1.2e-17 showed as 0 and
            // -0; from there f64's is good to 0.1%).
            let norm = |x: [f64; 3]| dot(x, x).sqrt();
            let values = [0, 1, 2].map(|k| {
                let (a, b) = (v[k], v[(k + 1) % 3]);
                let (p, q) = (sub(a, o), sub(b, o));
                let value = dot(d, cross(p, q));
                let rounding =
                    8.0 * f64::EPSILON * norm(d) * (norm(a) + norm(o)) * (norm(b) + norm(o));
                match value.abs() <= 1024.0 * rounding {
                    true => exact::orient_value(d, o, a, b),
                    false => value,
                }
            });
            let total: f64 = values.iter().sum();
            let weights = values.map(|x| x / total);
            let nearest = (0..3)
                .min_by(|&a, &b| weights[a].total_cmp(&weights[b]))
                .expect("three edges");
            Location::Inside {
                nearest,
                weight: weights[nearest],
            }
        }
        [k] => Location::Edge(k),
        // Edges i and j meet at their shared vertex.
        [i, j] => Location::Vertex(if j == (i + 1) % 3 { j } else { i }),
        _ => Location::EdgeOn,
    }
}

impl std::fmt::Display for Location {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        match self {
            Location::Inside { nearest, weight } => write!(
                f,
                "inside (nearest the edge {}: barycentric {weight:.1e})",
                EDGES[*nearest]
            ),
            Location::Edge(k) => write!(f, "on the edge {}", EDGES[*k]),
            Location::Vertex(k) => write!(f, "at vertex v{k}"),
            Location::Outside(edges) => {
                let names: Vec<&str> = edges.iter().map(|&k| EDGES[k]).collect();
                match names[..] {
                    [one] => write!(f, "outside, beyond the edge {one}"),
                    _ => write!(f, "outside, beyond the edges {}", names.join(" and ")),
                }
            }
            Location::EdgeOn => f.write_str("edge-on (the ray is parallel to its plane)"),
        }
    }
}

fn v3(v: [f64; 3]) -> String {
    format!("{} {} {}", v[0], v[1], v[2])
}

/// The lecture's linear system A·x = b for o + t·d = v₀ + u·e₁ + v·e₂: A = [−d e₁ e₂] (rows
/// here), b = o − v₀, x = (t, u, v) = A⁻¹·b.
#[derive(Clone, Debug, PartialEq)]
pub struct Terms {
    pub a: [[f64; 3]; 3],
    pub b: [f64; 3],
    pub x: [f64; 3],
}

impl WordedTerms for Terms {
    fn lines(&self) -> Vec<String> {
        let mut lines = vec!["shape: triangle".to_string()];
        let rows = self.a.iter().enumerate();
        lines.extend(rows.map(|(r, row)| format!("A_row{r}: {}", v3(*row))));
        lines.push(format!("b: {}", v3(self.b)));
        lines.push(format!("x_tuv: {}", v3(self.x)));
        lines
    }

    fn rows(&self, v3: &dyn Fn([f64; 3]) -> String) -> Vec<(&'static str, String)> {
        vec![
            ("A = [-d e1 e2]", v3(self.a[0])),
            ("", v3(self.a[1])),
            ("", v3(self.a[2])),
            ("b = o - v0", v3(self.b)),
            ("x = A^-1 b = (t,u,v)", v3(self.x)),
        ]
    }
}
