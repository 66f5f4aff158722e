//! The adaptive method (the default): the exact answer at nearly the f32 watertight speed.
//!
//! What it guarantees, for any finite inputs: the primitive it returns is exactly the nearest
//! one that the exact ray meets with tmin < t < tmax (closed triangles, a triangle seen
//! edge-on misses; spheres closed, a tangent touch hits), an exact tie going to the lower
//! primitive index; a miss means exactly no such primitive.
//!
//! t comes in two grades. A query returns the t of the level that decided the hit, with that
//! level's bound (the f32 filter: pbrt-v4's bound, doubled; f64 intervals: the interval;
//! the exact level: the exact t correctly rounded): what shading needs, at no extra cost.
//! [`rounded_t`] gives the exact t **correctly rounded** to the caller's precision (the
//! nearest value, ties to even; beyond the range ±∞ and in the subnormal range as IEEE 754
//! rounds) for f32 and f64 alike: `raylab trace` prints it for every path. It costs t in
//! plain f64 with a proved bound where that decides the rounding (f32: nearly always, about
//! half a BVH query) and one exact integer division elsewhere (f64: nearly always, a few µs).
//!
//! Three levels, each consulted only where the one before cannot decide:
//! 1. **f32 filter** ([`classify_f32`]): the watertight test, with a conservative bound `E` on
//!    the rounding error of its edge functions (from the box around the triangles, the ray
//!    origin and the sheared vertices, see [`edge_error`]). An edge function beyond ±E has a certain sign; t comes
//!    with pbrt-v4's bound, doubled. Nearly every ray is decided here.
//! 2. **f64 intervals** ([`triangle_interval`], [`sphere::interval`]): the same predicates
//!    (signs of det[d, pᵢ, pⱼ], t = det[p₀, p₁, p₂] / d·n) in outward-rounded interval
//!    arithmetic on the exact inputs. Decides everything but exact degeneracies.
//! 3. **Exact rationals** ([`super::exact`]): rays exactly through an edge or a vertex,
//!    exactly equal t's, an origin exactly on a sphere.
//!
//! [`Nearest`] runs the closest-hit search over candidates at whatever level each has
//! reached: two candidates whose t intervals overlap are refined until they separate, or
//! compared exactly.

use super::exact::{self, ExactT};
use super::triangle::{t_error_bound, WatertightRay};
use super::{sphere, Hit, Ray, Shape};
use crate::math::interval::{icross, idot, isub, iv3, Interval};
use crate::math::Real;
use std::cmp::Ordering;

/// How often the adaptive method's slower levels run, counted only while switched on
/// ([`count_levels`](levels::count_levels); `examples/speed_vs_error` reports them): off,
/// counting costs a load and a branch on the slow paths only.
pub mod levels {
    use std::sync::atomic::{AtomicBool, AtomicU64, Ordering::Relaxed};

    /// What is counted.
    #[derive(Clone, Copy, Debug, PartialEq, Eq)]
    pub enum Event {
        /// A candidate the f32 filter left unsure, tested in f32 with pbrt's bound.
        PreciseF32,
        /// A candidate tested in f64 interval arithmetic.
        F64Intervals,
        /// A candidate decided exactly (expansions or rationals).
        Exact,
        /// Two hits' t compared by exact rational t's.
        ExactT,
        /// A camera lane the packet kernels left ambiguous.
        CameraLaneAmbiguous,
        /// A shadow lane the packet kernels left unsure.
        ShadowLaneUnsure,
        /// A t rounded by [`super::rounded_t`] from plain f64 or an f64 interval.
        RoundedFromF64,
        /// A t rounded by [`super::rounded_t`] exactly.
        RoundedExactly,
    }

    const EVENTS: usize = Event::RoundedExactly as usize + 1;
    static ON: AtomicBool = AtomicBool::new(false);
    static COUNTS: [AtomicU64; EVENTS] = [const { AtomicU64::new(0) }; EVENTS];

    /// Switches counting on or off (the counts stay).
    pub fn count_levels(on: bool) {
        ON.store(on, Relaxed);
    }

    /// Counts `event` where counting is on.
    #[inline]
    pub fn note(event: Event) {
        if ON.load(Relaxed) {
            COUNTS[event as usize].fetch_add(1, Relaxed);
        }
    }

    /// Counts `n` of `event` where counting is on.
    #[inline]
    pub fn note_many(event: Event, n: u32) {
        if ON.load(Relaxed) {
            COUNTS[event as usize].fetch_add(n.into(), Relaxed);
        }
    }

    /// The count of `event` so far.
    pub fn count(event: Event) -> u64 {
        COUNTS[event as usize].load(Relaxed)
    }

    /// Sets every count to zero.
    pub fn reset() {
        for c in &COUNTS {
            c.store(0, Relaxed);
        }
    }
}

use levels::{note, Event};

/// An approximate hit: t with an interval certain to hold the exact t.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Approx {
    /// Estimate of t.
    pub t: f64,
    /// Lower end of the interval holding the exact t.
    pub lo: f64,
    /// Upper end.
    pub hi: f64,
    /// Barycentric weight of vertex 1 (0 for spheres).
    pub b1: f64,
    /// Barycentric weight of vertex 2.
    pub b2: f64,
    /// 0: the SIMD loop's f32 filter with its loose per-ray t bound, 1: f32 with pbrt's t
    /// bound, 2: f64 intervals.
    pub level: u8,
}

/// What a level could tell about one primitive.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Estimate {
    /// Certainly missed.
    Miss,
    /// Cannot tell: ask the next level.
    Unsure,
    /// Certainly hit (the line meets it; for spheres also within the query's range).
    Hit(Approx),
}

