//! The f64 geometry of a graded ray that `check`'s hints and the run's evidence share: its
//! origin and direction, a triangle's plane, Möller–Trumbore's determinant, which side the
//! ray meets, and how near two t's are.

use raylab::check::grade::Exact;
use raylab::geometry::Triangle;
use raylab::math::real::{cross, dot, sub};
use raylab::math::Real;

/// Möller–Trumbore's determinant e1·(d × e2) of ray `i` and triangle `tri` (−d·n), in f64.
pub(super) fn determinant<T: Real>(exact: &Exact<T>, i: usize, tri: &Triangle<T>) -> f64 {
    let (_, n) = plane_of(tri);
    -dot(o_and_d(exact, i).1, n)
}

/// Whether ray `i` meets triangle `tri`'s plane from its back (d·n > 0, beyond 10⁻⁶ of |d| |n|).
pub(super) fn faces_back<T: Real>(exact: &Exact<T>, i: usize, tri: &Triangle<T>) -> bool {
    let d = o_and_d(exact, i).1;
    let (_, n) = plane_of(tri);
    dot(d, n) > 1e-6 * length(d) * length(n)
}

/// Whether `x` and `y` agree to 10⁻⁶ of the larger (in f64).
pub(super) fn near(x: f64, y: f64) -> bool {
    (x - y).abs() <= 1e-6 * x.abs().max(y.abs()).max(1e-30)
}

/// A triangle's v0 and its normal n = (v1 − v0) × (v2 − v0), in f64 (d·n > 0: met from its
/// back).
pub(super) fn plane_of<T: Real>(tri: &Triangle<T>) -> ([f64; 3], [f64; 3]) {
    let v = tri.0.map(|p| p.map(|c| c.f64()));
    (v[0], cross(sub(v[1], v[0]), sub(v[2], v[0])))
}

/// Ray `i`'s origin and direction in f64.
pub(super) fn o_and_d<T: Real>(exact: &Exact<T>, i: usize) -> ([f64; 3], [f64; 3]) {
    let ray = &exact.rays[i].1.ray;
    (ray.o.map(|c| c.f64()), ray.d.map(|c| c.f64()))
}

/// |a|.
pub(super) fn length(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}
