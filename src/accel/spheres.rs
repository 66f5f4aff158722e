//! The shapes that are not triangles (spheres) in a hierarchy of their own: a BVH over their
//! boxes ([`Bvh::build_over_boxes`], the instances' top level's build), so that a scene of N
//! balls costs a ray O(log N) box tests, not N sphere tests.
//!
//! Every answer is the in-order loop's ([`super::reference::InOrder`], the reference): the
//! hierarchy only decides which spheres are tested, never how. That culling must never drop a
//! sphere the query would report:
//! - the boxes are the spheres' boxes rounded outwards to f32 (`outward`), so the exact
//!   queries (the adaptive search, the packets' f64 interval level) may cull by them;
//! - the inexact per-ray methods compute in f32 and can report a ray that passes within their
//!   rounding of a sphere as a hit, or a t a little before the true one; each ray's boxes are
//!   widened by a pad for that: 2⁻¹⁸·(|o|∞ + E) with E the largest box coordinate under the
//!   node whose children are tested (one far sphere widens only its own branch), some 64
//!   roundings of the ray's distance to any centre there, where the f32 test's own error is
//!   at most about 10 (`sphere::intersect`: o − c, one dot product and a projection, then
//!   r − |l|);
//! - the slab test is conservative as in [`super::bvh`], and boxes are culled against the
//!   best hit so far with its margin.
//!
//! A sphere whose box is not finite (a scene built by hand; the parser refuses them) stays out
//! of the hierarchy, in a short list tested one by one ([`Spheres::loose`]).
//!
//! Packets: [`Spheres::seed_packet`] (the nearest sphere per lane of 8 camera rays from the
//! eye) and [`Spheres::any_packet`] (which of 8 shadow segments from the light a sphere
//! blocks) walk the hierarchy with the packet walk of [`super::bvh`] and test the spheres it
//! reaches four lanes at a time with the sphere's f64 interval level
//! ([`sphere::interval_x4_of`]), each sphere seen once per frame from the eye and the light
//! ([`SpheresSeen`]). Where a packet's lanes part (small balls: each lane of a leaf meets
//! another sphere), the camera packets test a leaf's (sphere, lane) pairs four at a time
//! instead ([`sphere::interval_x4_gathered`]: the same bits per lane), in the spheres' order.

use super::bvh::{Aabb, Bvh, Leaves, PacketSlabs};
use super::layout::{merge, Layout};
use super::packet::PacketLimits;
use super::reference::{any_one_by_one, closest_one_by_one};
use crate::geometry::adaptive::{round_down, widen, Estimate, Search};
use crate::geometry::sphere::{self, DirectionLanes, DirectionsX4, FromOrigin};
use crate::geometry::triangle::WatertightRay;
use crate::geometry::{Hit, Method, Ray, Shape};
use crate::math::lanes::{Lanes, Lanes64};
use crate::math::simd::{avx512_avx2_or_baseline, Isa};
use rayon::prelude::*;
use wide::f32x8;

/// 2⁻¹⁸: the per-ray pad's relative size (see the module docs).
const PAD: f32 = 1.0 / (1u32 << 18) as f32;

/// The shapes other than triangles, in a hierarchy of their boxes.
#[derive(Clone, Debug, Default)]
pub(crate) struct Spheres {
    /// The shapes in the hierarchy's order (each leaf's contiguous), with their primitives.
    shapes: Vec<(Shape<f32>, u32)>,
    /// Their boxes, in that order (a packet tests each before the sphere itself).
    boxes: Vec<Aabb>,
    /// The hierarchy over their boxes.
    tree: Bvh,
    /// The largest |coordinate| of the boxes under each node of `tree`
    /// ([`Bvh::node_extents`]): the scale of the pad there.
    node_extents: Vec<f32>,
    /// Shapes whose box is not finite, tested one by one.
    loose: Vec<(Shape<f32>, u32)>,
}

/// A shape's box rounded outwards to f32 ([`Shape::box_f32`]; `None` where it is not finite).
fn outward(shape: &Shape<f32>) -> Option<([f32; 3], [f32; 3])> {
    let (lo, hi) = shape.box_f32();
    let finite = lo.iter().chain(&hi).all(|c| c.is_finite());
    (finite && (0..3).all(|k| lo[k] <= hi[k])).then_some((lo, hi))
}

