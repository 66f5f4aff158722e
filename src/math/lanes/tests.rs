//! The lane types compute the same bits: `Avx8` (in the AVX2 and AVX-512 builds) as
//! `wide`'s f32x8, `Avx4d` as `wide`'s f64x4, and `Avx16` as two halves of eight.

use super::*;
use crate::math::simd::{detected, has_avx2, SimdLevel};

/// Every operation of [`Lanes`] on both types (`Avx8` in the AVX2 and the AVX-512
/// builds), bit for bit, on values that probe the
/// corners (signed zeros, NaN, infinities, subnormals, ties).
fn both_lane_types_compute_the_same_bits() {
    if !has_avx2() {
        return; // nothing to compare with
    }
    let vals = [
        0.0,
        -0.0,
        1.0,
        -2.5,
        f32::NAN,
        f32::INFINITY,
        f32::NEG_INFINITY,
        1e-45,
        -3e38,
        0.1,
    ];
    let mut a = [0f32; 8];
    let mut b = [0f32; 8];
    for (i, x) in vals.iter().enumerate() {
        for (j, y) in vals.iter().enumerate() {
            a[(i + j) % 8] = *x;
            b[(i * 3 + j) % 8] = *y;
        }
        let r = check(a, b);
        assert!(r.is_empty(), "{a:?} {b:?}: {r:?}");
    }
}

fn bits(x: [f32; 8]) -> [u32; 8] {
    x.map(f32::to_bits)
}

#[allow(unsafe_code)]
fn check(a: [f32; 8], b: [f32; 8]) -> Vec<&'static str> {
    #[inline(always)]
    fn run<V: Lanes>(a: [f32; 8], b: [f32; 8]) -> Vec<[u32; 8]> {
        let (x, y) = (V::from_array(a), V::from_array(b));
        let m = x.simd_lt(y);
        vec![
            (x + y).to_array(),
            (x - y).to_array(),
            (x * y).to_array(),
            (x / y).to_array(),
            (-x).to_array(),
            (x & y).to_array(),
            (x | y).to_array(),
            (!x).to_array(),
            m.to_array(),
            x.simd_le(y).to_array(),
            x.simd_gt(y).to_array(),
            x.simd_ge(y).to_array(),
            x.simd_eq(y).to_array(),
            x.simd_ne(y).to_array(),
            m.bitselect(x, y).to_array(),
            x.bitselect(x, y).to_array(),
            x.abs().to_array(),
            x.max(y).to_array(),
            x.min(y).to_array(),
            x.fast_max(y).to_array(),
            x.fast_min(y).to_array(),
            x.abs().sqrt().to_array(),
            x.step_bits(y, m).to_array(),
            [f32::from_bits(x.to_bitmask()); 8],
            V::from_bitmask(x.to_bitmask() ^ y.to_bitmask() << 1).to_array(),
            [x.reduce_max(); 8],
            [m.bitselect(x, y).reduce_max(); 8],
            [x.reduce_min(); 8],
            [m.bitselect(x, y).reduce_min(); 8],
        ]
        .into_iter()
        .map(bits)
        .collect()
    }
    const NAMES: [&str; 29] = [
        "add",
        "sub",
        "mul",
        "div",
        "neg",
        "and",
        "or",
        "not",
        "lt",
        "le",
        "gt",
        "ge",
        "eq",
        "ne",
        "select",
        "select by bits",
        "abs",
        "max",
        "min",
        "fast_max",
        "fast_min",
        "sqrt",
        "step_bits",
        "bitmask",
        "from_bitmask",
        "reduce_max",
        "reduce_max of a select",
        "reduce_min",
        "reduce_min of a select",
    ];
    crate::math::simd::avx2_features! {
        fn avx2(a: [f32; 8], b: [f32; 8]) -> Vec<[u32; 8]> {
            run::<Avx8>(a, b)
        }
    }
    crate::math::simd::avx512_features! {
        fn avx512(a: [f32; 8], b: [f32; 8]) -> Vec<[u32; 8]> {
            run::<Avx8>(a, b)
        }
    }
    let wide = run::<f32x8>(a, b);
    // SAFETY: the CPU has AVX2 and FMA (checked by the caller).
    let mut builds = vec![unsafe { avx2(a, b) }];
    if detected() == SimdLevel::Avx512 {
        // SAFETY: the CPU has AVX-512 F, VL, BW, DQ and CD (just checked).
        builds.push(unsafe { avx512(a, b) });
    }
    let differ = |avx: &Vec<[u32; 8]>| {
        (wide.iter().zip(avx).zip(NAMES))
            .filter(|((w, v), _)| w != v)
            .map(|(_, name)| name)
            .collect::<Vec<_>>()
    };
    builds.iter().flat_map(differ).collect()
}

