//! Exact decisions in rational arithmetic: the last level of the adaptive method, reached only
//! when f64 intervals cannot decide (a ray exactly through an edge or vertex, two surfaces at
//! exactly the same t, an origin exactly on a sphere). Every float input is an exact rational,
//! so the answers here are the mathematically exact ones.
//!
//! The common exact question, which side of an edge a ray passes (the sign of det[d, a − o,
//! b − o]), is answered with Shewchuk's floating-point expansions ([`orient`]): exact, and
//! fast enough for the columns of pixels whose rays run exactly through a box's edges.
//! Everything else, rarer still, uses big rationals: a ray parameter is held as
//! t = a + b·√s (b = 0 for triangles; spheres have irrational roots), and compared by the
//! sign of sums of such terms (squaring only where the signs differ, so nothing is rounded).

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

fn sign(x: &Q) -> Ordering {
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
    fn rational(a: Q) -> Self {
        Self {
            a,
            b: Q::zero(),
            s: Q::zero(),
        }
    }

    /// The value rounded to f64 (for reporting t; never used for a decision).
    pub fn approx(&self) -> f64 {
        use num_traits::ToPrimitive;
        let a = self.a.to_f64().unwrap_or(f64::NAN);
        if self.b.is_zero() {
            return a;
        }
        a + self.b.to_f64().unwrap_or(f64::NAN) * self.s.to_f64().unwrap_or(f64::NAN).sqrt()
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

/// x + y = a + b exactly (Knuth's two-sum).
#[inline]
pub fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let x = a + b;
    let bv = x - a;
    let av = x - bv;
    (x, (a - av) + (b - bv))
}

/// x + y = a·b exactly: the fused multiply-add gives the rounding error where the CPU has it
/// (compiled in); otherwise Dekker's product with Veltkamp's split (exact for products clear
/// of overflow and underflow, which [`in_safe_range`] ensures), since software `fma` is slow.
#[inline]
fn two_prod(a: f64, b: f64) -> (f64, f64) {
    let x = a * b;
    if cfg!(target_feature = "fma") {
        return (x, a.mul_add(b, -x));
    }
    let split = |v: f64| {
        let c = 134_217_729.0 * v; // 2^27 + 1
        let hi = c - (c - v);
        (hi, v - hi)
    };
    let ((ah, al), (bh, bl)) = (split(a), split(b));
    let err = ((ah * bh - x) + ah * bl + al * bh) + al * bl;
    (x, err)
}

/// A nonoverlapping expansion in increasing magnitude, on the stack: the sum of its terms
/// is the exact value. 32 terms hold everything [`orient`] builds (at most 24).
#[derive(Clone, Copy)]
struct Expansion {
    t: [f64; 32],
    n: usize,
}

impl Expansion {
    fn of(terms: &[f64]) -> Self {
        let mut e = Self {
            t: [0.0; 32],
            n: terms.len(),
        };
        e.t[..terms.len()].copy_from_slice(terms);
        e
    }

    fn terms(&self) -> &[f64] {
        &self.t[..self.n]
    }

    /// self + b in place (Shewchuk's GROW-EXPANSION with zero elimination; each output
    /// term is written at or before the input term it came from).
    fn grow(&mut self, b: f64) {
        let mut q = b;
        let mut k = 0;
        for i in 0..self.n {
            let (s, err) = two_sum(q, self.t[i]);
            if err != 0.0 {
                self.t[k] = err;
                k += 1;
            }
            q = s;
        }
        if q != 0.0 || k == 0 {
            self.t[k] = q;
            k += 1;
        }
        self.n = k;
    }

    /// self + f.
    fn add(mut self, f: &Expansion) -> Self {
        for &x in f.terms() {
            self.grow(x);
        }
        self
    }

    /// self·b (Shewchuk's SCALE-EXPANSION with zero elimination).
    fn scale(&self, b: f64) -> Self {
        let mut h = Self::of(&[]);
        let push = |h: &mut Self, x: f64| {
            if x != 0.0 {
                h.t[h.n] = x;
                h.n += 1;
            }
        };
        let e = self.terms();
        let (mut q, err) = two_prod(e[0], b);
        push(&mut h, err);
        for &x in &e[1..] {
            let (p1, p0) = two_prod(x, b);
            let (s, err) = two_sum(q, p0);
            push(&mut h, err);
            // |p1| ≥ |s| here, so a fast two-sum would do; the plain one is as exact.
            let (s2, err) = two_sum(p1, s);
            push(&mut h, err);
            q = s2;
        }
        if q != 0.0 || h.n == 0 {
            h.t[h.n] = q;
            h.n += 1;
        }
        h
    }

    /// The sign of the exact value (the largest term's).
    fn sign(&self) -> Ordering {
        let top = self.terms().last().copied().unwrap_or(0.0);
        top.partial_cmp(&0.0).unwrap_or(Ordering::Equal)
    }
}

/// a·b − c·d as an expansion.
fn cross_term(a: f64, b: f64, c: f64, d: f64) -> Expansion {
    let (x1, x0) = two_prod(a, b);
    let (y1, y0) = two_prod(c, d);
    let mut e = Expansion::of(&[x0]);
    e.grow(x1);
    e.grow(-y0);
    e.grow(-y1);
    e
}

/// Inputs whose products of three stay clear of f64 underflow and overflow (every f32 is).
fn in_safe_range(x: f64) -> bool {
    x == 0.0 || (1e-90..=1e90).contains(&x.abs())
}

/// Shewchuk's `o3derrboundA`, (7 + 56ε)ε with ε = 2⁻⁵³: |computed − exact| of a 3×3
/// determinant is below it times the permanent.
const ORIENT_BOUND: f64 = (7.0 + 56.0 * f64::EPSILON / 2.0) * (f64::EPSILON / 2.0);

/// The exact sign of det[d, a − o, b − o]: which side of the edge (a, b) the line o + t·d
/// passes. `None` where a − o or b − o is not exact in f64 or an input is outside the safe
/// range (then the caller falls back to rationals).
pub fn orient(d: [f64; 3], o: [f64; 3], a: [f64; 3], b: [f64; 3]) -> Option<Ordering> {
    let mut pa = [0.0; 3];
    let mut pb = [0.0; 3];
    for k in 0..3 {
        let (x, ex) = two_sum(a[k], -o[k]);
        let (y, ey) = two_sum(b[k], -o[k]);
        if ex != 0.0 || ey != 0.0 {
            return None;
        }
        if ![x, y, d[k]].into_iter().all(in_safe_range) {
            return None;
        }
        (pa[k], pb[k]) = (x, y);
    }
    // The plain f64 determinant decides where it is clear of its rounding (Shewchuk's
    // orient3d bound, from entries that are exact here; no product can underflow or
    // overflow in the safe range): ~40 instructions against ~1,200 for the expansions.
    let (m0, m1, m2) = (pa[1] * pb[2], pa[2] * pb[1], pa[2] * pb[0]);
    let (m3, m4, m5) = (pa[0] * pb[2], pa[0] * pb[1], pa[1] * pb[0]);
    let det = d[0] * (m0 - m1) + d[1] * (m2 - m3) + d[2] * (m4 - m5);
    let permanent = d[0].abs() * (m0.abs() + m1.abs())
        + d[1].abs() * (m2.abs() + m3.abs())
        + d[2].abs() * (m4.abs() + m5.abs());
    let bound = ORIENT_BOUND * permanent;
    if det > bound {
        return Some(Ordering::Greater);
    }
    if -det > bound {
        return Some(Ordering::Less);
    }
    if let Some(sign) = orient_distilled(d, &pa, &pb) {
        return Some(sign);
    }
    let terms = [
        cross_term(pa[1], pb[2], pa[2], pb[1]).scale(d[0]),
        cross_term(pa[2], pb[0], pa[0], pb[2]).scale(d[1]),
        cross_term(pa[0], pb[1], pa[1], pb[0]).scale(d[2]),
    ];
    // Nonoverlapping, increasing magnitude, zeros removed: the last term carries the sign.
    Some(terms[0].add(&terms[1]).add(&terms[2]).sign())
}

/// The exact sign of det[d, pa, pb] (entries in the safe range) as the sign of a sum of at
/// most 24 exact products, by distillation ([`sum_sign`]); `None` where that does not settle
/// within its sweeps. Rays exactly through a wall's diagonal or a box's edge give exact zeros,
/// which the filter never decides: the Cornell box's 640×360 frame has ~850 of them, and this
/// takes ~630 instructions for each against ~1,700 for the expansions (callgrind).
fn orient_distilled(d: [f64; 3], pa: &[f64; 3], pb: &[f64; 3]) -> Option<Ordering> {
    let mut terms = [0.0; 24];
    let mut n = 0;
    for (k, &dk) in d.iter().enumerate() {
        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
        // pa_i·pb_j − pa_j·pb_i = (p − q) + p_err − q_err exactly, p − q as a two-sum.
        let (p, p_err) = two_prod(pa[i], pb[j]);
        let (q, q_err) = two_prod(pa[j], pb[i]);
        let (s, s_err) = two_sum(p, -q);
        for c in [s, s_err, p_err, -q_err] {
            if c != 0.0 {
                let (h, l) = two_prod(dk, c);
                for x in [h, l] {
                    if x != 0.0 {
                        terms[n] = x;
                        n += 1;
                    }
                }
            }
        }
    }
    sum_sign(&mut terms, n)
}

/// Distillation sweeps before [`sum_sign`] gives up (exact zeros of a few terms settle in 1–3).
const SWEEPS: usize = 6;

/// The exact sign of `terms[..n]`'s sum (no term overflowing): each sweep adds the terms in
/// turn, keeping every two-sum's rounding error as a term (the exact sum never changes), until
/// no error is left or the running sum outweighs them all. `None` after [`SWEEPS`] sweeps.
fn sum_sign(terms: &mut [f64; 24], mut n: usize) -> Option<Ordering> {
    for _ in 0..SWEEPS {
        let mut sum = 0.0;
        let mut kept = 0;
        for i in 0..n {
            let (s, err) = two_sum(sum, terms[i]);
            if err != 0.0 {
                terms[kept] = err;
                kept += 1;
            }
            sum = s;
        }
        // (The first two-sum, 0 + x, is exact: a sweep keeps at most n − 1 errors.)
        if kept == 0 {
            return sum.partial_cmp(&0.0);
        }
        // Σ|errors| computed in f64 is below the exact one by at most a relative (kept − 1)·ε
        // (ε = 2⁻⁵³, kept ≤ 24): the margin covers it and the product's rounding.
        let rest: f64 = terms[..kept].iter().map(|t| t.abs()).sum();
        if sum.abs() > rest * (1.0 + 64.0 * f64::EPSILON) {
            return sum.partial_cmp(&0.0);
        }
        terms[kept] = sum;
        n = kept + 1;
    }
    None
}

/// Which side of the plane of triangle `v` point `x` lies on: the exact sign of
/// det[v₁ − v₀, v₂ − v₀, x − v₀]; `None` where the expansions cannot be used (differences
/// not exact in f64).
pub fn plane_side(v: &[[f32; 3]; 3], x: [f64; 3]) -> Option<Ordering> {
    plane_side_f64(&v.map(|p| p.map(f64::from)), x)
}

/// [`plane_side`] for a triangle given in f64.
pub fn plane_side_f64(v: &[[f64; 3]; 3], x: [f64; 3]) -> Option<Ordering> {
    let mut d = [0.0; 3];
    for k in 0..3 {
        let (diff, err) = two_sum(v[1][k], -v[0][k]);
        if err != 0.0 {
            return None;
        }
        d[k] = diff;
    }
    orient(d, v[0], v[2], x)
}

/// Whether `x` lies exactly on the plane of triangle `v` (`None`: cannot tell, which callers
/// treat as "not known to be coplanar").
pub fn on_plane(v: &[[f32; 3]; 3], x: [f64; 3]) -> Option<bool> {
    plane_side(v, x).map(|s| s == Ordering::Equal)
}

/// The exact sign of det[d, a − o, b − o] in rationals (any finite inputs).
pub fn orient_rational(d: [f64; 3], o: [f64; 3], a: [f64; 3], b: [f64; 3]) -> Ordering {
    let o = qv(o);
    let (pa, pb) = (sub(&qv(a), &o), sub(&qv(b), &o));
    sign(&dot(&qv(d), &cross(&pa, &pb)))
}

/// The exact t of the line o + t·d at the plane of triangle v (`None` if parallel).
pub fn plane_t(o: [f64; 3], d: [f64; 3], v: &[[f64; 3]; 3]) -> Option<ExactT> {
    let o = qv(o);
    let p: [QV; 3] = [0, 1, 2].map(|i| sub(&qv(v[i]), &o));
    let n = cross(&sub(&p[1], &p[0]), &sub(&p[2], &p[0]));
    let den = dot(&qv(d), &n);
    if den.is_zero() {
        return None;
    }
    Some(ExactT::rational(dot(&p[0], &n) / den))
}

/// n / d (d > 0) correctly rounded to T: the binade 2^e ≤ |n/d| < 2^(e+1), the quantum
/// 2^(max(e, emin) − p + 1) of T there, one integer division and the remainder for the
/// rounding (ties to even); ∞ from 2^(emax+1) up.
fn round_ratio<T: Real>(n: &BigInt, d: &BigInt) -> T {
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

/// An f64 as m·2^e with an integer m (0 as 0·2^0).
fn integer_and_exponent(x: f64) -> (BigInt, i64) {
    let bits = x.to_bits();
    let (exp, frac) = (((bits >> 52) & 0x7ff) as i64, bits & ((1u64 << 52) - 1));
    let (m, e) = match exp {
        0 => (frac, -1074),
        _ => (frac | (1u64 << 52), exp - 1075),
    };
    let m = BigInt::from(m);
    (if x < 0.0 { -m } else { m }, e)
}

/// The exact t of the line o + t·d at the plane of triangle v correctly rounded to T
/// (`None` if parallel), in integers: every input is m·2^e, so with E the least exponent
/// they are all integers times 2^E, and t = p₀·n / d·n is a ratio of integers (both carry
/// 2^3E, which cancels), rounded by one division. No gcds: some 20× cheaper than
/// [`plane_t`] and [`ExactT::rounded`].
pub fn plane_t_rounded<T: Real>(o: [f64; 3], d: [f64; 3], v: &[[f64; 3]; 3]) -> Option<T> {
    let inputs = [o, d, v[0], v[1], v[2]].map(|p| p.map(integer_and_exponent));
    let least = inputs
        .iter()
        .flatten()
        .filter(|(m, _)| !m.is_zero())
        .map(|(_, e)| *e)
        .min()
        .unwrap_or(0);
    let [o, d, a, b, c] = inputs.map(|p| p.map(|(m, e)| m << (e - least) as u64));
    let sub = |x: &[BigInt; 3], y: &[BigInt; 3]| [0, 1, 2].map(|k| &x[k] - &y[k]);
    let dot = |x: &[BigInt; 3], y: &[BigInt; 3]| &x[0] * &y[0] + &x[1] * &y[1] + &x[2] * &y[2];
    let (p0, p1, p2) = (sub(&a, &o), sub(&b, &o), sub(&c, &o));
    let (e1, e2) = (sub(&p1, &p0), sub(&p2, &p0));
    let n = [
        &e1[1] * &e2[2] - &e1[2] * &e2[1],
        &e1[2] * &e2[0] - &e1[0] * &e2[2],
        &e1[0] * &e2[1] - &e1[1] * &e2[0],
    ];
    let den = dot(&d, &n);
    if den.is_zero() {
        return None;
    }
    let num = dot(&p0, &n);
    Some(match den < BigInt::zero() {
        true => round_ratio(&-num, &-den),
        false => round_ratio(&num, &den),
    })
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

fn cross(a: &QV, b: &QV) -> QV {
    [
        &a[1] * &b[2] - &a[2] * &b[1],
        &a[2] * &b[0] - &a[0] * &b[2],
        &a[0] * &b[1] - &a[1] * &b[0],
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::xorshift;

    fn t(a: f64, b: f64, s: f64) -> ExactT {
        ExactT {
            a: q(a),
            b: q(b),
            s: q(s),
        }
    }

    #[test]
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
        let mut next =
            || ((xorshift(&mut x) % 2001) as f64 - 1000.0) as f32 as f64 * 0.37f32 as f64;
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

    #[test]
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

    #[test]
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

    #[test]
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

    #[test]
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

    #[test]
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

    #[test]
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

    #[test]
    fn sphere_roots_with_origin_on_the_surface_and_tangent_rays() {
        let c = [0.0, 0.0, 5.0];
        // From the surface point (0,0,4) inward: t = 0 is not > 0, the far root t = 2 is.
        let hit = crate::geometry::sphere::exact(
            [0.0, 0.0, 4.0],
            [0.0, 0.0, 1.0],
            c,
            1.0,
            0.0,
            f64::INFINITY,
        )
        .unwrap();
        assert_eq!(hit.cmp_f(2.0), Ordering::Equal);
        // Tangent: touches at t = 5.
        let tan = crate::geometry::sphere::exact(
            [1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0],
            c,
            1.0,
            0.0,
            f64::INFINITY,
        )
        .unwrap();
        assert_eq!(tan.cmp_f(5.0), Ordering::Equal);
        assert!(crate::geometry::sphere::exact(
            [1.0f64.next_up(), 0.0, 0.0],
            [0.0, 0.0, 1.0],
            c,
            1.0,
            0.0,
            f64::INFINITY
        )
        .is_none());
    }

    #[test]
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
}
