//! `Avx8` and `Avx4d`: every operation one AVX instruction (or a few), through
//! `std::arch`; `Avx16`, the same with AVX-512 (the AVX-512 build only).
//!
//! Soundness: their operations execute AVX2 instructions, so such a value must exist only
//! where the CPU has AVX2. The types are private to the crate and named only in the AVX
//! builds of `avx512_avx2_or_baseline!` (`Avx4d` as `Avx8`'s `Lanes::F64`), reached after
//! the run-time check (`math::simd::level`) or through a token that check made
//! (`math::simd::Isa`), and in tests behind the same check; every constructor (`splat`, `from_array`, which the others
//! go through) asserts it in debug builds.

use super::{f32x8, LaneOps, Lanes, Lanes64};
use std::arch::x86_64::*;
use std::ops::{Add, BitAnd, BitAndAssign, BitOr, BitOrAssign, Div, Mul, Neg, Not, Sub};

/// 8 f32 lanes in one AVX register (see the module docs for when it may exist).
#[derive(Clone, Copy, Debug)]
#[repr(transparent)]
pub struct Avx8(__m256);

macro_rules! binary {
    ($ty:ident, $trait:ident, $method:ident, $op:ident) => {
        impl $trait for $ty {
            type Output = Self;
            #[inline(always)]
            fn $method(self, rhs: Self) -> Self {
                // SAFETY: such a value exists only where the CPU has AVX2 (the module's docs).
                Self(unsafe { $op(self.0, rhs.0) })
            }
        }
    };
}
binary!(Avx8, Add, add, _mm256_add_ps);
binary!(Avx8, Sub, sub, _mm256_sub_ps);
binary!(Avx8, Mul, mul, _mm256_mul_ps);
binary!(Avx8, Div, div, _mm256_div_ps);
binary!(Avx8, BitAnd, bitand, _mm256_and_ps);
binary!(Avx8, BitOr, bitor, _mm256_or_ps);

/// `-x` and `!x` (a flip of the sign bits, of every bit) and the assigning `&=`, `|=`,
/// for a lane type with its xor, splat, integer splat and cast intrinsics.
macro_rules! sign_not_assign {
    ($ty:ident, $xor:ident, $set1:ident, $set1_int:ident, $cast:ident) => {
        impl Neg for $ty {
            type Output = Self;
            #[inline(always)]
            fn neg(self) -> Self {
                // SAFETY: as in `binary!`.
                Self(unsafe { $xor(self.0, $set1(-0.0)) })
            }
        }

        impl Not for $ty {
            type Output = Self;
            #[inline(always)]
            fn not(self) -> Self {
                // SAFETY: as in `binary!`.
                Self(unsafe { $xor(self.0, $cast($set1_int(-1))) })
            }
        }

        impl BitAndAssign for $ty {
            #[inline(always)]
            fn bitand_assign(&mut self, rhs: Self) {
                *self = *self & rhs;
            }
        }

        impl BitOrAssign for $ty {
            #[inline(always)]
            fn bitor_assign(&mut self, rhs: Self) {
                *self = *self | rhs;
            }
        }
    };
}
/// The comparisons of [`LaneOps`] through the type's `cmp::<PREDICATE>` (ordered and
/// quiet, `simd_ne` unordered: true where either side is NaN).
macro_rules! compares_through_cmp {
    () => {
        #[inline(always)]
        fn simd_lt(self, rhs: Self) -> Self {
            self.cmp::<_CMP_LT_OQ>(rhs)
        }
        #[inline(always)]
        fn simd_le(self, rhs: Self) -> Self {
            self.cmp::<_CMP_LE_OQ>(rhs)
        }
        #[inline(always)]
        fn simd_gt(self, rhs: Self) -> Self {
            self.cmp::<_CMP_GT_OQ>(rhs)
        }
        #[inline(always)]
        fn simd_ge(self, rhs: Self) -> Self {
            self.cmp::<_CMP_GE_OQ>(rhs)
        }
        #[inline(always)]
        fn simd_eq(self, rhs: Self) -> Self {
            self.cmp::<_CMP_EQ_OQ>(rhs)
        }
        #[inline(always)]
        fn simd_ne(self, rhs: Self) -> Self {
            self.cmp::<_CMP_NEQ_UQ>(rhs)
        }
    };
}

