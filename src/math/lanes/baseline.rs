//! The baseline build's lanes: `wide`'s f32x8 (two SSE halves) as [`LaneOps`] and
//! [`Lanes`], and the 8-lane order of its reductions.

use super::{f32x8, f64x4, LaneOps, Lanes};

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
