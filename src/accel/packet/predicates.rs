//! The tests the queries share: a prepared triangle's edge tests and t interval for a
//! packet's lanes ([`EdgeTests`], [`t_interval`], [`block_crossings`]) and for one ray
//! ([`OriginTriangle::estimate`]), and a packet's max|dₖ| ([`max_component`]). Apart so that
//! the nearest and the shadow queries read one set of predicates.

use super::block::OriginBlock;
use super::{OriginTriangle, EDGE_ABS, MAX_PRODUCT};
use crate::geometry::adaptive::{Approx, Estimate};
use crate::math::lanes::{f32x8, LaneOps, Lanes};
use crate::math::simd::each3;

impl OriginTriangle {
    /// nᵢ = pⱼ × pₖ (rounded to f32): eᵢ = d·nᵢ are the edge functions of direction d.
    #[inline]
    pub fn edge_normals(&self) -> &[[f32; 3]; 3] {
        &self.n
    }

    /// Bounds on |computed eᵢ − exact eᵢ| for direction `d` (eᵢ = d·nᵢ computed in f32 as
    /// ((d₀·nᵢ₀ + d₁·nᵢ₁) + d₂·nᵢ₂)), the bounds of the edge tests; +∞ where the triangle's
    /// bounds are unusable.
    pub fn edge_bounds(&self, d: [f32; 3]) -> [f32; 3] {
        let dm = d.iter().fold(0f32, |m, c| m.max(c.abs())) * (1.0 + 1e-6);
        match self.usable && (self.n_max * dm) < MAX_PRODUCT {
            true => self.k.map(|k| k * dm + EDGE_ABS),
            false => [f32::INFINITY; 3],
        }
    }

    /// One ray's estimate (the edge tests of [`closest`] for a single direction d from the
    /// prepared origin, `d_max` = max|dₖ|), as the adaptive search's f32 level reports it: a
    /// certain miss, a certain crossing of the line with t in an interval, or unsure. Here t's
    /// determinant is d·normal, and a t whose bound exceeds about 6e-6 relative is left to the
    /// per-ray levels (which also keep the t they report that close).
    ///
    /// [`closest`]: super::closest
    #[inline]
    pub fn estimate(&self, d: [f32; 3], d_max: f32) -> Estimate {
        let dm = d_max * (1.0 + 1e-6);
        if !self.usable || self.n_max * dm >= MAX_PRODUCT || d_max.is_nan() {
            return Estimate::Unsure;
        }
        let e = each3(|i| {
            let n = &self.n[i];
            d[0] * n[0] + d[1] * n[1] + d[2] * n[2]
        });
        let bound = each3(|i| self.k[i] * dm + EDGE_ABS);
        let pos = each3(|i| e[i] > bound[i]);
        let neg = each3(|i| e[i] < -bound[i]);
        if pos.contains(&true) && neg.contains(&true) {
            return Estimate::Miss;
        }
        if !(pos == [true; 3] || neg == [true; 3]) {
            return Estimate::Unsure;
        }
        let n = self.normal;
        let det = d[0] * n[0] + d[1] * n[1] + d[2] * n[2];
        let rcp = 1.0 / det;
        let t = self.num * rcp;
        let r_det = ((self.k_det * dm + EDGE_ABS) * 1.0001) * rcp.abs();
        if r_det.is_nan() || r_det > 4e-6 {
            return Estimate::Unsure;
        }
        let sum = e[0] + e[1] + e[2];
        let err = t.abs() * (self.c_t + 1.4 * r_det) + 1e-37;
        let (lo, hi) = (t - err, t + err);
        if !(lo.is_finite() && hi.is_finite()) {
            return Estimate::Unsure;
        }
        Estimate::Hit(Approx {
            t: t as f64,
            lo: lo as f64,
            hi: hi as f64,
            b1: (e[1] / sum) as f64,
            b2: (e[2] / sum) as f64,
            level: 0,
        })
    }
}

/// The largest |dₖ| over a packet's directions (NaN if any is NaN).
pub fn max_component(d: &[f32x8; 3]) -> f32 {
    max_component_in(d)
}

