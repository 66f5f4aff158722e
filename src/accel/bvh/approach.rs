//! A ray from far away moved along itself to just before a box, for the walks of the exact
//! queries ([`Approach`]). The f32 slab tests round a ray's distances to its origin's size:
//! from 10⁶ scene sizes away they cannot tell a mesh's boxes apart, and a ray carried from
//! there into an instance's frame needs a pad the size of the mesh (`accel::instances`), so
//! every triangle of what a ray passes near went to the exact levels: a ball field 10⁷ away
//! took 2,100 interval tests a ray. Moved to the box in f64, its origin rounded to f32 there,
//! the ray culls as a near one does; the pad covers the rounding, and t on the two rays
//! differs by the distance moved. Only the exact queries walk moved rays: the inexact
//! methods' own f32 roundings reach beyond the exact ray, and the walks keep for them every
//! box their f32 test enters.

use super::node::Aabb;
use crate::accel::cull::Box3;
use crate::geometry::adaptive::{round_down, round_up};
use crate::geometry::Ray;

/// How many times the box's largest coordinate the origin's must be for the ray to move.
const FAR: f64 = 64.0;

/// A bound on f64's relative rounding of one sum or difference of two roundings (2⁻⁵⁰:
/// more than 2·2⁻⁵³ with room).
const F64_SLACK: f64 = 1.0 / (1u64 << 50) as f64;

/// What a walk does with a ray and its box ([`approach`]).
pub(crate) enum Approached {
    /// Walk it as it is (near enough, or nothing to gain).
    AsItIs,
    /// It certainly meets nothing in the box within (tmin, tmax).
    Misses,
    /// Walk this one instead.
    Moved(Approach),
}

/// A ray moved along itself to just before a box: its points at t are the given ray's at
/// t + `shift`, give or take `pad` in each coordinate.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Approach {
    /// The moved ray (the given direction, the origin moved and rounded to f32).
    pub ray: Ray,
    /// How far along the given ray the moved origin lies (an f64 distance ≥ 0).
    shift: f64,
    /// A bound on each coordinate of the moved origin's rounding (≥ 2⁻⁸⁶, so that the f32
    /// slab test takes it).
    pub pad: f32,
}

/// `ray` moved to just before box `b` where its origin's largest coordinate is over [`FAR`]
/// times the box's and it enters the box after tmin (the entry found in f64, widened).
pub(crate) fn approach(b: &Aabb, ray: &Ray, (tmin, tmax): (f32, f32)) -> Approached {
    let largest = |v: &[f32; 3]| v.iter().fold(0f64, |m, &c| m.max(f64::from(c).abs()));
    let (o_max, b_max) = (largest(&ray.o), largest(&b.lo).max(largest(&b.hi)));
    if !(b_max.is_finite() && o_max.is_finite() && o_max > FAR * b_max) {
        return Approached::AsItIs;
    }
    let inv = ray.d.map(|c| 1.0 / f64::from(c));
    let (lo, hi) = (b.lo, b.hi);
    let (t0, t1) = Box3 { lo, hi }.slab_interval_f64(0.0, ray.o, &inv, (tmin.into(), tmax.into()));
    if t0.is_nan() || t1.is_nan() || !t0.is_finite() || t0 <= f64::from(tmin) {
        return Approached::AsItIs;
    }
    if t0 > t1 {
        return Approached::Misses;
    }
    let (o, d) = (ray.o.map(f64::from), ray.d.map(f64::from));
    let mut moved = [0f32; 3];
    let mut err = 0f64;
    for k in 0..3 {
        // o + t0·d in f64 (within 2u·(|o| + |t0·d|) of exact), then to f32.
        let exact_ish = o[k] + t0 * d[k];
        moved[k] = exact_ish as f32;
        let rounding = (f64::from(moved[k]) - exact_ish).abs();
        err = err.max(rounding + F64_SLACK * (o[k].abs() + (t0 * d[k]).abs()));
    }
    let pad = round_up((err * (1.0 + F64_SLACK)).max(2f64.powi(-86)));
    if !(moved.iter().all(|c| c.is_finite()) && pad.is_finite()) {
        return Approached::AsItIs;
    }
    Approached::Moved(Approach {
        ray: Ray::new(moved, ray.d),
        shift: t0,
        pad,
    })
}

impl Approach {
    /// The query's (tmin, tmax) on the moved ray, rounded outwards (tmin at least 0: before
    /// the box there is nothing to find).
    pub(crate) fn range(&self, tmin: f32, tmax: f32) -> (f32, f32) {
        (self.local_down(tmin).max(0.0), self.local(tmax))
    }

    /// A distance on the given ray as one on the moved ray, rounded up.
    fn local(&self, t: f32) -> f32 {
        let x = f64::from(t) - self.shift;
        round_up(x + x.abs() * F64_SLACK)
    }

    fn local_down(&self, t: f32) -> f32 {
        let x = f64::from(t) - self.shift;
        round_down(x - x.abs() * F64_SLACK)
    }

    /// A distance on the moved ray as one on the given ray, rounded up.
    fn world(&self, t: f32) -> f32 {
        let x = f64::from(t) + self.shift;
        round_up(x + x.abs() * F64_SLACK)
    }

    /// One leaf visit of a walk of the moved ray, whose limit there is `t_far`: `visit` gets
    /// the limit on the given ray and hands back its new one and whether to stop. A limit
    /// handed back unchanged stays as it was (a round trip may grow it by a rounding).
    pub(crate) fn visit(&self, t_far: f32, visit: impl FnOnce(f32) -> (f32, bool)) -> (f32, bool) {
        let given = self.world(t_far);
        let (t, stop) = visit(given);
        (if t == given { t_far } else { self.local(t) }, stop)
    }
}
