//! The nearest hit of 8 camera rays from their shared origin: [`PacketNearest`] as
//! triangles are offered (one to every lane, a block to one lane, a leaf to a few lanes), and
//! [`closest`] over a list.

use super::block::{BlockIds, OriginBlock};
use super::predicates::{block_crossings, load, t_interval, EdgeTests};
use super::prepare::PreciseTriangle;
use super::{OriginTriangle, MAX_PRODUCT};
use crate::math::lanes::{f32x8, LaneOps, Lanes};
use crate::math::simd::{avx512_avx2_or_baseline, each3, with_cpu_isa, Isa};

/// What a packet found: per lane the nearest primitive (`u32::MAX` for none) and the lanes
/// that must be traced per ray.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PacketHits {
    pub prim: [u32; 8],
    pub ambiguous: u32,
}

impl PacketHits {
    /// Every lane ambiguous (nothing decided).
    pub fn undecided() -> Self {
        Self {
            prim: [u32::MAX; 8],
            ambiguous: 0xff,
        }
    }
}

/// What a packet knows before its triangles are offered: per lane a nearest candidate (an
/// id, `u32::MAX` for none) with an interval [`lo`, `hi`] holding its exact t (∞ for none),
/// and the lanes already ambiguous. The frame's queries seed a packet with the shapes other
/// than triangles this way ([`PacketNearest::seeded`]).
///
/// [`lo`]: PacketSeed::lo
/// [`hi`]: PacketSeed::hi
#[derive(Clone, Copy, Debug)]
pub struct PacketSeed {
    pub prim: [u32; 8],
    pub lo: [f32; 8],
    pub hi: [f32; 8],
    pub ambiguous: u32,
}

impl Default for PacketSeed {
    fn default() -> Self {
        Self {
            prim: [u32::MAX; 8],
            lo: [f32::INFINITY; 8],
            hi: [f32::INFINITY; 8],
            ambiguous: 0,
        }
    }
}

/// The nearest of `tris` along each of 8 directions from their shared origin, for
/// 0 < t < ∞. `d_max` ≥ every |dₖ| of the packet ([`max_component`]); lanes that could
/// overflow (or a NaN direction) are ambiguous. See `PacketNearest`.
///
/// [`max_component`]: super::max_component
pub fn closest(tris: &[OriginTriangle], d: &[f32x8; 3], d_max: f32) -> PacketHits {
    with_cpu_isa!(|isa| closest_seeded_in(isa, tris, d, d_max, None))
}

/// [`closest`] starting from `seed` ([`PacketNearest::seeded`]), in the build `isa` names.
#[inline(always)]
pub(crate) fn closest_seeded_in<I: Isa>(
    isa: I,
    tris: &[OriginTriangle],
    d: &[f32x8; 3],
    d_max: f32,
    seed: Option<&PacketSeed>,
) -> PacketHits {
    avx512_avx2_or_baseline!(token isa, lanes closest_body => (
        tris: &[OriginTriangle],
        d: &[f32x8; 3],
        d_max: f32,
        seed: Option<&PacketSeed>
    ) -> PacketHits)
}

#[inline(always)]
fn closest_body<V: Lanes>(
    tris: &[OriginTriangle],
    d: &[f32x8; 3],
    d_max: f32,
    seed: Option<&PacketSeed>,
) -> PacketHits {
    let mut nearest = PacketNearest::<V>::seeded(d, d_max, seed);
    for tri in tris {
        nearest.offer(tri, tri.prim);
    }
    nearest.finish()
}

/// [`closest`] inside a kernel already in lanes `V` of any width (a tile loop compiled for
/// the CPU as a whole: no call and no dispatch per packet): the nearest's ids into
/// `prim[..V::WIDTH]`, and the ambiguous lanes returned.
#[inline(always)]
pub(crate) fn closest_in<V: LaneOps>(
    tris: &[OriginTriangle],
    d: [V; 3],
    d_max: f32,
    prim: &mut [u32],
) -> u32 {
    let mut nearest = PacketNearest::<V>::new_in(d, d_max);
    for tri in tris {
        nearest.offer(tri, tri.prim);
    }
    nearest.finish_into(prim)
}

/// The lane of `mask` (not empty) with the least of `x`, the first of equals.
#[inline(always)]
fn least_of(mask: u32, x: &[f32]) -> usize {
    let mut rest = mask & (mask - 1);
    let mut w = mask.trailing_zeros() as usize;
    while rest != 0 {
        let c = rest.trailing_zeros() as usize;
        rest &= rest - 1;
        if x[c] < x[w] {
            w = c;
        }
    }
    w
}