impl Spheres {
    /// The hierarchy over `shapes` (each with its primitive index; copies already left out).
    pub(crate) fn build(shapes: Vec<(Shape<f32>, u32)>) -> Self {
        let boxes: Vec<Option<([f32; 3], [f32; 3])>> =
            shapes.par_iter().map(|s| outward(&s.0)).collect();
        let mut placed = Vec::with_capacity(shapes.len());
        let mut placed_boxes = Vec::with_capacity(shapes.len());
        let mut loose = Vec::new();
        for (shape, b) in shapes.into_iter().zip(boxes) {
            match b {
                Some(b) => {
                    placed.push(shape);
                    placed_boxes.push(b);
                }
                None => loose.push(shape),
            }
        }
        let tree = Bvh::build_over_boxes(&placed_boxes);
        let order = tree.triangles().1;
        let shapes = order.iter().map(|&i| placed[i as usize]).collect();
        let boxes = (order.iter())
            .map(|&i| {
                let (lo, hi) = placed_boxes[i as usize];
                Aabb { lo, hi }
            })
            .collect();
        Self {
            shapes,
            boxes,
            node_extents: tree.node_extents(),
            tree,
            loose,
        }
    }

    /// How many shapes.
    pub(crate) fn len(&self) -> usize {
        self.shapes.len() + self.loose.len()
    }

    /// Whether there are none.
    pub(crate) fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Every shape with its primitive: the hierarchy's, then the loose ones.
    pub(crate) fn shapes(&self) -> impl Iterator<Item = &(Shape<f32>, u32)> {
        self.shapes.iter().chain(&self.loose)
    }

    /// The shapes outside the hierarchy (boxes not finite), tested one by one.
    pub(crate) fn loose(&self) -> &[(Shape<f32>, u32)] {
        &self.loose
    }

    /// Bytes held.
    pub(crate) fn memory_bytes(&self) -> usize {
        let shape = std::mem::size_of::<(Shape<f32>, u32)>();
        self.tree.memory_bytes()
            + (self.shapes.len() + self.loose.len()) * shape
            + self.boxes.len() * std::mem::size_of::<Aabb>()
            + self.node_extents.len() * std::mem::size_of::<f32>()
    }

    /// Boxes of the hierarchy's top `depth` levels, for the frames' tile culling.
    pub(crate) fn top_boxes(&self, depth: usize) -> Vec<super::cull::TreeNode> {
        (self.tree.top_levels(depth).into_iter())
            .map(|n| ((n.bounds.lo, n.bounds.hi), n.children))
            .collect()
    }

    /// |o|∞ of `ray`.
    fn norm(ray: &Ray) -> f32 {
        ray.o.iter().fold(0.0f32, |m, c| m.max(c.abs()))
    }

    /// The pad of `ray`'s boxes under wide node `node`, with E the largest |coordinate| of
    /// the boxes there: what the f32 tests of the spheres inside need (so that one far
    /// sphere does not widen every box of the scene).
    #[inline]
    fn pad_under(&self, o: f32, node: usize) -> f32 {
        (o + self.node_extents[node]) * PAD
    }

    /// Visits the shapes `ray` may reach with tmin < t < tmax, nearer boxes first, every box
    /// widened where `padded` (the inexact methods: [`Spheres::pad_under`]; the exact queries
    /// cull by the outward boxes alone): `visit` gets each and the current far bound, and
    /// returns the new far bound and whether to stop.
    #[inline]
    fn walk(
        &self,
        ray: &Ray,
        (tmin, tmax): (f32, f32),
        padded: bool,
        mut visit: impl FnMut(&(Shape<f32>, u32), f32) -> (f32, bool),
    ) {
        let o = Self::norm(ray);
        let pad_of = |node: usize| match padded {
            true => self.pad_under(o, node),
            false => 0.0,
        };
        // The root's is the largest: every box lies under it.
        let pad = match self.node_extents.is_empty() {
            true => 0.0,
            false => pad_of(0),
        };
        self.tree.traverse_padded(
            ray,
            (tmin, tmax),
            (pad, pad_of),
            |first, count, mut t_far| {
                for shape in &self.shapes[first..first + count] {
                    let stop;
                    (t_far, stop) = visit(shape, t_far);
                    if stop {
                        return (t_far, true);
                    }
                }
                (t_far, false)
            },
        );
    }
}

