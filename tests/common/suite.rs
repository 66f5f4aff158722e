//! The hard-case suite's exact reference (the families are the library's,
//! `raylab::check::suite`, re-exported here), written independently of the library's own
//! exact level:
//! every f32 input is an exact rational (`num-rational`), hit or miss is decided for the closed
//! triangle or sphere, the nearest primitive (exact ties to the lower index), and t. The
//! intersection's sums and products are taken on dyadic rationals m·2ᵉ ([`Dyadic`]), which
//! every float is: exact, without the gcd a rational reduces by after every operation.
//!
//! Shared by tests/library/hard_cases.rs (which asserts on it) and examples/speed_vs_error.rs
//! (which reports speed against error on it).

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Signed, ToPrimitive, Zero};
pub use raylab::check::suite::*;
use raylab::geometry::{Ray, Shape, Sphere, Triangle};
use raylab::math::Real;
use std::cmp::Ordering;
use std::collections::HashMap;
use std::hash::{Hash, Hasher};
use std::sync::{LazyLock, Mutex};

pub type Q = BigRational;

pub fn q(x: f32) -> Q {
    Q::from_float(x).expect("finite")
}

/// Any finite f32 or f64 as the exact rational it is.
pub fn qr<T: Real>(x: T) -> Q {
    Q::from_float(x.f64()).expect("finite")
}

/// An exact t: a rational, or an irrational sphere root known within 2⁻²⁵⁶ relative.
#[derive(Clone, Debug)]
pub enum RefT {
    Exact(Q),
    Between(Q, Q),
}

impl RefT {
    fn bounds(&self) -> (&Q, &Q) {
        match self {
            RefT::Exact(x) => (x, x),
            RefT::Between(lo, hi) => (lo, hi),
        }
    }

    /// Exact comparison; an irrational root never equals another number here (the families
    /// hold one sphere each), so its bounds always separate.
    pub fn cmp(&self, other: &RefT) -> Ordering {
        if let (RefT::Exact(a), RefT::Exact(b)) = (self, other) {
            return a.cmp(b);
        }
        let ((alo, ahi), (blo, bhi)) = (self.bounds(), other.bounds());
        if ahi < blo {
            Ordering::Less
        } else if alo > bhi {
            Ordering::Greater
        } else {
            panic!("reference cannot order {self:?} and {other:?}")
        }
    }

    pub fn f64(&self) -> f64 {
        self.bounds().0.to_f64().unwrap()
    }

    /// The value correctly rounded to T (nearest, ties to even, IEEE overflow and
    /// underflow), or `None` where an irrational root's bounds round apart.
    pub fn rounded<T: Real + Bits>(&self) -> Option<T> {
        let (lo, hi) = self.bounds();
        let (a, b) = (round_q::<T>(lo), round_q::<T>(hi));
        (a.to_bits_u64() == b.to_bits_u64()).then_some(a)
    }
}

/// Bit patterns, to compare floats bit for bit in tests (−0 ≠ +0).
pub trait Bits {
    fn to_bits_u64(self) -> u64;
}
impl Bits for f32 {
    fn to_bits_u64(self) -> u64 {
        self.to_bits() as u64
    }
}
impl Bits for f64 {
    fn to_bits_u64(self) -> u64 {
        self.to_bits()
    }
}

/// x rounded to the nearest value of T with ties to even, written from the definition with
/// integers (independent of the library's search over midpoints): the binade of x, its
/// quantum 2^(max(e, emin) − p + 1), the quotient and remainder, ∞ from 2^(emax+1) up.
pub fn round_q<T: Real>(x: &Q) -> T {
    let (precision, emin, emax): (i64, i64, i64) = match std::mem::size_of::<T>() {
        4 => (24, -126, 127),
        _ => (53, -1022, 1023),
    };
    if x.is_zero() {
        return T::zero();
    }
    let negative = x.is_negative();
    let (n, d) = (x.numer().abs(), x.denom().clone());
    let shifted = |v: &BigInt, by: i64| -> BigInt {
        if by >= 0 {
            v << by as usize
        } else {
            v >> (-by) as usize
        }
    };
    // 2^e ≤ |x| < 2^(e+1).
    let mut e = n.bits() as i64 - d.bits() as i64;
    let below = if e >= 0 {
        n < shifted(&d, e)
    } else {
        shifted(&n, -e) < d
    };
    if below {
        e -= 1;
    }
    let quantum = e.max(emin) - (precision - 1);
    let (num, den) = if quantum >= 0 {
        (n, shifted(&d, quantum))
    } else {
        (shifted(&n, -quantum), d)
    };
    let (mut m, r) = (&num / &den, &num % &den);
    let twice_r: BigInt = r * 2;
    if twice_r > den || (twice_r == den && (&m % 2u32) == BigInt::one()) {
        m += 1;
    }
    let magnitude = if m.bits() as i64 + quantum > emax + 1 {
        f64::INFINITY
    } else {
        let m = m.to_f64().expect("at most 2^53");
        m * 2f64.powi((quantum / 2) as i32) * 2f64.powi((quantum - quantum / 2) as i32)
    };
    let v = T::of(magnitude);
    if negative {
        -v
    } else {
        v
    }
}

