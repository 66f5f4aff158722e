//! The f32 lanes the hot kernels compute in: [`LaneOps`], the operations at any width, and
//! [`Lanes`], 8 lanes with what the 8-lane kernels need besides. Three types: `wide`'s
//! `f32x8` (two SSE halves: the baseline build), `Avx8` (one 256-bit AVX register: the AVX2
//! and AVX-512 builds) and `Avx16` (one 512-bit register: the AVX-512 build's 16-ray camera
//! packets), the AVX types used only inside a kernel's build for them
//! (`avx2_or_baseline!` in `math::simd`).
//!
//! Why two types: `wide` picks its implementation when the crate is compiled
//! (`cfg(target_feature = "avx")`), so without `-C target-cpu` its f32x8 stays two SSE
//! halves even inside a function compiled for AVX2, and the kernels ran at half width
//! (bunny 640×360 flat, one thread: 12% slower than the same code built with
//! `target-cpu=native`). Plain `[f32; 8]` lanes left to LLVM's vectoriser came out half 128-
//! and half 256-bit, and 3% slower than `wide`.
//!
//! Both types compute the same bits: the same IEEE operations lane by lane, no contraction to
//! FMA, `max`/`min` keeping `self` where `rhs` is NaN (and `rhs` where `self` is), the
//! `fast_` forms as x86's `maxps`/`minps`, comparisons giving all-ones or all-zeros lanes,
//! `bitselect` bitwise (tests/packet.rs compares the two builds bit for bit).

use std::ops::{Add, BitAnd, BitAndAssign, BitOr, BitOrAssign, Div, Mul, Neg, Not, Sub};
pub use wide::{f32x8, f64x4};

/// The lane operations the kernels use (`wide`'s names), at any width: 8 lanes ([`Lanes`])
/// or 16 (`Avx16`, the AVX-512 build's camera packets over a small scene).
pub trait LaneOps:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + BitAnd<Output = Self>
    + BitOr<Output = Self>
    + Not<Output = Self>
    + BitAndAssign
    + BitOrAssign
{
    /// The number of lanes (8 or 16).
    const WIDTH: usize;
    /// The 8 lanes of the same build (a BVH node's 8 children, a block's 8 triangles).
    type Eight: Lanes;
    fn splat(x: f32) -> Self;
    /// Lanes from `a[..WIDTH]`.
    fn load(a: &[f32]) -> Self;
    /// The lanes into `out[..WIDTH]`.
    fn store(self, out: &mut [f32]);
    fn sqrt(self) -> Self;
    fn simd_lt(self, rhs: Self) -> Self;
    fn simd_le(self, rhs: Self) -> Self;
    fn simd_gt(self, rhs: Self) -> Self;
    fn simd_ge(self, rhs: Self) -> Self;
    fn simd_eq(self, rhs: Self) -> Self;
    /// True where unequal or unordered.
    fn simd_ne(self, rhs: Self) -> Self;
    /// `self` as a mask: `if_one`'s bits where its bits are set, else `if_zero`'s.
    fn bitselect(self, if_one: Self, if_zero: Self) -> Self;
    /// Bit l set where lane l's sign bit is.
    fn to_bitmask(self) -> u32;
    fn abs(self) -> Self;
    /// The larger; `self` where `rhs` is NaN, `rhs` where `self` is.
    fn max(self, rhs: Self) -> Self;
    /// The smaller; `self` where `rhs` is NaN, `rhs` where `self` is.
    fn min(self, rhs: Self) -> Self;
    /// x86 `maxps`: `self` where it is greater, else `rhs`.
    fn fast_max(self, rhs: Self) -> Self;
    /// x86 `minps`: `self` where it is smaller, else `rhs`.
    fn fast_min(self, rhs: Self) -> Self;
    /// The greatest lane by x86 `maxps`'s rule (`a` where `a > b`, else `b`); 8 lanes in
    /// this order: lanes l and l + 4, then those pairs 0 and 2, 1 and 3, then the two left
    /// (without NaN, every order gives the same).
    fn reduce_max(self) -> f32;
    /// The least lane by x86 `minps`'s rule (`a` where `a < b`, else `b`), in
    /// [`LaneOps::reduce_max`]'s order.
    fn reduce_min(self) -> f32;
    /// All-ones lanes where bit l of `mask` is set, else zeros (a mask for `bitselect`).
    fn from_bitmask(mask: u32) -> Self;
    /// Lane l is lane l mod 8 of `x`.
    fn repeat_eight(x: Self::Eight) -> Self;

    /// Lane `l`.
    #[inline(always)]
    fn lane(self, l: usize) -> f32 {
        let mut all = [0.0f32; 16];
        self.store(&mut all);
        all[l & 15]
    }
    #[inline(always)]
    fn zero() -> Self {
        Self::splat(0.0)
    }
    #[inline(always)]
    fn one() -> Self {
        Self::splat(1.0)
    }
    /// Every lane's bit set.
    #[inline(always)]
    fn full() -> u32 {
        u32::MAX >> (32 - Self::WIDTH)
    }
    #[inline(always)]
    fn all(self) -> bool {
        self.to_bitmask() == Self::full()
    }
    #[inline(always)]
    fn any(self) -> bool {
        self.to_bitmask() != 0
    }
    #[inline(always)]
    fn none(self) -> bool {
        self.to_bitmask() == 0
    }
}