/// [`max_component`] in lanes `V`.
#[inline(always)]
pub(crate) fn max_component_in<V: LaneOps>(d: &[V; 3]) -> f32 {
    let (a, b, c) = (d[0].abs(), d[1].abs(), d[2].abs());
    // A sum of magnitudes is NaN only where a component is (fast_max may drop a NaN).
    let sum = a + b + c;
    if sum.simd_ne(sum).any() {
        return f32::NAN;
    }
    // (Magnitudes, no NaN: the same value in any order.)
    LaneOps::reduce_max(a.fast_max(b).fast_max(c))
}

/// The edge tests of one prepared triangle for 8 directions from its origin: the edge
/// functions eᵢ = d·nᵢ, and the lanes that certainly miss it (edges of both signs beyond
/// their bounds), certainly cross it in front (all three of the numerator's sign: t > 0) or
/// behind (t < 0). Other lanes are undecided.
pub(super) struct EdgeTests<V> {
    pub(super) e: [V; 3],
    pub(super) miss: V,
    pub(super) front: V,
    pub(super) behind: V,
}

impl<V: LaneOps> EdgeTests<V> {
    /// `dm`: max|dₖ| rounded up.
    #[inline(always)]
    pub(super) fn new(tri: &OriginTriangle, d: &[V; 3], dm: f32) -> Self {
        // (No closures: where the offer sits in a cold branch (after `Bvh::precise`), the
        // closure stayed a call, compiled without the kernel's target features: every lane
        // operation in it a call of its own.)
        #[inline(always)]
        fn edge<V: LaneOps>(n: &[f32; 3], d: &[V; 3]) -> V {
            d[0] * V::splat(n[0]) + d[1] * V::splat(n[1]) + d[2] * V::splat(n[2])
        }
        let n = &tri.n;
        let e = [edge(&n[0], d), edge(&n[1], d), edge(&n[2], d)];
        let k = tri.k.map(|k| k * dm + EDGE_ABS);
        let bound = [V::splat(k[0]), V::splat(k[1]), V::splat(k[2])];
        let (miss, all_pos, all_neg) = edge_signs(&e, &bound);
        // In front: the sign of det (that of the eᵢ) is the numerator's.
        let (front, behind) = match tri.num > 0.0 {
            true => (all_pos, all_neg),
            false => (all_neg, all_pos),
        };
        Self {
            e,
            miss,
            front,
            behind,
        }
    }
}

/// t = num/det per lane with its interval (lo, hi), and the lanes where that interval is
/// tight enough to use (see [`PacketNearest`] for the bound). The determinant det = d·N is
/// taken as e₀ + e₁ + e₂ (two additions: the eᵢ are at hand), except for a triangle whose
/// eᵢ are large against their sum (small and far from the origin: their bound relative to
/// det grows as distance / size), where it is d·normal: with the sum, a bunny filling the
/// view from 4 units away left 7.5% of its camera lanes ambiguous (traced per ray), with
/// d·normal 0.5%.
///
/// [`PacketNearest`]: super::PacketNearest
#[inline(always)]
pub(super) fn t_interval<V: LaneOps>(
    tri: &OriginTriangle,
    e: &[V; 3],
    d: &[V; 3],
    dm: f32,
) -> (V, V, V) {
    let (det, bound) = match tri.det_from_normal {
        false => (e[0] + e[1] + e[2], tri.k_sum * dm + 3.0 * EDGE_ABS),
        true => {
            let n = &tri.normal;
            let det = d[0] * V::splat(n[0]) + d[1] * V::splat(n[1]) + d[2] * V::splat(n[2]);
            (det, tri.k_det * dm + EDGE_ABS)
        }
    };
    t_within(V::splat(tri.num), det, V::splat(bound), V::splat(tri.c_t))
}

/// Per lane, from the edge functions `e` and their rounding bounds: the lanes that
/// certainly miss (edges of both signs beyond their bounds), and those whose three edges
/// are certainly all positive, or all negative.
#[inline(always)]
fn edge_signs<V: LaneOps>(e: &[V; 3], bound: &[V; 3]) -> (V, V, V) {
    let pos = [
        e[0].simd_gt(bound[0]),
        e[1].simd_gt(bound[1]),
        e[2].simd_gt(bound[2]),
    ];
    let neg = [
        e[0].simd_lt(-bound[0]),
        e[1].simd_lt(-bound[1]),
        e[2].simd_lt(-bound[2]),
    ];
    let miss = (pos[0] | pos[1] | pos[2]) & (neg[0] | neg[1] | neg[2]);
    (miss, pos[0] & pos[1] & pos[2], neg[0] & neg[1] & neg[2])
}

