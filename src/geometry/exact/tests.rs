//! The exact level's tests: expansions and distillation against rationals, exact
//! comparisons of irrational parameters, closed edges, and correct rounding.

use super::expansion::{orient_distilled, sum_sign, two_prod};
use super::rational::sign;
use super::*;
use crate::math::xorshift;
use num_bigint::BigInt;
use num_traits::Zero;
use std::cmp::Ordering;

fn t(a: f64, b: f64, s: f64) -> ExactT {
    ExactT {
        a: q(a),
        b: q(b),
        s: q(s),
    }
}

fn orient_is_exact_where_f64_is_not() {
    let (d, o) = ([0.0, 0.0, 1.0], [0.0; 3]);
    // The edge from (1, 1e-30·k) … along x: which side of the z axis?
    let a = [1.0, 1.0, 0.0];
    let b = [-1.0, -1.0, 0.0];
    assert_eq!(
        orient(d, o, a, b),
        Some(Ordering::Equal),
        "through the origin"
    );
    let b2 = [-1.0, -1.0f64.next_up(), 0.0];
    assert_eq!(orient(d, o, a, b2), Some(orient_rational(d, o, a, b2)));
    assert_ne!(orient(d, o, a, b2), Some(Ordering::Equal));
    // Random f32 inputs: expansions agree with rationals.
    let mut x = 12345u64;
    let mut next = || ((xorshift(&mut x) % 2001) as f64 - 1000.0) as f32 as f64 * 0.37f32 as f64;
    for _ in 0..2000 {
        let p: Vec<[f64; 3]> = (0..4).map(|_| [next(), next(), next()]).collect();
        // A direction towards the midpoint of a and b makes exact zeros common.
        let mid = [0, 1, 2].map(|k| 0.5 * (p[2][k] + p[3][k]) - p[1][k]);
        for d in [p[0], mid] {
            assert_eq!(
                orient(d, p[1], p[2], p[3]).unwrap(),
                orient_rational(d, p[1], p[2], p[3])
            );
        }
    }
}

/// A random f32 with a full 24-bit mantissa in (−scale/2, scale/2), as f64.
fn full_f32(x: &mut u64, scale: f64) -> f64 {
    let m = (xorshift(x) >> 40) as f64 / (1u64 << 24) as f64 - 0.5;
    (m * scale) as f32 as f64
}

fn distilled_orient_is_exact_on_exact_zeros_and_near_misses() {
    // Lines exactly through an edge (direction towards a point of the edge, in f32, as a
    // camera ray through a wall's diagonal), and nudged an ulp off it: the distilled sign
    // must equal the rational one, and settle nearly all of them (else the expansions do
    // the work and this stage is only a cost).
    let mut x = 424242u64;
    let mut next = |scale: f64| full_f32(&mut x, scale);
    let (mut settled, mut zeros, mut cases) = (0, 0, 0);
    for i in 0..3000 {
        let scale = 10f64.powi(i % 21 - 10);
        let p: Vec<[f64; 3]> = (0..3)
            .map(|_| [next(scale), next(scale), next(scale)])
            .collect();
        let (o, a, b) = (p[0], p[1], p[2]);
        let pa = [0, 1, 2].map(|k| a[k] - o[k]);
        let pb = [0, 1, 2].map(|k| b[k] - o[k]);
        if (0..3).any(|k| pa[k] + o[k] != a[k] || pb[k] + o[k] != b[k]) {
            continue; // not exact in f64: orient leaves these to the rationals
        }
        // Towards a or b (an exact zero), the midpoint (zero where exact), or nudged.
        let towards = [
            pa,
            pb,
            [0, 1, 2].map(|k| (0.5 * (pa[k] + pb[k])) as f32 as f64),
        ];
        for (t, mut d) in towards.into_iter().enumerate() {
            if i % 3 == 1 {
                d[t % 3] = (d[t % 3] as f32).next_up() as f64;
            }
            cases += 1;
            let exact = orient_rational(d, o, a, b);
            zeros += (exact == Ordering::Equal) as u32;
            if let Some(s) = orient_distilled(d, &pa, &pb) {
                assert_eq!(s, exact, "{d:?} {o:?} {a:?} {b:?}");
                settled += 1;
            }
        }
    }
    assert!(zeros > cases / 3, "{zeros} exact zeros of {cases}");
    assert!(settled * 100 > cases * 99, "{settled} of {cases} settled");
}

