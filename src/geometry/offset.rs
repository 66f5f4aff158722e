//! Hit points with a conservative bound on their rounding error, and ray origins offset by that
//! bound (pbrt-v4 §6.8.6), so a secondary ray can never re-hit the surface it leaves: the offset
//! origin lies strictly on the outgoing side of every point the computed hit point may stand for.
//! Each shape makes its own points ([`Primitive::surface_point`](super::Primitive::surface_point)).

use crate::math::real::{abs, add, dot, scale, V3};
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
/// by). `tests/library/shading_point.rs` checks both against exact rational points on the hard-case
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
