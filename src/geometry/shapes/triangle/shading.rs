//! A triangle's shading point as the renderer takes it: the barycentrics of the triangle
//! prepared for the ray's origin (`OriginTriangle`, as the camera packets compute them),
//! lanes at a time ([`shading_points`]) or for one ray, with the point's bounds
//! ([`surface_point_prepared`]), and the unit normal ([`unit_normal`]).

use crate::accel::OriginTriangle;
use crate::geometry::offset::{normalize, UNDERFLOW};
use crate::geometry::SurfacePoint;
use crate::math::lanes::Lanes;
use crate::math::real::{cross, dot, sub};
use crate::math::simd::{avx512_avx2_or_baseline, each3};
use crate::math::Real;

/// The unit geometric normal along (v₁ − v₀) × (v₂ − v₀), as [`SurfacePoint`] has it: in
/// f32, or for a face whose cross product falls below 2⁻⁶⁰ in f64 (edges of 10⁻²⁰ and less:
/// their products underflowed f32, and a face of 10⁻²⁴ had the normal 0 and shaded black).
pub fn unit_normal(v: &[[f32; 3]; 3]) -> [f32; 3] {
    let n = cross(sub(v[1], v[0]), sub(v[2], v[0]));
    let largest = n[0].abs().max(n[1].abs()).max(n[2].abs());
    if largest >= SMALL_NORMAL || largest.is_nan() {
        return normalize(n);
    }
    let w = v.map(|p| p.map(f64::from));
    let n = cross(sub(w[1], w[0]), sub(w[2], w[0]));
    let length = dot(n, n).sqrt();
    match length > 0.0 {
        true => n.map(|c| (c / length) as f32),
        false => [0.0; 3],
    }
}

/// 2⁻⁶⁰: below it a face's cross product is taken in f64 ([`unit_normal`]).
const SMALL_NORMAL: f32 = 1.0 / (1u64 << 60) as f32;

