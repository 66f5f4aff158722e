//! The adaptive method (the default): the exact answer at nearly the f32 watertight speed.
//!
//! What it guarantees, for any finite inputs: the primitive it returns is exactly the nearest
//! one that the exact ray meets with tmin < t < tmax (closed triangles, a triangle seen
//! edge-on misses; spheres closed, a tangent touch hits), an exact tie going to the lower
//! primitive index; a miss means exactly no such primitive. The t it reports is within the
//! stated bound of the exact t (f32 rounding of it, for f32 callers).
//!
//! Three levels, each consulted only where the one before cannot decide:
//! 1. **f32 filter** ([`classify_f32`]): the watertight test, with a conservative bound `E` on
//!    the rounding error of its edge functions (from the box around the triangles and the ray
//!    origin, see [`edge_bound`]). An edge function beyond ±E has a certain sign; t comes
//!    with pbrt-v4's bound, doubled. Nearly every ray is decided here.
//! 2. **f64 intervals** ([`triangle_interval`], [`sphere_interval`]): the same predicates
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
use super::{Hit, Ray, Shape};
use crate::math::interval::{icross, idot, isub, iv3, Interval};
use crate::math::Real;
use std::cmp::Ordering;

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
    /// 0: from the f32 filter, 1: from f64 intervals.
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

/// A bound E on the rounding error of the f32 watertight edge functions for triangles inside
/// the box [lo, hi], seen from `o`.
///
/// With p = v − o and the shear S (|Sx|, |Sy| ≤ 1, z being the largest axis of d), each
/// sheared coordinate carries at most γ₄·(|pₓ| + |Sₓ·p_z|) ≤ γ₄·2·max|p| error, and each edge
/// function x_j·y_k − y_j·x_k at most γ₁₁·2·M² with M = 2·max|p| (Higham-style counting; see
/// the module docs). E = 3·γ₁₆·M² leaves a margin of 2 for the rounding of E itself.
/// `f32::INFINITY` where the bound would not hold (the filter then decides nothing).
#[inline]
pub fn edge_bound(o: [f32; 3], lo: [f32; 3], hi: [f32; 3]) -> f32 {
    let mut m = 0.0f32;
    for k in 0..3 {
        m = m.max((hi[k] - o[k]).abs()).max((o[k] - lo[k]).abs());
    }
    let m = 2.0 * m * (1.0 + 1.0 / (1 << 20) as f32);
    if !(MIN_EXTENT..=MAX_EXTENT).contains(&m) {
        return f32::INFINITY;
    }
    3.0 * f32::error_gamma(16) * m * m
}

/// Level 1: the f32 watertight test with a certain sign for every edge function, or `Unsure`.
/// `e_bound` comes from [`edge_bound`] for a box holding the triangle.
#[inline]
pub fn classify_f32(r: &WatertightRay<f32>, v: &[[f32; 3]; 3], e_bound: f32) -> Estimate {
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
    let e = e_bound;
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
    approx_f32(t, bound, vv * rcp, w * rcp)
}

/// The f32 filter's hit as an interval (pbrt's t bound, doubled for margin).
#[inline]
pub fn approx_f32(t: f32, bound: f32, b1: f32, b2: f32) -> Estimate {
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
        level: 0,
    })
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
        level: 1,
    })
}

/// Level 2 for a sphere: the nearest root with tmin < t < tmax in f64 intervals.
pub fn sphere_interval(
    o: [f64; 3],
    d: [f64; 3],
    centre: [f64; 3],
    radius: f64,
    tmin: f64,
    tmax: f64,
) -> Estimate {
    let d = iv3(d);
    let f = isub(iv3(o), iv3(centre));
    let a = idot(d, d);
    let b = idot(f, d);
    let k = idot(f, f) - Interval::point(radius).square();
    let disc = b.square() - a * k;
    match disc.sign() {
        Some(Ordering::Less) => return Estimate::Miss,
        Some(Ordering::Greater) => {}
        _ => return Estimate::Unsure,
    }
    let Some(root) = disc.sqrt() else {
        return Estimate::Unsure;
    };
    for t in [(-b - root).checked_div(a), (-b + root).checked_div(a)] {
        let Some(t) = t.filter(|t| t.is_finite()) else {
            return Estimate::Unsure;
        };
        if t.hi <= tmin {
            continue;
        }
        if t.lo >= tmax {
            return Estimate::Miss;
        }
        if t.lo > tmin && t.hi < tmax {
            return Estimate::Hit(Approx {
                t: t.mid(),
                lo: t.lo,
                hi: t.hi,
                b1: 0.0,
                b2: 0.0,
                level: 1,
            });
        }
        return Estimate::Unsure;
    }
    Estimate::Miss
}

