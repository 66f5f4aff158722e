//! f64 interval arithmetic with outward rounding: the middle level of the adaptive method.
//!
//! Every operation rounds to nearest (error ≤ ½ ulp) and then widens each end by one ulp, so
//! the exact real result of the same operations on the exact inputs always lies inside. No
//! hand-derived error bound is needed, which is why the adaptive method uses it for every case
//! the f32 filter cannot decide. f32 and f64 inputs are exact as degenerate intervals.

use crate::math::lanes::{f64x4, Lanes64};
use std::cmp::Ordering;
use std::ops::{Add, Mul, Neg, Sub};

/// A closed interval [lo, hi] holding an unknown real.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interval {
    /// Lower end.
    pub lo: f64,
    /// Upper end.
    pub hi: f64,
}

impl Interval {
    /// The exact value x.
    #[inline]
    pub fn point(x: f64) -> Self {
        Self { lo: x, hi: x }
    }

    /// [lo, hi] from rounded-to-nearest ends widened outward as [`IntervalX4`] widens them
    /// (see there): by |x|·2⁻⁵² + 2⁻¹⁰⁷⁴, at least one ulp, with no branches. For finite
    /// ends (an infinite one gives NaN).
    #[inline(always)]
    pub fn loosely_widened(lo: f64, hi: f64) -> Self {
        Self {
            lo: lo - (lo.abs() * f64::EPSILON + TINY),
            hi: hi + (hi.abs() * f64::EPSILON + TINY),
        }
    }

    /// self² for finite ends, widened as [`Interval::loosely_widened`] widens, never below 0
    /// (the scalar form of [`IntervalX4::square`]).
    #[inline(always)]
    pub fn loosely_squared(self) -> Self {
        let (a, b) = (self.lo * self.lo, self.hi * self.hi);
        let lo = match (self.lo >= 0.0, self.hi <= 0.0) {
            (true, _) => a,
            (_, true) => b,
            _ => 0.0,
        };
        let w = Self::loosely_widened(lo, a.max(b));
        Self {
            lo: w.lo.max(0.0),
            hi: w.hi,
        }
    }

    /// [lo, hi] from rounded-to-nearest ends, widened outward by one ulp.
    #[inline]
    fn widened(lo: f64, hi: f64) -> Self {
        Self {
            lo: lo.next_down(),
            hi: hi.next_up(),
        }
    }

    /// The sign if the interval decides it: `Some(Equal)` only for [0, 0]. NaN ends (from
    /// overflow to ±∞ and ∞ − ∞) decide nothing.
    #[inline]
    pub fn sign(self) -> Option<Ordering> {
        if self.lo > 0.0 {
            Some(Ordering::Greater)
        } else if self.hi < 0.0 {
            Some(Ordering::Less)
        } else if self.lo == 0.0 && self.hi == 0.0 {
            Some(Ordering::Equal)
        } else {
            None
        }
    }

    /// Whether both ends are finite (so the interval means something).
    #[inline]
    pub fn is_finite(self) -> bool {
        self.lo.is_finite() && self.hi.is_finite()
    }

    /// The midpoint (an estimate for reporting, not a bound).
    #[inline]
    pub fn mid(self) -> f64 {
        0.5 * self.lo + 0.5 * self.hi
    }

    /// self / rhs; `None` if rhs may be zero.
    #[inline]
    pub fn checked_div(self, rhs: Interval) -> Option<Interval> {
        if rhs.lo <= 0.0 && rhs.hi >= 0.0 || !rhs.is_finite() {
            return None;
        }
        let q = [
            self.lo / rhs.lo,
            self.lo / rhs.hi,
            self.hi / rhs.lo,
            self.hi / rhs.hi,
        ];
        Some(Self::widened(min4(q), max4(q)))
    }

    /// √self, `None` if self may be negative.
    #[inline]
    pub fn sqrt(self) -> Option<Interval> {
        if self.lo < 0.0 || self.lo.is_nan() {
            return None;
        }
        Some(Self::widened(self.lo.sqrt(), self.hi.sqrt()).clamp_low())
    }

    /// self², tighter than self·self when the interval holds 0.
    #[inline]
    pub fn square(self) -> Interval {
        let (a, b) = (self.lo * self.lo, self.hi * self.hi);
        if self.lo >= 0.0 || self.hi <= 0.0 {
            Self::widened(a.min(b), a.max(b)).clamp_low()
        } else {
            Self::widened(0.0, a.max(b)).clamp_low()
        }
    }

    /// A square or root is never negative.
    #[inline]
    fn clamp_low(self) -> Self {
        Self {
            lo: self.lo.max(0.0),
            hi: self.hi,
        }
    }
}

#[inline]
fn min4(a: [f64; 4]) -> f64 {
    a[0].min(a[1]).min(a[2].min(a[3]))
}