/// A dyadic rational m·2ᵉ: sums, differences and products stay dyadic and exact.
#[derive(Clone, Debug)]
pub struct Dyadic {
    m: BigInt,
    e: i64,
}

impl Dyadic {
    /// A finite f32 or f64 as the dyadic it is, from its bits.
    pub fn of<T: Real>(x: T) -> Dyadic {
        let x = x.f64();
        assert!(x.is_finite(), "{x} is not finite");
        let bits = x.to_bits();
        let (biased, fraction) = (((bits >> 52) & 0x7ff) as i64, bits & ((1 << 52) - 1));
        let (mantissa, e) = match biased {
            0 => (fraction, -1074),
            _ => (fraction | 1 << 52, biased - 1075),
        };
        let m = BigInt::from(mantissa);
        let m = if bits >> 63 == 1 { -m } else { m };
        Dyadic { m, e }
    }

    /// Both mantissas at the smaller exponent.
    fn aligned(&self, other: &Dyadic) -> (BigInt, BigInt, i64) {
        let e = self.e.min(other.e);
        let (a, b) = (&self.m << (self.e - e), &other.m << (other.e - e));
        (a, b, e)
    }

    fn is_zero(&self) -> bool {
        self.m.is_zero()
    }

    fn is_negative(&self) -> bool {
        self.m.is_negative()
    }

    pub fn to_q(&self) -> Q {
        match self.e >= 0 {
            true => Q::from_integer(&self.m << self.e),
            false => Q::new(self.m.clone(), BigInt::one() << -self.e),
        }
    }

    /// √x within bounds 2⁻²⁵⁶ apart (relative), exact when x is a square: √(m·2²ᵏ)·2^(e/2 − k)
    /// with e made even.
    fn sqrt(&self) -> RefT {
        let k = 256;
        let (m, e) = match self.e.rem_euclid(2) {
            0 => (self.m.clone(), self.e),
            _ => (&self.m << 1, self.e - 1),
        };
        let big: BigInt = m << (2 * k);
        let s = big.sqrt();
        let scaled = |m: BigInt| Dyadic { m, e: e / 2 - k }.to_q();
        if &s * &s == big {
            RefT::Exact(scaled(s))
        } else {
            RefT::Between(scaled(s.clone()), scaled(s + 1))
        }
    }
}

/// Sums, differences and products of dyadics, exact: as `&Q`'s, so [`sub`], [`cross`] and
/// [`dot`] serve both.
impl std::ops::Add<&Dyadic> for &Dyadic {
    type Output = Dyadic;
    fn add(self, other: &Dyadic) -> Dyadic {
        let (a, b, e) = self.aligned(other);
        Dyadic { m: a + b, e }
    }
}

impl std::ops::Sub<&Dyadic> for &Dyadic {
    type Output = Dyadic;
    fn sub(self, other: &Dyadic) -> Dyadic {
        let (a, b, e) = self.aligned(other);
        Dyadic { m: a - b, e }
    }
}

impl std::ops::Mul<&Dyadic> for &Dyadic {
    type Output = Dyadic;
    fn mul(self, other: &Dyadic) -> Dyadic {
        Dyadic {
            m: &self.m * &other.m,
            e: self.e + other.e,
        }
    }
}

impl std::ops::Add for Dyadic {
    type Output = Dyadic;
    fn add(self, other: Dyadic) -> Dyadic {
        &self + &other
    }
}

impl std::ops::Sub for Dyadic {
    type Output = Dyadic;
    fn sub(self, other: Dyadic) -> Dyadic {
        &self - &other
    }
}

