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

use crate::math::real::{cross, dot, sub, V3};
use crate::math::Real;

/// Whether the triangle has zero area (its vertices on one line, or coincident), decided
/// exactly ([`super::exact::zero_area`]). Such a triangle is no surface: no method hits it,
/// whatever its rounding would give (the watertight test's shear can leave it a sliver).
pub fn zero_area<T: Real>(v: &[V3<T>; 3]) -> bool {
    super::exact::zero_area(&v.map(|p| p.map(Real::f64)))
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
#[inline]
pub fn t_error_bound<T: Real>(p: &[[T; 3]; 3], sz: T, e: [T; 3], rcp: T) -> T {
    let max3 = |a: T, b: T, c: T| a.abs().max(b.abs()).max(c.abs());
    let max_z = max3(p[0][2], p[1][2], p[2][2]);
    let max_zt = max_z * sz.abs();
    let max_xt = max3(p[0][0], p[1][0], p[2][0]);
    let max_yt = max3(p[0][1], p[1][1], p[2][1]);
    let delta_z = T::error_gamma(3) * max_zt;
    let delta_x = T::error_gamma(5) * (max_xt + max_z);
    let delta_y = T::error_gamma(5) * (max_yt + max_z);
    let two = T::one() + T::one();
    let three = two + T::one();
    let delta_e = two * (T::error_gamma(2) * max_xt * max_yt + delta_y * max_xt + delta_x * max_yt);
    let max_e = max3(e[0], e[1], e[2]);
    three * (T::error_gamma(3) * max_e * max_zt + delta_e * max_zt + delta_z * max_e) * rcp.abs()
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