fn sum_sign_settles_cancelling_sums() {
    let sign_of = |v: &[f64]| {
        let mut terms = [0.0; 24];
        terms[..v.len()].copy_from_slice(v);
        sum_sign(&mut terms, v.len())
    };
    assert_eq!(sign_of(&[1.0, 1e-30, -1.0]), Some(Ordering::Greater));
    assert_eq!(
        sign_of(&[1e300, -1e-300, -1e300, 1e-300, 3.0, -3.0]),
        Some(Ordering::Equal)
    );
    assert_eq!(sign_of(&[]), Some(Ordering::Equal));
    // 0.1 + 0.2 − 0.30000000000000004 + 2⁻⁵⁶: the rationals say which sign.
    let v = [0.1, 0.2, -0.30000000000000004, 2f64.powi(-56)];
    let exact: Q = v.map(q).into_iter().sum();
    assert_ne!(exact, Q::zero());
    assert_eq!(sign_of(&v), Some(sign(&exact)));
}

fn orient_filter_defers_near_zero_determinants() {
    // Points a few ulps off the plane through 0, v1 and v2 (full 53-bit mantissas, many
    // scales): the plain f64 determinant is then mostly rounding, and the filter must
    // leave those to the expansions (every answer checked against rationals).
    let mut x = 5551212u64;
    let mut next =
        |scale: f64| ((xorshift(&mut x) >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * scale;
    let mut off_plane = 0;
    for i in 0..4000usize {
        let scale = 10f64.powi((i % 31) as i32 - 15);
        let v1 = [next(scale), next(scale), next(scale)];
        let v2 = [next(scale), next(scale), next(scale)];
        // On the plane (rounded), then nudged by up to 3 ulps in one axis.
        let w = [next(1.0), next(1.0)];
        let mut p = [0, 1, 2].map(|k| w[0] * v1[k] + w[1] * v2[k]);
        let axis = i % 3;
        for _ in 0..i % 4 {
            p[axis] = if i % 8 < 4 {
                p[axis].next_up()
            } else {
                p[axis].next_down()
            };
        }
        if let Some(s) = orient(v1, [0.0; 3], v2, p) {
            assert_eq!(
                s,
                orient_rational(v1, [0.0; 3], v2, p),
                "{v1:?} {v2:?} {p:?}"
            );
            off_plane += (s != Ordering::Equal) as u32;
        }
    }
    assert!(off_plane > 1000, "{off_plane} off the plane");
}

fn orient_is_exact_for_full_mantissas_and_wide_magnitudes() {
    // Full 24-bit mantissas over 1e-20..1e20, the products' low halves nonzero: the
    // split product (no FMA in the baseline x86-64 build) must stay exact.
    let mut x = 987654321u64;
    let mut next = |scale: f64| full_f32(&mut x, scale);
    for i in 0..3000 {
        let scale = 10f64.powi(i % 41 - 20);
        let p: Vec<[f64; 3]> = (0..4)
            .map(|_| [next(scale), next(scale), next(scale)])
            .collect();
        let mid = [0, 1, 2].map(|k| ((0.5 * (p[2][k] + p[3][k])) as f32) as f64 - p[1][k]);
        for d in [p[0], mid] {
            if let Some(s) = orient(d, p[1], p[2], p[3]) {
                assert_eq!(s, orient_rational(d, p[1], p[2], p[3]), "{d:?} {p:?}");
            }
        }
        // Full 53-bit mantissas for the product itself.
        let (a, b) = (
            next(scale) * (1.0 + 1e-9),
            next(1.0 / scale) * (1.0 - 3e-10),
        );
        let (hi, lo) = two_prod(a, b);
        assert_eq!(q(hi) + q(lo), q(a) * q(b), "{a} * {b}");
    }
}

fn compares_irrational_parameters_exactly() {
    // 1 + √2 vs 2.414213562373095 (a double just below 1 + √2).
    assert_eq!(t(1.0, 1.0, 2.0).cmp_f(2.414213562373095), Ordering::Greater);
    assert_eq!(t(1.0, 1.0, 2.0).cmp_f(2.4142135623730954), Ordering::Less);
    // 2√2 = √8.
    assert_eq!(t(0.0, 2.0, 2.0).cmp_t(&t(0.0, 1.0, 8.0)), Ordering::Equal);
    assert_eq!(
        t(3.0, -1.0, 2.0).cmp_t(&t(0.0, 1.0, 2.0)),
        Ordering::Greater
    ); // 3 − √2 > √2
    assert_eq!(t(2.0, -1.0, 2.0).cmp_t(&t(0.0, 1.0, 2.0)), Ordering::Less); // 2 − √2 < √2
    assert_eq!(t(0.5, 0.0, 0.0).cmp_f(f64::INFINITY), Ordering::Less);
}

fn edges_are_closed_and_plane_t_is_exact() {
    let v = [[0.0, 0.0, 3.0], [1.0, 0.0, 3.0], [0.0, 1.0, 3.0]];
    // Through the hypotenuse's midpoint, exactly: that edge's sign is 0.
    let (o, d) = ([0.0; 3], [0.5, 0.5, 3.0]);
    assert_eq!(orient(d, o, v[1], v[2]), Some(Ordering::Equal));
    assert_eq!(plane_t(o, d, &v).unwrap().cmp_f(1.0), Ordering::Equal);
    // One ulp of 0.5 outside: the sign is decided, opposite to the other edges'.
    let d2 = [0.5f64.next_up(), 0.5, 3.0];
    let s = orient(d2, o, v[1], v[2]).unwrap();
    assert_ne!(s, Ordering::Equal);
    assert_eq!(s, orient(d2, o, v[0], v[1]).unwrap().reverse());
    // In the plane: no t.
    assert!(plane_t([0.0, 0.0, 3.0], [1.0, 1.0, 0.0], &v).is_none());
}

fn rounds_to_nearest_with_ties_to_even_overflow_and_underflow() {
    let two = |k: i32| match k >= 0 {
        true => Q::from_integer(BigInt::from(1) << k as usize),
        false => Q::new(BigInt::from(1), BigInt::from(1) << (-k) as usize),
    };
    let r = |x: Q| ExactT::rational(x);
    let one = two(0);
    // Ties go to the even neighbour: 1 + 2⁻²⁴ to 1, 1 + 3·2⁻²⁴ to 1 + 2⁻²², in f32.
    assert_eq!(r(&one + two(-24)).rounded::<f32>(), 1.0);
    assert_eq!(
        r(&one + two(-23) + two(-24)).rounded::<f32>(),
        1.0 + 2f32.powi(-22)
    );
    assert_eq!(
        r(&one + two(-24) + two(-80)).rounded::<f32>(),
        1.0f32.next_up()
    );
    assert_eq!(
        r(-(&one + two(-24) + two(-80))).rounded::<f32>(),
        -1.0f32.next_up()
    );
    assert_eq!(r(&one + two(-53)).rounded::<f64>(), 1.0);
    assert_eq!(
        r(&one + two(-53) + two(-200)).rounded::<f64>(),
        1.0f64.next_up()
    );
    // Subnormals and underflow: half the least subnormal is a tie to (signed) zero.
    assert_eq!(r(two(-150)).rounded::<f32>().to_bits(), 0);
    assert_eq!(
        r(-two(-150)).rounded::<f32>().to_bits(),
        (-0.0f32).to_bits()
    );
    assert_eq!(r(two(-150) + two(-300)).rounded::<f32>(), f32::from_bits(1));
    assert_eq!(
        r(two(-1075) + two(-1200)).rounded::<f64>(),
        f64::from_bits(1)
    );
    assert_eq!(
        r(two(-1074) * Q::from_integer(3.into())).rounded::<f64>(),
        f64::from_bits(3)
    );
    // Overflow from half an ulp above the largest finite value, as IEEE rounds.
    let half_ulp = two(103);
    let max = q(f32::MAX as f64);
    assert_eq!(r(&max + &half_ulp - two(-50)).rounded::<f32>(), f32::MAX);
    assert_eq!(r(&max + &half_ulp).rounded::<f32>(), f32::INFINITY);
    assert_eq!(r(-(&max + &half_ulp)).rounded::<f32>(), f32::NEG_INFINITY);
    assert_eq!(r(two(1024)).rounded::<f64>(), f64::INFINITY);
    assert_eq!(r(two(1023)).rounded::<f64>(), 2f64.powi(1023));
    // From a guess that overflowed f64 (approx() is NaN or ∞): still found.
    let huge = Q::from_integer(BigInt::from(7) << 1500usize);
    assert_eq!(
        r(&huge / Q::from_integer(BigInt::from(1) << 1400usize)).rounded::<f64>(),
        7.0 * 2f64.powi(100)
    );
    // Irrational: 1 + √2 and a root 2⁻¹⁰⁰⁰·√3 (its parts underflow an f64 estimate).
    assert_eq!(t(1.0, 1.0, 2.0).rounded::<f64>(), 1.0 + 2f64.sqrt());
    assert_eq!(t(1.0, 1.0, 2.0).rounded::<f32>(), 1.0 + 2f32.sqrt());
    let tiny = ExactT {
        a: Q::zero(),
        b: two(-1000),
        s: Q::from_integer(3.into()),
    };
    assert_eq!(tiny.rounded::<f64>(), 3f64.sqrt() * 2f64.powi(-1000));
}

/// `approx` within a few ulps of the correctly rounded value where a and b·√s cancel: t =
/// a − √(a² − 2a·u) ≈ u for a from 1 to 2¹⁰⁰ (a ray starting just inside a huge sphere),
/// which the plain f64 sum a + b·√s got wrong by up to a's own size.
fn approx_is_within_ulps_where_the_root_cancels() {
    for k in (0..=100).step_by(5) {
        for u in [0.25, 1.0 / 3.0, 1e-5] {
            let a = q(2f64.powi(k));
            let s = &a * &a - q(2.0) * &a * q(u);
            let t = ExactT { a, b: q(-1.0), s };
            let (got, exact) = (t.approx(), t.rounded::<f64>());
            let ulps = (got - exact).abs() / (exact * f64::EPSILON);
            assert!(ulps <= 8.0, "2^{k}, u {u}: approx {got}, exact {exact}");
        }
    }
    // Terms of one sign, and a zero part, as before.
    assert_eq!(t(1.0, 1.0, 4.0).approx(), 3.0);
    assert_eq!(t(0.0, -1.0, 4.0).approx(), -2.0);
    assert_eq!(t(5.0, 0.0, 4.0).approx(), 5.0);
}

/// This module's tests, for tests/unit.rs to run.
pub(crate) const TESTS: &[(&str, fn())] = &[
    (
        "orient_is_exact_where_f64_is_not",
        orient_is_exact_where_f64_is_not,
    ),
    (
        "distilled_orient_is_exact_on_exact_zeros_and_near_misses",
        distilled_orient_is_exact_on_exact_zeros_and_near_misses,
    ),
    (
        "sum_sign_settles_cancelling_sums",
        sum_sign_settles_cancelling_sums,
    ),
    (
        "orient_filter_defers_near_zero_determinants",
        orient_filter_defers_near_zero_determinants,
    ),
    (
        "orient_is_exact_for_full_mantissas_and_wide_magnitudes",
        orient_is_exact_for_full_mantissas_and_wide_magnitudes,
    ),
    (
        "compares_irrational_parameters_exactly",
        compares_irrational_parameters_exactly,
    ),
    (
        "edges_are_closed_and_plane_t_is_exact",
        edges_are_closed_and_plane_t_is_exact,
    ),
    (
        "rounds_to_nearest_with_ties_to_even_overflow_and_underflow",
        rounds_to_nearest_with_ties_to_even_overflow_and_underflow,
    ),
    (
        "approx_is_within_ulps_where_the_root_cancels",
        approx_is_within_ulps_where_the_root_cancels,
    ),
];
