//! One float trait so each intersection routine is written once and runs in f32 (rendering)
//! or f64 (the `trace --precision f64` reference), plus small vector helpers on `[T; 3]`.

use num_traits::Float;
use std::fmt::{Debug, Display};
use std::str::FromStr;

/// f32 or f64.
pub trait Real:
    Float + Debug + Display + std::fmt::LowerExp + FromStr + Send + Sync + 'static
{
    /// Half an ulp of 1: the unit roundoff u of the IEEE format.
    const UNIT_ROUNDOFF: Self;
    /// 16 times the least subnormal: far more than the absolute error a rounding that
    /// underflows adds (half the least subnormal), the term an error bound made only of
    /// relative ones lacks.
    const UNDERFLOW: Self;
    /// Converts from f64 (rounding to nearest for f32).
    fn of(x: f64) -> Self;
    /// Widens to f64 (exact).
    fn f64(self) -> f64;
    /// The next representable value towards +∞.
    fn up(self) -> Self;
    /// The next representable value towards −∞.
    fn down(self) -> Self;
    /// The largest [`Real::key`] (that of the largest finite value).
    const MAX_KEY: i64;
    /// Significand bits p, and the binary exponents of the least and largest normal values.
    const PRECISION: i64;
    const MIN_NORMAL_EXP: i64;
    const MAX_EXP: i64;
    /// The value's place among the finite values in order: +0 is 0, the next value up is 1,
    /// the next down −1 (−0 counts as +0), so a search over keys is a search over values.
    fn key(self) -> i64;
    /// The finite value with that key (|k| ≤ [`Real::MAX_KEY`]).
    fn from_key(k: i64) -> Self;

    /// Higham's γ(n) = n·u / (1 − n·u): the relative error bound of n rounded operations.
    #[inline]
    fn error_gamma(n: u32) -> Self {
        let nu = Self::of(n as f64) * Self::UNIT_ROUNDOFF;
        nu / (Self::one() - nu)
    }
}

impl Real for f32 {
    const UNIT_ROUNDOFF: Self = f32::EPSILON * 0.5;
    const UNDERFLOW: Self = f32::from_bits(16);
    #[inline]
    fn of(x: f64) -> Self {
        x as f32
    }
    #[inline]
    fn f64(self) -> f64 {
        self as f64
    }
    #[inline]
    fn up(self) -> Self {
        self.next_up()
    }
    #[inline]
    fn down(self) -> Self {
        self.next_down()
    }
    const MAX_KEY: i64 = f32::MAX.to_bits() as i64;
    const PRECISION: i64 = 24;
    const MIN_NORMAL_EXP: i64 = -126;
    const MAX_EXP: i64 = 127;
    fn key(self) -> i64 {
        let magnitude = (self.to_bits() & 0x7fff_ffff) as i64;
        if self < 0.0 {
            -magnitude
        } else {
            magnitude
        }
    }
    fn from_key(k: i64) -> Self {
        let magnitude = f32::from_bits(k.unsigned_abs() as u32);
        if k < 0 {
            -magnitude
        } else {
            magnitude
        }
    }
}

impl Real for f64 {
    const UNIT_ROUNDOFF: Self = f64::EPSILON * 0.5;
    const UNDERFLOW: Self = f64::from_bits(16);
    #[inline]
    fn of(x: f64) -> Self {
        x
    }
    #[inline]
    fn f64(self) -> f64 {
        self
    }
    #[inline]
    fn up(self) -> Self {
        self.next_up()
    }
    #[inline]
    fn down(self) -> Self {
        self.next_down()
    }
    const MAX_KEY: i64 = f64::MAX.to_bits() as i64;
    const PRECISION: i64 = 53;
    const MIN_NORMAL_EXP: i64 = -1022;
    const MAX_EXP: i64 = 1023;
    fn key(self) -> i64 {
        let magnitude = (self.to_bits() & !(1u64 << 63)) as i64;
        if self < 0.0 {
            -magnitude
        } else {
            magnitude
        }
    }
    fn from_key(k: i64) -> Self {
        let magnitude = f64::from_bits(k.unsigned_abs());
        if k < 0 {
            -magnitude
        } else {
            magnitude
        }
    }
}