impl Layout for Spheres {
    fn closest(&self, ray: &Ray, method: Method, tmin: f32, tmax: f32, best: &mut Option<Hit>) {
        let far = |best: &Option<Hit>| best.map_or(tmax, |h| h.t.next_up());
        self.walk(ray, (tmin, far(best)), true, |&(shape, prim), _| {
            if let Some((t, b1, b2)) = shape.intersect(ray, method, tmin, far(best)) {
                merge(best, Some(Hit { t, prim, b1, b2 }));
            }
            (far(best), false)
        });
        closest_one_by_one(self.loose.iter().copied(), ray, method, tmin, tmax, best);
    }

    fn closest_exact(&self, ray: &Ray, _: &WatertightRay<f32>, search: &mut Search) {
        let (tmin, tmax) = (round_down(search.tmin()), search.t_far32());
        self.walk(ray, (tmin, tmax), false, |(shape, prim), _| {
            if line_may_meet(ray, shape) {
                search.offer_shape(*prim, widen(shape), Estimate::Unsure);
            }
            (search.t_far32(), false)
        });
        for (shape, prim) in &self.loose {
            if line_may_meet(ray, shape) {
                search.offer_shape(*prim, widen(shape), Estimate::Unsure);
            }
        }
    }

    fn any(&self, ray: &Ray, method: Method, tmin: f32, tmax: f32, skip: u32) -> bool {
        let mut hit = false;
        self.walk(ray, (tmin, tmax), true, |&(shape, prim), t_far| {
            hit = prim != skip && shape.intersect(ray, method, tmin, tmax).is_some();
            (t_far, hit)
        });
        hit || any_one_by_one(self.loose.iter().copied(), ray, method, tmin, tmax, skip)
    }

    fn any_exact(&self, ray: &Ray, _: &WatertightRay<f32>, search: &Search, skip: u32) -> bool {
        let nearest = search.checker();
        let mut hit = false;
        let (tmin, tmax) = (round_down(search.tmin()), search.t_far32());
        let confirms = |shape: &Shape<f32>, prim: u32| {
            prim != skip
                && line_may_meet(ray, shape)
                && nearest.confirms(widen(shape), Estimate::Unsure)
        };
        self.walk(ray, (tmin, tmax), false, |(shape, prim), t_far| {
            hit = confirms(shape, *prim);
            (t_far, hit)
        });
        hit || (self.loose.iter()).any(|(shape, prim)| confirms(shape, *prim))
    }
}

/// Whether the line of `ray` may come within a sphere's radius of its centre, decided in f64
/// with a bound 45 times f64's rounding of every step (any other shape: true). A ray from
/// 10⁹ away was handed to interval arithmetic for every sphere its walk reached (~90× the
/// time of a near ray over the ball field), where this refuses all but the few near it.
fn line_may_meet(ray: &Ray, shape: &Shape<f32>) -> bool {
    use crate::math::real::{cross, cross_size, dot, sub};
    let Shape::Sphere(s) = shape else {
        return true;
    };
    let (o, d) = (ray.o.map(f64::from), ray.d.map(f64::from));
    let oc = sub(o, s.centre.map(f64::from));
    // |oc × d| = (the line's distance from the centre)·|d|; each component within `err`.
    let (cross, err) = (cross(oc, d), cross_size(oc, d).map(|x| 1e-14 * x));
    let lower: f64 = (0..3)
        .map(|k| (cross[k].abs() - err[k]).max(0.0).powi(2))
        .sum();
    let (d2, r) = (dot(d, d), f64::from(s.radius));
    // (NaN from an infinite direction: not surely apart, so it may meet.)
    let surely_apart = lower * (1.0 - 1e-14) > r * r * d2 * (1.0 + 1e-14);
    !surely_apart
}

/// The spheres of the hierarchy seen from one origin (the eye, or the light), in its order,
/// for the packets' interval test: made once per frame.
pub(crate) struct SpheresSeen {
    o: [f32; 3],
    from: Vec<Option<FromOrigin>>,
}

impl Spheres {
    /// The hierarchy's spheres seen from `o`.
    pub(crate) fn seen_from(&self, o: [f32; 3]) -> SpheresSeen {
        let o64 = o.map(f64::from);
        SpheresSeen {
            o,
            from: (self.shapes.par_iter())
                .with_min_len(256)
                .map(|(s, _)| s.seen_from(o64))
                .collect(),
        }
    }
}

/// The id a packet's lanes give a sphere ([`SphereSeed`]): beyond every primitive and BVH
/// slot, so that no kernel maps it.
pub(crate) const SEEDED: u32 = u32::MAX - 1;