pub fn sub<N>(a: &[N; 3], b: &[N; 3]) -> [N; 3]
where
    for<'x> &'x N: std::ops::Sub<&'x N, Output = N>,
{
    [&a[0] - &b[0], &a[1] - &b[1], &a[2] - &b[2]]
}
pub fn cross<N: std::ops::Sub<Output = N>>(a: &[N; 3], b: &[N; 3]) -> [N; 3]
where
    for<'x> &'x N: std::ops::Mul<&'x N, Output = N>,
{
    [
        &a[1] * &b[2] - &a[2] * &b[1],
        &a[2] * &b[0] - &a[0] * &b[2],
        &a[0] * &b[1] - &a[1] * &b[0],
    ]
}
pub fn dot<N: std::ops::Add<Output = N>>(a: &[N; 3], b: &[N; 3]) -> N
where
    for<'x> &'x N: std::ops::Mul<&'x N, Output = N>,
{
    &a[0] * &b[0] + &a[1] * &b[1] + &a[2] * &b[2]
}

/// Exact t of the ray on one primitive with tmin < t (nearest root for a sphere).
fn exact_t<T: Real>(shape: &Shape<T>, o: &[Dyadic; 3], d: &[Dyadic; 3], tmin: &Q) -> Option<RefT> {
    match shape {
        Shape::Triangle(Triangle(v)) => {
            let v = v.map(|p| p.map(Dyadic::of));
            let e1 = sub(&v[1], &v[0]);
            let e2 = sub(&v[2], &v[0]);
            let p = cross(d, &e2);
            let det = dot(&e1, &p);
            if det.is_zero() {
                return None; // in the plane or degenerate: a miss by convention
            }
            let s0 = sub(o, &v[0]);
            let qv = cross(&s0, &e1);
            // b1 = n1 / det and b2 = n2 / det: inside where both are ≥ 0 and 1 − b1 − b2 =
            // (det − n1 − n2) / det is too, each a numerator of det's sign or zero.
            let (n1, n2) = (dot(&s0, &p), dot(d, &qv));
            let at_least_0 = |n: &Dyadic| n.is_zero() || n.is_negative() == det.is_negative();
            let rest = &det - &(&n1 + &n2);
            let inside = at_least_0(&n1) && at_least_0(&n2) && at_least_0(&rest);
            if !inside {
                return None;
            }
            let t = dot(&e2, &qv).to_q() / det.to_q();
            (&t > tmin).then_some(RefT::Exact(t))
        }
        Shape::Sphere(Sphere { centre, radius }) => {
            let f = sub(o, &centre.map(Dyadic::of));
            let r = Dyadic::of(*radius);
            let a = dot(d, d);
            let b = dot(&f, d);
            let c = dot(&f, &f) - &r * &r;
            let disc = &b * &b - &a * &c;
            if disc.is_negative() {
                return None;
            }
            let root = disc.sqrt();
            let (lo, hi) = root.bounds();
            let (a, nb) = (a.to_q(), -b.to_q());
            let near = match &root {
                RefT::Exact(s) => RefT::Exact((&nb - s) / &a),
                _ => RefT::Between((&nb - hi) / &a, (&nb - lo) / &a),
            };
            let far = match &root {
                RefT::Exact(s) => RefT::Exact((&nb + s) / &a),
                _ => RefT::Between((&nb + lo) / &a, (&nb + hi) / &a),
            };
            let tmin = RefT::Exact(tmin.clone());
            [near, far]
                .into_iter()
                .find(|t| t.cmp(&tmin) == Ordering::Greater)
        }
    }
}

/// Exact nearest hit with t > 0: (t, primitive), ties to the lower index. Remembered for the
/// process (by the exact values of the shapes and the ray, whatever their precision): a test
/// binary asks the same suite rays from several tests, and the exact answer is the costliest
/// part of each.
pub fn exact_nearest<T: Real>(shapes: &[Shape<T>], ray: &Ray<T>) -> Option<(RefT, u32)> {
    let key = NearestKey::of(shapes, ray);
    let known = NEAREST
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .get(&key)
        .cloned();
    known.unwrap_or_else(|| {
        let answer = exact_nearest_between(shapes, ray, &Q::zero(), None);
        let mut memo = NEAREST.lock().unwrap_or_else(|e| e.into_inner());
        memo.insert(key, answer.clone());
        answer
    })
}

/// An exact nearest hit: (t, primitive), or none.
pub type Nearest = Option<(RefT, u32)>;

/// [`exact_nearest`]'s answers so far.
static NEAREST: LazyLock<Mutex<HashMap<NearestKey, Nearest>>> = LazyLock::new(Default::default);