/// 8 lanes, with what the 8-lane kernels (BVH walks, preparing triangles, shading) need
/// beyond [`LaneOps`].
pub trait Lanes: LaneOps {
    /// The f64 lanes of the same build (for preparing triangles).
    type F64: Lanes64;
    fn from_array(a: [f32; 8]) -> Self;
    fn to_array(self) -> [f32; 8];
    /// From the kernels' public form.
    fn from_wide(x: f32x8) -> Self;
    /// To the kernels' public form.
    fn to_wide(self) -> f32x8;
    /// Lane by lane, the bit patterns as integers: `self − a + b` (wrapping).
    fn step_bits(self, a: Self, b: Self) -> Self;

    /// Per lane the bit pattern of `bits[l]` (ids moved through float lanes).
    #[inline(always)]
    fn from_bits(bits: [u32; 8]) -> Self {
        let b = bits;
        Self::from_array([
            f32::from_bits(b[0]),
            f32::from_bits(b[1]),
            f32::from_bits(b[2]),
            f32::from_bits(b[3]),
            f32::from_bits(b[4]),
            f32::from_bits(b[5]),
            f32::from_bits(b[6]),
            f32::from_bits(b[7]),
        ])
    }
}

/// The 8-lane order of [`LaneOps::reduce_max`] and `reduce_min`, lane by lane, `pick`
/// choosing of two (`maxps`'s or `minps`'s rule).
#[inline(always)]
fn reduce8(a: [f32; 8], pick: impl Fn(f32, f32) -> f32) -> f32 {
    let m = [
        pick(a[0], a[4]),
        pick(a[1], a[5]),
        pick(a[2], a[6]),
        pick(a[3], a[7]),
    ];
    pick(pick(m[0], m[2]), pick(m[1], m[3]))
}

impl LaneOps for f32x8 {
    const WIDTH: usize = 8;
    type Eight = f32x8;
    #[inline(always)]
    fn splat(x: f32) -> Self {
        f32x8::splat(x)
    }
    #[inline(always)]
    fn load(a: &[f32]) -> Self {
        f32x8::from(<[f32; 8]>::try_from(&a[..8]).expect("8 lanes"))
    }
    #[inline(always)]
    fn store(self, out: &mut [f32]) {
        out[..8].copy_from_slice(&f32x8::to_array(self));
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        f32x8::sqrt(self)
    }
    #[inline(always)]
    fn simd_lt(self, rhs: Self) -> Self {
        f32x8::simd_lt(self, rhs)
    }
    #[inline(always)]
    fn simd_le(self, rhs: Self) -> Self {
        f32x8::simd_le(self, rhs)
    }
    #[inline(always)]
    fn simd_gt(self, rhs: Self) -> Self {
        f32x8::simd_gt(self, rhs)
    }
    #[inline(always)]
    fn simd_ge(self, rhs: Self) -> Self {
        f32x8::simd_ge(self, rhs)
    }
    #[inline(always)]
    fn simd_eq(self, rhs: Self) -> Self {
        f32x8::simd_eq(self, rhs)
    }
    #[inline(always)]
    fn simd_ne(self, rhs: Self) -> Self {
        f32x8::simd_ne(self, rhs)
    }
    #[inline(always)]
    fn bitselect(self, if_one: Self, if_zero: Self) -> Self {
        f32x8::bitselect(self, if_one, if_zero)
    }
    #[inline(always)]
    fn to_bitmask(self) -> u32 {
        f32x8::to_bitmask(self)
    }
    #[inline(always)]
    fn abs(self) -> Self {
        f32x8::abs(self)
    }
    #[inline(always)]
    fn max(self, rhs: Self) -> Self {
        f32x8::max(self, rhs)
    }
    #[inline(always)]
    fn min(self, rhs: Self) -> Self {
        f32x8::min(self, rhs)
    }
    #[inline(always)]
    fn fast_max(self, rhs: Self) -> Self {
        f32x8::fast_max(self, rhs)
    }
    #[inline(always)]
    fn fast_min(self, rhs: Self) -> Self {
        f32x8::fast_min(self, rhs)
    }
    #[inline(always)]
    fn reduce_max(self) -> f32 {
        reduce8(self.to_array(), |x, y| if x > y { x } else { y })
    }
    #[inline(always)]
    fn reduce_min(self) -> f32 {
        reduce8(self.to_array(), |x, y| if x < y { x } else { y })
    }
    #[inline(always)]
    fn from_bitmask(mask: u32) -> Self {
        let lane = |l: u32| if mask & (1 << l) != 0 { u32::MAX } else { 0 };
        <Self as Lanes>::from_bits(std::array::from_fn(|l| lane(l as u32)))
    }
    #[inline(always)]
    fn repeat_eight(x: f32x8) -> Self {
        x
    }
}