/// The spheres along a camera packet, found before its triangles.
pub(crate) struct SphereSeed {
    /// The nearest sphere's t interval per lane (rounded outwards to f32).
    pub(crate) lo: [f32; 8],
    pub(crate) hi: [f32; 8],
    /// Lanes the interval level cannot decide (two spheres too close to order, or one it
    /// cannot tell hit from miss): to be traced per ray.
    pub(crate) ambiguous: u32,
    /// The nearest sphere's primitive per lane (`u32::MAX`: none).
    pub(crate) prims: [u32; 8],
}

/// Shadow lanes decided by the spheres.
pub(crate) struct SphereLanes {
    /// Certainly blocked by one of them.
    pub(crate) blocked: u32,
    /// Not blocked for certain, and one of them the interval cannot decide: per ray.
    pub(crate) unsure: u32,
}

/// Lanes 4·`half` to 4·`half` + 3 of the directions `d` (per axis), in f64, prepared for
/// every sphere the packet meets.
#[inline(always)]
fn half_in_f64<F: Lanes64>(d: &[[f32; 8]; 3], half: usize) -> DirectionsX4<F> {
    // (No closure around the lanes: see `math::interval::idot_x4`.)
    let axis = |k: usize| -> [f64; 4] { std::array::from_fn(|l| f64::from(d[k][4 * half + l])) };
    let (x, y, z) = (axis(0), axis(1), axis(2));
    DirectionsX4::new([F::from_array(x), F::from_array(y), F::from_array(z)])
}

/// A camera packet's state in the spheres' walk: the nearest sphere's interval per lane.
struct Nearest<V: Lanes> {
    /// The directions as two halves of four lanes, and lane by lane.
    halves: [DirectionsX4<V::F64>; 2],
    d: DirectionLanes,
    lo: [f64; 8],
    hi: [f64; 8],
    /// [`reach`] of `hi`, kept as nearer spheres are taken (the walk asks at every leaf).
    reach: V,
    prims: [u32; 8],
    /// Lanes asked.
    live: u32,
    /// Lanes left to the per-ray search.
    undecided: u32,
}

impl<V: Lanes> PacketLimits<V> for Nearest<V> {
    #[inline(always)]
    fn live(&self) -> u32 {
        self.live & !self.undecided
    }
    #[inline(always)]
    fn limit(&self) -> V {
        self.reach
    }
}

/// (2⁻¹⁶ + 2⁻²¹): [`reach`]'s relative margin.
const REACH_MARGIN: f64 = 1.0 / 65536.0 + 1.0 / 2097152.0;

/// Per lane, the nearest sphere's far bound `hi` with the hierarchies' culling margin, in
/// f32 (∞ while there is none): at least `r + 2⁻¹⁶·|r|` (rounded to f32), with r the least
/// f32 ≥ hi, the margin the triangles' walks keep. In lanes, without rounding each lane
/// upwards: hi grows by (2⁻¹⁶ + 2⁻²¹)·|hi| + 2⁻¹⁴⁹ in f64, and rounding that to the
/// nearest f32 takes off at most 2⁻²⁴ of it, or 2⁻¹⁵⁰ among the subnormals.
#[inline(always)]
fn reach<V: Lanes>(hi: &[f64; 8]) -> V {
    let margin = V::F64::splat(REACH_MARGIN);
    let least = V::F64::splat(f64::from(f32::from_bits(1)));
    let (low, high) = (
        V::F64::from_array([hi[0], hi[1], hi[2], hi[3]]),
        V::F64::from_array([hi[4], hi[5], hi[6], hi[7]]),
    );
    // (No closure around the lanes: see `math::interval::idot_x4`.)
    let low = (low + low.abs() * margin + least).to_f32();
    let high = (high + high.abs() * margin + least).to_f32();
    V::from_array([
        low[0], low[1], low[2], low[3], high[0], high[1], high[2], high[3],
    ])
}

/// A shadow packet's state in the spheres' walk.
struct Blocking<'a, F> {
    d: [DirectionsX4<F>; 2],
    segments: &'a super::ShadowSegments,
    blocked: u32,
    unsure: u32,
}

impl<V: Lanes> PacketLimits<V> for Blocking<'_, V::F64> {
    #[inline(always)]
    fn live(&self) -> u32 {
        self.segments.live & !self.blocked
    }
    #[inline(always)]
    fn limit(&self) -> V {
        V::splat(1.0 + 1.0 / 65536.0)
    }
}