/// `v` with the lanes of `mask` (a lane mask) set to `x`. (A blend: a scalar written
/// into the vector's memory stalled the vector load after it.)
#[inline(always)]
fn with_lane<V: LaneOps>(v: V, mask: V, x: f32) -> V {
    mask.bitselect(V::splat(x), v)
}

/// The nearest candidate so far of each of 8 rays from the shared origin, as triangles are
/// offered in any order (all of a small scene's, or a BVH's leaves as the rays reach them).
///
/// Error bound of t, for a lane whose three eᵢ have one certain sign: the computed
/// det̃ = ẽ₀ + ẽ₁ + ẽ₂ is within ΣK·max|d| + γ₂|det̃|/(1 − γ₂) of the exact one, i.e. a
/// relative r_det ≤ ΣK·max|d|·|1/det̃|·(1 + u) + 2.1u (or, with det̃ = d·normal, within
/// k_det·max|d| + `EDGE_ABS`, the dot product's rounding included: r_det ≤
/// (k_det·max|d| + EDGE_ABS)·|1/det̃|·(1 + u)), kept ≤ 1/4 (else ambiguous); the
/// numerator's relative error is r_num; t̃ = fl(num·fl(1/det̃)) adds two roundings. Then
/// |t/t̃ − 1| ≤ (r_num + r_det)/(1 − r_det)·(1 + 3u) + 3u ≤ 1.4·(r_num + r_det) + 4u, and
/// 1e-37 is added for results in the subnormal range.
///
/// A lane keeps a candidate only while its t interval lies wholly below every other offered
/// triangle's, so a lane that ends undecided-free holds the exact nearest of all offered
/// triangles; and any triangle not offered whose exact t exceeds the lane's [`reach`]
/// cannot change that.
///
/// [`reach`]: PacketNearest::reach
pub struct PacketNearest<V = f32x8> {
    d: [V; 3],
    /// max|dₖ| rounded up.
    dm: f32,
    pub(super) best_lo: V,
    pub(super) best_hi: V,
    /// The nearest's ids as bit patterns (only ever moved bitwise); u32::MAX for none.
    best_prim: V,
    ambiguous: V,
}

impl<V: LaneOps> PacketNearest<V> {
    /// [`PacketNearest::seeded`] without a seed, inside a kernel already in lanes `V`.
    #[inline(always)]
    pub(crate) fn new_in(d: [V; 3], d_max: f32) -> Self {
        let inf = V::splat(f32::INFINITY);
        let none = V::zero().simd_ne(V::zero());
        Self {
            d,
            dm: d_max * (1.0 + 1e-6),
            best_lo: inf,
            best_hi: inf,
            best_prim: V::splat(f32::from_bits(u32::MAX)),
            // Every lane, where max|d| is not finite.
            ambiguous: if d_max.is_finite() { none } else { !none },
        }
    }

    /// The lanes already ambiguous (bit l for lane l).
    #[inline]
    pub fn ambiguous(&self) -> u32 {
        self.ambiguous.to_bitmask()
    }

    /// Per lane, an upper bound on the exact t of its nearest candidate (∞ while none).
    #[inline]
    pub fn reach(&self) -> V {
        self.best_hi
    }

    /// Offers one triangle to every lane; a lane that takes it as its nearest records `id`.
    #[inline(always)]
    pub fn offer(&mut self, tri: &OriginTriangle, id: u32) {
        self.offer_as::<false>(tri, id);
    }

    /// [`PacketNearest::offer`] unless the triangle would leave a lane ambiguous that is not
    /// yet: then nothing changes and the answer is false (the caller offers it again with
    /// tighter bounds, [`OriginTriangle::new`]).
    #[inline(always)]
    pub fn offer_decided(&mut self, tri: &OriginTriangle, id: u32) -> bool {
        self.offer_as::<true>(tri, id)
    }

