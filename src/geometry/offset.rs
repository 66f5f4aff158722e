//! Hit points with a conservative bound on their rounding error, and ray origins offset by that
//! bound (pbrt-v4 §6.8.6), so a secondary ray can never re-hit the surface it leaves: the offset
//! origin lies strictly on the outgoing side of every point the computed hit point may stand for.

use super::{Hit, Ray, Shape};
use crate::math::real::{abs, add, cross, dot, scale, sub, V3};
use crate::math::Real;

/// A surface point with its error bound and unit geometric normal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfacePoint {
    /// The computed point.
    pub p: V3<f32>,
    /// Per-axis bound on |p − exact point|.
    pub p_error: V3<f32>,
    /// Unit geometric normal (for a triangle, along (v1 − v0) × (v2 − v0)).
    pub n: V3<f32>,
}

impl SurfacePoint {
    /// Builds the hit point of `hit` on `shape` (the shape the hit's `prim` refers to).
    ///
    /// Triangles interpolate the vertices with the barycentrics, which keeps the point on the
    /// triangle's plane to within γ(7)·Σ|bᵢ·vᵢ|; spheres re-project o + t·d onto the surface,
    /// which bounds the error by γ(6)·(|c| + |p − c|).
    pub fn new(shape: &Shape<f32>, ray: &Ray<f32>, hit: &Hit<f32>) -> Self {
        match shape {
            Shape::Triangle(v) => {
                let b0 = 1.0 - hit.b1 - hit.b2;
                let (p0, p1, p2) = (scale(v[0], b0), scale(v[1], hit.b1), scale(v[2], hit.b2));
                let p = add(add(p0, p1), p2);
                let sum = add(add(abs(p0), abs(p1)), abs(p2));
                let p_error = scale(sum, f32::error_gamma(7));
                let n = normalize(cross(sub(v[1], v[0]), sub(v[2], v[0])));
                Self { p, p_error, n }
            }
            Shape::Sphere { centre, radius } => {
                let raw = ray.at(hit.t);
                let rel = sub(raw, *centre);
                let len = dot(rel, rel).sqrt();
                let n = if len > 0.0 {
                    scale(rel, 1.0 / len)
                } else {
                    [0.0, 0.0, 1.0]
                };
                let p = add(*centre, scale(n, *radius));
                let p_error = scale(add(abs(*centre), abs(sub(p, *centre))), f32::error_gamma(6));
                Self { p, p_error, n }
            }
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
