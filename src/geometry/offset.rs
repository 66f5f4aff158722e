//! Hit points with a conservative bound on their rounding error, and ray origins offset by that
//! bound (pbrt-v4 §6.8.6), so a secondary ray can never re-hit the surface it leaves: the offset
//! origin lies strictly on the outgoing side of every point the computed hit point may stand for.

use super::{adaptive, sphere, Ray, Shape};
use crate::math::lanes::f64x4;
use crate::math::real::{abs, add, dot, scale, sub, V3};
use crate::math::Real;

/// The absolute part of a surface point's error bound: its roundings below f32's normal
/// range (2⁻¹⁵⁰ each at most), with room to spare.
pub const UNDERFLOW: f32 = 8.0 * f32::from_bits(1);

/// A surface point with its error bounds and unit geometric normal.
///
/// Two bounds, per axis, both conservative: `p_error` bounds p's distance from the surface
/// (the box p ± `p_error` holds a point of the exact primitive: the offset of a secondary
/// ray's origin needs only this), `hit_error` its distance from the exact hit point x of the
/// ray that found it (|pₖ − xₖ| ≤ `hit_error`ₖ: what shading at p rather than at x may be off
/// by). `tests/shading_point.rs` checks both against exact rational points on the hard-case
/// suite.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfacePoint {
    /// The computed point.
    pub p: V3<f32>,
    /// Per-axis bound on the distance from p to the primitive's surface.
    pub p_error: V3<f32>,
    /// Per-axis bound on |p − exact hit point|.
    pub hit_error: V3<f32>,
    /// Unit geometric normal (for a triangle, along (v1 − v0) × (v2 − v0)).
    pub n: V3<f32>,
}

impl SurfacePoint {
    /// Where `ray`'s hit on `shape` is shaded, for a shape other than a triangle (`None` for a
    /// triangle, whose point the renderer takes from its packet shading): for a sphere, its
    /// f64 interval root's midpoint (or the correctly rounded t where the interval cannot
    /// decide) re-projected by [`SurfacePoint::on_sphere`].
    pub fn on_curved(shape: &Shape<f32>, ray: &Ray<f32>) -> Option<Self> {
        let Shape::Sphere { centre, radius } = *shape else {
            return None;
        };
        let (o, d) = (ray.o.map(f64::from), ray.d.map(f64::from));
        let (c, r) = (centre.map(f64::from), f64::from(radius));
        let from = sphere::FromOrigin::new(o, c, r);
        let root = sphere::interval_x4(&from, &d.map(f64x4::splat), 0.0, f64::INFINITY);
        let (t, t_error) = match root.hit.to_bitmask() & 1 {
            1 => {
                let (lo, hi) = (root.lo.to_array()[0], root.hi.to_array()[0]);
                let t = (0.5 * lo + 0.5 * hi) as f32;
                let off = (f64::from(t) - lo).max(hi - f64::from(t));
                (t, (off * (1.0 + 1e-6)) as f32 + f32::from_bits(1))
            }
            _ => {
                let t = adaptive::rounded_t(shape, ray, 0.0, f32::INFINITY);
                let t = t.unwrap_or(f32::NAN);
                (t, t.abs() * f32::EPSILON / 2.0 + f32::from_bits(1))
            }
        };
        Some(Self::on_sphere(centre, radius, ray, t, t_error))
    }

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

/// Unit vector along `v` (returns `v` unchanged if it is zero). Where |v|² overflows or
/// underflows f32 (a face's cross product beyond about 1.8e19 or below 1e-19: edges of a few
/// 1e9 or 1e-10 units), `v` is first divided by its largest component.
pub fn normalize(v: V3<f32>) -> V3<f32> {
    let len2 = dot(v, v);
    if len2.is_finite() && len2 >= f32::MIN_POSITIVE {
        return scale(v, 1.0 / len2.sqrt());
    }
    let largest = v[0].abs().max(v[1].abs()).max(v[2].abs());
    if !(largest > 0.0 && largest.is_finite()) {
        return v;
    }
    let u = v.map(|c| c / largest);
    scale(u, 1.0 / dot(u, u).sqrt())
}

/// Moves `p` along the unit normal `n` by the error bound projected on `n`, to the side of
/// direction `w`, then one ulp further away, as pbrt-v4 `OffsetRayOrigin` does.
pub fn offset_ray_origin<T: Real>(p: V3<T>, p_error: V3<T>, n: V3<T>, w: V3<T>) -> V3<T> {
    let d = dot(abs(n), p_error);
    let mut offset = scale(n, d);
    if dot(w, n) < T::zero() {
        offset = scale(offset, -T::one());
    }
    let mut po = add(p, offset);
    for k in 0..3 {
        if offset[k] > T::zero() {
            po[k] = po[k].up();
        } else if offset[k] < T::zero() {
            po[k] = po[k].down();
        }
    }
    po
}