/// The hierarchy's leaves as the packets test them: spheres seen from the packet's origin,
/// each after its box (a leaf's box holds four; a lane that enters it meets about one of
/// theirs).
struct SeenLeaves<'a, V> {
    spheres: &'a Spheres,
    seen: &'a SpheresSeen,
    slabs: &'a PacketSlabs<V>,
}

impl<V: Lanes> SeenLeaves<'_, V> {
    /// The lanes of `lanes` that enter sphere `j`'s box before `limit` (all of them where
    /// the slab test cannot be trusted).
    #[inline(always)]
    fn entering(&self, j: usize, limit: V, lanes: u32) -> u32 {
        match self.slabs.trusted {
            true => self.slabs.enter(&self.spheres.boxes[j], limit, lanes).0,
            false => lanes,
        }
    }
}

impl<V: Lanes> Leaves<V, Nearest<V>> for SeenLeaves<'_, V> {
    #[inline(always)]
    fn visit(&mut self, s: &mut Nearest<V>, first: usize, count: usize, lanes: u32) {
        // (The limit as the leaf is entered: it only shrinks as spheres are taken.)
        let limit = PacketLimits::<V>::limit(s);
        // The leaf's (sphere, lane) pairs, tested four at a time in the order of the
        // spheres: a lane meets the spheres in the same order as one by one.
        let mut pairs = Pairs::default();
        for j in first..first + count {
            let mut lanes = self.entering(j, limit, lanes & s.live & !s.undecided);
            if lanes == 0 {
                continue;
            }
            let Some(from) = &self.seen.from[j] else {
                s.undecided |= lanes;
                continue;
            };
            let prim = self.spheres.shapes[j].1;
            if lanes.count_ones() >= SPLAT_LANES {
                // Many lanes in this sphere: tested in the packet's own lane order, after
                // the pairs of the spheres before it.
                self.nearest_of(s, &mut pairs);
                s.nearest_in_halves(from, prim, lanes);
                continue;
            }
            while lanes != 0 {
                if pairs.len == 4 {
                    self.nearest_of(s, &mut pairs);
                }
                let at = pairs.len;
                pairs.from[at] = Some(from);
                pairs.prim[at] = prim;
                pairs.lane[at] = lanes.trailing_zeros() as usize;
                pairs.len += 1;
                lanes &= lanes - 1;
            }
        }
        self.nearest_of(s, &mut pairs);
    }
}

/// A sphere that at least this many of a packet's lanes enter is tested against the
/// packet's two halves of four lanes; one that fewer enter, in (sphere, lane) pairs.
const SPLAT_LANES: u32 = 6;

impl<V: Lanes> Nearest<V> {
    /// Tests sphere `from` (primitive `prim`) on `lanes`, four lanes of the packet at a time.
    #[inline(always)]
    fn nearest_in_halves(&mut self, from: &FromOrigin, prim: u32, lanes: u32) {
        let mut moved = 0;
        for half in 0..2 {
            let bits = (lanes & !self.undecided) >> (4 * half) & 0xf;
            if bits == 0 {
                continue;
            }
            let at = 4 * half;
            let (lo, hi) = (&self.lo[at..at + 4], &self.hi[at..at + 4]);
            let lo = V::F64::from_array([lo[0], lo[1], lo[2], lo[3]]);
            let hi = V::F64::from_array([hi[0], hi[1], hi[2], hi[3]]);
            let r = sphere::interval_x4_of(from, &self.halves[half], 0.0, f64::INFINITY);
            let nearer = r.hit & r.hi.simd_lt(lo);
            let farther = r.hit & r.lo.simd_gt(hi);
            // Too close to order, or the interval cannot tell: per ray.
            let undecided = (!(r.miss | nearer | farther)).to_bitmask() & bits;
            self.undecided |= undecided << at;
            let (lo, hi) = (nearer.bitselect(r.lo, lo), nearer.bitselect(r.hi, hi));
            self.lo[at..at + 4].copy_from_slice(&lo.to_array());
            self.hi[at..at + 4].copy_from_slice(&hi.to_array());
            let taken = nearer.to_bitmask() & bits;
            for l in (0..4).filter(|l| taken & (1 << l) != 0) {
                self.prims[at + l] = prim;
            }
            // (Every lane whose hi moved, asked or not, so that the reach stays hi's.)
            moved |= nearer.to_bitmask();
        }
        if moved != 0 {
            self.reach = reach(&self.hi);
        }
    }
}