    /// Offers `tri` as [`PacketNearest::offer`] offers its f32 rounding, unless that would
    /// leave a live lane ambiguous: then each live lane tests it in f64
    /// ([`PreciseTriangle`]), and only a lane that f64 cannot decide either is ambiguous.
    /// (Inlined, with the f64 test a call: a cold call of this generic code was compiled
    /// without the kernel's target features, every lane operation a call of its own.)
    #[inline(always)]
    pub(crate) fn offer_precise(&mut self, tri: &PreciseTriangle, id: u32) {
        if self.offer_decided(&tri.rounded, id) {
            return;
        }
        let live = !self.ambiguous.to_bitmask() & V::full();
        if !tri.usable {
            self.ambiguous = V::zero().simd_eq(V::zero());
            return;
        }
        let mut ambiguous = 0;
        let mut rest = live;
        while rest != 0 {
            let l = rest.trailing_zeros() as usize;
            rest &= rest - 1;
            let d = [self.d[0].lane(l), self.d[1].lane(l), self.d[2].lane(l)];
            match tri.crossing(d) {
                Some(None) => {}
                Some(Some((lo, hi))) if hi < self.best_lo.lane(l) => self.set_best(l, lo, hi, id),
                Some(Some((lo, _))) if lo > self.best_hi.lane(l) => {}
                _ => ambiguous |= 1 << l,
            }
        }
        self.ambiguous |= V::from_bitmask(ambiguous);
    }

    #[inline(always)]
    fn offer_as<const DECIDED: bool>(&mut self, tri: &OriginTriangle, id: u32) -> bool {
        let (d, dm) = (&self.d, self.dm);
        if !tri.usable || tri.n_max * dm >= MAX_PRODUCT || !dm.is_finite() {
            // (Only an unusable triangle can hold the origin in its plane.)
            if tri.in_plane {
                return true;
            }
            if DECIDED && !self.ambiguous.all() {
                return false;
            }
            self.ambiguous = V::zero().simd_eq(V::zero());
            return true;
        }
        let EdgeTests {
            e,
            miss,
            front,
            behind,
        } = EdgeTests::new(tri, d, dm);
        if miss.all() {
            return true;
        }
        let undecided = !(miss | front | behind);
        if DECIDED && (undecided & !self.ambiguous).any() {
            return false;
        }
        if front.none() {
            self.ambiguous |= undecided;
            return true;
        }
        let (lo, hi, tight) = t_interval(tri, &e, d, dm);
        let nearer = hi.simd_lt(self.best_lo);
        let farther = lo.simd_gt(self.best_hi);
        // Overlapping intervals, or a loose one: the per-ray search orders them.
        let unordered = front & !(tight & (nearer | farther));
        if DECIDED && (unordered & !self.ambiguous).any() {
            return false;
        }
        self.ambiguous |= undecided | unordered;
        let take = front & tight & nearer;
        self.best_lo = take.bitselect(lo, self.best_lo);
        self.best_hi = take.bitselect(hi, self.best_hi);
        self.best_prim = take.bitselect(V::splat(f32::from_bits(id)), self.best_prim);
        true
    }

    /// Offers lanes `tris` of `block` (their ids as `ids` says) to ray lane `l` alone, the eight
    /// triangles in the vector's lanes: for a leaf only lane `l` reaches (at the preview
    /// sizes most are: 70% of Igea's leaf visits at 640×360, 99% at 320×180), one pass
    /// instead of one per triangle for all 8 rays. The same operations per triangle as
    /// [`PacketNearest::offer`] (the same bits). Done (true) when every triangle is
    /// decided for the lane and the nearest among them and the lane's best is certain;
    /// otherwise nothing changes and the answer is false (the caller offers them one by
    /// one). (An ambiguous lane is traced per ray
    /// afterwards: what the pass does to it does not matter.)
    #[inline(always)]
    pub(crate) fn offer_block_to_lane(
        &mut self,
        block: &OriginBlock,
        tris: u32,
        ids: BlockIds,
        l: usize,
    ) -> bool {
        // The block's 8 triangles in the build's 8 lanes, whatever the packet's width.
        type T<V> = <V as LaneOps>::Eight;
        if !self.block_usable(block, tris) {
            return false;
        }
        let dm = self.dm;
        // (No closures: in the AVX2 kernel they stayed calls.)
        let d = [
            T::<V>::splat(self.d[0].lane(l)),
            T::<V>::splat(self.d[1].lane(l)),
            T::<V>::splat(self.d[2].lane(l)),
        ];
        let Some((front, lo, hi)) = block_crossings(block, &d, dm, tris, block.det_from_normal)
        else {
            return false;
        };
        if front == 0 {
            return true;
        }
        let his = hi.to_array();
        match self.lane_decision(l, front, lo, &his) {
            None => false,
            Some(None) => true,
            Some(Some(w)) => {
                let id = match ids {
                    BlockIds::From(base) => base + w as u32,
                    BlockIds::Prims => block.prim[w],
                };
                self.set_best(l, lo.to_array()[w], his[w], id);
                true
            }
        }
    }