/// Smallest and largest box extents for which the f32 filter's bound holds (no underflow in
/// the products, no overflow of the square). Outside them the filter defers.
const MIN_EXTENT: f32 = 1.0 / (1u64 << 40) as f32;
const MAX_EXTENT: f32 = (1u64 << 60) as f32;

/// M for the f32 filter's error bound: 2·max|v − o| over the box [lo, hi] (a bound on the
/// magnitudes |pₓ| + |Sₓ·p_z| that the sheared coordinates of its vertices are computed
/// from, as |Sₓ|, |S_y| ≤ 1), or `f32::INFINITY` where the bound would not hold.
#[inline]
pub fn box_extent(o: [f32; 3], lo: [f32; 3], hi: [f32; 3]) -> f32 {
    let mut m = 0.0f32;
    for k in 0..3 {
        m = m.max((hi[k] - o[k]).abs()).max((o[k] - lo[k]).abs());
    }
    let m = 2.0 * m * (1.0 + 1.0 / (1 << 20) as f32);
    if (MIN_EXTENT..=MAX_EXTENT).contains(&m) {
        m
    } else {
        f32::INFINITY
    }
}

/// γ(n) for f32, at compile time.
const fn gamma32(n: f32) -> f32 {
    let nu = n * (f32::EPSILON * 0.5);
    nu / (1.0 - nu)
}

/// The constants of [`edge_error`]: E = C1·M·m + C2·M² + tiny.
const EDGE_C1: f32 = 2.0 * gamma32(10.0);
const EDGE_C2: f32 = 4.0 * gamma32(4.0) * gamma32(4.0);

/// A bound E on the rounding error of a watertight f32 edge function x_j·y_k − y_j·x_k, from
/// M ([`box_extent`]) and m = the largest |x|, |y| of the three computed sheared vertices.
///
/// Each sheared coordinate x = pₓ + Sₓ·p_z is computed with error ≤ γ₄·(|pₓ| + |Sₓ·p_z|)
/// ≤ γ₄·M (one rounding each for p, S, the product and the sum), so
/// |x̃ⱼỹₖ − xⱼyₖ| ≤ γ₄·M·|ỹₖ| + (|x̃ⱼ| + γ₄·M)·γ₄·M ≤ 2γ₄·M·m + γ₄²·M², twice, plus the
/// rounding of the two products and the difference (≤ 4u·m², m ≤ M·(1 + γ₄)): in all at
/// most γ₉·M·m + 2γ₄²·M². E doubles that (margin for the rounding of E itself), and adds
/// 1e-37 for products that fall into the subnormal range.
#[inline]
pub fn edge_error(m_box: f32, m_lane: f32) -> f32 {
    EDGE_C1 * m_box * m_lane + EDGE_C2 * m_box * m_box + 1e-37
}

/// Level 1: the f32 watertight test with a certain sign for every edge function, or `Unsure`.
/// `m_box` comes from [`box_extent`] for a box holding the triangle.
#[inline]
pub fn classify_f32(r: &WatertightRay<f32>, v: &[[f32; 3]; 3], m_box: f32) -> Estimate {
    let [kx, ky, kz] = r.k;
    let [sx, sy, sz] = r.s;
    let sheared = |p: [f32; 3]| {
        let (x, y, z) = (p[kx] - r.o[kx], p[ky] - r.o[ky], p[kz] - r.o[kz]);
        [x + sx * z, y + sy * z, z]
    };
    let [a, b, c] = v.map(sheared);
    let u = c[0] * b[1] - c[1] * b[0];
    let w = b[0] * a[1] - b[1] * a[0];
    let vv = a[0] * c[1] - a[1] * c[0];
    // max|x|, |y| with plain compares (f32::max's NaN rules cost more; a NaN coordinate
    // makes the edge functions NaN, which decide nothing anyway).
    let big = |m: f32, x: f32| if x.abs() > m { x.abs() } else { m };
    let m = big(
        big(big(a[0].abs(), a[1]), big(b[0].abs(), b[1])),
        big(c[0].abs(), c[1]),
    );
    let e = edge_error(m_box, m);
    if (u < -e || vv < -e || w < -e) && (u > e || vv > e || w > e) {
        return Estimate::Miss;
    }
    let all_pos = u > e && vv > e && w > e;
    let all_neg = u < -e && vv < -e && w < -e;
    if !(all_pos || all_neg) {
        return Estimate::Unsure;
    }
    let det = u + vv + w;
    let rcp = 1.0 / det;
    let t = (u * a[2] + vv * b[2] + w * c[2]) * sz * rcp;
    let bound = t_error_bound(&[a, b, c], sz, [u, vv, w], rcp);
    approx_f32(t, bound, vv * rcp, w * rcp, 1)
}

/// The smallest f32 ≥ x.
#[inline]
pub fn round_up(x: f64) -> f32 {
    let y = x as f32;
    if (y as f64) < x {
        y.next_up()
    } else {
        y
    }
}

/// The largest f32 ≤ x.
#[inline]
pub fn round_down(x: f64) -> f32 {
    let y = x as f32;
    if (y as f64) > x {
        y.next_down()
    } else {
        y
    }
}

/// The f32 filter's hit as an interval (the t bound doubled for margin); `level` 0 for the
/// loose bound of [`loose_t_bound`], 1 for pbrt's.
#[inline]
pub fn approx_f32(t: f32, bound: f32, b1: f32, b2: f32, level: u8) -> Estimate {
    if !(t.is_finite() && bound.is_finite()) {
        return Estimate::Unsure;
    }
    let (t, slack) = (t as f64, 2.0 * bound as f64);
    Estimate::Hit(Approx {
        t,
        lo: t - slack,
        hi: t + slack,
        b1: b1 as f64,
        b2: b2 as f64,
        level,
    })
}