impl Lanes for f32x8 {
    type F64 = f64x4;
    #[inline(always)]
    fn from_array(a: [f32; 8]) -> Self {
        f32x8::from(a)
    }
    #[inline(always)]
    fn to_array(self) -> [f32; 8] {
        f32x8::to_array(self)
    }
    #[inline(always)]
    fn from_wide(x: f32x8) -> Self {
        x
    }
    #[inline(always)]
    fn to_wide(self) -> f32x8 {
        self
    }
    #[inline(always)]
    fn step_bits(self, a: Self, b: Self) -> Self {
        use wide::{bytemuck::cast, i32x8};
        let (x, a, b): (i32x8, i32x8, i32x8) = (cast(self), cast(a), cast(b));
        cast(x - a + b)
    }
}

/// 4 f64 lanes, with what preparing 4 triangles at once needs ([`Lanes`]' semantics).
pub trait Lanes64:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + BitAnd<Output = Self>
{
    fn splat(x: f64) -> Self;
    fn from_array(a: [f64; 4]) -> Self;
    fn to_array(self) -> [f64; 4];
    fn simd_lt(self, rhs: Self) -> Self;
    fn simd_gt(self, rhs: Self) -> Self;
    fn to_bitmask(self) -> u32;
    fn abs(self) -> Self;
    /// The larger; `self` where `rhs` is NaN, `rhs` where `self` is (as `f64::max`).
    fn max(self, rhs: Self) -> Self;
    /// x86 `maxpd`: `self` where it is greater, else `rhs`.
    fn fast_max(self, rhs: Self) -> Self;
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
    fn simd_gt(self, rhs: Self) -> Self {
        f64x4::simd_gt(self, rhs)
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
    fn max(self, rhs: Self) -> Self {
        f64x4::max(self, rhs)
    }
    #[inline(always)]
    fn fast_max(self, rhs: Self) -> Self {
        f64x4::fast_max(self, rhs)
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

#[cfg(all(test, target_arch = "x86_64"))]
pub(crate) use avx::Avx4d;
#[cfg(target_arch = "x86_64")]
pub(crate) use avx::{Avx16, Avx8};

/// `Avx8` and `Avx4d`: every operation one AVX instruction (or a few), through
/// `std::arch`; `Avx16`, the same with AVX-512 (the AVX-512 build only).
///
/// Soundness: their operations execute AVX2 instructions, so such a value must exist only
/// where the CPU has AVX2. The types are private to the crate and named only in the AVX2 arm
/// of `avx2_or_baseline!`, after the run-time check ([`super::simd::level`]), and in
/// tests behind the same check; every constructor (`splat`, `from_array`, which the others
/// go through) asserts it in debug builds.
#[cfg(target_arch = "x86_64")]
#[allow(unsafe_code)]
mod avx {
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
            // SAFETY: as in `binary!`.
            Self(unsafe { _mm256_cmp_pd::<_CMP_LT_OQ>(self.0, rhs.0) })
        }
        #[inline(always)]
        fn simd_gt(self, rhs: Self) -> Self {
            // SAFETY: as in `binary!`.
            Self(unsafe { _mm256_cmp_pd::<_CMP_GT_OQ>(self.0, rhs.0) })
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
}

#[cfg(all(test, target_arch = "x86_64"))]
mod tests {
    use super::*;
    use crate::math::simd::{detected, has_avx2, SimdLevel};

    /// Every operation of [`Lanes`] on both types (`Avx8` in the AVX2 and the AVX-512
    /// builds), bit for bit, on values that probe the
    /// corners (signed zeros, NaN, infinities, subnormals, ties).
    #[test]
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
        #[target_feature(enable = "avx2,fma")]
        fn avx2(a: [f32; 8], b: [f32; 8]) -> Vec<[u32; 8]> {
            run::<Avx8>(a, b)
        }
        #[target_feature(enable = "avx512f,avx512vl,avx512bw,avx512dq,avx512cd,avx2,fma")]
        fn avx512(a: [f32; 8], b: [f32; 8]) -> Vec<[u32; 8]> {
            run::<Avx8>(a, b)
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

    /// `Avx16` computes as two 8-lane halves: every [`LaneOps`] operation, bit for bit, on
    /// the same corner values, against `wide`'s f32x8 on each half (the bitmask as the
    /// halves' masks side by side; `reduce_max` as the halves' lane-wise `maxps`, then the
    /// 8-lane order).
    #[test]
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

    #[target_feature(enable = "avx512f,avx512vl,avx512bw,avx512dq,avx512cd,avx2,fma")]
    fn avx512_ops(a: &[f32], b: &[f32]) -> Vec<Vec<u32>> {
        ops::<Avx16>(a, b)
    }

    #[target_feature(enable = "avx512f,avx512vl,avx512bw,avx512dq,avx512cd,avx2,fma")]
    fn avx512_reduce_max(a: &[f32]) -> f32 {
        Avx16::load(a).reduce_max()
    }
}
