//! The f64 geometry of a graded ray that `check`'s hints and the run's evidence share: its
//! origin and direction, a triangle's plane, Möller–Trumbore's determinant (and what a small
//! one loses), which side the ray meets, and how near two t's are.

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

/// Where the exact hit is on a triangle whose Möller–Trumbore determinant e1·(d × e2) (e1 =
/// v1 − v0, e2 = v2 − v0) is not 0 but small, what that loses, as facts: in f32, one below
/// its smallest normal number underflows; one below the rounding of its terms can come out 0
/// or with the other sign; and one below 10⁻⁴ and below every determinant of a hit the
/// program answered right (`smallest_met`: else an epsilon on it would have lost those too)
/// is lost to the textbook's |det| < ε test. (Correct f32 programs were told of the epsilon
/// alone.)
pub(super) fn small_determinant<T: Real>(
    exact: &Exact<T>,
    i: usize,
    prim: u32,
    smallest_met: f64,
) -> Option<String> {
    let raylab::geometry::Shape::Triangle(tri) = exact.shape(prim) else {
        return None;
    };
    let det = determinant(exact, i, &tri);
    let (v, (_, d)) = (tri.0.map(|p| p.map(|c| c.f64())), o_and_d(exact, i));
    let terms = length(sub(v[1], v[0])) * length(d) * length(sub(v[2], v[0]));
    let f32 = T::PRECISION <= 24;
    let underflows = f32 && det.abs() < f32::MIN_POSITIVE as f64;
    let rounds = det.abs() < 3.0 * T::UNIT_ROUNDOFF.f64() * terms;
    let epsilon = det.abs() < 1e-4 && det.abs() < smallest_met;
    let lost = "an epsilon on it (|det| < ε: no hit) loses the hit, where only det = 0 is \
                parallel";
    let why =
        match (underflows, rounds, epsilon) {
            (true, _, _) => format!(
            ", below f32's smallest normal number {:.1e}: in f32 it comes out 0 or without its \
             digits (f64 holds it){}",
            f32::MIN_POSITIVE,
            if epsilon { format!("; and {lost}") } else { String::new() }
        ),
            (false, true, false) => format!(
                ", below the rounding of its terms in {}: rounded, it can come out 0 or with the \
             other sign",
                if f32 { "f32" } else { "f64" }
            ),
            (false, true, true) => format!(
            ", near 0: {lost} (and it is below the rounding of its terms in {}: rounded, it can \
             come out 0 or with the other sign)",
            if f32 { "f32" } else { "f64" }
        ),
            (false, false, true) => format!(", near 0: {lost}"),
            (false, false, false) => return None,
        };
    (det != 0.0).then(|| {
        format!(
            "the triangle's determinant e1·(d × e2) (e1 = v1 − v0, e2 = v2 − v0) is {det:.1e}{why}"
        )
    })
}