/// Coefficients (A, B) of a per-ray bound A + B·|1/det| on pbrt's t error bound, valid for
/// every triangle inside a box of extent `m_box` ([`box_extent`]) whose edge signs are all
/// certain. It costs two operations per lane instead of about thirty; where it is too loose
/// to order two hits, the search recomputes pbrt's bound for just those two.
///
/// Derivation: with all edge functions of one sign, |det| ≥ max|e|, so max|e|·|1/det| ≤ 1;
/// every sheared |x|, |y| is ≤ M and |z| ≤ M/2 (see [`box_extent`]). Substituted into
/// pbrt's 3·(γ₃·max|e|·Zₜ + δₑ·Zₜ + δ_z·max|e|)·|1/det| with Zₜ = max|z|·|S_z|:
/// ≤ |S_z|·M·(3γ₃ + 3(γ₂ + 3γ₅)·M²·|1/det|), and 1% on top for the rounding of this.
#[inline]
pub fn loose_t_bound(m_box: f32, sz: f32) -> (f32, f32) {
    let k = 1.01 * m_box * sz.abs();
    (
        k * 3.0003 * gamma32(3.0),
        k * 3.0 * (gamma32(2.0) + 3.0 * gamma32(5.0)) * m_box * m_box,
    )
}

/// The f32 test with pbrt's t bound, from f32 inputs (level 1), for a triangle found by the
/// loose level.
fn precise_f32(o: [f32; 3], d: [f32; 3], v: &[[f32; 3]; 3]) -> Estimate {
    let Some(r) = WatertightRay::new(o, d) else {
        return Estimate::Unsure;
    };
    let (mut lo, mut hi) = (v[0], v[0]);
    for p in &v[1..] {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    classify_f32(&r, v, box_extent(o, lo, hi))
}

/// Level 2 for a triangle: the signs of det[d, pᵢ, pⱼ] and t in f64 intervals.
pub fn triangle_interval(o: [f64; 3], d: [f64; 3], v: &[[f64; 3]; 3]) -> Estimate {
    let (o, d) = (iv3(o), iv3(d));
    let p = v.map(|vi| isub(iv3(vi), o));
    let e = [(1, 2), (2, 0), (0, 1)].map(|(i, j)| idot(d, icross(p[i], p[j])));
    let s = e.map(Interval::sign);
    if s.contains(&Some(Ordering::Less)) && s.contains(&Some(Ordering::Greater)) {
        return Estimate::Miss;
    }
    if s.contains(&None) {
        return Estimate::Unsure;
    }
    if s.iter().all(|x| *x == Some(Ordering::Equal)) {
        return Estimate::Miss; // the line lies in the triangle's plane
    }
    let den = e[0] + e[1] + e[2];
    let num = idot(p[0], icross(p[1], p[2]));
    let Some(t) = num.checked_div(den) else {
        return Estimate::Unsure;
    };
    if !t.is_finite() {
        return Estimate::Unsure;
    }
    let dm = den.mid();
    Estimate::Hit(Approx {
        t: t.mid(),
        lo: t.lo,
        hi: t.hi,
        b1: e[1].mid() / dm,
        b2: e[2].mid() / dm,
        level: 2,
    })
}

/// Where an exactly decided triangle hit lies: two hits at the same edge line or vertex (the
/// same f32 coordinates) are at the same t, which settles an exact tie without computing t.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Feature {
    Interior,
    Edge([[f64; 3]; 2]),
    Vertex([f64; 3]),
    Root,
}

/// A hit decided exactly: t as an interval where one is known, the exact t once needed.
#[derive(Clone, Debug)]
struct Decided {
    t: Option<Interval>,
    point: Feature,
    exact: Option<ExactT>,
    b1: f64,
    b2: f64,
}

/// A candidate's t at the level it has reached.
#[derive(Clone, Debug)]
enum Level {
    Approx(Approx),
    Decided(Box<Decided>),
}

#[derive(Clone, Debug)]
struct Candidate {
    prim: u32,
    shape: Shape<f64>,
    level: Level,
}

/// The closest-hit search of the adaptive method over candidates offered in any order.
#[derive(Clone, Debug)]
pub struct Nearest {
    o: [f64; 3],
    d: [f64; 3],
    tmin: f64,
    tmax: f64,
    best: Option<Candidate>,
    /// Whether the inputs are f32, so that the f32 levels may be consulted.
    f32_inputs: bool,
}

impl Nearest {
    /// A search along `ray` for tmin < t < tmax.
    pub fn new<T: Real>(ray: &Ray<T>, tmin: T, tmax: T) -> Self {
        Self {
            o: ray.o.map(Real::f64),
            d: ray.d.map(Real::f64),
            tmin: tmin.f64(),
            tmax: tmax.f64(),
            best: None,
            f32_inputs: false,
        }
    }

    /// A search whose candidates may come from the f32 levels (f32 inputs only).
    pub fn with_f32_levels(ray: &Ray<f32>, tmin: f32, tmax: f32) -> Self {
        Self {
            f32_inputs: true,
            ..Self::new(ray, tmin, tmax)
        }
    }

    /// The query's tmin.
    pub fn tmin(&self) -> f64 {
        self.tmin
    }

    /// An upper bound on the exact t of the best hit so far (tmax without one): anything
    /// that certainly starts beyond it cannot win.
    #[inline]
    pub fn t_far(&self) -> f64 {
        match &self.best {
            None => self.tmax,
            Some(c) => match &c.level {
                Level::Approx(a) => a.hi.min(self.tmax),
                Level::Decided(x) => match (&x.t, &x.exact) {
                    (Some(t), _) => t.hi.min(self.tmax),
                    // approx() is rounded (a few ulps for a root): step well past it.
                    (None, Some(t)) => {
                        let v = t.approx();
                        (v + v.abs() * 1e-9 + f64::MIN_POSITIVE).min(self.tmax)
                    }
                    (None, None) => self.tmax,
                },
            },
        }
    }