/// Up to four (sphere, lane) pairs.
#[derive(Default)]
struct Pairs<'a> {
    from: [Option<&'a FromOrigin>; 4],
    prim: [u32; 4],
    lane: [usize; 4],
    len: usize,
}

impl<V: Lanes> SeenLeaves<'_, V> {
    /// Tests the `pairs` gathered (if any) at once and takes, pair by pair, each sphere
    /// nearer than its lane's nearest; a lane the interval level cannot decide is left to the
    /// per-ray search. Empties `pairs`.
    #[inline(always)]
    fn nearest_of(&self, s: &mut Nearest<V>, pairs: &mut Pairs) {
        if pairs.len == 0 {
            return;
        }
        // (Unused slots hold an earlier batch's pair, or the first pair's sphere and lane 0:
        // their answers are not read.)
        let first = pairs.from[0].expect("a pair");
        let spheres = pairs.from.map(|from| from.unwrap_or(first));
        let r: sphere::LanesX4<V::F64> =
            sphere::interval_x4_gathered(spheres, &s.d, pairs.lane, 0.0, f64::INFINITY);
        let (hit, miss) = (r.hit.to_bitmask(), r.miss.to_bitmask());
        let (lo, hi) = (r.lo.to_array(), r.hi.to_array());
        let mut taken = false;
        for i in 0..pairs.len {
            let l = pairs.lane[i];
            if s.undecided & (1 << l) != 0 {
                continue;
            }
            let hit = hit & (1 << i) != 0;
            let nearer = hit && hi[i] < s.lo[l];
            let farther = hit && lo[i] > s.hi[l];
            if nearer {
                (s.lo[l], s.hi[l]) = (lo[i], hi[i]);
                s.prims[l] = pairs.prim[i];
                taken = true;
            } else if !farther && miss & (1 << i) == 0 {
                // Too close to order, or the interval cannot tell: per ray.
                s.undecided |= 1 << l;
            }
        }
        if taken {
            s.reach = reach(&s.hi);
        }
        pairs.len = 0;
    }
}

impl<'a, V: Lanes> Leaves<V, Blocking<'a, V::F64>> for SeenLeaves<'_, V> {
    #[inline(always)]
    fn visit(&mut self, s: &mut Blocking<'a, V::F64>, first: usize, count: usize, lanes: u32) {
        let limit = PacketLimits::<V>::limit(s);
        for j in first..first + count {
            let prim = self.spheres.shapes[j].1;
            let lanes = self.entering(j, limit, lanes & s.segments.live & !s.blocked);
            for half in 0..2 {
                let bits = (lanes & s.segments.live & !s.blocked) >> (4 * half) & 0xf;
                if bits == 0 {
                    continue;
                }
                let own = (0..4).fold(0, |m, l| {
                    m | ((s.segments.skip(4 * half + l) == prim) as u32) << l
                });
                let Some(from) = &self.seen.from[j] else {
                    s.unsure |= (bits & !own) << (4 * half);
                    continue;
                };
                let r = sphere::interval_x4_of(from, &s.d[half], 0.0, 1.0);
                s.blocked |= (r.hit.to_bitmask() & bits & !own) << (4 * half);
                // Another sphere may still block such a lane for certain.
                s.unsure |= ((!(r.hit | r.miss)).to_bitmask() & bits & !own) << (4 * half);
            }
        }
    }
}

impl Spheres {
    /// The nearest sphere along each live lane of 8 camera rays from `seen`'s origin with
    /// directions `d`, as the f64 interval level decides it (see [`SphereSeed`]).
    /// In the build `isa` names.
    #[inline(always)]
    pub(crate) fn seed_packet<I: Isa>(
        &self,
        isa: I,
        seen: &SpheresSeen,
        d: &[f32x8; 3],
        live: u32,
    ) -> SphereSeed {
        let spheres = self;
        avx512_avx2_or_baseline!(token isa, lanes seed_body => (
            spheres: &Spheres,
            seen: &SpheresSeen,
            d: &[f32x8; 3],
            live: u32
        ) -> SphereSeed)
    }

