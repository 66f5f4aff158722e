//! The adaptive method's fast paths for the renderer: camera rays in packets of 8 against
//! triangles prepared for the camera's position ([`closest`]; per ray in BVH leaves:
//! [`OriginTriangle::estimate`]), and shadow rays from the light in packets of 8
//! ([`any`]: the same test for the light's position).
//!
//! All camera rays of a frame leave the same origin o. With pᵢ = vᵢ − o, the exact
//! predicates of the adaptive method are the signs of eᵢ = d·(pⱼ × pₖ) ((i, j, k) cyclic; eᵢ
//! weighs vertex i) and t = det[p₀, p₁, p₂] / (e₀ + e₁ + e₂). The cross products and the
//! determinant depend on the triangle alone, so they are computed once per frame with bounds
//! on their error: in f64 for a frame's lists ([`OriginTriangles::new`]), in f32 for a BVH's
//! leaves (`OriginTriangle::new8`, bounds about twice as loose; a triangle those leave
//! undecided for a live lane is prepared again in f64, [`PacketNearest::offer_decided`]);
//! per ray and triangle there remain three f32 dot products, whose rounding error is at most
//! Kᵢ·max|dₖ| with Kᵢ fixed per triangle. An eᵢ beyond that bound has a certain sign, t
//! comes with a certain interval, and a lane keeps the nearest candidate only while its
//! interval lies wholly below the others'. Every lane that cannot be decided so (a ray
//! within rounding of an edge, two hits too close to order, a degenerate case) is reported
//! `ambiguous`, and the caller traces it with the per-ray adaptive search, which decides
//! exactly. So a decided lane's primitive is exactly the one the per-ray search returns.
//!
//! The files: `prepare.rs` prepares triangles for one origin in f64, one or four at a time
//! ([`OriginTriangle::new`], `PreciseTriangle`, the frame's lists [`OriginTriangles`]);
//! `block.rs` eight at a time in f32 for the leaves of a hierarchy (`OriginBlock`);
//! `predicates.rs` holds the edge tests and t intervals the queries share;
//! `nearest.rs` the nearest hit of a packet ([`PacketNearest`], [`closest`]); `shadow.rs` the
//! shadow rays' test ([`ShadowPacket`], [`any`]); `exact_lane.rs` the exact
//! answers for the lanes a packet leaves ambiguous ([`closest_exact_lane`],
//! [`any_exact_lane`]). This file keeps the bounds' constants and the prepared triangle
//! itself, whose fields every file reads.

mod block;
mod exact_lane;
mod nearest;
mod predicates;
mod prepare;
mod shadow;
mod sink;
#[cfg(feature = "unit-tests")]
#[deny(dead_code)]
pub(crate) mod tests;

pub(crate) use block::{BlockIds, OriginBlock, TriangleLanes};
pub use exact_lane::{any_exact_lane, closest_exact_lane};
pub use nearest::{closest, PacketHits, PacketNearest, PacketSeed};
pub(crate) use nearest::{closest_in, closest_seeded_in};
pub use predicates::max_component;
pub(crate) use predicates::max_component_in;
pub use prepare::OriginTriangles;
pub(crate) use prepare::{quad_indices, PreciseTriangle};
pub(crate) use shadow::any_in;
pub use shadow::{any, ShadowHits, ShadowPacket};
pub(crate) use sink::{PacketLimits, PacketSink};

use std::ops::{Mul, Sub};

/// Unit roundoff of f32 and f64.
const U32: f64 = 1.0 / (1u64 << 24) as f64;
const U64: f64 = 1.0 / (1u64 << 53) as f64;

/// Largest |nₖ| sum (and |det|) prepared: larger ones make every ray ambiguous.
const MAX_MAGNITUDE: f64 = 1e36;

/// Absolute slack of the f64 bounds ([`PreciseTriangle`]): products in f64's subnormal range
/// and the bounds' own roundings there (far below any value they decide).
const TINY64: f64 = 1e-300;

/// Largest max|dₖ|·Σ|nₖ| a packet may reach (far from f32 overflow).
const MAX_PRODUCT: f32 = 1e37;

/// Absolute part of each edge bound: the dot product's products in the subnormal range
/// (2^-150 each) and the rounding of Kᵢ·max|d| there.
const EDGE_ABS: f32 = 1e-44;

/// One triangle seen from the shared origin.
#[derive(Clone, Copy, Debug)]
pub struct OriginTriangle {
    /// nᵢ = pⱼ × pₖ rounded to f32, so that eᵢ = d·nᵢ.
    n: [[f32; 3]; 3],
    /// Kᵢ: |computed eᵢ − exact eᵢ| ≤ Kᵢ·max|dₖ| + [`EDGE_ABS`] (rounding up included).
    k: [f32; 3],
    /// K₀ + K₁ + K₂.
    k_sum: f32,
    /// Whether t's determinant is taken as d·normal (bound `k_det`) rather than as
    /// e₀ + e₁ + e₂ (bound `k_sum`): where the sum's bound is the looser by more than 4×,
    /// a small triangle far from the origin (see [`t_interval`]).
    ///
    /// [`t_interval`]: predicates::t_interval
    det_from_normal: bool,
    /// The largest Σₖ|nᵢₖ|, for the overflow check.
    n_max: f32,
    /// det[p₀, p₁, p₂] rounded to f32 (its sign is certain).
    num: f32,
    /// Relative error coefficient of t apart from the determinant's part.
    c_t: f32,
    /// The normal (v₁ − v₀) × (v₂ − v₀) rounded to f32: d·n is the determinant of t without
    /// the cancellation of e₀ + e₁ + e₂ (for a small triangle far from the origin the eᵢ are
    /// large and their sum small).
    normal: [f32; 3],
    /// |computed d·normal − exact| ≤ k_det·max|dₖ| + [`EDGE_ABS`].
    k_det: f32,
    /// Primitive index in the scene.
    pub prim: u32,
    /// False where the bounds cannot be used (the origin within rounding of the triangle's
    /// plane, huge magnitudes, non-finite input): every ray is then ambiguous.
    usable: bool,
    /// The origin lies exactly in the triangle's plane (found exactly where `usable` is
    /// false): a ray from it meets the plane at t = 0 or lies in it, so no packet (t > 0)
    /// meets the triangle. (A camera on the floor, a light on the ceiling: before, every
    /// packet that reached such a triangle went per ray to exact arithmetic, ~1,000× slower.)
    in_plane: bool,
}

/// a − b, for the preparations' f64, f64-lane and f32-lane arithmetic alike (always inlined:
/// in the AVX2 kernels a call would leave the lane operations as calls too).
#[inline(always)]
fn sub<T: Copy + Sub<Output = T>>(a: [T; 3], b: [T; 3]) -> [T; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// a × b, as [`sub`].
#[inline(always)]
fn cross<T: Copy + Sub<Output = T> + Mul<Output = T>>(a: [T; 3], b: [T; 3]) -> [T; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