    /// Whether a candidate whose exact t is ≥ `lo` certainly loses (ties must be kept for
    /// the index rule, so only strictly beyond the best counts).
    #[inline]
    pub fn beyond(&self, lo: f64) -> bool {
        lo >= self.tmax || (self.best.is_some() && lo > self.t_far())
    }

    /// The nearest hit found.
    pub fn hit(&self) -> Option<Hit<f64>> {
        self.hit_in::<f64>()
    }

    /// The nearest hit in f32 (an exact level's t rounded straight to f32: rounding it to
    /// f64 first took ~20 exact comparisons where f32 needs 2 or 3, ~0.7M instructions for
    /// each hit near a sphere's contact with another surface).
    pub fn hit_f32(&self) -> Option<Hit<f32>> {
        self.hit_in::<f32>()
    }

    fn hit_in<T: Real>(&self) -> Option<Hit<T>> {
        self.best.as_ref().map(|c| {
            let (t, b1, b2) = match &c.level {
                Level::Approx(a) => (T::of(a.t), a.b1, a.b2),
                Level::Decided(x) => {
                    let t = match (&x.t, &x.exact) {
                        (_, Some(e)) => e.rounded::<T>(),
                        (Some(t), None) => T::of(t.mid()),
                        (None, None) => T::of(f64::NAN),
                    };
                    (t, x.b1, x.b2)
                }
            };
            Hit {
                t,
                prim: c.prim,
                b1: T::of(b1),
                b2: T::of(b2),
            }
        })
    }

    /// Offers primitive `prim` with what a cheaper level found out about it.
    pub fn offer(&mut self, prim: u32, shape: Shape<f64>, estimate: Estimate) {
        let Some(mut cand) = self.in_range(prim, shape, estimate) else {
            return;
        };
        let Some(mut best) = self.best.take() else {
            self.best = Some(cand);
            return;
        };
        let order = loop {
            // Disjoint t intervals order the two at any level (a decided hit beside one only
            // estimated: refining the estimate to exact cost ~0.5M instructions per ray along
            // a quad's diagonal that hit a sphere in front of it).
            if let (Some(x), Some(y)) = (t_bounds(&cand.level), t_bounds(&best.level)) {
                if x.1 < y.0 {
                    break Ordering::Less;
                }
                if x.0 > y.1 {
                    break Ordering::Greater;
                }
            }
            if let (Level::Decided(_), Level::Decided(_)) = (&cand.level, &best.level) {
                break self.cmp_decided(&mut cand, &mut best);
            }
            // Overlapping: refine the less refined one (or both at the same level).
            let (lc, lb) = (rank(&cand.level), rank(&best.level));
            if lc <= lb {
                match self.refine(&cand) {
                    Some(l) => cand.level = l,
                    None => {
                        self.best = Some(best); // it was not a hit after all
                        return;
                    }
                }
            }
            if lb <= lc {
                match self.refine(&best) {
                    Some(l) => best.level = l,
                    None => {
                        self.best = Some(cand);
                        return;
                    }
                }
            }
        };
        let wins = order == Ordering::Less || (order == Ordering::Equal && cand.prim < best.prim);
        self.best = Some(if wins { cand } else { best });
    }

    /// Whether the primitive is certainly hit with tmin < t < tmax (an any-hit query).
    pub fn confirms(&self, shape: Shape<f64>, estimate: Estimate) -> bool {
        self.in_range(0, shape, estimate).is_some()
    }

    /// Orders two exactly decided hits by t: by their intervals, by a shared edge or vertex
    /// (or identical triangles), and only failing those by exact rational t.
    fn cmp_decided(&self, a: &mut Candidate, b: &mut Candidate) -> Ordering {
        let (Level::Decided(x), Level::Decided(y)) = (&a.level, &b.level) else {
            unreachable!("both decided");
        };
        if let (Some(tx), Some(ty)) = (x.t, y.t) {
            if tx.hi < ty.lo {
                return Ordering::Less;
            }
            if tx.lo > ty.hi {
                return Ordering::Greater;
            }
        }
        if x.point != Feature::Interior && x.point != Feature::Root && x.point == y.point {
            return Ordering::Equal;
        }
        if let (Shape::Triangle(p), Shape::Triangle(q)) = (&a.shape, &b.shape) {
            // Two hits on one plane are at the same t (the line crosses it once: a line in
            // the plane misses). Deciding that from three exact orientations spares the
            // rational t's, which made a ray through 10⁴ overlapping coplanar faces cost
            // 10⁴ big-number divisions.
            if same_vertices(p, q) || coplanar(p, q) {
                return Ordering::Equal;
            }
        }
        note(Event::ExactT);
        let tx = self.exact_t(a);
        let ty = self.exact_t(b);
        match (tx, ty) {
            (Some(tx), Some(ty)) => tx.cmp_t(&ty),
            _ => Ordering::Equal, // unreachable for a decided hit (its plane is not parallel)
        }
    }

    /// The exact t of a decided candidate, computed once.
    fn exact_t(&self, c: &mut Candidate) -> Option<ExactT> {
        let Level::Decided(x) = &mut c.level else {
            return None;
        };
        if x.exact.is_none() {
            if let Shape::Triangle(v) = &c.shape {
                x.exact = exact::plane_t(self.o, self.d, v);
            }
        }
        x.exact.clone()
    }