/// `Avx4d` (in the AVX2 and AVX-512 builds) computes every [`Lanes64`] operation as `wide`'s
/// f64x4, bit for bit, on the same kind of corner values: the spheres' interval test runs
/// in either, by build.
fn both_f64_lane_types_compute_the_same_bits() {
    if !has_avx2() {
        return; // nothing to compare with
    }
    let vals = [
        0.0,
        -0.0,
        1.0,
        -2.5,
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
        5e-324,
        -1.7e308,
        0.1,
    ];
    let (mut a, mut b) = ([0f64; 4], [0f64; 4]);
    for (i, x) in vals.iter().enumerate() {
        for (j, y) in vals.iter().enumerate() {
            a[(i + j) % 4] = *x;
            b[(i * 3 + j) % 4] = *y;
            // SAFETY: the CPU has AVX2 and FMA (checked above).
            #[allow(unsafe_code)]
            let mut builds = vec![unsafe { f64_ops_avx2(a, b) }];
            if detected() == SimdLevel::Avx512 {
                // SAFETY: the CPU has AVX-512 F, VL, BW, DQ and CD (just checked).
                #[allow(unsafe_code)]
                builds.push(unsafe { f64_ops_avx512(a, b) });
            }
            let base = f64_ops::<f64x4>(a, b);
            for avx in &builds {
                for ((w, v), name) in base.iter().zip(avx).zip(F64_OPS) {
                    assert_eq!(w, v, "{name}: {a:?} {b:?}");
                }
            }
        }
    }
}

const F64_OPS: [&str; 25] = [
    "add",
    "sub",
    "mul",
    "div",
    "neg",
    "and",
    "or",
    "not",
    "lt",
    "le",
    "gt",
    "ge",
    "finite",
    "select",
    "select by bits",
    "abs",
    "sqrt",
    "sqrt of any",
    "max",
    "fast_max",
    "fast_min",
    "bitmask",
    "to_f32",
    "round_f32",
    "splat",
];

/// [`F64_OPS`] on lanes `a` and `b`, as bit patterns.
#[inline(always)]
fn f64_ops<F: Lanes64>(a: [f64; 4], b: [f64; 4]) -> Vec<[u64; 4]> {
    let (x, y) = (F::from_array(a), F::from_array(b));
    let m = x.simd_lt(y);
    let bits = |v: F| v.to_array().map(f64::to_bits);
    vec![
        bits(x + y),
        bits(x - y),
        bits(x * y),
        bits(x / y),
        bits(-x),
        bits(x & y),
        bits(x | y),
        bits(!x),
        bits(m),
        bits(x.simd_le(y)),
        bits(x.simd_gt(y)),
        bits(x.simd_ge(y)),
        bits(x.is_finite()),
        bits(m.bitselect(x, y)),
        bits(x.bitselect(y, x)),
        bits(x.abs()),
        bits(x.abs().sqrt()),
        bits(x.sqrt()),
        bits(x.max(y)),
        bits(x.fast_max(y)),
        bits(x.fast_min(y)),
        [x.to_bitmask() as u64; 4],
        x.to_f32().map(|v| v.to_bits() as u64),
        bits(x.round_f32()),
        bits(F::splat(a[1])),
    ]
}

crate::math::simd::avx2_features! {
    fn f64_ops_avx2(a: [f64; 4], b: [f64; 4]) -> Vec<[u64; 4]> {
        f64_ops::<Avx4d>(a, b)
    }
}

crate::math::simd::avx512_features! {
    fn f64_ops_avx512(a: [f64; 4], b: [f64; 4]) -> Vec<[u64; 4]> {
        f64_ops::<Avx4d>(a, b)
    }
}

