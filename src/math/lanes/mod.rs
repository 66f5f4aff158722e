//! The f32 lanes the hot kernels compute in: [`LaneOps`], the operations at any width, and
//! [`Lanes`], 8 lanes with what the 8-lane kernels need besides. Three types: `wide`'s
//! `f32x8` (two SSE halves: the baseline build), `Avx8` (one 256-bit AVX register: the AVX2
//! and AVX-512 builds) and `Avx16` (one 512-bit register: the AVX-512 build's 16-ray camera
//! packets), the AVX types used only inside a kernel's build for them
//! (`avx512_avx2_or_baseline!` in `math::simd`).
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
//! `bitselect` bitwise (tests/library/packet.rs compares the two builds bit for bit).
//!
//! The files: this one holds the traits, [`LaneOps`] and [`Lanes`]; `baseline.rs` their
//! implementation for `wide`'s f32x8, `lanes64.rs` the f64 lanes ([`Lanes64`], `wide`'s
//! f64x4), `avx.rs` the AVX types (`Avx8`, `Avx16`, `Avx4d`) and `tests.rs` the bit-for-bit
//! comparison of the builds.

#[cfg(target_arch = "x86_64")]
#[allow(unsafe_code)]
mod avx;
mod baseline;
mod lanes64;
#[cfg(all(feature = "unit-tests", target_arch = "x86_64"))]
#[deny(dead_code)]
pub(crate) mod tests;

pub use lanes64::Lanes64;
use std::ops::{Add, BitAnd, BitAndAssign, BitOr, BitOrAssign, Div, Mul, Neg, Not, Sub};
pub use wide::{f32x8, f64x4};

#[cfg(all(feature = "unit-tests", target_arch = "x86_64"))]
pub(crate) use avx::Avx4d;
#[cfg(target_arch = "x86_64")]
pub(crate) use avx::{Avx16, Avx8};

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
    /// The f64 lanes of the same build (preparing triangles, the spheres' interval test).
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