    /// The candidate, refined until it is certainly hit within (tmin, tmax), or `None`.
    fn in_range(&self, prim: u32, shape: Shape<f64>, estimate: Estimate) -> Option<Candidate> {
        let mut cand = Candidate {
            prim,
            shape,
            level: match estimate {
                Estimate::Miss => return None,
                Estimate::Unsure => Level::Approx(Approx {
                    t: 0.0,
                    lo: f64::NEG_INFINITY,
                    hi: f64::INFINITY,
                    b1: 0.0,
                    b2: 0.0,
                    level: if self.f32_inputs { 0 } else { 1 },
                }),
                Estimate::Hit(a) => Level::Approx(a),
            },
        };
        loop {
            let (lo, hi) = match &cand.level {
                Level::Approx(a) => (a.lo, a.hi),
                Level::Decided(x) => {
                    x.t.map_or((f64::NEG_INFINITY, f64::INFINITY), |t| (t.lo, t.hi))
                }
            };
            if lo > self.tmin && hi < self.tmax {
                return Some(cand);
            }
            if hi <= self.tmin || lo >= self.tmax {
                return None;
            }
            if let Level::Decided(_) = cand.level {
                let t = self.exact_t(&mut cand)?;
                let inside =
                    t.cmp_f(self.tmin) == Ordering::Greater && t.cmp_f(self.tmax) == Ordering::Less;
                return inside.then_some(cand);
            }
            cand.level = self.refine(&cand)?;
        }
    }

    /// The next level's answer for a candidate; `None` if it turns out to be a miss.
    fn refine(&self, c: &Candidate) -> Option<Level> {
        let mut level = match &c.level {
            Level::Approx(a) => a.level,
            Level::Decided(..) => unreachable!("decided candidates are never refined"),
        };
        while level < 2 {
            // (Counted where a level runs a test: a sphere has no f32 level.)
            let est = match (&c.shape, level) {
                (Shape::Triangle(v), 0) if self.f32_inputs => {
                    note(Event::PreciseF32);
                    precise_f32(
                        self.o.map(|x| x as f32),
                        self.d.map(|x| x as f32),
                        &v.map(|p| p.map(|x| x as f32)),
                    )
                }
                (Shape::Triangle(v), 1) => {
                    note(Event::F64Intervals);
                    triangle_interval(self.o, self.d, v)
                }
                (Shape::Sphere { centre, radius }, 1) => {
                    note(Event::F64Intervals);
                    sphere::interval(self.o, self.d, *centre, *radius, self.tmin, self.tmax)
                }
                _ => Estimate::Unsure,
            };
            match est {
                Estimate::Miss => return None,
                Estimate::Hit(a) => return Some(Level::Approx(a)),
                Estimate::Unsure => level += 1,
            }
        }
        note(Event::Exact);
        match &c.shape {
            Shape::Triangle(v) => decide_triangle(self.o, self.d, v),
            Shape::Sphere { centre, radius } => {
                sphere::exact(self.o, self.d, *centre, *radius, self.tmin, self.tmax).map(|t| {
                    Level::Decided(Box::new(Decided {
                        t: None,
                        point: Feature::Root,
                        exact: Some(t),
                        b1: 0.0,
                        b2: 0.0,
                    }))
                })
            }
        }
    }
}

/// The exact level for a triangle: exact edge signs (expansions, or rationals where those
/// cannot be used), which edge or vertex the line passes through, and t as an interval.
fn decide_triangle(o: [f64; 3], d: [f64; 3], v: &[[f64; 3]; 3]) -> Option<Level> {
    const EDGES: [(usize, usize); 3] = [(1, 2), (2, 0), (0, 1)];
    let s = EDGES.map(|(i, j)| {
        exact::orient(d, o, v[i], v[j]).unwrap_or_else(|| exact::orient_rational(d, o, v[i], v[j]))
    });
    let mixed = s.contains(&Ordering::Less) && s.contains(&Ordering::Greater);
    let zeros: Vec<usize> = (0..3).filter(|&k| s[k] == Ordering::Equal).collect();
    if mixed || zeros.len() == 3 {
        return None;
    }
    let point = match zeros[..] {
        [] => Feature::Interior,
        [k] => {
            let (i, j) = EDGES[k];
            let mut e = [v[i], v[j]];
            e.sort_by(|a, b| {
                a.iter()
                    .zip(b)
                    .fold(Ordering::Equal, |o, (x, y)| o.then(x.total_cmp(y)))
            });
            Feature::Edge(e)
        }
        // Two edges through the line: it passes through the vertex they share (the one
        // opposite the third edge).
        _ => Feature::Vertex(v[3 - zeros[0] - zeros[1]]),
    };
    let (t, b1, b2) = triangle_t_interval(o, d, v);
    Some(Level::Decided(Box::new(Decided {
        t,
        point,
        exact: None,
        b1,
        b2,
    })))
}

/// t = det[p₀, p₁, p₂] / d·n as an interval (if d·n is certainly non-zero), with estimates
/// of the barycentrics.
fn triangle_t_interval(
    o: [f64; 3],
    d: [f64; 3],
    v: &[[f64; 3]; 3],
) -> (Option<Interval>, f64, f64) {
    let (o, d) = (iv3(o), iv3(d));
    let p = v.map(|vi| isub(iv3(vi), o));
    let e = [(1, 2), (2, 0), (0, 1)].map(|(i, j)| idot(d, icross(p[i], p[j])));
    let den = e[0] + e[1] + e[2];
    let num = idot(p[0], icross(p[1], p[2]));
    let t = num.checked_div(den).filter(|t| t.is_finite());
    let dm = den.mid();
    (
        t,
        (e[1].mid() / dm).clamp(0.0, 1.0),
        (e[2].mid() / dm).clamp(0.0, 1.0),
    )
}

/// Whether triangle `q` lies exactly in the plane of triangle `p` (false where the exact test
/// cannot be made with expansions: the caller then compares exact t's).
fn coplanar(p: &[[f64; 3]; 3], q: &[[f64; 3]; 3]) -> bool {
    q.iter()
        .all(|x| exact::plane_side_f64(p, *x) == Some(Ordering::Equal))
}

