//! The adaptive method's level counters (`geometry::adaptive::levels`, reported by
//! examples/speed_vs_error): they count what the search does, and only while switched on.
//! (One test in its own binary: the counters are global.)

use raylab::accel::{Accel, AccelChoice};
use raylab::geometry::adaptive::{self, levels, levels::Event};
use raylab::geometry::{Method, Ray, Shape};

#[test]
fn levels_count_the_slow_paths_only_while_on() {
    // Two triangles sharing the edge x = y of the unit square.
    let shapes = vec![
        Shape::from([[0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [1.0, 1.0, 1.0]]),
        Shape::from([[0.0, 0.0, 1.0], [1.0, 1.0, 1.0], [0.0, 1.0, 1.0]]),
    ];
    let accel = Accel::build(&shapes, AccelChoice::Flat);
    let closest = |o: [f32; 3], d: [f32; 3]| {
        let ray = Ray::new(o, d);
        let hit = accel.closest_hit(&ray, Method::Adaptive, 0.0, f32::INFINITY);
        hit.map(|h| {
            (
                h.prim,
                adaptive::rounded_t(&shapes[h.prim as usize], &ray, 0.0, f32::INFINITY),
            )
        })
    };
    let slow = [
        Event::PreciseF32,
        Event::F64Intervals,
        Event::Exact,
        Event::ExactT,
    ];
    let counts = || slow.map(levels::count);

    // Off: nothing is counted, even on a ray exactly through the shared edge.
    levels::reset();
    assert_eq!(
        closest([0.5, 0.5, 0.0], [0.0, 0.0, 1.0]),
        Some((0, Some(1.0)))
    );
    assert_eq!(counts(), [0; 4]);

    levels::count_levels(true);
    // A ray well inside one triangle: the f32 filter decides, t rounds from plain f64.
    assert_eq!(
        closest([0.8, 0.2, 0.0], [0.0, 0.0, 1.0]),
        Some((0, Some(1.0)))
    );
    assert_eq!(counts(), [0; 4]);
    assert_eq!(levels::count(Event::RoundedFromF64), 1);
    // Exactly through the shared edge: only exact arithmetic decides it (a tie, to the lower
    // index).
    assert_eq!(
        closest([0.5, 0.5, 0.0], [0.0, 0.0, 1.0]),
        Some((0, Some(1.0)))
    );
    let [precise, intervals, exact, _] = counts();
    assert!(
        precise >= 1 && intervals >= 1 && exact >= 1,
        "{:?}",
        counts()
    );
    levels::count_levels(false);
    let before = counts();
    closest([0.5, 0.5, 0.0], [0.0, 0.0, 1.0]);
    assert_eq!(counts(), before, "counted while off");
}
