//! Unit tests of the spheres' hierarchy: the lane forms of its rounding, and how many
//! spheres a ray's walk reaches.

use super::{reach, rounded_f32, Spheres};
use crate::geometry::adaptive::{round_down, round_up};
use crate::geometry::{Ray, Shape};
use crate::math::lanes::{f32x8, f64x4, Lanes64};

/// Positive f64 values where rounding to f32 is hard: around f32's subnormals, its
/// least normal, its largest value and beyond, exact f32 values, the midpoints between
/// two (ties), a few f64 ulps either side of both, and random values over every scale.
fn hard_values() -> Vec<f64> {
    let mut v = vec![
        f64::from_bits(1),
        // Half the least f32 subnormal: a tie between it and 0.
        f64::from(f32::from_bits(1)) / 2.0,
        f64::MIN_POSITIVE,
        1.0,
        2.5,
        f64::MAX,
        f64::INFINITY,
    ];
    let mut f32s = vec![
        f32::from_bits(1),
        f32::from_bits(2),
        f32::from_bits(0x7f_ffff),
        f32::MIN_POSITIVE,
        1.0,
        1.5,
        0.1,
        3.0e-3,
        65536.0,
        f32::MAX,
    ];
    let mut x = 0x2545f4914f6cdd1du64;
    for _ in 0..4_000 {
        let bits = (crate::math::xorshift(&mut x) as u32) & 0x7fff_ffff;
        if f32::from_bits(bits).is_finite() && bits != 0 {
            f32s.push(f32::from_bits(bits));
        }
    }
    for y in f32s {
        let (y, up) = (f64::from(y), f64::from(y.next_up()));
        let mid = y + (up - y) / 2.0;
        for c in [y, mid, up.min(f64::MAX)] {
            for steps in -2i64..=2 {
                v.push(f64::from_bits((c.to_bits() as i64 + steps) as u64));
            }
        }
    }
    v.retain(|c| *c > 0.0);
    v
}

fn lanes_of(values: &[f64]) -> impl Iterator<Item = [f64x4; 2]> + '_ {
    values.chunks(8).map(|c| {
        let lane = |l: usize| c.get(l).copied().unwrap_or(f64::INFINITY);
        [0, 1].map(|h| f64x4::from_array(std::array::from_fn(|l| lane(4 * h + l))))
    })
}

/// The lanes' rounding to f32 is `round_down` and `round_up`, bit for bit.
fn bounds_round_to_f32_as_one_value_does() {
    let values = hard_values();
    for pair in lanes_of(&values) {
        for half in pair {
            let (down, up) = (rounded_f32(half, false), rounded_f32(half, true));
            for (l, x) in half.to_array().into_iter().enumerate() {
                assert_eq!(down[l].to_bits(), round_down(x).to_bits(), "down {x:e}");
                assert_eq!(up[l].to_bits(), round_up(x).to_bits(), "up {x:e}");
            }
        }
    }
}

/// The walk's reach is never nearer than the margin `r + 2⁻¹⁶·|r|` (r the least f32 ≥
/// hi) it stands for, and beyond it by at most 2⁻¹⁸ of it.
fn reach_keeps_the_culling_margin() {
    let values = hard_values();
    let mut beyond = 0u32;
    for pair in lanes_of(&values) {
        let hi: Vec<f64> = pair.iter().flat_map(|h| h.to_array()).collect();
        let got = reach::<f32x8>(&hi.clone().try_into().expect("8")).to_array();
        for l in 0..8 {
            let r = round_up(hi[l]);
            let margin = r + r.abs() * (1.0 / 65536.0);
            assert!(got[l] >= margin, "hi {:e}: {} < {}", hi[l], got[l], margin);
            let loose = margin + margin * (1.0 / 262144.0) + f32::from_bits(2);
            assert!(got[l] <= loose, "hi {:e}: {} > {}", hi[l], got[l], loose);
            beyond += u32::from(got[l] > margin);
        }
    }
    // (The margin is kept without rounding each lane upwards: some lanes land beyond.)
    assert!(beyond > 0);
}

/// How many spheres `ray`'s walk reaches (padded: an inexact method's walk).
fn reached(spheres: &Spheres, ray: &Ray, padded: bool) -> usize {
    let mut n = 0;
    spheres.walk(ray, (0.0, f32::INFINITY), padded, |_, t_far| {
        n += 1;
        (t_far, false)
    });
    n
}

/// A ray along a column of a field of 4,096 small balls reaches that column's 16 and the
/// rest of their leaves (4 balls a leaf): with a sphere 2·10¹¹ away in the scene (whose coordinates widen only its own
/// branch's pad), and from 10⁶ away in the exact queries (which need no pad at all). Either
/// used to widen every box enough to reach the whole field.
fn a_ray_reaches_only_the_balls_along_it() {
    let ball = |i: u32| {
        let at = [i % 16, i / 16 % 16, i / 256].map(|k| k as f32 * 0.1);
        (Shape::sphere(at, 0.01), i)
    };
    let field: Vec<(Shape<f32>, u32)> = (0..4096).map(ball).collect();
    let mut with_far = field.clone();
    with_far.push((Shape::sphere([2e11, 0.0, 0.0], 1.0), 4096));
    let (field, with_far) = (Spheres::build(field), Spheres::build(with_far));
    let near = Ray::new([0.0, 0.0, -1.0], [0.0, 0.0, 1.0]);
    let far = Ray::new([0.0, 0.0, -1e6], [0.0, 0.0, 1.0]);
    for (what, n) in [
        ("near, inexact", reached(&field, &near, true)),
        ("near, exact", reached(&field, &near, false)),
        (
            "near, inexact, a far sphere",
            reached(&with_far, &near, true),
        ),
        ("from afar, exact", reached(&field, &far, false)),
    ] {
        assert!(
            (16..=128).contains(&n),
            "{what}: {n} of 4,096 balls reached"
        );
    }
}

pub(crate) const TESTS: crate::unit_tests::Tests = &[
    (
        "bounds_round_to_f32_as_one_value_does",
        bounds_round_to_f32_as_one_value_does,
    ),
    (
        "reach_keeps_the_culling_margin",
        reach_keeps_the_culling_margin,
    ),
    (
        "a_ray_reaches_only_the_balls_along_it",
        a_ray_reaches_only_the_balls_along_it,
    ),
];