/// Whether two triangles have the same three vertices (in any order).
fn same_vertices(p: &[[f64; 3]; 3], q: &[[f64; 3]; 3]) -> bool {
    p.iter().all(|a| q.contains(a)) && q.iter().all(|a| p.contains(a))
}

/// An interval holding the candidate's exact t, where its level has one.
fn t_bounds(l: &Level) -> Option<(f64, f64)> {
    match l {
        Level::Approx(a) => Some((a.lo, a.hi)),
        Level::Decided(x) => x.t.map(|t| (t.lo, t.hi)),
    }
}

fn rank(l: &Level) -> u8 {
    match l {
        Level::Approx(a) => a.level,
        Level::Decided(..) => 3,
    }
}

/// The closest-hit search as the fast paths run it: while every candidate is decided by the
/// f32 filter and their intervals do not overlap, a few compares per candidate; at the first
/// that is not (an unsure lane, overlapping t's, t near tmin), everything so far moves into a
/// [`Nearest`] and the search goes on there.
#[derive(Clone, Debug)]
pub struct Search {
    tmin: f64,
    tmax: f64,
    tmax32: f32,
    fast: Option<FastBest>,
    slow: Option<Box<Nearest>>,
    ray: Ray<f32>,
}

#[derive(Clone, Copy, Debug)]
struct FastBest {
    prim: u32,
    tri: [[f32; 3]; 3],
    approx: Approx,
    /// `approx.hi` rounded up to f32, for box culling.
    far32: f32,
}

impl Search {
    /// A search along `ray` for tmin < t < tmax.
    #[inline]
    pub fn new(ray: &Ray<f32>, tmin: f32, tmax: f32) -> Self {
        Self {
            tmin: tmin as f64,
            tmax: tmax as f64,
            tmax32: tmax,
            fast: None,
            slow: None,
            ray: *ray,
        }
    }

    /// The query's tmin.
    #[inline]
    pub fn tmin(&self) -> f64 {
        self.tmin
    }

    /// An upper bound on the exact t of the best hit so far (tmax without one).
    #[inline]
    pub fn t_far(&self) -> f64 {
        match (&self.slow, &self.fast) {
            (Some(n), _) => n.t_far(),
            (None, Some(b)) => b.approx.hi.min(self.tmax),
            (None, None) => self.tmax,
        }
    }

    /// [`Search::t_far`] rounded up to f32.
    #[inline]
    pub fn t_far32(&self) -> f32 {
        match (&self.slow, &self.fast) {
            (Some(n), _) => round_up(n.t_far()),
            (None, Some(b)) => b.far32,
            (None, None) => self.tmax32,
        }
    }

    /// Offers triangle `prim` with the f32 filter's estimate.
    #[inline]
    pub fn offer_triangle(&mut self, prim: u32, tri: &[[f32; 3]; 3], mut est: Estimate) {
        if let Some(n) = &mut self.slow {
            n.offer(prim, widen(&Shape::Triangle(*tri)), est);
            return;
        }
        while let Estimate::Hit(a) = est {
            if a.hi <= self.tmin || a.lo >= self.tmax {
                return;
            }
            if a.lo > self.tmin && a.hi < self.tmax {
                match &mut self.fast {
                    None => {}
                    Some(b) if a.lo > b.approx.hi => return,
                    Some(b) if a.hi < b.approx.lo => {}
                    Some(b) => {
                        // Overlapping: tighten the loose bounds first.
                        if a.level == 0 {
                            est = precise_f32(self.ray.o, self.ray.d, tri);
                            continue;
                        }
                        if b.approx.level == 0 {
                            match precise_f32(self.ray.o, self.ray.d, &b.tri) {
                                Estimate::Hit(x) => {
                                    b.approx = x;
                                    b.far32 = round_up(x.hi);
                                    continue;
                                }
                                _ => break,
                            }
                        }
                        break;
                    }
                }
                self.fast = Some(FastBest {
                    prim,
                    tri: *tri,
                    approx: a,
                    far32: round_up(a.hi.min(self.tmax)),
                });
                return;
            }
            if a.level > 0 {
                break;
            }
            est = precise_f32(self.ray.o, self.ray.d, tri);
        }
        if est != Estimate::Miss {
            self.go_slow()
                .offer(prim, widen(&Shape::Triangle(*tri)), est);
        }
    }

    /// Offers any primitive (spheres go straight to the exact search).
    pub fn offer_shape(&mut self, prim: u32, shape: Shape<f64>, est: Estimate) {
        self.go_slow().offer(prim, shape, est);
    }

    fn go_slow(&mut self) -> &mut Nearest {
        if self.slow.is_none() {
            let mut n = Nearest::with_f32_levels(&self.ray, self.tmin as f32, self.tmax as f32);
            if let Some(b) = self.fast.take() {
                n.offer(
                    b.prim,
                    widen(&Shape::Triangle(b.tri)),
                    Estimate::Hit(b.approx),
                );
            }
            self.slow = Some(Box::new(n));
        }
        self.slow.as_mut().expect("just set")
    }

    /// The nearest hit.
    #[inline]
    pub fn hit(&self) -> Option<Hit<f32>> {
        match (&self.slow, &self.fast) {
            (Some(n), _) => n.hit_f32(),
            (None, Some(b)) => Some(Hit {
                t: b.approx.t as f32,
                prim: b.prim,
                b1: b.approx.b1 as f32,
                b2: b.approx.b2 as f32,
            }),
            (None, None) => None,
        }
    }