/// A candidate's t at the level it has reached.
#[derive(Clone, Debug)]
enum Level {
    Approx(Approx),
    Exact(ExactT, f64, f64),
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
                // approx() is rounded (a few ulps for a root): step well past it.
                Level::Exact(t, ..) => {
                    let x = t.approx();
                    (x + x.abs() * 1e-9 + f64::MIN_POSITIVE).min(self.tmax)
                }
            },
        }
    }

    /// Whether a candidate whose exact t is ≥ `lo` certainly loses (ties must be kept for
    /// the index rule, so only strictly beyond the best counts).
    #[inline]
    pub fn beyond(&self, lo: f64) -> bool {
        lo >= self.tmax
            || match &self.best {
                Some(Candidate {
                    level: Level::Approx(a),
                    ..
                }) => lo > a.hi,
                _ => false,
            }
    }

    /// The nearest hit found.
    pub fn hit(&self) -> Option<Hit<f64>> {
        self.best.as_ref().map(|c| {
            let (t, b1, b2) = match &c.level {
                Level::Approx(a) => (a.t, a.b1, a.b2),
                Level::Exact(t, b1, b2) => (t.approx(), *b1, *b2),
            };
            Hit {
                t,
                prim: c.prim,
                b1,
                b2,
            }
        })
    }

    /// The nearest hit in f32.
    pub fn hit_f32(&self) -> Option<Hit<f32>> {
        self.hit().map(|h| Hit {
            t: h.t as f32,
            prim: h.prim,
            b1: h.b1 as f32,
            b2: h.b2 as f32,
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
            match (&cand.level, &best.level) {
                (Level::Approx(x), Level::Approx(y)) if x.hi < y.lo => break Ordering::Less,
                (Level::Approx(x), Level::Approx(y)) if x.lo > y.hi => break Ordering::Greater,
                (Level::Exact(x, ..), Level::Exact(y, ..)) => break x.cmp_t(y),
                _ => {}
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
                    level: 0,
                }),
                Estimate::Hit(a) => Level::Approx(a),
            },
        };
        loop {
            match &cand.level {
                Level::Approx(a) => {
                    if a.lo > self.tmin && a.hi < self.tmax {
                        return Some(cand);
                    }
                    if a.hi <= self.tmin || a.lo >= self.tmax {
                        return None;
                    }
                }
                Level::Exact(t, ..) => {
                    let inside = t.cmp_f(self.tmin) == Ordering::Greater
                        && t.cmp_f(self.tmax) == Ordering::Less;
                    return inside.then_some(cand);
                }
            }
            cand.level = self.refine(&cand)?;
        }
    }

    /// The next level's answer for a candidate; `None` if it turns out to be a miss.
    fn refine(&self, c: &Candidate) -> Option<Level> {
        let level = match &c.level {
            Level::Approx(a) => a.level,
            Level::Exact(..) => unreachable!("exact candidates are never refined"),
        };
        if level == 0 {
            let est = match &c.shape {
                Shape::Triangle(v) => triangle_interval(self.o, self.d, v),
                Shape::Sphere { centre, radius } => {
                    sphere_interval(self.o, self.d, *centre, *radius, self.tmin, self.tmax)
                }
            };
            match est {
                Estimate::Miss => return None,
                Estimate::Hit(a) => return Some(Level::Approx(a)),
                Estimate::Unsure => {}
            }
        }
        match &c.shape {
            Shape::Triangle(v) => {
                exact::triangle(self.o, self.d, v).map(|(t, b1, b2)| Level::Exact(t, b1, b2))
            }
            Shape::Sphere { centre, radius } => {
                exact::sphere(self.o, self.d, *centre, *radius, self.tmin, self.tmax)
                    .map(|t| Level::Exact(t, 0.0, 0.0))
            }
        }
    }
}

fn rank(l: &Level) -> u8 {
    match l {
        Level::Approx(a) => a.level,
        Level::Exact(..) => 2,
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