    /// Whether lanes `tris` of `block` can be tested at all: prepared usable, their
    /// products within range for these rays, and max|dₖ| finite.
    #[inline(always)]
    fn block_usable(&self, block: &OriginBlock, tris: u32) -> bool {
        type T<V> = <V as LaneOps>::Eight;
        let n_ok = (load::<T<V>>(&block.n_max) * T::<V>::splat(self.dm))
            .simd_lt(T::<V>::splat(MAX_PRODUCT))
            .to_bitmask();
        tris & !(block.usable & n_ok) == 0 && self.dm.is_finite()
    }

    /// Ray lane `l`'s decision on a block pass's front triangles `front` (their t intervals'
    /// low ends `lo` and high ends `his`, by lane): `Some(Some(w))` where the triangle in
    /// lane w is certainly nearer than the lane's best and than every other, `Some(None)`
    /// where every one is certainly farther than its best, `None` where the order is not
    /// certain.
    #[inline(always)]
    fn lane_decision<W: LaneOps>(
        &self,
        l: usize,
        front: u32,
        lo: W,
        his: &[f32],
    ) -> Option<Option<usize>> {
        // (Early returns: written with `bool::then_some`, the bunny's 640×360 frame took 3%
        // longer, code generation.)
        let w = least_of(front, his);
        let (best_lo, best_hi) = (self.best_lo.lane(l), self.best_hi.lane(l));
        if his[w] < best_lo {
            let farther = lo.simd_gt(W::splat(his[w])).to_bitmask();
            if front & !(1 << w) & !farther != 0 {
                return None;
            }
            return Some(Some(w));
        }
        // No nearer than the best: every one must be certainly farther.
        if front & !lo.simd_gt(W::splat(best_hi)).to_bitmask() != 0 {
            return None;
        }
        Some(None)
    }

    /// Ray lane `l`'s nearest so far: the interval (lo, hi) of triangle `id`.
    #[inline(always)]
    fn set_best(&mut self, l: usize, lo: f32, hi: f32, id: u32) {
        let lane = V::from_bitmask(1 << l);
        self.best_lo = with_lane(self.best_lo, lane, lo);
        self.best_hi = with_lane(self.best_hi, lane, hi);
        self.best_prim = with_lane(self.best_prim, lane, f32::from_bits(id));
    }

    /// Offers a leaf prepared as met (its `len` ≤ 4 triangles in lanes 0–3 of `block`, again
    /// in lanes 4–7, see `Bvh::prepare_leaf`; triangle j's id `base + j`) to the two to four
    /// ray lanes of `rays` alone: four triangles by `V::WIDTH / 4` rays in each pass of the
    /// packet's lanes, where offering each triangle to the whole packet takes a pass per
    /// triangle (at 640×360, leaves reached by two to four lanes are 60% of the bunny's
    /// leaf visits and a third of Igea's). Per ray, the same decisions as
    /// [`PacketNearest::offer_block_to_lane`]; done (true) when every ray is decided,
    /// otherwise nothing changes and the answer is false.
    #[inline(always)]
    pub(crate) fn offer_leaf_to_lanes(
        &mut self,
        block: &OriginBlock,
        len: usize,
        base: u32,
        rays: u32,
    ) -> bool {
        debug_assert!((1..=4).contains(&len) && (2..=4).contains(&rays.count_ones()));
        let leaf = (1u32 << len) - 1;
        if !self.block_usable(block, leaf) {
            return false;
        }
        let mut lanes = [0usize; 4];
        let mut count = 0;
        let mut rest = rays;
        while rest != 0 {
            lanes[count] = rest.trailing_zeros() as usize;
            rest &= rest - 1;
            count += 1;
        }
        let per_pass = V::WIDTH / 4;
        let mut takes = [None; 4];
        if !self.leaf_pass(block, leaf, lanes, 0, count.min(per_pass), &mut takes) {
            return false;
        }
        if count > per_pass
            && !self.leaf_pass(block, leaf, lanes, per_pass, count - per_pass, &mut takes)
        {
            return false;
        }
        for (&l, take) in lanes.iter().zip(&takes).take(count) {
            if let Some((lo, hi, j)) = *take {
                self.set_best(l, lo, hi, base + j as u32);
            }
        }
        true
    }