    /// Whether triangle `tri` is certainly hit within (tmin, tmax) (an any-hit query).
    #[inline]
    pub fn confirms_triangle(&self, tri: &[[f32; 3]; 3], est: Estimate) -> bool {
        match est {
            Estimate::Miss => false,
            Estimate::Hit(a) if a.lo > self.tmin && a.hi < self.tmax => true,
            Estimate::Hit(a) if a.hi <= self.tmin || a.lo >= self.tmax => false,
            _ => Nearest::with_f32_levels(&self.ray, self.tmin as f32, self.tmax as f32)
                .confirms(widen(&Shape::Triangle(*tri)), est),
        }
    }
}

/// The adaptive nearest hit over shapes by brute force, starting at the interval level (no
/// f32 filter): the reference that the fast paths are tested against.
pub fn closest_hit_reference<T: Real>(
    shapes: &[Shape<T>],
    ray: &Ray<T>,
    tmin: T,
    tmax: T,
) -> Option<Hit<f64>> {
    let mut n = Nearest::new(ray, tmin, tmax);
    for (i, s) in shapes.iter().enumerate() {
        n.offer(i as u32, widen(s), Estimate::Unsure);
    }
    n.hit()
}

/// The t at which `ray` meets `shape` (the plane of a triangle; a sphere's nearest root with
/// tmin < t < tmax), correctly rounded to T: the exact t rounded to the nearest value of T,
/// ties to even, overflowing to ±∞ and underflowing as IEEE 754 rounding does. `None` where
/// there is no such t (a line parallel to the plane, a sphere missed in the range).
///
/// It gives t for a primitive a query found; whether the ray meets the triangle inside its
/// edges is the query's business. Exact arithmetic only where t in f64 with its bound
/// (`plane_t_f64`; a sphere's f64 interval) cannot decide the rounding: for f32, nearly
/// never; for f64, nearly always (an f64 bound decides an f64 rounding only when it is 0).
pub fn rounded_t<T: Real>(shape: &Shape<T>, ray: &Ray<T>, tmin: T, tmax: T) -> Option<T> {
    let (o, d) = (ray.o.map(Real::f64), ray.d.map(Real::f64));
    let (tmin, tmax) = (tmin.f64(), tmax.f64());
    let decides = |lo: f64, hi: f64| {
        let r = T::of(lo);
        (lo > tmin && hi < tmax && r == T::of(hi)).then_some(r)
    };
    match widen(shape) {
        Shape::Triangle(v) => {
            if let Some((t, err)) = plane_t_f64(o, d, &v) {
                if let Some(r) = decides(t - err, t + err) {
                    note(Event::RoundedFromF64);
                    return Some(r);
                }
            }
            note(Event::RoundedExactly);
            exact::plane_t_rounded(o, d, &v)
        }
        Shape::Sphere { centre, radius } => {
            if let Estimate::Hit(a) = sphere::interval(o, d, centre, radius, tmin, tmax) {
                if let Some(r) = decides(a.lo, a.hi) {
                    note(Event::RoundedFromF64);
                    return Some(r);
                }
            }
            note(Event::RoundedExactly);
            Some(sphere::exact(o, d, centre, radius, tmin, tmax)?.rounded())
        }
    }
}

/// t = p₀·n / d·n of the plane of v in plain f64 (pᵢ = vᵢ − o, n = (p₁ − p₀) × (p₂ − p₀)),
/// with a bound on its error; `None` for inputs where over- or underflow could void it.
///
/// Every path through num and den is at most 7 roundings deep, so (Higham, ch. 3)
/// |fl(x) − x| ≤ γ₇·x_abs, with x_abs the same sums and products over absolute values; that
/// is computed in f64 too (rounding it adds at most γ₇ more), so err_x = 2γ₈·x_abs bounds it.
/// The quotient adds one rounding: |t̃ − t| ≤ (|t̃|·err_den + err_num)/(|den| − err_den) + u|t̃|.
/// About 40 ns; it decides an f32 rounding unless t lies within ~2⁻⁴⁰ of a midpoint.
fn plane_t_f64(o: [f64; 3], d: [f64; 3], v: &[[f64; 3]; 3]) -> Option<(f64, f64)> {
    use crate::math::real::{cross, dot, sub};
    // Inputs 0 or within 2^±200 (every f32 is): nothing overflows, and every nonzero
    // difference, edge and product of two is a multiple of 2⁻²⁵² and ≥ 2⁻⁷⁵⁶, normal. Only
    // the last products (into num and den) may underflow, each by < 2⁻¹⁰⁷⁴: the 8·2⁻¹⁰⁷⁴.
    let safe = |x: &f64| *x == 0.0 || (2f64.powi(-200)..=2f64.powi(200)).contains(&x.abs());
    if !o.iter().chain(&d).chain(v.iter().flatten()).all(safe) {
        return None;
    }
    // The same sums and products over absolute values.
    let add_abs = |a: [f64; 3], b: [f64; 3]| [0, 1, 2].map(|k| a[k].abs() + b[k].abs());
    let cross_abs = |a: [f64; 3], b: [f64; 3]| {
        [
            a[1] * b[2] + a[2] * b[1],
            a[2] * b[0] + a[0] * b[2],
            a[0] * b[1] + a[1] * b[0],
        ]
    };
    let p = v.map(|vi| sub(vi, o));
    let p_abs = v.map(|vi| add_abs(vi, o));
    let n = cross(sub(p[1], p[0]), sub(p[2], p[0]));
    let n_abs = cross_abs(add_abs(p_abs[1], p_abs[0]), add_abs(p_abs[2], p_abs[0]));
    let (num, den) = (dot(p[0], n), dot(d, n));
    let (num_abs, den_abs) = (dot(p_abs[0], n_abs), dot(d.map(f64::abs), n_abs));
    const G8: f64 = 8.0 * f64::EPSILON * 0.5 / (1.0 - 8.0 * f64::EPSILON * 0.5);
    const UNDERFLOW: f64 = 8.0 * f64::MIN_POSITIVE * f64::EPSILON; // 8·2⁻¹⁰⁷⁴
    let err_num = 2.0 * G8 * num_abs + UNDERFLOW;
    let err_den = 2.0 * G8 * den_abs + UNDERFLOW;
    if den.abs() <= 2.0 * err_den {
        return None;
    }
    let t = num / den;
    let err = (t.abs() * err_den + err_num) / (den.abs() - err_den) * (1.0 + 4.0 * f64::EPSILON)
        + t.abs() * f64::EPSILON;
    (t.is_finite() && err.is_finite()).then_some((t, err))
}