/// t = num/det per lane with its interval (lo, hi), and the lanes where it is tight enough
/// to use, from det's rounding bound and the triangle's c_t (see [`PacketNearest`]).
///
/// [`PacketNearest`]: super::PacketNearest
#[inline(always)]
fn t_within<V: LaneOps>(num: V, det: V, det_bound: V, c_t: V) -> (V, V, V) {
    let rcp = V::one() / det;
    let t = num * rcp;
    let r_det = (det_bound * V::splat(1.0001)) * rcp.abs();
    let tight = r_det.simd_le(V::splat(0.25));
    let err = t.abs() * (c_t + V::splat(1.4) * r_det) + V::splat(1e-37);
    (t - err, t + err, tight)
}

/// The block passes' tests ([`PacketNearest::offer_block_to_lane`],
/// [`PacketNearest::offer_leaf_to_lanes`]): lane l of `W` tests the block's triangle in lane
/// l mod 8 against direction `d` at lane l, as [`PacketNearest::offer`] tests it (the same
/// operations, the same bits; `by_normal`: the lanes whose det is d·normal). Of the lanes
/// `tris`: those certainly in front, and every lane's t interval; `None` if one of them is
/// left undecided, or in front with a loose interval.
///
/// [`PacketNearest::offer_block_to_lane`]: super::PacketNearest::offer_block_to_lane
/// [`PacketNearest::offer_leaf_to_lanes`]: super::PacketNearest::offer_leaf_to_lanes
/// [`PacketNearest::offer`]: super::PacketNearest::offer
#[inline(always)]
pub(super) fn block_crossings<W: LaneOps>(
    block: &OriginBlock,
    d: &[W; 3],
    dm: f32,
    tris: u32,
    by_normal: u32,
) -> Option<(u32, W, W)> {
    // (Helpers as always-inlined items, not closures: see `EdgeTests::new`.)
    #[inline(always)]
    fn field<W: LaneOps>(x: &[f32; 8]) -> W {
        W::repeat_eight(load(x))
    }
    #[inline(always)]
    fn dot<W: LaneOps>(d: &[W; 3], n: &[[f32; 8]; 3]) -> W {
        d[0] * field(&n[0]) + d[1] * field(&n[1]) + d[2] * field(&n[2])
    }
    let e = [
        dot(d, &block.n[0]),
        dot(d, &block.n[1]),
        dot(d, &block.n[2]),
    ];
    let (dm_v, abs) = (W::splat(dm), W::splat(EDGE_ABS));
    let bound = [
        field::<W>(&block.k[0]) * dm_v + abs,
        field::<W>(&block.k[1]) * dm_v + abs,
        field::<W>(&block.k[2]) * dm_v + abs,
    ];
    let (miss, all_pos, all_neg) = edge_signs(&e, &bound);
    let num: W = field(&block.num);
    let num_pos = num.simd_gt(W::zero());
    let front = num_pos.bitselect(all_pos, all_neg).to_bitmask() & tris;
    let behind = num_pos.bitselect(all_neg, all_pos).to_bitmask();
    if tris & !(miss.to_bitmask() | front | behind) != 0 {
        return None;
    }
    if front == 0 {
        return Some((0, W::zero(), W::zero()));
    }
    // t's interval per triangle, as `t_interval` bounds det.
    let by_normal = W::from_bitmask(by_normal);
    let det = by_normal.bitselect(dot(d, &block.normal), e[0] + e[1] + e[2]);
    let det_bound = by_normal.bitselect(
        field::<W>(&block.k_det) * dm_v + abs,
        field::<W>(&block.k_sum) * dm_v + W::splat(3.0 * EDGE_ABS),
    );
    let (lo, hi, tight) = t_within(num, det, det_bound, field(&block.c_t));
    if front & !tight.to_bitmask() != 0 {
        return None;
    }
    Some((front, lo, hi))
}

/// A field of an [`OriginBlock`] as lanes.
#[inline(always)]
pub(super) fn load<V: Lanes>(field: &[f32; 8]) -> V {
    V::from_array(*field)
}