/// [`LaneOps::max`] and [`LaneOps::min`] from the `fast_` forms: `self` where `rhs` is
/// NaN (the x86 forms give `rhs` there).
macro_rules! nan_keeping_max_min {
    () => {
        #[inline(always)]
        fn max(self, rhs: Self) -> Self {
            rhs.cmp::<_CMP_UNORD_Q>(rhs)
                .bitselect(self, self.fast_max(rhs))
        }
        #[inline(always)]
        fn min(self, rhs: Self) -> Self {
            rhs.cmp::<_CMP_UNORD_Q>(rhs)
                .bitselect(self, self.fast_min(rhs))
        }
    };
}

sign_not_assign!(
    Avx8,
    _mm256_xor_ps,
    _mm256_set1_ps,
    _mm256_set1_epi32,
    _mm256_castsi256_ps
);

impl Avx8 {
    #[inline(always)]
    fn cmp<const OP: i32>(self, rhs: Self) -> Self {
        // SAFETY: as in `binary!`.
        Self(unsafe { _mm256_cmp_ps::<OP>(self.0, rhs.0) })
    }
}

impl LaneOps for Avx8 {
    const WIDTH: usize = 8;
    type Eight = Avx8;
    #[inline(always)]
    fn splat(x: f32) -> Self {
        debug_assert!(is_x86_feature_detected!("avx2"));
        // SAFETY: as in `binary!`.
        Self(unsafe { _mm256_set1_ps(x) })
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        // SAFETY: as in `binary!`.
        Self(unsafe { _mm256_sqrt_ps(self.0) })
    }
    compares_through_cmp!();
    #[inline(always)]
    fn bitselect(self, if_one: Self, if_zero: Self) -> Self {
        // SAFETY: as in `binary!`.
        Self(unsafe {
            _mm256_or_ps(
                _mm256_and_ps(self.0, if_one.0),
                _mm256_andnot_ps(self.0, if_zero.0),
            )
        })
    }
    #[inline(always)]
    fn to_bitmask(self) -> u32 {
        // SAFETY: as in `binary!`.
        unsafe { _mm256_movemask_ps(self.0) as u32 }
    }
    #[inline(always)]
    fn reduce_max(self) -> f32 {
        // SAFETY: as in `binary!`.
        unsafe {
            let m = _mm_max_ps(
                _mm256_castps256_ps128(self.0),
                _mm256_extractf128_ps::<1>(self.0),
            );
            let m = _mm_max_ps(m, _mm_movehl_ps(m, m));
            _mm_cvtss_f32(_mm_max_ss(m, _mm_shuffle_ps::<1>(m, m)))
        }
    }
    #[inline(always)]
    fn abs(self) -> Self {
        // SAFETY: as in `binary!`.
        Self(unsafe { _mm256_andnot_ps(_mm256_set1_ps(-0.0), self.0) })
    }
    nan_keeping_max_min!();
    #[inline(always)]
    fn fast_max(self, rhs: Self) -> Self {
        // SAFETY: as in `binary!`.
        Self(unsafe { _mm256_max_ps(self.0, rhs.0) })
    }
    #[inline(always)]
    fn fast_min(self, rhs: Self) -> Self {
        // SAFETY: as in `binary!`.
        Self(unsafe { _mm256_min_ps(self.0, rhs.0) })
    }
    #[inline(always)]
    fn load(a: &[f32]) -> Self {
        debug_assert!(is_x86_feature_detected!("avx2"));
        let a = &a[..8];
        // SAFETY: as in `binary!`; the load reads the 8 floats of `a`.
        Self(unsafe { _mm256_loadu_ps(a.as_ptr()) })
    }
    #[inline(always)]
    fn store(self, out: &mut [f32]) {
        let out = &mut out[..8];
        // SAFETY: as in `binary!`; the store writes the 8 floats of `out`.
        unsafe { _mm256_storeu_ps(out.as_mut_ptr(), self.0) };
    }
    #[inline(always)]
    fn reduce_min(self) -> f32 {
        // SAFETY: as in `binary!`.
        unsafe {
            let m = _mm_min_ps(
                _mm256_castps256_ps128(self.0),
                _mm256_extractf128_ps::<1>(self.0),
            );
            let m = _mm_min_ps(m, _mm_movehl_ps(m, m));
            _mm_cvtss_f32(_mm_min_ss(m, _mm_shuffle_ps::<1>(m, m)))
        }
    }
    #[inline(always)]
    fn from_bitmask(mask: u32) -> Self {
        // The mask in every lane, each lane's bit tested: three instructions, where the
        // trait's lane-by-lane form built an array.
        // SAFETY: as in `binary!` (AVX2 for the integer lanes).
        Self(unsafe {
            let bits = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
            let m = _mm256_and_si256(_mm256_set1_epi32(mask as i32), bits);
            _mm256_castsi256_ps(_mm256_cmpeq_epi32(m, bits))
        })
    }
    #[inline(always)]
    fn repeat_eight(x: Avx8) -> Self {
        x
    }
}