/// The shading points of up to 8 rays (directions `d`, lanes) from the origin a triangle
/// (vertices `v`) was prepared for, with `edge` its edge normals
/// (`OriginTriangle::edge_normals`: eᵢ = d·nᵢ), lanes at a time: p = Σ b̃ᵢ·vᵢ with the
/// barycentrics b̃ᵢ = ẽᵢ/S̃ clamped into the triangle, and its bound on the distance to the
/// triangle's plane ([`SurfacePoint`]'s `p` and `p_error`). The renderer's shading packets
/// and [`Triangle`](super::Triangle)'s [`Primitive::surface_point`](super::Primitive::surface_point) both compute it here.
#[inline(always)]
pub(crate) fn shading_points<V: Lanes>(
    d: &[V; 3],
    edge: &[[V; 3]; 3],
    v: &[[V; 3]; 3],
) -> ([V; 3], [V; 3]) {
    let dot = |a: &[V; 3], b: &[V; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let e = [dot(d, &edge[0]), dot(d, &edge[1]), dot(d, &edge[2])];
    let rcp = V::one() / (e[0] + e[1] + e[2]);
    let (b1, b2) = (e[1] * rcp, e[2] * rcp);
    let inf = V::splat(f32::INFINITY);
    let finite = b1.abs().simd_lt(inf) & b2.abs().simd_lt(inf);
    let third = V::splat(1.0 / 3.0);
    // (No NaN is left for max and min to treat.)
    let b1 = finite
        .bitselect(b1, third)
        .fast_max(V::zero())
        .fast_min(V::one());
    let b2 = finite
        .bitselect(b2, third)
        .fast_max(V::zero())
        .fast_min(V::one() - b1);
    let b0 = (V::one() - b1) - b2;
    let gamma7 = V::splat(f32::error_gamma(7));
    // Below f32's normal range a rounding is absolute (up to 2⁻¹⁵⁰ each, five here).
    let underflow = V::splat(UNDERFLOW);
    let mut p = [V::zero(); 3];
    let mut p_error = [V::zero(); 3];
    for k in 0..3 {
        let (q0, q1, q2) = (v[0][k] * b0, v[1][k] * b1, v[2][k] * b2);
        p[k] = (q0 + q1) + q2;
        p_error[k] = ((q0.abs() + q1.abs()) + q2.abs()) * gamma7 + underflow;
    }
    (p, p_error)
}

/// `shading_points` for one ray (in every lane of the build the CPU runs, as the packets
/// do): its `p` and `p_error`. The one choice of a build inside a frame (per hit shaded per
/// ray, through [`Primitive::surface_point`](super::Primitive::surface_point)): the baseline lanes here, with no choice, made
/// the per-ray methods' shaded frames 12–15% slower (Cornell 640×360, release, AVX-512).
fn shading_point_of_one(
    edge: &[[f32; 3]; 3],
    v: &[[f32; 3]; 3],
    d: [f32; 3],
) -> ([f32; 3], [f32; 3]) {
    avx512_avx2_or_baseline!(lanes shading_point_of_one_body => (
        edge: &[[f32; 3]; 3],
        v: &[[f32; 3]; 3],
        d: [f32; 3]
    ) -> ([f32; 3], [f32; 3]))
}

#[inline(always)]
fn shading_point_of_one_body<V: Lanes>(
    edge: &[[f32; 3]; 3],
    v: &[[f32; 3]; 3],
    d: [f32; 3],
) -> ([f32; 3], [f32; 3]) {
    let splat3 = |x: &[f32; 3]| each3(|k| V::splat(x[k]));
    let (edge, v) = (each3(|i| splat3(&edge[i])), each3(|i| splat3(&v[i])));
    let (p, p_error) = shading_points::<V>(&splat3(&d), &edge, &v);
    let first = |x: &[V; 3]| each3(|k| x[k].to_array()[0]);
    (first(&p), first(&p_error))
}

/// [`Primitive::surface_point`](super::Primitive::surface_point) along `d` on triangle `v` (unit normal `n`) prepared for the
/// ray's origin (`tri`) once a frame, not again for each hit: the same bits.
pub fn surface_point_prepared(
    tri: &OriginTriangle,
    v: &[[f32; 3]; 3],
    n: [f32; 3],
    d: [f32; 3],
) -> SurfacePoint {
    let (p, p_error) = shading_point_of_one(tri.edge_normals(), v, d);
    let hit_error = hit_error(tri, v, d, p_error);
    SurfacePoint {
        p,
        p_error,
        hit_error,
        n,
    }
}

/// [`Triangle`](super::Triangle)'s `hit_error` of its surface point (see [`Primitive::surface_point`](super::Primitive::surface_point) there).
fn hit_error(tri: &OriginTriangle, v: &[[f32; 3]; 3], d: [f32; 3], p_error: [f32; 3]) -> [f32; 3] {
    let u = f64::from(f32::EPSILON) / 2.0;
    let gamma2 = 2.0 * u / (1.0 - 2.0 * u);
    let n = tri.edge_normals();
    let e = n.map(|n| d[0] * n[0] + d[1] * n[1] + d[2] * n[2]);
    let sum = e[0] + e[1] + e[2];
    let rcp = 1.0 / sum;
    let weights_finite = (e[1] * rcp).is_finite() && (e[2] * rcp).is_finite();
    let bounds = tri.edge_bounds(d).map(f64::from);
    let abs_e = e.map(|x| f64::from(x).abs());
    let b_sum = bounds.iter().sum::<f64>() + gamma2 * abs_e.iter().sum::<f64>();
    let s = f64::from(sum).abs();
    let beta = [0, 1, 2].map(|i| {
        ((bounds[i] + b_sum) / s + gamma2 * abs_e[i] / s) * (1.0 + 1e-6) + 2f64.powi(-148)
    });
    let cap = 1.0 + 2.0 * u;
    let (d1, d2) = match weights_finite && beta.iter().all(|b| b.is_finite()) {
        true => {
            let d1 = beta[1].min(cap);
            (d1, beta[2].max(d1 + u).min(cap))
        }
        false => (cap, cap),
    };
    [0, 1, 2].map(|k| {
        let edge = |i: usize| (f64::from(v[i][k]) - f64::from(v[0][k])).abs() * (1.0 + 2.0 * u);
        let along = d1 * edge(1) + d2 * edge(2) + u * f64::from(v[0][k]).abs();
        ((along + f64::from(p_error[k])) * (1.0 + 1e-6)) as f32
    })
}
