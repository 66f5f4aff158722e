//! The closest-hit search over candidates at whatever level each has reached ([`Nearest`]):
//! overlapping t intervals refined until they separate, or compared exactly; and a
//! triangle's exact level (its edge signs, the edge or vertex the line passes through).

use super::estimate::{Approx, Estimate};
use super::filter::precise_f32;
use super::interval::{triangle_interval, triangle_t_interval};
use super::levels::{note, Event};
use crate::geometry::exact::{self, ExactT};
use crate::geometry::{sphere, Hit, Ray, Shape};
use crate::math::interval::Interval;
use crate::math::Real;
use std::cmp::Ordering;

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
