//! The adaptive method (the default): the exact answer at nearly the f32 watertight speed.
//!
//! What it guarantees, for any finite inputs: the primitive it returns is exactly the nearest
//! one that the exact ray meets with tmin < t < tmax (closed triangles, a triangle seen
//! edge-on misses; spheres closed, a tangent touch hits), an exact tie going to the lower
//! primitive index; a miss means exactly no such primitive.
//!
//! t comes in two grades. A query returns the t of the level that decided the hit, with that
//! level's bound (the f32 filter: pbrt-v4's bound, doubled; f64 intervals: the interval;
//! the exact level: the exact t correctly rounded): what shading needs, at no extra cost.
//! [`rounded_t`] gives the exact t **correctly rounded** to the caller's precision (the
//! nearest value, ties to even; beyond the range ±∞ and in the subnormal range as IEEE 754
//! rounds) for f32 and f64 alike: `raylab trace` prints it for every path. It costs t in
//! plain f64 with a proved bound where that decides the rounding (f32: nearly always, about
//! half a BVH query) and one exact integer division elsewhere (f64: nearly always, a few µs).
//!
//! Three levels, each consulted only where the one before cannot decide:
//! 1. **f32 filter** ([`classify_f32`]): the watertight test, with a conservative bound `E` on
//!    the rounding error of its edge functions (from the box around the triangles, the ray
//!    origin and the sheared vertices, see [`edge_error`]). An edge function beyond ±E has a
//!    certain sign; t comes with pbrt-v4's bound, doubled. Nearly every ray is decided here.
//! 2. **f64** ([`triangle_f64`], [`triangle_interval`], [`sphere::interval`]): the same
//!    predicates (signs of det[d, pᵢ, pⱼ], t = det[p₀, p₁, p₂] / d·n) on the exact inputs, for
//!    a triangle first in plain f64 with a proved bound (the f64 filter), then where that
//!    cannot tell in outward-rounded interval arithmetic. Decides everything but exact
//!    degeneracies.
//! 3. **Exact rationals** ([`super::exact`]): rays exactly through an edge or a vertex,
//!    exactly equal t's, an origin exactly on a sphere.
//!
//! [`Nearest`] runs the closest-hit search over candidates at whatever level each has
//! reached: two candidates whose t intervals overlap are refined until they separate, or
//! compared exactly.
//!
//! Each shape runs its own levels ([`Primitive`]'s hooks: `f32_filter`, `f64_intervals`,
//! `decide_exactly`, `exact_t`, `same_t`, `t_in_f64`, `t_rounded`), in answers of the kinds in
//! `estimate.rs`; nothing here names a kind of shape.
//!
//! The files: `estimate.rs` holds what a level tells about one primitive ([`Estimate`],
//! [`Approx`], the exact level's [`Decided`]), which the shapes' own levels answer in;
//! `filter.rs` the f32 filter (level 1: [`box_extent`], [`edge_error`], [`classify_f32`], the
//! outward roundings to f32); `interval.rs` a triangle's f64 interval level; `nearest.rs` the
//! search over candidates at any level ([`Nearest`]); `search.rs` the search as the fast
//! paths run it ([`Search`]) and the brute-force reference; `rounded.rs` t correctly rounded
//! ([`rounded_t`]) and a triangle's t in f64 with its bound; `levels.rs` the counts of the
//! slower levels; `tests.rs` the tests of the f64 t bound and of the rounding. This file
//! keeps which level decides a shape ([`deciding_level`]) and a shape in f64 ([`widen`]).
//!
//! [`Primitive`]: crate::geometry::Primitive
//! [`sphere::interval`]: crate::geometry::sphere::interval

pub(super) mod estimate;
mod filter;
pub(crate) mod interval;
pub mod levels;
mod nearest;
pub(crate) mod rounded;
mod search;
#[cfg(feature = "unit-tests")]
#[deny(dead_code)]
pub(crate) mod tests;

pub use estimate::{Approx, Decided, Estimate, Feature};
pub(crate) use filter::precise_f32;
pub use filter::{
    approx_f32, box_extent, classify_f32, edge_error, loose_t_bound, round_down, round_up,
};
pub use interval::{triangle_f64, triangle_interval};
pub use nearest::Nearest;
pub use rounded::rounded_t;
pub use search::{closest_hit_reference, closest_hit_reference_by, Search};

use crate::geometry::{Ray, Shape};
use crate::math::Real;

/// Which level decides whether `ray` meets `shape` at all (the ray inspector shows it):
/// "f32 filter", "f64 filter" (a triangle's), "f64 intervals" or "exact" (the shape's own
/// levels: a sphere has no filter). (Comparing t's with other candidates may need a finer
/// level still; that is the search's business.)
pub fn deciding_level(shape: &Shape<f32>, ray: &Ray<f32>) -> &'static str {
    let (o, d) = (ray.o.map(f64::from), ray.d.map(f64::from));
    let decided = |e: Estimate| e != Estimate::Unsure;
    let f64_filter = |v: &[[f32; 3]; 3]| decided(triangle_f64(o, d, &v.map(|p| p.map(f64::from))));
    if shape.f32_filter(ray.o, ray.d).is_some_and(decided) {
        "f32 filter"
    } else if shape.triangle().is_some_and(f64_filter) {
        "f64 filter"
    } else if decided(shape.f64_intervals(o, d, 0.0, f64::INFINITY)) {
        "f64 intervals"
    } else {
        "exact"
    }
}

/// A shape in f64 (exact for f32 input).
pub fn widen<T: Real>(s: &Shape<T>) -> Shape<f64> {
    s.widen()
}
