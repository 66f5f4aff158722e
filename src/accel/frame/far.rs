//! When camera packets cost more than rays one at a time: an eye far from a mesh of small
//! triangles.
//!
//! The packets test triangles prepared for the eye, their vertices less the eye in f32
//! (`OriginTriangle`). Those differences are rounded to about 2⁻²⁴ of the eye's distance, and
//! once that is a good part of a triangle's side the f32 bounds decide few lanes: each goes on
//! to the f64 tests, lane by lane. The per-ray walk instead moves the ray in f64 up to the
//! hierarchy's box first (`bvh::approach`), where f32 decides again. The bunny (69,451
//! triangles, sides ~10⁻³ of a 0.15-unit model) filling a 320×180 view, 2 threads, packets
//! against per ray (the cracks view) in Mrays/s: from 100 units 8.4 against 3.9, from 1,000
//! 3.8 against 3.7, from 10⁴ 1.9 against 3.8; Igea (0.1 across, sides ~5·10⁻⁴) from 600 1.94
//! against 1.93. The rule: per ray once the eye's rounding, its farthest distance from the
//! box × 2⁻²⁴, passes [`SIDE_SHARE`] of the triangles' typical side: the bunny (side
//! 1.4·10⁻³) from ~1,500 units, Igea from ~500, sides of 2 units only from ~2·10⁶. Only in
//! frames without shadows: the per-ray tile loop asks their segments per ray too, and from
//! 2,000 units the bunny's shadows frame took 20% longer so.
//! (`tests/library/far_and_grazing.rs` renders such a frame as the per-ray path does.)

use super::Box3;
use crate::accel::IndexedTriangle;

/// The share of a typical triangle side the eye's f32 rounding may reach before camera
/// packets go per ray.
pub(super) const SIDE_SHARE: f64 = 1.0 / 16.0;

/// How many triangles, spread evenly, [`typical_side`] measures at most.
const SAMPLED: usize = 1024;

/// The median of the largest side of the triangles' boxes (of at most [`SAMPLED`] of them,
/// evenly spread): 0 for none.
pub(crate) fn typical_side(tris: &[IndexedTriangle]) -> f32 {
    let step = tris.len().div_ceil(SAMPLED).max(1);
    let mut sides: Vec<f32> = (tris.iter().step_by(step))
        .map(|(v, _)| {
            (0..3)
                .map(|k| {
                    let (lo, hi) = (v.iter().map(|p| p[k]))
                        .fold((f32::MAX, f32::MIN), |(l, h), x| (l.min(x), h.max(x)));
                    hi - lo
                })
                .fold(0.0, f32::max)
        })
        .collect();
    if sides.is_empty() {
        return 0.0;
    }
    let middle = sides.len() / 2;
    *sides.select_nth_unstable_by(middle, f32::total_cmp).1
}

/// Whether camera packets from `eye` would leave most lanes to f64 tests over triangles of
/// typical side `side` inside `bounds` (see the module's note).
pub(super) fn too_far_for_packets(eye: [f32; 3], bounds: &Box3, side: f32) -> bool {
    let farthest = (0..3)
        .map(|k| {
            let e = f64::from(eye[k]);
            (e - f64::from(bounds.lo[k]))
                .abs()
                .max((e - f64::from(bounds.hi[k])).abs())
        })
        .fold(0.0, f64::max);
    farthest * f64::from(f32::EPSILON) / 2.0 > SIDE_SHARE * f64::from(side)
}

#[cfg(feature = "unit-tests")]
#[deny(dead_code)]
pub(crate) mod tests {
    use super::*;

    fn the_typical_side_is_the_median_of_the_sampled_boxes() {
        let tri = |s: f32| ([[0.0, 0.0, 0.0], [s, 0.0, 0.0], [0.0, s / 2.0, 0.0]], 0);
        let tris: Vec<_> = [1.0, 3.0, 2.0, 100.0, 0.5].map(tri).to_vec();
        assert_eq!(typical_side(&tris), 2.0);
        assert_eq!(typical_side(&[]), 0.0);
        // 10,000 triangles: every tenth measured, the median of those.
        let many: Vec<_> = (0..10_000).map(|i| tri(i as f32)).collect();
        assert_eq!(typical_side(&many), 5000.0);
    }

    fn packets_go_per_ray_once_the_eyes_rounding_nears_a_side() {
        let unit = Box3 {
            lo: [0.0; 3],
            hi: [1.0; 3],
        };
        // Sides of 10⁻³: from ~1,050 units away (2⁻²⁴ · d > 10⁻³ / 16).
        assert!(!too_far_for_packets([0.0, 0.0, -1000.0], &unit, 1e-3));
        assert!(too_far_for_packets([0.0, 0.0, -1100.0], &unit, 1e-3));
        assert!(too_far_for_packets([2e3, 0.5, 0.5], &unit, 1e-3));
        // Sides of 2 (the Cornell box's walls): not before ~2·10⁶.
        assert!(!too_far_for_packets([0.0, 0.0, -1e6], &unit, 2.0));
        assert!(too_far_for_packets([0.0, 0.0, -3e6], &unit, 2.0));
        // No triangle to measure (side 0): any distance is too far, and none is near.
        assert!(too_far_for_packets([0.0, 0.0, -1.0], &unit, 0.0));
    }

    /// This module's tests, for tests/unit.rs to run.
    pub(crate) const TESTS: &[(&str, fn())] = &[
        (
            "the_typical_side_is_the_median_of_the_sampled_boxes",
            the_typical_side_is_the_median_of_the_sampled_boxes,
        ),
        (
            "packets_go_per_ray_once_the_eyes_rounding_nears_a_side",
            packets_go_per_ray_once_the_eyes_rounding_nears_a_side,
        ),
    ];
}
