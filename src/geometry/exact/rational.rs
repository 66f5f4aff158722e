//! Big rationals: `Q` and its vectors, the exact ray parameter [`ExactT`] (a + b·√s), the
//! signs of sums of such terms, and a ratio of integers correctly rounded.

use crate::math::Real;
use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::Zero;
use std::cmp::Ordering;

pub(crate) type Q = BigRational;

/// An exact float as a rational (inputs are checked finite before they get here).
pub(crate) fn q(x: f64) -> Q {
    Q::from_float(x).unwrap_or_else(Q::zero)
}

pub(super) fn sign(x: &Q) -> Ordering {
    x.cmp(&Q::zero())
}

/// An exact ray parameter a + b·√s (s ≥ 0).
#[derive(Clone, Debug, PartialEq)]
pub struct ExactT {
    pub(crate) a: Q,
    pub(crate) b: Q,
    pub(crate) s: Q,
}

impl ExactT {
    pub(super) fn rational(a: Q) -> Self {
        Self {
            a,
            b: Q::zero(),
            s: Q::zero(),
        }
    }

    /// The value in f64 within a few ulps (NaN or ∞ where a part is beyond f64's range): the
    /// start of [`ExactT::rounded`]'s search, and the best hit's bound in the adaptive
    /// search's culling ([`crate::geometry::adaptive`]), which widens it by 10⁻⁹ of itself.
    ///
    /// Where a and b·√s have opposite signs, a + b·√s cancels (a ray from just inside a
    /// sphere of radius 10³⁰: a ≈ 10³⁰, the sum ≈ 1, the f64 sum off by 10¹⁴): it is then
    /// (a² − b²s) / (a − b·√s), the numerator exact in rationals and the denominator a sum of
    /// two terms of one sign.
    pub fn approx(&self) -> f64 {
        use num_traits::ToPrimitive;
        let f64_of = |x: &Q| x.to_f64().unwrap_or(f64::NAN);
        let a = f64_of(&self.a);
        if self.b.is_zero() || self.s.is_zero() {
            return a;
        }
        let root_term = f64_of(&self.b) * f64_of(&self.s).sqrt();
        if self.a.is_zero() || sign(&self.a) == sign(&self.b) {
            return a + root_term;
        }
        let numerator = &self.a * &self.a - &self.b * &self.b * &self.s;
        let stable = f64_of(&numerator) / (a - root_term);
        match stable.is_finite() {
            true => stable,
            false => a + root_term,
        }
    }

    /// Exact comparison with another parameter.
    pub fn cmp_t(&self, other: &ExactT) -> Ordering {
        sign_sum(
            &(&self.a - &other.a),
            &self.b,
            &self.s,
            &(-&other.b),
            &other.s,
        )
    }

    /// Exact comparison with a float (tmin, tmax); +∞ is above everything.
    pub fn cmp_f(&self, x: f64) -> Ordering {
        if x == f64::INFINITY {
            return Ordering::Less;
        }
        if x == f64::NEG_INFINITY {
            return Ordering::Greater;
        }
        self.cmp_q(&q(x))
    }

    /// Exact comparison with a rational.
    fn cmp_q(&self, x: &Q) -> Ordering {
        sign_lin(&(&self.a - x), &self.b, &self.s)
    }