#[inline]
fn max4(a: [f64; 4]) -> f64 {
    a[0].max(a[1]).max(a[2].max(a[3]))
}

impl From<f64> for Interval {
    fn from(x: f64) -> Self {
        Self::point(x)
    }
}

impl Add for Interval {
    type Output = Interval;
    #[inline]
    fn add(self, r: Interval) -> Interval {
        Self::widened(self.lo + r.lo, self.hi + r.hi)
    }
}

impl Sub for Interval {
    type Output = Interval;
    #[inline]
    fn sub(self, r: Interval) -> Interval {
        Self::widened(self.lo - r.hi, self.hi - r.lo)
    }
}

impl Neg for Interval {
    type Output = Interval;
    #[inline]
    fn neg(self) -> Interval {
        Self {
            lo: -self.hi,
            hi: -self.lo,
        }
    }
}

impl Mul for Interval {
    type Output = Interval;
    #[inline]
    fn mul(self, r: Interval) -> Interval {
        let p = [
            self.lo * r.lo,
            self.lo * r.hi,
            self.hi * r.lo,
            self.hi * r.hi,
        ];
        // f64::min/max would drop a NaN (0·∞); keep it so the result decides nothing.
        if p.iter().any(|x| x.is_nan()) {
            return Self {
                lo: f64::NAN,
                hi: f64::NAN,
            };
        }
        Self::widened(min4(p), max4(p))
    }
}

/// A 3-vector of intervals.
pub type IV3 = [Interval; 3];

/// Exact inputs as a vector of point intervals.
#[inline]
pub fn iv3(p: [f64; 3]) -> IV3 {
    p.map(Interval::point)
}

/// a − b
#[inline]
pub fn isub(a: IV3, b: IV3) -> IV3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// a · b
#[inline]
pub fn idot(a: IV3, b: IV3) -> Interval {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// a × b
#[inline]
pub fn icross(a: IV3, b: IV3) -> IV3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Four intervals side by side (the caller's f64 lanes, [`Lanes64`]: a kernel's own build's,
/// one AVX register in the AVX builds, or `wide`'s f64x4; the same bits in each), for the
/// packets' lanes: the operations of [`Interval`] for finite ends, each end widened outward by
/// |x|·2⁻⁵² + 2⁻¹⁰⁷⁴ instead of one ulp (at least one ulp, so at least as wide: two vector
/// operations where `next_down` and `next_up` are a dozen). Ends that over- or underflow are
/// not looked after: callers keep the magnitudes where neither can happen (f32 inputs) and
/// treat non-finite ends as undecided.
#[derive(Clone, Copy, Debug)]
pub struct IntervalX4<F = f64x4> {
    pub lo: F,
    pub hi: F,
}

/// The least subnormal f64, 2⁻¹⁰⁷⁴.
const TINY: f64 = f64::MIN_POSITIVE * f64::EPSILON;

impl<F: Lanes64> IntervalX4<F> {
    /// The exact values x.
    #[inline(always)]
    pub fn point(x: F) -> Self {
        Self { lo: x, hi: x }
    }

    /// One interval in every lane.
    #[inline(always)]
    pub fn splat(x: Interval) -> Self {
        Self {
            lo: F::splat(x.lo),
            hi: F::splat(x.hi),
        }
    }

    /// [lo, hi] from rounded-to-nearest ends, widened outward: the exact x − δ with
    /// δ ≥ ulp(x) is at most `next_down(x)`, and rounding keeps it there (monotone).
    #[inline(always)]
    fn widened(lo: F, hi: F) -> Self {
        let (eps, tiny) = (F::splat(f64::EPSILON), F::splat(TINY));
        Self {
            lo: lo - (lo.abs() * eps + tiny),
            hi: hi + (hi.abs() * eps + tiny),
        }
    }

    /// The lanes where lo and hi are both finite.
    #[inline(always)]
    pub fn finite(self) -> F {
        self.lo.is_finite() & self.hi.is_finite()
    }

    /// x², never below 0 (as [`Interval::square`]).
    #[inline(always)]
    pub fn square(self) -> Self {
        let zero = F::splat(0.0);
        let (l2, h2) = (self.lo * self.lo, self.hi * self.hi);
        let pos = self.lo.simd_ge(zero);
        let neg = self.hi.simd_le(zero);
        let lo = pos.bitselect(l2, neg.bitselect(h2, zero));
        let hi = l2.fast_max(h2);
        let w = Self::widened(lo, hi);
        Self {
            lo: w.lo.fast_max(zero),
            hi: w.hi,
        }
    }

    /// √x for lanes with x.lo ≥ 0 (others: NaN ends).
    #[inline(always)]
    pub fn sqrt(self) -> Self {
        Self::widened(self.lo.sqrt(), self.hi.sqrt())
    }

    /// x / r for lanes where r.lo > 0 (others: meaningless).
    #[inline(always)]
    pub fn div_positive(self, r: Self) -> Self {
        Self::hull([
            self.lo / r.lo,
            self.lo / r.hi,
            self.hi / r.lo,
            self.hi / r.hi,
        ])
    }

    /// x · r for lanes where r.lo > 0 (others: meaningless): with r positive the least
    /// product is x.lo times an end of r, the greatest x.hi times one.
    #[inline(always)]
    pub fn mul_positive(self, r: Self) -> Self {
        let (a, b) = (self.lo * r.lo, self.lo * r.hi);
        let (c, d) = (self.hi * r.lo, self.hi * r.hi);
        Self::widened(a.fast_min(b), c.fast_max(d))
    }

    /// The widened interval from the least to the greatest of four rounded end products or
    /// quotients (no NaN among them: finite ends).
    #[inline(always)]
    fn hull(q: [F; 4]) -> Self {
        let lo = q[0].fast_min(q[1]).fast_min(q[2].fast_min(q[3]));
        let hi = q[0].fast_max(q[1]).fast_max(q[2].fast_max(q[3]));
        Self::widened(lo, hi)
    }
}

impl<F: Lanes64> Add for IntervalX4<F> {
    type Output = Self;
    #[inline(always)]
    fn add(self, r: Self) -> Self {
        Self::widened(self.lo + r.lo, self.hi + r.hi)
    }
}

impl<F: Lanes64> Sub for IntervalX4<F> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, r: Self) -> Self {
        Self::widened(self.lo - r.hi, self.hi - r.lo)
    }
}

