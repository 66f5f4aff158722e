//! Exact decisions in rational arithmetic: the last level of the adaptive method, reached only
//! when f64 intervals cannot decide (a ray exactly through an edge or vertex, two surfaces at
//! exactly the same t, an origin exactly on a sphere). Every float input is an exact rational,
//! so the answers here are the mathematically exact ones.
//!
//! The common exact question, which side of an edge a ray passes (the sign of det[d, a − o,
//! b − o]), is answered with Shewchuk's floating-point expansions ([`orient`]): exact, and
//! fast enough for the columns of pixels whose rays run exactly through a box's edges.
//! Everything else, rarer still, uses big rationals: a ray parameter is held as
//! t = a + b·√s (b = 0 for triangles; spheres have irrational roots), and compared by the
//! sign of sums of such terms (squaring only where the signs differ, so nothing is rounded).
//!
//! The files: `rational.rs` holds the big rationals (`Q`, the exact ray parameter
//! [`ExactT`], its comparisons and its correct rounding); `expansion.rs` the floating-point
//! expansions and [`orient`]; `triangle.rs` the exact questions about a triangle (whether it
//! has zero area, by an f64 filter and then expansions, [`zero_area`]; which side of an edge
//! in rationals, which side of its plane, t at its plane, exact or correctly rounded);
//! `tests.rs` their tests. A sphere's exact level is with the sphere
//! (`geometry::sphere::exact`).

mod expansion;
mod rational;
#[cfg(feature = "unit-tests")]
#[deny(dead_code)]
pub(crate) mod tests;
mod triangle;

pub use expansion::{orient, two_sum};
pub use rational::ExactT;
#[cfg(feature = "unit-tests")]
pub(crate) use rational::QV;
pub(crate) use rational::{dot, q, qv, sub, Q};
pub use triangle::{
    on_plane, orient_rational, orient_value, plane_side, plane_side_f64, plane_t, plane_t_rounded,
    zero_area, zero_area_contact,
};