impl Lanes for Avx8 {
    type F64 = Avx4d;
    #[inline(always)]
    fn from_array(a: [f32; 8]) -> Self {
        debug_assert!(is_x86_feature_detected!("avx2"));
        // SAFETY: as in `binary!`; the load reads the 8 floats of `a`.
        Self(unsafe { _mm256_loadu_ps(a.as_ptr()) })
    }
    #[inline(always)]
    fn to_array(self) -> [f32; 8] {
        let mut a = [0f32; 8];
        // SAFETY: as in `binary!`; the store writes the 8 floats of `a`.
        unsafe { _mm256_storeu_ps(a.as_mut_ptr(), self.0) };
        a
    }
    #[inline(always)]
    fn from_wide(x: f32x8) -> Self {
        Self::from_array(x.to_array())
    }
    #[inline(always)]
    fn to_wide(self) -> f32x8 {
        f32x8::from(self.to_array())
    }
    #[inline(always)]
    fn step_bits(self, a: Self, b: Self) -> Self {
        // SAFETY: as in `binary!` (AVX2 for the integer lanes: an Avx8 is made only in the
        // AVX2 builds).
        Self(unsafe {
            let (x, a, b) = (
                _mm256_castps_si256(self.0),
                _mm256_castps_si256(a.0),
                _mm256_castps_si256(b.0),
            );
            _mm256_castsi256_ps(_mm256_add_epi32(_mm256_sub_epi32(x, a), b))
        })
    }
}

/// 16 f32 lanes in one AVX-512 register: made only in the AVX-512 build, after the same
/// run-time check as [`Avx8`] (AVX-512 F and DQ for the operations here). Masks are
/// lanes of all ones or zeros, as in the 8-lane types: a compare's mask register is
/// spread into lanes (`vpmovm2d`), and LLVM folds most of those back.
#[derive(Clone, Copy, Debug)]
#[repr(transparent)]
pub struct Avx16(__m512);

binary!(Avx16, Add, add, _mm512_add_ps);
binary!(Avx16, Sub, sub, _mm512_sub_ps);
binary!(Avx16, Mul, mul, _mm512_mul_ps);
binary!(Avx16, Div, div, _mm512_div_ps);
binary!(Avx16, BitAnd, bitand, _mm512_and_ps);
binary!(Avx16, BitOr, bitor, _mm512_or_ps);

sign_not_assign!(
    Avx16,
    _mm512_xor_ps,
    _mm512_set1_ps,
    _mm512_set1_epi32,
    _mm512_castsi512_ps
);

impl Avx16 {
    #[inline(always)]
    fn cmp<const OP: i32>(self, rhs: Self) -> Self {
        // SAFETY: as in `binary!`.
        Self(unsafe {
            _mm512_castsi512_ps(_mm512_movm_epi32(_mm512_cmp_ps_mask::<OP>(self.0, rhs.0)))
        })
    }
}