/// `Avx16` computes as two 8-lane halves: every [`LaneOps`] operation, bit for bit, on
/// the same corner values, against `wide`'s f32x8 on each half (the bitmask as the
/// halves' masks side by side; `reduce_max` as the halves' lane-wise `maxps`, then the
/// 8-lane order).
fn sixteen_lanes_compute_as_two_halves_of_eight() {
    if detected() < SimdLevel::Avx512 {
        return; // no Avx16 on this CPU
    }
    let vals = [
        0.0,
        -0.0,
        1.0,
        -2.5,
        f32::NAN,
        f32::INFINITY,
        f32::NEG_INFINITY,
        1e-45,
        -3e38,
        0.1,
    ];
    let (mut a, mut b) = ([0f32; 16], [0f32; 16]);
    for (i, x) in vals.iter().enumerate() {
        for (j, y) in vals.iter().enumerate() {
            a[(i + j) % 16] = *x;
            b[(i * 3 + j * 5) % 16] = *y;
        }
        // SAFETY: the CPU has AVX-512 F, VL, BW, DQ and CD (checked above).
        #[allow(unsafe_code)]
        let wide16 = unsafe { avx512_ops(&a, &b) };
        let (lo, hi) = (
            ops::<f32x8>(&a[..8], &b[..8]),
            ops::<f32x8>(&a[8..], &b[8..]),
        );
        for (k, name) in OPS.iter().enumerate() {
            let halves = if *name == "bitmask" {
                vec![lo[k][0] | hi[k][0] << 8]
            } else {
                [&lo[k][..], &hi[k][..]].concat()
            };
            assert_eq!(wide16[k], halves, "{name}: {a:?} {b:?}");
        }
        let (x, y) = (f32x8::from(&a[..8]), f32x8::from(&a[8..]));
        #[allow(unsafe_code)]
        // SAFETY: as above.
        let max16 = unsafe { avx512_reduce_max(&a) };
        assert_eq!(
            max16.to_bits(),
            x.fast_max(y).reduce_max().to_bits(),
            "{a:?}"
        );
    }
}

const OPS: [&str; 22] = [
    "add", "sub", "mul", "div", "neg", "and", "or", "not", "lt", "le", "gt", "ge", "eq", "ne",
    "select", "abs", "max", "min", "fast_max", "fast_min", "sqrt", "bitmask",
];

/// The lanes' bit patterns.
#[inline(always)]
fn lane_bits<V: LaneOps>(v: V) -> Vec<u32> {
    let mut out = [0f32; 16];
    v.store(&mut out);
    out[..V::WIDTH].iter().map(|x| x.to_bits()).collect()
}

/// [`OPS`] on lanes `a` and `b`.
#[inline(always)]
fn ops<V: LaneOps>(a: &[f32], b: &[f32]) -> Vec<Vec<u32>> {
    let (x, y) = (V::load(a), V::load(b));
    let m = x.simd_lt(y);
    vec![
        lane_bits(x + y),
        lane_bits(x - y),
        lane_bits(x * y),
        lane_bits(x / y),
        lane_bits(-x),
        lane_bits(x & y),
        lane_bits(x | y),
        lane_bits(!x),
        lane_bits(m),
        lane_bits(x.simd_le(y)),
        lane_bits(x.simd_gt(y)),
        lane_bits(x.simd_ge(y)),
        lane_bits(x.simd_eq(y)),
        lane_bits(x.simd_ne(y)),
        lane_bits(m.bitselect(x, y)),
        lane_bits(x.abs()),
        lane_bits(x.max(y)),
        lane_bits(x.min(y)),
        lane_bits(x.fast_max(y)),
        lane_bits(x.fast_min(y)),
        lane_bits(x.abs().sqrt()),
        vec![x.to_bitmask()],
    ]
}

crate::math::simd::avx512_features! {
    fn avx512_ops(a: &[f32], b: &[f32]) -> Vec<Vec<u32>> {
        ops::<Avx16>(a, b)
    }
}

crate::math::simd::avx512_features! {
    fn avx512_reduce_max(a: &[f32]) -> f32 {
        Avx16::load(a).reduce_max()
    }
}

/// This module's tests, for tests/unit.rs to run.
pub(crate) const TESTS: &[(&str, fn())] = &[
    (
        "both_lane_types_compute_the_same_bits",
        both_lane_types_compute_the_same_bits,
    ),
    (
        "both_f64_lane_types_compute_the_same_bits",
        both_f64_lane_types_compute_the_same_bits,
    ),
    (
        "sixteen_lanes_compute_as_two_halves_of_eight",
        sixteen_lanes_compute_as_two_halves_of_eight,
    ),
];