/// Which level decides whether `ray` meets `shape` at all (the ray inspector shows it):
/// "f32 filter", "f64 intervals" or "exact". (Comparing t's with other candidates may need a
/// finer level still; that is the search's business.)
pub fn deciding_level(shape: &Shape<f32>, ray: &Ray<f32>) -> &'static str {
    let (o, d) = (ray.o.map(f64::from), ray.d.map(f64::from));
    let decided = |e: Estimate| e != Estimate::Unsure;
    match shape {
        Shape::Triangle(v) => {
            if decided(precise_f32(ray.o, ray.d, v)) {
                "f32 filter"
            } else if decided(triangle_interval(o, d, &v.map(|p| p.map(f64::from)))) {
                "f64 intervals"
            } else {
                "exact"
            }
        }
        Shape::Sphere { centre, radius } => {
            let c = centre.map(f64::from);
            match decided(sphere::interval(
                o,
                d,
                c,
                *radius as f64,
                0.0,
                f64::INFINITY,
            )) {
                true => "f64 intervals",
                false => "exact",
            }
        }
    }
}

/// A shape in f64 (exact for f32 input).
pub fn widen<T: Real>(s: &Shape<T>) -> Shape<f64> {
    match s {
        Shape::Triangle(v) => Shape::Triangle(v.map(|p| p.map(Real::f64))),
        Shape::Sphere { centre, radius } => Shape::Sphere {
            centre: centre.map(Real::f64),
            radius: radius.f64(),
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// A float of any magnitude from 2⁻¹⁹⁵ to 2¹⁹⁵ (the bound's range), either sign.
    fn wide() -> impl Strategy<Value = f64> {
        (-1.0f64..1.0, -195i32..195).prop_map(|(m, e)| m * 2f64.powi(e))
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(3000))]
        /// plane_t_f64's bound holds the exact t, for grazing rays (d nearly in the plane)
        /// and for coordinates of any magnitude in its range.
        #[test]
        fn the_f64_plane_t_bound_holds_the_exact_t(
            v in prop::array::uniform3(prop::array::uniform3(-4.0f64..4.0)),
            o in prop::array::uniform3(-8.0f64..8.0),
            b in (0.0f64..1.0, 0.0f64..1.0),
            tilt in -60i32..0,
            scale in -190i32..190,
            wild in prop::array::uniform3(wide()),
        ) {
            let s = 2f64.powi(scale);
            let v = v.map(|p| p.map(|x| x * s));
            let o = o.map(|x| x * s);
            // Aim at a point of the plane, then tilt d into the plane by 2^tilt.
            let target = [0, 1, 2].map(|k| v[0][k] + b.0 * (v[1][k] - v[0][k]) + b.1 * (v[2][k] - v[0][k]));
            let along = [0, 1, 2].map(|k| v[1][k] - v[0][k]);
            let w = 2f64.powi(tilt);
            for d in [
                [0, 1, 2].map(|k| target[k] - o[k]),
                [0, 1, 2].map(|k| along[k] + w * (target[k] - o[k])),
                wild,
            ] {
                let Some((t, err)) = plane_t_f64(o, d, &v) else { continue };
                let exact = exact::plane_t(o, d, &v).expect("not parallel where the bound holds");
                prop_assert_ne!(exact.cmp_f(t - err), Ordering::Less, "t {} err {}", t, err);
                prop_assert_ne!(exact.cmp_f(t + err), Ordering::Greater, "t {} err {}", t, err);
            }
        }
    }

    #[test]
    fn rounded_t_agrees_with_the_exact_rounding_on_both_levels() {
        // A grazing ray: the f64 bound cannot decide the f32 rounding of a t whose
        // d·n cancels this far, so the integer level gives it (exactly 1/4).
        let v = [
            [0.0, 0.0, 0.0],
            [1.4742268323898315, 0.0, 1.9907678365707397],
            [0.0, 1.0, 0.0],
        ];
        let o = [0.4116266369819641, 0.25, 0.5558527708053589];
        let d = [1.3019471168518066, 0.0, 1.758124589920044];
        let tri32 = Shape::Triangle(v.map(|p| p.map(|x| x as f32)));
        let ray32 = Ray::new(o.map(|x| x as f32), d.map(|x| x as f32));
        assert_eq!(rounded_t(&tri32, &ray32, 0.0, f32::INFINITY), Some(0.25));
        // A plain ray: decided by the f64 bound, equal to the exact rounding.
        let ray = Ray::new([0.1f32, 0.2, -3.0], [0.013, -0.02, 1.0]);
        let tri = [[-1.0f32, -1.0, 1.0], [1.0, -1.0, 1.0], [0.0, 1.0, 1.0]];
        let wide = tri.map(|p| p.map(f64::from));
        let (o, d) = (ray.o.map(f64::from), ray.d.map(f64::from));
        let (t, err) = plane_t_f64(o, d, &wide).unwrap();
        assert_eq!((t - err) as f32, (t + err) as f32);
        let exact: f32 = exact::plane_t(o, d, &wide).unwrap().rounded();
        assert_eq!(
            rounded_t(&Shape::Triangle(tri), &ray, 0.0, f32::INFINITY),
            Some(exact)
        );
        assert_eq!(exact::plane_t_rounded::<f32>(o, d, &wide), Some(exact));
    }
}