impl<F: Lanes64> Neg for IntervalX4<F> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        Self {
            lo: -self.hi,
            hi: -self.lo,
        }
    }
}

impl<F: Lanes64> Mul for IntervalX4<F> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, r: Self) -> Self {
        Self::hull([
            self.lo * r.lo,
            self.lo * r.hi,
            self.hi * r.lo,
            self.hi * r.hi,
        ])
    }
}

/// a · b for intervals `a` and exact lanes `b`.
///
/// (No closures here or in the sphere's lane test: a closure is compiled without the AVX
/// build's features, so the AVX lanes' operations in it stay calls.)
#[inline(always)]
pub fn idot_x4<F: Lanes64>(a: &[IntervalX4<F>; 3], b: &[F; 3]) -> IntervalX4<F> {
    times_exact(a[0], b[0]) + times_exact(a[1], b[1]) + times_exact(a[2], b[2])
}

/// One term of [`idot_x4`]: the interval `a` times the exact lanes `b`.
#[inline(always)]
fn times_exact<F: Lanes64>(a: IntervalX4<F>, b: F) -> IntervalX4<F> {
    let (x, y) = (a.lo * b, a.hi * b);
    IntervalX4::widened(x.fast_min(y), x.fast_max(y))
}

#[cfg(feature = "unit-tests")]
#[deny(dead_code)]
pub(crate) mod tests {
    use super::*;

    fn encloses_the_exact_result_of_a_cancelling_sum() {
        // 1e16 + 1 − 1e16 = 1 exactly; plain f64 gives 0.
        let x = Interval::point(1e16) + Interval::point(1.0) - Interval::point(1e16);
        assert!(x.lo <= 1.0 && x.hi >= 1.0, "{x:?}");
        assert_eq!(x.sign(), None, "too wide to decide, and says so");
    }

    fn signs_products_and_roots() {
        let a = Interval::point(3.0) * Interval::point(-2.0);
        assert_eq!(a.sign(), Some(Ordering::Less));
        assert!(a.lo <= -6.0 && a.hi >= -6.0);
        let r = Interval::point(2.0).sqrt().unwrap();
        assert!(r.lo * r.lo <= 2.0 && r.hi * r.hi >= 2.0);
        assert!(Interval::point(-1e-300).sqrt().is_none());
        assert_eq!(Interval::point(0.0).sign(), Some(Ordering::Equal));
        assert!(Interval::point(1.0)
            .checked_div(Interval { lo: -1.0, hi: 1.0 })
            .is_none());
        let sq = Interval { lo: -2.0, hi: 3.0 }.square();
        assert!(sq.lo == 0.0 && sq.hi >= 9.0);
        let inf = Interval::point(f64::INFINITY) * Interval::point(0.0);
        assert_eq!(inf.sign(), None);
    }

    /// This module's tests, for tests/unit.rs to run.
    pub(crate) const TESTS: &[(&str, fn())] = &[
        (
            "encloses_the_exact_result_of_a_cancelling_sum",
            encloses_the_exact_result_of_a_cancelling_sum,
        ),
        ("signs_products_and_roots", signs_products_and_roots),
    ];
}