impl LaneOps for Avx16 {
    const WIDTH: usize = 16;
    type Eight = Avx8;
    #[inline(always)]
    fn splat(x: f32) -> Self {
        debug_assert!(is_x86_feature_detected!("avx512dq"));
        // SAFETY: as in `binary!`.
        Self(unsafe { _mm512_set1_ps(x) })
    }
    #[inline(always)]
    fn load(a: &[f32]) -> Self {
        debug_assert!(is_x86_feature_detected!("avx512dq"));
        let a = &a[..16];
        // SAFETY: as in `binary!`; the load reads the 16 floats of `a`.
        Self(unsafe { _mm512_loadu_ps(a.as_ptr()) })
    }
    #[inline(always)]
    fn store(self, out: &mut [f32]) {
        let out = &mut out[..16];
        // SAFETY: as in `binary!`; the store writes the 16 floats of `out`.
        unsafe { _mm512_storeu_ps(out.as_mut_ptr(), self.0) };
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        // SAFETY: as in `binary!`.
        Self(unsafe { _mm512_sqrt_ps(self.0) })
    }
    compares_through_cmp!();
    #[inline(always)]
    fn bitselect(self, if_one: Self, if_zero: Self) -> Self {
        // SAFETY: as in `binary!`.
        Self(unsafe {
            _mm512_or_ps(
                _mm512_and_ps(self.0, if_one.0),
                _mm512_andnot_ps(self.0, if_zero.0),
            )
        })
    }
    #[inline(always)]
    fn to_bitmask(self) -> u32 {
        // SAFETY: as in `binary!`.
        unsafe { _mm512_movepi32_mask(_mm512_castps_si512(self.0)) as u32 }
    }
    #[inline(always)]
    fn abs(self) -> Self {
        // SAFETY: as in `binary!`.
        Self(unsafe { _mm512_andnot_ps(_mm512_set1_ps(-0.0), self.0) })
    }
    nan_keeping_max_min!();
    #[inline(always)]
    fn fast_max(self, rhs: Self) -> Self {
        // SAFETY: as in `binary!`.
        Self(unsafe { _mm512_max_ps(self.0, rhs.0) })
    }
    #[inline(always)]
    fn fast_min(self, rhs: Self) -> Self {
        // SAFETY: as in `binary!`.
        Self(unsafe { _mm512_min_ps(self.0, rhs.0) })
    }
    #[inline(always)]
    fn reduce_max(self) -> f32 {
        // The two halves by `maxps`, then the 8-lane order.
        // SAFETY: as in `binary!`.
        let half = unsafe {
            Avx8(_mm256_max_ps(
                _mm512_castps512_ps256(self.0),
                _mm512_extractf32x8_ps::<1>(self.0),
            ))
        };
        half.reduce_max()
    }
    #[inline(always)]
    fn reduce_min(self) -> f32 {
        // The two halves by `minps`, then the 8-lane order.
        // SAFETY: as in `binary!`.
        let half = unsafe {
            Avx8(_mm256_min_ps(
                _mm512_castps512_ps256(self.0),
                _mm512_extractf32x8_ps::<1>(self.0),
            ))
        };
        half.reduce_min()
    }
    #[inline(always)]
    fn from_bitmask(mask: u32) -> Self {
        // SAFETY: as in `binary!`.
        Self(unsafe { _mm512_castsi512_ps(_mm512_movm_epi32(mask as u16)) })
    }
    #[inline(always)]
    fn repeat_eight(x: Avx8) -> Self {
        // SAFETY: as in `binary!`.
        Self(unsafe { _mm512_insertf32x8::<1>(_mm512_castps256_ps512(x.0), x.0) })
    }
}

/// 4 f64 lanes in one AVX register (made, like [`Avx8`], only where the CPU has AVX2).
#[derive(Clone, Copy, Debug)]
#[repr(transparent)]
pub struct Avx4d(__m256d);

binary!(Avx4d, Add, add, _mm256_add_pd);
binary!(Avx4d, Sub, sub, _mm256_sub_pd);
binary!(Avx4d, Mul, mul, _mm256_mul_pd);
binary!(Avx4d, Div, div, _mm256_div_pd);
binary!(Avx4d, BitAnd, bitand, _mm256_and_pd);
binary!(Avx4d, BitOr, bitor, _mm256_or_pd);
sign_not_assign!(
    Avx4d,
    _mm256_xor_pd,
    _mm256_set1_pd,
    _mm256_set1_epi64x,
    _mm256_castsi256_pd
);