    /// The value correctly rounded to T: the nearest value of T, a tie to the one with the
    /// even last bit, beyond the largest finite value ±∞ and in the subnormal range as IEEE
    /// 754's rounding to nearest does (a value that rounds to zero gives a zero of its sign).
    ///
    /// Found by exact comparisons with the midpoints between neighbouring values of T (the
    /// boundaries of what rounds to each), starting at [`ExactT::approx`] and doubling the
    /// step until the value is bracketed, then bisecting: two or three comparisons when the
    /// estimate is good, about 130 where it overflowed (huge or tiny magnitudes in f64).
    pub fn rounded<T: Real>(&self) -> T {
        if self.b.is_zero() || self.s.is_zero() {
            return round_ratio(self.a.numer(), self.a.denom());
        }
        let value = |k: i64| q(T::from_key(k).f64());
        // Above the largest finite value, IEEE rounds to ∞ from half an ulp beyond it.
        let overflow = {
            let max = value(T::MAX_KEY);
            &max + (&max - value(T::MAX_KEY - 1)) / Q::from_integer(BigInt::from(2))
        };
        let boundary = |k: i64| -> Q {
            match k {
                k if k == T::MAX_KEY => overflow.clone(),
                k if k == -T::MAX_KEY - 1 => -overflow.clone(),
                k => (value(k) + value(k + 1)) / Q::from_integer(BigInt::from(2)),
            }
        };
        // at_or_below(k): the value rounds to key k or lower; key −MAX−1 stands for −∞,
        // MAX+1 for +∞. Monotone in k, so the answer is the smallest k where it holds.
        let (bottom, top) = (-T::MAX_KEY - 1, T::MAX_KEY + 1);
        let at_or_below = |k: i64| {
            k == top
                || match self.cmp_q(&boundary(k)) {
                    Ordering::Less => true,
                    Ordering::Equal => k % 2 == 0,
                    Ordering::Greater => false,
                }
        };
        let guess = self.approx();
        let start = match guess.is_nan() {
            true => 0,
            false => T::of(guess).max(-T::max_value()).min(T::max_value()).key(),
        };
        // Invariant once bracketed: !at_or_below(lo), at_or_below(hi).
        let (mut lo, mut hi);
        let mut step = 1i64;
        if at_or_below(start) {
            hi = start;
            loop {
                if hi == bottom {
                    return T::neg_infinity();
                }
                let probe = hi.saturating_sub(step).max(bottom);
                if !at_or_below(probe) {
                    lo = probe;
                    break;
                }
                hi = probe;
                step = step.saturating_mul(2);
            }
        } else {
            lo = start;
            loop {
                let probe = lo.saturating_add(step).min(top);
                if at_or_below(probe) {
                    hi = probe;
                    break;
                }
                lo = probe;
                step = step.saturating_mul(2);
            }
        }
        while hi - lo > 1 {
            let mid = lo + (hi - lo) / 2;
            if at_or_below(mid) {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        match hi {
            k if k == top => T::infinity(),
            0 if self.cmp_q(&Q::zero()) == Ordering::Less => -T::zero(),
            k => T::from_key(k),
        }
    }
}

/// Sign of p + q·√s.
fn sign_lin(p: &Q, qq: &Q, s: &Q) -> Ordering {
    let sq = if s.is_zero() {
        Ordering::Equal
    } else {
        sign(qq)
    };
    let sp = sign(p);
    if sq == Ordering::Equal || sp == sq {
        return sp;
    }
    if sp == Ordering::Equal {
        return sq;
    }
    // Opposite signs: the larger magnitude wins.
    match (p * p).cmp(&(qq * qq * s)) {
        Ordering::Greater => sp,
        Ordering::Less => sq,
        Ordering::Equal => Ordering::Equal,
    }
}

/// Sign of p + q·√s + r·√u.
fn sign_sum(p: &Q, qq: &Q, s: &Q, r: &Q, u: &Q) -> Ordering {
    // Sign of x = q√s + r√u.
    let sx = {
        let a = if s.is_zero() {
            Ordering::Equal
        } else {
            sign(qq)
        };
        let b = if u.is_zero() {
            Ordering::Equal
        } else {
            sign(r)
        };
        if a == Ordering::Equal || a == b {
            b
        } else if b == Ordering::Equal {
            a
        } else {
            match (qq * qq * s).cmp(&(r * r * u)) {
                Ordering::Greater => a,
                Ordering::Less => b,
                Ordering::Equal => Ordering::Equal,
            }
        }
    };
    let sp = sign(p);
    if sx == Ordering::Equal || sp == sx {
        return sp;
    }
    if sp == Ordering::Equal {
        return sx;
    }
    // Opposite signs: compare p² with x² = q²s + r²u + 2qr√(su).
    let rest = p * p - qq * qq * s - r * r * u;
    let two = Q::from_integer(BigInt::from(2));
    match sign_lin(&rest, &(-(two * qq * r)), &(s * u)) {
        Ordering::Greater => sp,
        Ordering::Less => sx,
        Ordering::Equal => Ordering::Equal,
    }
}

/// n / d (d > 0) correctly rounded to T: the binade 2^e ≤ |n/d| < 2^(e+1), the quantum
/// 2^(max(e, emin) − p + 1) of T there, one integer division and the remainder for the
/// rounding (ties to even); ∞ from 2^(emax+1) up.
pub(super) fn round_ratio<T: Real>(n: &BigInt, d: &BigInt) -> T {
    use num_traits::{Signed, ToPrimitive};
    if n.is_zero() {
        return T::zero();
    }
    let (a, d) = (n.abs(), d.abs());
    let shift = |v: &BigInt, by: i64| -> BigInt {
        match by >= 0 {
            true => v << by as u64,
            false => v >> (-by) as u64,
        }
    };
    let mut e = a.bits() as i64 - d.bits() as i64;
    let below = match e >= 0 {
        true => a < shift(&d, e),
        false => shift(&a, -e) < d,
    };
    if below {
        e -= 1;
    }
    let quantum = e.max(T::MIN_NORMAL_EXP) - (T::PRECISION - 1);
    let (num, den) = match quantum >= 0 {
        true => (a, shift(&d, quantum)),
        false => (shift(&a, -quantum), d),
    };
    let (mut m, r) = (&num / &den, &num % &den);
    let twice_r = r << 1u32;
    if twice_r > den || (twice_r == den && m.bit(0)) {
        m += 1;
    }
    let magnitude = if m.bits() as i64 + quantum > T::MAX_EXP + 1 {
        T::infinity()
    } else {
        // m < 2^54 is exact in f64, and so is m·2^quantum (in two steps, so that neither
        // factor leaves the range); T::of is then exact too.
        let m = m.to_f64().unwrap_or(f64::NAN);
        let half = (quantum / 2) as i32;
        T::of(m * 2f64.powi(half) * 2f64.powi(quantum as i32 - half))
    };
    match n.is_negative() {
        true => -magnitude,
        false => magnitude,
    }
}

pub(crate) type QV = [Q; 3];

pub(crate) fn qv(p: [f64; 3]) -> QV {
    p.map(q)
}

pub(crate) fn sub(a: &QV, b: &QV) -> QV {
    [&a[0] - &b[0], &a[1] - &b[1], &a[2] - &b[2]]
}

pub(crate) fn dot(a: &QV, b: &QV) -> Q {
    &a[0] * &b[0] + &a[1] * &b[1] + &a[2] * &b[2]
}

pub(super) fn cross(a: &QV, b: &QV) -> QV {
    [
        &a[1] * &b[2] - &a[2] * &b[1],
        &a[2] * &b[0] - &a[0] * &b[2],
        &a[0] * &b[1] - &a[1] * &b[0],
    ]
}