/// A query of [`exact_nearest`]: the shapes' exact values (every coordinate's f64 bits, in
/// order, with each shape's kind) hashed twice with different keys, their count, and the ray's.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
struct NearestKey {
    shapes: (u64, u64, usize),
    ray: [u64; 6],
}

impl NearestKey {
    fn of<T: Real>(shapes: &[Shape<T>], ray: &Ray<T>) -> NearestKey {
        let bits = |x: &T| x.f64().to_bits();
        let hash = |seed: u64| {
            let mut h = std::hash::DefaultHasher::new();
            seed.hash(&mut h);
            for shape in shapes {
                match shape {
                    Shape::Triangle(Triangle(v)) => {
                        0u8.hash(&mut h);
                        v.iter().flatten().map(bits).for_each(|b| b.hash(&mut h));
                    }
                    Shape::Sphere(Sphere { centre, radius }) => {
                        1u8.hash(&mut h);
                        centre
                            .iter()
                            .chain([radius])
                            .map(bits)
                            .for_each(|b| b.hash(&mut h));
                    }
                }
            }
            h.finish()
        };
        let o = ray.o.each_ref().map(bits);
        let d = ray.d.each_ref().map(bits);
        NearestKey {
            shapes: (hash(1), hash(2), shapes.len()),
            ray: [o[0], o[1], o[2], d[0], d[1], d[2]],
        }
    }
}

/// Exact nearest hit with tmin < t < tmax (tmax `None`: ∞), ties to the lower index.
pub fn exact_nearest_between<T: Real>(
    shapes: &[Shape<T>],
    ray: &Ray<T>,
    tmin: &Q,
    tmax: Option<&Q>,
) -> Option<(RefT, u32)> {
    let (o, d) = (ray.o.map(Dyadic::of), ray.d.map(Dyadic::of));
    let mut best: Option<(RefT, u32)> = None;
    for (i, s) in shapes.iter().enumerate() {
        let Some(t) = exact_t(s, &o, &d, tmin) else {
            continue;
        };
        let below = tmax.is_none_or(|m| t.cmp(&RefT::Exact(m.clone())) == Ordering::Less);
        if below
            && best
                .as_ref()
                .is_none_or(|(bt, _)| t.cmp(bt) == Ordering::Less)
        {
            best = Some((t, i as u32));
        }
    }
    best
}

#[derive(Default)]
pub struct Counts {
    pub rays: usize,
    pub leaks: usize,
    pub false_hits: usize,
    pub wrong_nearest: usize,
    pub pass_through: usize,
    pub rel_errors: Vec<f64>,
}

impl Counts {
    /// Rays answered wrongly in any way (a leak is also a pass-through: counted once).
    pub fn wrong(&self) -> usize {
        self.false_hits + self.wrong_nearest + self.pass_through
    }

    /// Scores one answer `got` = (t, primitive) against the exact reference.
    pub fn add(
        &mut self,
        shapes: &[Shape<f32>],
        ray: &Ray<f32>,
        exact: &Option<(RefT, u32)>,
        got: Option<(f64, u32)>,
    ) {
        self.rays += 1;
        match (exact, got) {
            (Some(_), None) => {
                self.leaks += 1;
                self.pass_through += 1;
            }
            (None, Some(_)) => self.false_hits += 1,
            (Some((t, prim)), Some((gt, gprim))) => {
                if *prim != gprim {
                    // A primitive exactly behind the nearest surface: slipped through it.
                    // (One the exact ray does not meet at all is a wrong primitive.)
                    let (o, d) = (ray.o.map(Dyadic::of), ray.d.map(Dyadic::of));
                    let beyond = exact_t(&shapes[gprim as usize], &o, &d, &Q::zero())
                        .is_some_and(|gt_exact| gt_exact.cmp(t) == Ordering::Greater);
                    if beyond {
                        self.pass_through += 1;
                    } else {
                        self.wrong_nearest += 1;
                    }
                } else {
                    let t = t.f64();
                    self.rel_errors.push(((gt - t) / t).abs());
                }
            }
            (None, None) => {}
        }
    }

    /// The relative t error at `quantile` (0.5: median, 1: largest).
    pub fn rel(&self, quantile: f64) -> f64 {
        let mut e = self.rel_errors.clone();
        e.sort_by(f64::total_cmp);
        let i = ((e.len() as f64 - 1.0) * quantile).round() as usize;
        e.get(i).copied().unwrap_or(0.0)
    }
}