/// `x` written exactly: the whole decimal expansion of the binary value (every finite float
/// has one: m·2⁻ᵏ = m·5ᵏ / 10ᵏ), without an exponent; −0 keeps its sign. Read as f32 (where
/// `x` is one), as f64 or as an exact rational, it is the same number, so a file of them means
/// the same to every reader. An f32 takes at most 160 characters, most far fewer (0.1f32 is
/// `0.100000001490116119384765625`).
pub fn exact_decimal(x: f64) -> String {
    use num_bigint::BigUint;
    if !x.is_finite() {
        return format!("{x}");
    }
    let sign = if x.is_sign_negative() { "-" } else { "" };
    let bits = x.to_bits();
    let (biased, fraction) = ((bits >> 52 & 0x7ff) as i64, bits & ((1 << 52) - 1));
    let (mut m, mut e) = match biased {
        0 => (fraction, -1074),
        _ => (fraction | 1 << 52, biased - 1075),
    };
    if m == 0 {
        return format!("{sign}0");
    }
    let zeros = (m.trailing_zeros() as i64).min(-e).max(0);
    m >>= zeros;
    e += zeros;
    if e >= 0 {
        return format!("{sign}{}", BigUint::from(m) << e as usize);
    }
    let k = (-e) as usize;
    let digits = (BigUint::from(m) * BigUint::from(5u32).pow(k as u32)).to_string();
    let digits = format!(
        "{}{digits}",
        "0".repeat((k + 1).saturating_sub(digits.len()))
    );
    let (whole, frac) = digits.split_at(digits.len() - k);
    format!("{sign}{whole}.{frac}")
}

/// A 3-vector as a plain array: the geometry works on these so it is generic over [`Real`].
pub type V3<T> = [T; 3];

/// a − b
#[inline]
pub fn sub<T: Real>(a: V3<T>, b: V3<T>) -> V3<T> {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// a + b
#[inline]
pub fn add<T: Real>(a: V3<T>, b: V3<T>) -> V3<T> {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// s · a
#[inline]
pub fn scale<T: Real>(a: V3<T>, s: T) -> V3<T> {
    [a[0] * s, a[1] * s, a[2] * s]
}

/// a · b
#[inline]
pub fn dot<T: Real>(a: V3<T>, b: V3<T>) -> T {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// a × b
#[inline]
pub fn cross<T: Real>(a: V3<T>, b: V3<T>) -> V3<T> {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// The sizes of [`cross`]'s products, |a₁b₂| + |a₂b₁| and so on: each component's rounding
/// is within a few units of the last place of its size.
#[inline]
pub fn cross_size<T: Real>(a: V3<T>, b: V3<T>) -> V3<T> {
    [
        (a[1] * b[2]).abs() + (a[2] * b[1]).abs(),
        (a[2] * b[0]).abs() + (a[0] * b[2]).abs(),
        (a[0] * b[1]).abs() + (a[1] * b[0]).abs(),
    ]
}

/// Component-wise |a|.
#[inline]
pub fn abs<T: Real>(a: V3<T>) -> V3<T> {
    [a[0].abs(), a[1].abs(), a[2].abs()]
}

/// Whether all three components are finite.
#[inline]
pub fn finite<T: Real>(a: V3<T>) -> bool {
    a[0].is_finite() && a[1].is_finite() && a[2].is_finite()
}

#[cfg(feature = "unit-tests")]
#[deny(dead_code)]
pub(crate) mod tests {
    use super::*;

    fn keys_count_the_finite_values_in_order() {
        for x in [
            0.0f32,
            1e-45,
            1.0,
            -1.0,
            f32::MAX,
            -f32::MAX,
            3.5e-39,
            -7.25,
        ] {
            assert_eq!(f32::from_key(x.key()), x);
            assert_eq!(x.next_up().key(), x.key() + 1, "{x}");
        }
        for x in [0.0f64, 5e-324, 1.0, -1.0, f64::MAX, -f64::MAX, -2.5e-310] {
            assert_eq!(f64::from_key(x.key()), x);
            assert_eq!(x.next_up().key(), x.key() + 1, "{x}");
        }
        assert_eq!((-0.0f32).key(), 0);
        assert_eq!(f32::MAX.key(), f32::MAX_KEY);
        assert_eq!(f64::MAX.key(), f64::MAX_KEY);
    }

    /// This module's tests, for tests/unit.rs to run.
    pub(crate) const TESTS: &[(&str, fn())] = &[(
        "keys_count_the_finite_values_in_order",
        keys_count_the_finite_values_in_order,
    )];
}
