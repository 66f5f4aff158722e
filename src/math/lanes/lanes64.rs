//! The f64 lanes that preparing 4 triangles at once and the spheres' interval test
//! ([`crate::math::interval::IntervalX4`]) compute in: [`Lanes64`], and its baseline
//! implementation for `wide`'s f64x4 (`Avx4d` in `avx.rs` is the AVX one).

use super::f64x4;
use std::ops::{Add, BitAnd, BitOr, Div, Mul, Neg, Not, Sub};

/// 4 f64 lanes, with what preparing 4 triangles and testing 4 rays against a sphere need
/// ([`Lanes`]' semantics).
///
/// [`Lanes`]: super::Lanes
pub trait Lanes64:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + BitAnd<Output = Self>
    + BitOr<Output = Self>
    + Not<Output = Self>
{
    fn splat(x: f64) -> Self;
    fn from_array(a: [f64; 4]) -> Self;
    fn to_array(self) -> [f64; 4];
    fn simd_lt(self, rhs: Self) -> Self;
    fn simd_le(self, rhs: Self) -> Self;
    fn simd_gt(self, rhs: Self) -> Self;
    fn simd_ge(self, rhs: Self) -> Self;
    /// All-ones lanes where the value is neither infinite nor NaN.
    fn is_finite(self) -> Self;
    /// `self` as a mask: `if_one`'s bits where its bits are set, else `if_zero`'s.
    fn bitselect(self, if_one: Self, if_zero: Self) -> Self;
    fn to_bitmask(self) -> u32;
    fn abs(self) -> Self;
    fn sqrt(self) -> Self;
    /// The larger; `self` where `rhs` is NaN, `rhs` where `self` is (as `f64::max`).
    fn max(self, rhs: Self) -> Self;
    /// x86 `maxpd`: `self` where it is greater, else `rhs`.
    fn fast_max(self, rhs: Self) -> Self;
    /// x86 `minpd`: `self` where it is smaller, else `rhs`.
    fn fast_min(self, rhs: Self) -> Self;
    /// Each lane rounded to f32 (as `x as f32`).
    fn to_f32(self) -> [f32; 4];
    /// Each lane rounded to f32 and back.
    fn round_f32(self) -> Self;
}

impl Lanes64 for f64x4 {
    #[inline(always)]
    fn splat(x: f64) -> Self {
        f64x4::splat(x)
    }
    #[inline(always)]
    fn from_array(a: [f64; 4]) -> Self {
        f64x4::from(a)
    }
    #[inline(always)]
    fn to_array(self) -> [f64; 4] {
        f64x4::to_array(self)
    }
    #[inline(always)]
    fn simd_lt(self, rhs: Self) -> Self {
        f64x4::simd_lt(self, rhs)
    }
    #[inline(always)]
    fn simd_le(self, rhs: Self) -> Self {
        f64x4::simd_le(self, rhs)
    }
    #[inline(always)]
    fn simd_gt(self, rhs: Self) -> Self {
        f64x4::simd_gt(self, rhs)
    }
    #[inline(always)]
    fn simd_ge(self, rhs: Self) -> Self {
        f64x4::simd_ge(self, rhs)
    }
    #[inline(always)]
    fn is_finite(self) -> Self {
        f64x4::is_finite(self)
    }
    #[inline(always)]
    fn bitselect(self, if_one: Self, if_zero: Self) -> Self {
        f64x4::bitselect(self, if_one, if_zero)
    }
    #[inline(always)]
    fn to_bitmask(self) -> u32 {
        f64x4::to_bitmask(self)
    }
    #[inline(always)]
    fn abs(self) -> Self {
        f64x4::abs(self)
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        f64x4::sqrt(self)
    }
    #[inline(always)]
    fn max(self, rhs: Self) -> Self {
        f64x4::max(self, rhs)
    }
    #[inline(always)]
    fn fast_max(self, rhs: Self) -> Self {
        f64x4::fast_max(self, rhs)
    }
    #[inline(always)]
    fn fast_min(self, rhs: Self) -> Self {
        f64x4::fast_min(self, rhs)
    }
    #[inline(always)]
    fn to_f32(self) -> [f32; 4] {
        let a = self.to_array();
        [a[0] as f32, a[1] as f32, a[2] as f32, a[3] as f32]
    }
    #[inline(always)]
    fn round_f32(self) -> Self {
        let a = self.to_f32();
        f64x4::from([a[0] as f64, a[1] as f64, a[2] as f64, a[3] as f64])
    }
}
