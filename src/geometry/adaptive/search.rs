//! The closest-hit search as the fast paths run it ([`Search`]: a few compares per
//! candidate while the f32 filter decides, a [`Nearest`] from the first that it does not),
//! and the brute-force reference over shapes ([`closest_hit_reference`]).

use super::estimate::{Approx, Estimate};
use super::filter::{precise_f32, round_up};
use super::nearest::Nearest;
use super::widen;
use crate::geometry::{Hit, Ray, Shape};
use crate::math::Real;

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

    /// An exact any-hit check over the query's interval, for shapes the f32 level does not
    /// take ([`Nearest::confirms`]).
    pub fn checker(&self) -> Nearest {
        Nearest::new(&self.ray, self.tmin as f32, self.tmax32)
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
            n.offer(prim, widen(&Shape::from(*tri)), est);
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
            self.go_slow().offer(prim, widen(&Shape::from(*tri)), est);
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
                n.offer(b.prim, widen(&Shape::from(b.tri)), Estimate::Hit(b.approx));
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
            _ if stays_on_one_side(&self.ray, self.tmin, self.tmax, tri) => false,
            _ => Nearest::with_f32_levels(&self.ray, self.tmin as f32, self.tmax as f32)
                .confirms(widen(&Shape::from(*tri)), est),
        }
    }
}

/// Whether the ray for tmin ≤ t ≤ tmax stays strictly on one side of the triangle's plane,
/// decided in f64 with a bound 45 times f64's rounding of every step: then it meets no point
/// of the triangle. A shadow segment to a far light runs nearly parallel to every plane that
/// holds the light's direction (a vertical wall under a light high above), where the f32
/// filter decides nothing; from just off the surface it departs, and this says so without
/// the interval arithmetic.
fn stays_on_one_side(ray: &Ray<f32>, tmin: f64, tmax: f64, tri: &[[f32; 3]; 3]) -> bool {
    use crate::math::real::{abs, add, cross, cross_size, dot, sub};
    let v = tri.map(|p| p.map(f64::from));
    let (o, d) = (ray.o.map(f64::from), ray.d.map(f64::from));
    let (e1, e2) = (sub(v[1], v[0]), sub(v[2], v[0]));
    let n = cross(e1, e2);
    // |n| plus a bound on its rounding, per axis (its products' sizes).
    let n_size = add(abs(n), cross_size(e1, e2));
    let s = sub(o, v[0]);
    let (a, b) = (dot(s, n), dot(d, n));
    let (a_size, b_size) = (dot(abs(s), n_size), dot(abs(d), n_size));
    const BOUND: f64 = 1e-14;
    // The side at t: a + t·b, its sign certain beyond the bound (an infinite end: b's sign).
    let side = |t: f64| -> f64 {
        let (value, size) = match t.is_infinite() {
            true => (t.signum() * b, b_size),
            false => (
                a + t * b,
                a_size + t.abs() * b_size + (a.abs() + (t * b).abs()),
            ),
        };
        match value.abs() > BOUND * size {
            true => value.signum(),
            false => 0.0,
        }
    };
    let (from, to) = (side(tmin), side(tmax));
    from != 0.0 && from == to
}

/// The adaptive nearest hit over shapes by brute force, starting at the interval level (no
/// f32 filter): the reference that the fast paths are tested against.
pub fn closest_hit_reference<T: Real>(
    shapes: &[Shape<T>],
    ray: &Ray<T>,
    tmin: T,
    tmax: T,
) -> Option<Hit<f64>> {
    closest_hit_reference_by(shapes.len(), |i| shapes[i as usize], ray, tmin, tmax)
}

/// [`closest_hit_reference`] over `count` shapes given by their index (a scene's primitives,
/// its instances' triangles placed, without a list of them all).
pub fn closest_hit_reference_by<T: Real>(
    count: usize,
    shape: impl Fn(u32) -> Shape<T>,
    ray: &Ray<T>,
    tmin: T,
    tmax: T,
) -> Option<Hit<f64>> {
    let mut n = Nearest::new(ray, tmin, tmax);
    for i in 0..count as u32 {
        n.offer(i, widen(&shape(i)), Estimate::Unsure);
    }
    n.hit()
}
