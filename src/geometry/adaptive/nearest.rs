//! The closest-hit search over candidates at whatever level each has reached ([`Nearest`]):
//! overlapping t intervals refined until they separate, or compared exactly. Each candidate's
//! levels are its shape's own ([`Primitive`](crate::geometry::Primitive)).

use super::estimate::{Approx, Decided, Estimate, Feature};
use super::levels::{note, Event};
use crate::geometry::exact::ExactT;
use crate::geometry::{Hit, Ray, Shape};
use crate::math::Real;
use std::cmp::Ordering;

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
    /// (or hits the shapes know to be at the same t: [`Shape::same_t`]), and only failing
    /// those by exact rational t.
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
        // Known to be equal without computing them (two triangles in one plane).
        if a.shape.same_t(&b.shape) {
            return Ordering::Equal;
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
            x.exact = c.shape.exact_t(self.o, self.d, self.tmin, self.tmax);
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
            let est = if level == 0 {
                let narrow = |v: [f64; 3]| v.map(|x| x as f32);
                let filtered = match self.f32_inputs {
                    true => c.shape.f32_filter(narrow(self.o), narrow(self.d)),
                    false => None,
                };
                if filtered.is_some() {
                    note(Event::PreciseF32);
                }
                filtered.unwrap_or(Estimate::Unsure)
            } else {
                note(Event::F64Intervals);
                c.shape.f64_intervals(self.o, self.d, self.tmin, self.tmax)
            };
            match est {
                Estimate::Miss => return None,
                Estimate::Hit(a) => return Some(Level::Approx(a)),
                Estimate::Unsure => level += 1,
            }
        }
        note(Event::Exact);
        let (o, d) = (self.o, self.d);
        let decided = c.shape.decide_exactly(o, d, self.tmin, self.tmax)?;
        Some(Level::Decided(Box::new(decided)))
    }
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