    /// Which live lanes of shadow segments `s` (from `seen`'s origin, the light) a sphere
    /// blocks for certain, each lane skipping its own primitive, and which it leaves unsure,
    /// in the build `isa` names.
    #[inline(always)]
    pub(crate) fn any_packet<I: Isa>(
        &self,
        isa: I,
        seen: &SpheresSeen,
        s: &super::ShadowSegments,
    ) -> SphereLanes {
        let spheres = self;
        avx512_avx2_or_baseline!(token isa, lanes any_packet_body => (
            spheres: &Spheres,
            seen: &SpheresSeen,
            s: &super::ShadowSegments
        ) -> SphereLanes)
    }
}

#[inline(always)]
fn seed_body<V: Lanes>(
    spheres: &Spheres,
    seen: &SpheresSeen,
    d: &[f32x8; 3],
    live: u32,
) -> SphereSeed {
    let lanes = d.map(|c| c.to_array());
    let halves = [half_in_f64::<V::F64>(&lanes, 0), half_in_f64(&lanes, 1)];
    let mut state = Nearest {
        d: DirectionLanes::new(&halves),
        halves,
        lo: [f64::INFINITY; 8],
        hi: [f64::INFINITY; 8],
        reach: V::splat(f32::INFINITY),
        prims: [u32::MAX; 8],
        live: live & 0xff,
        undecided: 0,
    };
    if !spheres.loose.is_empty() {
        // (Not finite: the per-ray queries decide.)
        state.undecided = state.live;
    }
    let slabs = PacketSlabs::<V>::new(seen.o, d, spheres.tree.boxes_tame());
    let mut leaves = SeenLeaves {
        spheres,
        seen,
        slabs: &slabs,
    };
    spheres
        .tree
        .walk_packet(&slabs, 0.0, &mut state, &mut leaves);
    let mut out = SphereSeed {
        lo: [f32::INFINITY; 8],
        hi: [f32::INFINITY; 8],
        ambiguous: state.undecided & state.live,
        prims: state.prims,
    };
    for half in 0..2 {
        let at = 4 * half;
        let (lo, hi) = (&state.lo[at..at + 4], &state.hi[at..at + 4]);
        let (lo, hi) = (
            rounded_f32(V::F64::from_array([lo[0], lo[1], lo[2], lo[3]]), false),
            rounded_f32(V::F64::from_array([hi[0], hi[1], hi[2], hi[3]]), true),
        );
        out.lo[at..at + 4].copy_from_slice(&lo);
        out.hi[at..at + 4].copy_from_slice(&hi);
    }
    out
}

/// Lanes `x`, each > 0 or +∞ (a nearest sphere's bounds: its hits lie beyond t = 0), as
/// the greatest f32 ≤ x (`up` false) or the least f32 ≥ x: `x as f32`, then one step in
/// the bits (for a positive f32, the next one) in the lanes where that rounded the wrong way.
#[inline(always)]
fn rounded_f32<F: Lanes64>(x: F, up: bool) -> [f32; 4] {
    let nearest = x.to_f32();
    let back = x.round_f32();
    let wrong = match up {
        true => back.simd_lt(x),
        false => back.simd_gt(x),
    }
    .to_bitmask();
    std::array::from_fn(|l| {
        debug_assert!(x.to_array()[l] > 0.0, "{:?}", x.to_array());
        let step = (wrong >> l) & 1;
        let bits = nearest[l].to_bits();
        f32::from_bits(if up { bits + step } else { bits - step })
    })
}

#[inline(always)]
fn any_packet_body<V: Lanes>(
    spheres: &Spheres,
    seen: &SpheresSeen,
    s: &super::ShadowSegments,
) -> SphereLanes {
    let lanes = s.d.map(|c| c.to_array());
    let mut state = Blocking {
        d: [half_in_f64(&lanes, 0), half_in_f64(&lanes, 1)],
        segments: s,
        blocked: 0,
        unsure: 0,
    };
    if !spheres.loose.is_empty() {
        state.unsure = s.live;
    }
    let slabs = PacketSlabs::<V>::new(seen.o, &s.d, spheres.tree.boxes_tame());
    let mut leaves = SeenLeaves {
        spheres,
        seen,
        slabs: &slabs,
    };
    spheres
        .tree
        .walk_packet(&slabs, 0.0, &mut state, &mut leaves);
    let blocked = state.blocked & s.live;
    SphereLanes {
        blocked,
        unsure: state.unsure & s.live & !blocked,
    }
}

#[cfg(feature = "unit-tests")]
#[deny(dead_code)]
pub(crate) mod tests;