impl Avx4d {
    #[inline(always)]
    fn cmp<const OP: i32>(self, rhs: Self) -> Self {
        // SAFETY: as in `binary!`.
        Self(unsafe { _mm256_cmp_pd::<OP>(self.0, rhs.0) })
    }
}

impl Lanes64 for Avx4d {
    #[inline(always)]
    fn splat(x: f64) -> Self {
        debug_assert!(is_x86_feature_detected!("avx2"));
        // SAFETY: as in `binary!`.
        Self(unsafe { _mm256_set1_pd(x) })
    }
    #[inline(always)]
    fn from_array(a: [f64; 4]) -> Self {
        debug_assert!(is_x86_feature_detected!("avx2"));
        // SAFETY: as in `binary!`; the load reads the 4 doubles of `a`.
        Self(unsafe { _mm256_loadu_pd(a.as_ptr()) })
    }
    #[inline(always)]
    fn to_array(self) -> [f64; 4] {
        let mut a = [0f64; 4];
        // SAFETY: as in `binary!`; the store writes the 4 doubles of `a`.
        unsafe { _mm256_storeu_pd(a.as_mut_ptr(), self.0) };
        a
    }
    #[inline(always)]
    fn simd_lt(self, rhs: Self) -> Self {
        self.cmp::<_CMP_LT_OQ>(rhs)
    }
    #[inline(always)]
    fn simd_le(self, rhs: Self) -> Self {
        self.cmp::<_CMP_LE_OQ>(rhs)
    }
    #[inline(always)]
    fn simd_gt(self, rhs: Self) -> Self {
        self.cmp::<_CMP_GT_OQ>(rhs)
    }
    #[inline(always)]
    fn simd_ge(self, rhs: Self) -> Self {
        self.cmp::<_CMP_GE_OQ>(rhs)
    }
    #[inline(always)]
    fn is_finite(self) -> Self {
        // |x| < ∞: false for ±∞ and (unordered) for NaN.
        self.abs().cmp::<_CMP_LT_OQ>(Self::splat(f64::INFINITY))
    }
    #[inline(always)]
    fn bitselect(self, if_one: Self, if_zero: Self) -> Self {
        // SAFETY: as in `binary!`.
        Self(unsafe {
            _mm256_or_pd(
                _mm256_and_pd(if_one.0, self.0),
                _mm256_andnot_pd(self.0, if_zero.0),
            )
        })
    }
    #[inline(always)]
    fn to_bitmask(self) -> u32 {
        // SAFETY: as in `binary!`.
        unsafe { _mm256_movemask_pd(self.0) as u32 }
    }
    #[inline(always)]
    fn abs(self) -> Self {
        // SAFETY: as in `binary!`.
        Self(unsafe { _mm256_andnot_pd(_mm256_set1_pd(-0.0), self.0) })
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        // SAFETY: as in `binary!`.
        Self(unsafe { _mm256_sqrt_pd(self.0) })
    }
    #[inline(always)]
    fn max(self, rhs: Self) -> Self {
        // SAFETY: as in `binary!`.
        Self(unsafe {
            let nan = _mm256_cmp_pd::<_CMP_UNORD_Q>(rhs.0, rhs.0);
            _mm256_blendv_pd(_mm256_max_pd(self.0, rhs.0), self.0, nan)
        })
    }
    #[inline(always)]
    fn fast_max(self, rhs: Self) -> Self {
        // SAFETY: as in `binary!`.
        Self(unsafe { _mm256_max_pd(self.0, rhs.0) })
    }
    #[inline(always)]
    fn fast_min(self, rhs: Self) -> Self {
        // SAFETY: as in `binary!`.
        Self(unsafe { _mm256_min_pd(self.0, rhs.0) })
    }
    #[inline(always)]
    fn to_f32(self) -> [f32; 4] {
        let mut a = [0f32; 4];
        // SAFETY: as in `binary!`; the store writes the 4 floats of `a`.
        unsafe { _mm_storeu_ps(a.as_mut_ptr(), _mm256_cvtpd_ps(self.0)) };
        a
    }
    #[inline(always)]
    fn round_f32(self) -> Self {
        // SAFETY: as in `binary!`.
        Self(unsafe { _mm256_cvtps_pd(_mm256_cvtpd_ps(self.0)) })
    }
}