    /// One pass of [`PacketNearest::offer_leaf_to_lanes`]: the leaf's triangles (lanes
    /// `leaf` of the block's 0–3) to ray lane `lanes[from + g]` in lanes 4g to 4g + 3, for
    /// the `groups` groups g; each ray's nearest, if nearer than its best, into
    /// `takes[from + g]` as (lo, hi, triangle). False if some ray is left undecided.
    #[inline(always)]
    fn leaf_pass(
        &self,
        block: &OriginBlock,
        leaf: u32,
        lanes: [usize; 4],
        from: usize,
        groups: usize,
        takes: &mut [Option<(f32, f32, usize)>; 4],
    ) -> bool {
        let tris = (leaf * 0x1111) & (u32::MAX >> (32 - 4 * groups));
        let mut d = [
            V::splat(self.d[0].lane(lanes[from])),
            V::splat(self.d[1].lane(lanes[from])),
            V::splat(self.d[2].lane(lanes[from])),
        ];
        for g in 1..groups {
            let (group, l) = (V::from_bitmask(0xf << (4 * g)), lanes[from + g]);
            d = [
                group.bitselect(V::splat(self.d[0].lane(l)), d[0]),
                group.bitselect(V::splat(self.d[1].lane(l)), d[1]),
                group.bitselect(V::splat(self.d[2].lane(l)), d[2]),
            ];
        }
        let by_normal = (block.det_from_normal & 0xf) * 0x1111;
        let Some((front, lo, hi)) = block_crossings(block, &d, self.dm, tris, by_normal) else {
            return false;
        };
        if front == 0 {
            return true;
        }
        let (mut los, mut his) = ([0f32; 16], [0f32; 16]);
        lo.store(&mut los);
        hi.store(&mut his);
        for g in 0..groups {
            let front = front & (0xf << (4 * g));
            if front == 0 {
                continue;
            }
            match self.lane_decision(lanes[from + g], front, lo, &his) {
                None => return false,
                Some(None) => {}
                Some(Some(w)) => takes[from + g] = Some((los[w], his[w], w & 3)),
            }
        }
        true
    }

    /// Every lane ambiguous (nothing decided).
    #[inline(always)]
    pub(crate) fn all_ambiguous(&mut self) {
        self.ambiguous = V::zero().simd_eq(V::zero());
    }

    /// Per lane the id of the nearest (u32::MAX for none) into `prim[..WIDTH]`; returns the
    /// ambiguous lanes.
    #[inline(always)]
    pub(crate) fn finish_into(&self, prim: &mut [u32]) -> u32 {
        let mut bits = [0.0f32; 16];
        self.best_prim.store(&mut bits);
        for (p, b) in prim[..V::WIDTH].iter_mut().zip(bits) {
            *p = b.to_bits();
        }
        self.ambiguous.to_bitmask()
    }
}

impl<V: Lanes> PacketNearest<V> {
    /// A nearest-hit state for directions `d` (`d_max` ≥ every |dₖ|) holding `seed`'s
    /// candidates and ambiguous lanes, if any.
    #[inline(always)]
    pub fn seeded(d: &[f32x8; 3], d_max: f32, seed: Option<&PacketSeed>) -> Self {
        Self::seeded_in(each3(|k| V::from_wide(d[k])), d_max, seed)
    }

    /// [`PacketNearest::seeded`] inside a kernel already in lanes `V`.
    #[inline(always)]
    pub(crate) fn seeded_in(d: [V; 3], d_max: f32, seed: Option<&PacketSeed>) -> Self {
        let mut nearest = Self::new_in(d, d_max);
        if let Some(seed) = seed {
            nearest.best_lo = V::from_array(seed.lo);
            nearest.best_hi = V::from_array(seed.hi);
            nearest.best_prim = V::from_bits(seed.prim);
            nearest.ambiguous |= V::from_bitmask(seed.ambiguous);
        }
        nearest
    }

    /// [`PacketNearest::finish`] of the state so far.
    #[cfg(feature = "unit-tests")]
    pub(super) fn finish_ref(&self) -> PacketHits {
        PacketHits {
            prim: self.best_prim.to_array().map(f32::to_bits),
            ambiguous: self.ambiguous.to_bitmask(),
        }
    }

    /// Per lane the id of the nearest (u32::MAX for none), and the ambiguous lanes.
    pub fn finish(self) -> PacketHits {
        PacketHits {
            prim: self.best_prim.to_array().map(f32::to_bits),
            ambiguous: self.ambiguous.to_bitmask(),
        }
    }
}
