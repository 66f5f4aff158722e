//! The small-scene path: triangles in structure-of-arrays blocks of 8, tested 8 at a time with
//! the watertight method (`wide::f32x8`, SSE or AVX as compiled).
//!
//! Each lane runs exactly the scalar [`watertight_pre`] operations in the same order (no fused
//! multiply-add), and lanes whose edge function rounds to 0 are re-decided by the scalar f64
//! path, so the answers are bit-identical to the scalar loop; the tests hold it to that. Padding
//! lanes hold NaN vertices, which fail every comparison and so never hit.

use super::cull::Box3;
use super::layout::{merge, Layout, TriangleLayout};
use super::packet::{OriginBlock, OriginTriangle, OriginTriangles, PacketSink, PreciseTriangle};
use super::prepared::{LeafCache, Prepared, Reached, BLOCK};
use super::reference::{any_one_by_one, closest_one_by_one};
use super::IndexedTriangle;
use crate::geometry::adaptive::{
    approx_f32, box_extent, edge_error, loose_t_bound, round_down, Estimate, Search,
};
use crate::geometry::triangle::{beyond_tmin, edge_functions, watertight_pre, WatertightRay};
use crate::geometry::{Hit, Method, Ray, Shape};
use crate::math::lanes::{LaneOps, Lanes};
use crate::math::Real;
use wide::f32x8;

/// Eight triangles: `v[vertex][axis]` lanes, and their primitive indices.
#[derive(Clone, Debug)]
struct Block {
    v: [[f32x8; 3]; 3],
    prim: [u32; 8],
    /// Box around the block's triangles (for the adaptive filter's error bound).
    lo: [f32; 3],
    hi: [f32; 3],
    /// Lanes holding a triangle.
    valid: u32,
    /// The triangles again, for the rare lanes the adaptive method must look at closely.
    tris: [[[f32; 3]; 3]; 8],
}

/// Triangles packed for the 8-wide loop.
#[derive(Clone, Debug, Default)]
pub struct FlatLoop {
    blocks: Vec<Block>,
    len: usize,
    /// Box around all the triangles: the adaptive filter's bound is taken once per ray from
    /// it (small scenes; per block it cost more than it saved).
    lo: [f32; 3],
    hi: [f32; 3],
}

impl FlatLoop {
    /// Packs triangles (with their primitive indices) in the given order.
    pub fn new(tris: &[IndexedTriangle]) -> Self {
        let blocks = tris
            .chunks(8)
            .map(|chunk| {
                let mut lanes = [[[f32::NAN; 8]; 3]; 3];
                let mut prim = [u32::MAX; 8];
                let (mut lo, mut hi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
                let mut tris = [[[f32::NAN; 3]; 3]; 8];
                for (l, (tri, p)) in chunk.iter().enumerate() {
                    tris[l] = *tri;
                    for (vi, vert) in tri.iter().enumerate() {
                        for (a, c) in vert.iter().enumerate() {
                            lanes[vi][a][l] = *c;
                            lo[a] = lo[a].min(*c);
                            hi[a] = hi[a].max(*c);
                        }
                    }
                    prim[l] = *p;
                }
                Block {
                    v: lanes.map(|vert| vert.map(f32x8::from)),
                    prim,
                    lo,
                    hi,
                    valid: (1u32 << chunk.len()) - 1,
                    tris,
                }
            })
            .collect::<Vec<Block>>();
        let (mut blocks_lo, mut blocks_hi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
        for b in &blocks {
            for k in 0..3 {
                blocks_lo[k] = blocks_lo[k].min(b.lo[k]);
                blocks_hi[k] = blocks_hi[k].max(b.hi[k]);
            }
        }
        Self {
            blocks,
            len: tris.len(),
            lo: blocks_lo,
            hi: blocks_hi,
        }
    }

    /// How many triangles.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Bytes of the blocks' lanes.
    pub fn memory_bytes(&self) -> usize {
        self.len.div_ceil(8) * std::mem::size_of::<[[f32x8; 3]; 4]>()
    }

    /// The triangles as shapes with their primitive indices, in the order they were packed
    /// (primitive order).
    fn in_order(&self) -> impl Iterator<Item = (Shape<f32>, u32)> + '_ {
        (self.blocks.iter()).flat_map(|b| {
            (0..8)
                .filter(|l| b.valid >> l & 1 == 1)
                .map(|l| (Shape::from(b.tris[l]), b.prim[l]))
        })
    }

    /// The triangle in block `b`, lane `l`.
    fn triangle(&self, b: usize, l: usize) -> [[f32; 3]; 3] {
        self.blocks[b].tris[l]
    }

    /// The watertight nearest hit, 8 lanes a block, with tmin < t < tmax; among equal t the
    /// lowest primitive index wins ([`FlatLoop::closest_watertight_scalar`] is its twin).
    pub fn closest_watertight(&self, r: &WatertightRay<f32>, tmin: f32, tmax: f32) -> Option<Hit> {
        let mut best: Option<Hit> = None;
        let mut t_far = tmax;
        for b in 0..self.blocks.len() {
            let Some((mask, t, b1, b2)) = self.test_block(b, r, tmin, t_far) else {
                continue;
            };
            let (prim, t_arr) = (&self.blocks[b].prim, t.to_array());
            let mut bits = mask;
            while bits != 0 {
                let l = bits.trailing_zeros() as usize;
                bits &= bits - 1;
                let better = match &best {
                    None => true,
                    Some(h) => t_arr[l] < h.t || (t_arr[l] == h.t && prim[l] < h.prim),
                };
                if better {
                    best = Some(Hit {
                        t: t_arr[l],
                        prim: prim[l],
                        b1: b1.to_array()[l],
                        b2: b2.to_array()[l],
                    });
                }
            }
            if let Some(h) = &best {
                // Keep equal-t hits of lower index reachable: accept t ≤ best (strict < next up).
                t_far = h.t.next_up();
            }
        }
        best
    }

    /// The lanes of block `b` holding primitive `prim` (a bit mask).
    #[inline]
    fn lanes_of(&self, b: usize, prim: u32) -> u32 {
        let p = &self.blocks[b].prim;
        (0..8).fold(0, |m, l| if p[l] == prim { m | 1 << l } else { m })
    }

    /// Tests one block; `None` if no lane hits, else the lane mask, t and barycentrics.
    #[inline]
    fn test_block(
        &self,
        b: usize,
        r: &WatertightRay<f32>,
        tmin: f32,
        tmax: f32,
    ) -> Option<(u32, f32x8, f32x8, f32x8)> {
        let sz = f32x8::splat(r.s[2]);
        let ([[ax, ay, az], [bx, by, bz], [cx, cy, cz]], [mut u, mut vv, mut w]) =
            shear(&self.blocks[b].v, r);
        let zero = f32x8::ZERO;
        let exact_zero = u.simd_eq(zero) | vv.simd_eq(zero) | w.simd_eq(zero);
        if exact_zero.any() {
            // Rare: re-decide those lanes exactly as the scalar path does.
            let bits = exact_zero.to_bitmask();
            let (mut ua, mut va, mut wa) = (u.to_array(), vv.to_array(), w.to_array());
            let (axa, aya, bxa, bya, cxa, cya) = (
                ax.to_array(),
                ay.to_array(),
                bx.to_array(),
                by.to_array(),
                cx.to_array(),
                cy.to_array(),
            );
            for l in 0..8 {
                if bits & (1 << l) != 0 {
                    (ua[l], va[l], wa[l]) =
                        edge_functions(axa[l], aya[l], bxa[l], bya[l], cxa[l], cya[l]);
                }
            }
            (u, vv, w) = (f32x8::from(ua), f32x8::from(va), f32x8::from(wa));
        }
        let neg = u.simd_lt(zero) | vv.simd_lt(zero) | w.simd_lt(zero);
        let pos = u.simd_gt(zero) | vv.simd_gt(zero) | w.simd_gt(zero);
        let mixed = (neg & pos).to_bitmask();
        if mixed == 0xff {
            return None;
        }
        let det = u + vv + w;
        let t_scaled = (u * az + vv * bz + w * cz) * sz;
        let rcp = f32x8::ONE / det;
        let t = t_scaled * rcp;
        let mut ok =
            (t.simd_gt(f32x8::splat(tmin)) & t.simd_lt(f32x8::splat(tmax)) & det.simd_ne(zero))
                .to_bitmask()
                & !mixed;
        if ok != 0 {
            // The t error bound, lane-wise with exactly the scalar bound's operations;
            // lanes it cannot clear of tmin are re-decided by the scalar f64 path.
            let bound = t_error_bound_x8(
                [[ax, ay, az], [bx, by, bz], [cx, cy, cz]],
                sz,
                [u, vv, w],
                rcp,
            );
            let unsure = (t - bound).simd_le(f32x8::splat(tmin)).to_bitmask() & ok;
            let mut bits = unsure;
            while bits != 0 {
                let l = bits.trailing_zeros() as usize;
                bits &= bits - 1;
                let (tl, bl) = (t.to_array()[l], bound.to_array()[l]);
                if !beyond_tmin(r, &self.triangle(b, l), tl, bl, tmin) {
                    ok &= !(1 << l);
                }
            }
        }
        (ok != 0).then_some((ok, t, vv * rcp, w * rcp))
    }
}

/// A block's vertices translated to the ray origin and sheared into its frame, and the three
/// edge functions (u weighs v0, vv v1, w v2), with exactly the scalar test's operations (no
/// fused multiply-add), so lanes equal the scalar results bit for bit.
#[inline(always)]
fn shear(v: &[[f32x8; 3]; 3], r: &WatertightRay<f32>) -> ([[f32x8; 3]; 3], [f32x8; 3]) {
    let [kx, ky, kz] = r.k;
    let (sx, sy) = (f32x8::splat(r.s[0]), f32x8::splat(r.s[1]));
    let (ox, oy, oz) = (
        f32x8::splat(r.o[kx]),
        f32x8::splat(r.o[ky]),
        f32x8::splat(r.o[kz]),
    );
    // Written out rather than with `array::map`, which did not inline for 32-byte lanes.
    #[inline(always)]
    fn sheared(
        p: &[f32x8; 3],
        (kx, ky, kz): (usize, usize, usize),
        (ox, oy, oz): (f32x8, f32x8, f32x8),
        (sx, sy): (f32x8, f32x8),
    ) -> [f32x8; 3] {
        let (px, py, pz) = (p[kx] - ox, p[ky] - oy, p[kz] - oz);
        [px + sx * pz, py + sy * pz, pz]
    }
    let (k, o, s) = ((kx, ky, kz), (ox, oy, oz), (sx, sy));
    let (a, b, c) = (
        sheared(&v[0], k, o, s),
        sheared(&v[1], k, o, s),
        sheared(&v[2], k, o, s),
    );
    let u = c[0] * b[1] - c[1] * b[0];
    let w = b[0] * a[1] - b[1] * a[0];
    let vv = a[0] * c[1] - a[1] * c[0];
    ([a, b, c], [u, vv, w])
}

/// One block under the adaptive method's f32 filter: lanes whose edge signs are all certain
/// (`sure`, with t, its bound and barycentrics) and lanes it cannot decide (`unsure`).
struct BlockFilter {
    sure: u32,
    unsure: u32,
    t: [f32; 8],
    bound: [f32; 8],
    b1: [f32; 8],
    b2: [f32; 8],
}

impl BlockFilter {
    /// What the filter knows about lane `l`: a hit with the loose t interval, or unsure.
    #[inline]
    fn estimate(&self, l: usize) -> Estimate {
        if self.sure & (1 << l) != 0 {
            approx_f32(self.t[l], self.bound[l], self.b1[l], self.b2[l], 0)
        } else {
            Estimate::Unsure
        }
    }
}

impl FlatLoop {
    /// The adaptive method's f32 filter on one block (see `geometry::adaptive`). Sure lanes
    /// whose t interval lies certainly below `tmin` or beyond `t_far` are dropped here.
    #[inline(always)]
    fn filter_block(
        &self,
        b: usize,
        r: &WatertightRay<f32>,
        (edge_bound, t_bound): (f32, (f32, f32)),
        tmin: f32,
        t_far: f32,
    ) -> Option<BlockFilter> {
        let blk = &self.blocks[b];
        let sz = f32x8::splat(r.s[2]);
        let ([[_, _, az], [_, _, bz], [_, _, cz]], [u, vv, w]) = shear(&blk.v, r);
        let ep = f32x8::splat(edge_bound);
        let en = -ep;
        let neg = u.simd_lt(en) | vv.simd_lt(en) | w.simd_lt(en);
        let pos = u.simd_gt(ep) | vv.simd_gt(ep) | w.simd_gt(ep);
        let maybe = !(neg & pos).to_bitmask() & blk.valid;
        if maybe == 0 {
            return None;
        }
        let all_pos = u.simd_gt(ep) & vv.simd_gt(ep) & w.simd_gt(ep);
        let all_neg = u.simd_lt(en) & vv.simd_lt(en) & w.simd_lt(en);
        let sure = (all_pos | all_neg).to_bitmask() & maybe;
        let mut out = BlockFilter {
            sure,
            unsure: maybe & !sure,
            t: [0.0; 8],
            bound: [0.0; 8],
            b1: [0.0; 8],
            b2: [0.0; 8],
        };
        if sure != 0 {
            let det = u + vv + w;
            let rcp = f32x8::ONE / det;
            let t = (u * az + vv * bz + w * cz) * sz * rcp;
            // The loose per-ray bound A + B·|1/det| (`adaptive::loose_t_bound`).
            let bound = f32x8::splat(t_bound.0) + f32x8::splat(t_bound.1) * rcp.abs();
            // The interval [t − 2·bound, t + 2·bound] (as `approx_f32` makes it), widened by
            // a few ulps of t for the rounding of these f32 operations.
            let slack = f32x8::splat(2.5) * bound + t.abs() * f32x8::splat(1.0 / (1 << 22) as f32);
            let out_of_reach =
                (t - slack).simd_gt(f32x8::splat(t_far)) | (t + slack).simd_lt(f32x8::splat(tmin));
            out.sure &= !out_of_reach.to_bitmask();
            out.t = t.to_array();
            out.bound = bound.to_array();
            out.b1 = (vv * rcp).to_array();
            out.b2 = (w * rcp).to_array();
        }
        (out.sure | out.unsure != 0).then_some(out)
    }

    /// The adaptive filter's edge-function error bound for this ray, from the box around all
    /// the triangles (`adaptive::edge_error` with m ≤ M: looser than per lane, but nearly
    /// free, and small scenes have large triangles).
    /// With it, the loose t bound's coefficients.
    #[inline]
    fn bounds(&self, r: &WatertightRay<f32>) -> (f32, (f32, f32)) {
        let m = box_extent(r.o, self.lo, self.hi);
        (edge_error(m, m), loose_t_bound(m, r.s[2]))
    }

    /// Whether `ray` may meet a triangle with tmin ≤ t ≤ tmax: the f64 slab test against the
    /// box around them all. Asked where a block's f32 filter is unsure: from an origin far
    /// from small triangles (a camera 10¹² away from the Cornell box) the filter decides none
    /// of them, and each went to interval arithmetic (3.6 µs a ray for the box's 30).
    fn box_may_meet(&self, ray: &Ray, tmin: f64, tmax: f64) -> bool {
        let inv = ray.d.map(|c| 1.0 / f64::from(c));
        let whole = Box3 {
            lo: self.lo,
            hi: self.hi,
        };
        let (t0, t1) = whole.slab_interval_f64(0.0, ray.o, &inv, (tmin, tmax));
        t0 <= t1
    }
}

/// [`t_error_bound`](crate::geometry::triangle::t_error_bound) for 8 lanes, operation for operation (so bit-identical per lane).
#[inline]
fn t_error_bound_x8(p: [[f32x8; 3]; 3], sz: f32x8, e: [f32x8; 3], rcp: f32x8) -> f32x8 {
    let max3 = |a: f32x8, b: f32x8, c: f32x8| a.abs().max(b.abs()).max(c.abs());
    let g = |n| f32x8::splat(f32::error_gamma(n));
    let tiny = f32x8::splat(f32::UNDERFLOW);
    let max_z = max3(p[0][2], p[1][2], p[2][2]);
    let max_zt = max_z * sz.abs() + tiny;
    let max_xt = max3(p[0][0], p[1][0], p[2][0]);
    let max_yt = max3(p[0][1], p[1][1], p[2][1]);
    let delta_z = g(3) * max_zt;
    let delta_x = g(5) * (max_xt + max_z);
    let delta_y = g(5) * (max_yt + max_z);
    let two = f32x8::ONE + f32x8::ONE;
    let three = two + f32x8::ONE;
    let delta_e = two * (g(2) * max_xt * max_yt + delta_y * max_xt + delta_x * max_yt);
    let max_e = max3(e[0], e[1], e[2]);
    let underflow = tiny * (f32x8::ONE + rcp.abs() * (f32x8::ONE + three * sz.abs()));
    three * (g(3) * max_e * max_zt + delta_e * max_zt + delta_z * max_e) * rcp.abs() + underflow
}

impl FlatLoop {
    /// The scalar twin of the block loop, for tests: the same triangles in the same order.
    pub fn closest_watertight_scalar(
        &self,
        r: &WatertightRay<f32>,
        tmin: f32,
        tmax: f32,
    ) -> Option<Hit> {
        let mut best: Option<Hit> = None;
        let mut t_far = tmax;
        for b in 0..self.blocks.len() {
            for l in 0..8 {
                let prim = self.blocks[b].prim[l];
                if prim == u32::MAX {
                    continue;
                }
                if let Some((t, b1, b2)) = watertight_pre(r, &self.triangle(b, l), tmin, t_far) {
                    t_far = t;
                    best = Some(Hit { t, prim, b1, b2 });
                }
            }
        }
        best
    }
}

/// The watertight method and the exact one in lanes; the others one triangle at a time in
/// primitive order, through the shape's own test.
impl Layout for FlatLoop {
    fn closest(&self, ray: &Ray, method: Method, tmin: f32, tmax: f32, best: &mut Option<Hit>) {
        match method {
            Method::Watertight => {
                let r = WatertightRay::new(ray.o, ray.d);
                merge(
                    best,
                    r.and_then(|r| self.closest_watertight(&r, tmin, tmax)),
                );
            }
            _ => closest_one_by_one(self.in_order(), ray, method, tmin, tmax, best),
        }
    }

    fn closest_exact(&self, ray: &Ray, r: &WatertightRay<f32>, search: &mut Search) {
        let tmin = round_down(search.tmin());
        let e = self.bounds(r);
        let mut box_asked = false;
        for (b, blk) in self.blocks.iter().enumerate() {
            let Some(f) = self.filter_block(b, r, e, tmin, search.t_far32()) else {
                continue;
            };
            if f.unsure != 0 && !std::mem::replace(&mut box_asked, true) {
                let (tmin, tmax) = (search.tmin(), f64::from(search.t_far32()));
                if !self.box_may_meet(ray, tmin, tmax) {
                    return;
                }
            }
            let mut bits = f.sure | f.unsure;
            while bits != 0 {
                let l = bits.trailing_zeros() as usize;
                bits &= bits - 1;
                let est = f.estimate(l);
                search.offer_triangle(blk.prim[l], &blk.tris[l], est);
            }
        }
    }

    fn any(&self, ray: &Ray, method: Method, tmin: f32, tmax: f32, skip: u32) -> bool {
        match method {
            Method::Watertight => WatertightRay::new(ray.o, ray.d).is_some_and(|r| {
                (0..self.blocks.len()).any(|b| {
                    self.test_block(b, &r, tmin, tmax)
                        .is_some_and(|(mask, ..)| mask & !self.lanes_of(b, skip) != 0)
                })
            }),
            _ => any_one_by_one(self.in_order(), ray, method, tmin, tmax, skip),
        }
    }

    fn any_exact(&self, ray: &Ray, r: &WatertightRay<f32>, search: &Search, skip: u32) -> bool {
        let (tmin, tmax) = (round_down(search.tmin()), search.t_far32());
        let e = self.bounds(r);
        let mut box_asked = false;
        for (b, blk) in self.blocks.iter().enumerate() {
            let Some(f) = self.filter_block(b, r, e, tmin, tmax) else {
                continue;
            };
            let mut bits = (f.sure | f.unsure) & !self.lanes_of(b, skip);
            if f.unsure & bits != 0 && !std::mem::replace(&mut box_asked, true) {
                // (A miss of the box is a miss of every triangle.)
                if !self.box_may_meet(ray, search.tmin(), f64::from(tmax)) {
                    return false;
                }
            }
            while bits != 0 {
                let l = bits.trailing_zeros() as usize;
                bits &= bits - 1;
                let est = f.estimate(l);
                if search.confirms_triangle(&blk.tris[l], est) {
                    return true;
                }
            }
        }
        false
    }

    /// Every triangle, a block of 8 at a time, prepared for `o` in f32 (from `prepared`'s
    /// list or cache, or as met), each again in f64 where the f32 bounds would leave a live
    /// lane undecided: the BVH's leaf visit without the boxes (a small scene's triangles,
    /// or every triangle where the flat loop was chosen).
    #[inline(always)]
    fn packet_into<V: LaneOps, S: PacketSink<V>>(
        &self,
        sink: &mut S,
        o: [f32; 3],
        prepared: Prepared<'_>,
        _: [V; 3],
    ) {
        let prepared = match prepared.fits(o, self.len) {
            true => prepared,
            false => Prepared::AsMet,
        };
        let mut scratch = None;
        for (b, block) in self.blocks.iter().enumerate() {
            if sink.live() == 0 {
                return;
            }
            let count = block.valid.count_ones() as usize;
            let prepared_block = match prepared {
                Prepared::All(list) => {
                    for t in &list.tris[BLOCK * b..][..count] {
                        sink.take(t);
                    }
                    continue;
                }
                Prepared::AsMet => {
                    let out = scratch.get_or_insert_with(OriginBlock::default);
                    self.prepare_block::<V::Eight>(b, o, out);
                    &*out
                }
                Prepared::Once(cache) => self.cached_block::<V::Eight>(cache, b, o),
            };
            for l in 0..count {
                if !sink.take_decided(&prepared_block.get(l)) {
                    sink.take_precise(&self.precise(b, l, o));
                }
            }
        }
    }
}

/// Every triangle in one box; no walk of its own beside `packet_into`.
impl TriangleLayout for FlatLoop {
    const NAME: &'static str = "flat";

    fn build(tris: &[IndexedTriangle]) -> Self {
        FlatLoop::new(tris)
    }

    fn len(&self) -> usize {
        self.len
    }

    fn memory_bytes(&self) -> usize {
        FlatLoop::memory_bytes(self)
    }

    /// In the loop's order (block by block: the slots of a list and a cache alike).
    fn prepared_for(&self, origin: [f32; 3]) -> OriginTriangles {
        let blocks = &self.blocks;
        OriginTriangles::prepare(
            self.len,
            |i| {
                (
                    &blocks[i / BLOCK].tris[i % BLOCK],
                    blocks[i / BLOCK].prim[i % BLOCK],
                )
            },
            origin,
        )
    }

    fn bounding_box(&self) -> Option<Box3> {
        (self.len > 0).then_some(Box3 {
            lo: self.lo,
            hi: self.hi,
        })
    }
}

/// The packet walk's preparations (see [`FlatLoop::packet_into`](Layout::packet_into)).
impl FlatLoop {
    /// Block `b` prepared for `o` in f32 in `V`'s lanes; a short block repeats its last
    /// triangle (the padding lanes' NaN vertices would make every ray ambiguous).
    #[inline(always)]
    fn prepare_block<V: Lanes>(&self, b: usize, o: [f32; 3], out: &mut OriginBlock) {
        let block = &self.blocks[b];
        let last = block.valid.count_ones() as usize - 1;
        let i: [usize; BLOCK] = std::array::from_fn(|l| l.min(last));
        let t = &block.tris;
        OriginTriangle::new8::<V>(
            [
                &t[i[0]], &t[i[1]], &t[i[2]], &t[i[3]], &t[i[4]], &t[i[5]], &t[i[6]], &t[i[7]],
            ],
            o,
            i.map(|l| block.prim[l]),
            out,
        );
    }

    /// Block `b` prepared for `o`: from `cache`, or prepared now and kept there.
    #[inline(always)]
    fn cached_block<'c, V: Lanes>(
        &self,
        cache: &'c LeafCache,
        b: usize,
        o: [f32; 3],
    ) -> &'c OriginBlock {
        if let Some(ready) = cache.block(b) {
            return ready;
        }
        match cache.reach(b) {
            Reached::Ready(ready) => ready,
            Reached::Claimed(mut claim) => {
                self.prepare_block::<V>(b, o, claim.block());
                claim.ready()
            }
        }
    }

    /// Block `b`'s lane `l` prepared for `o` in f64, for the lanes its f32 preparation
    /// leaves undecided (rare: out of the way of the walk).
    #[cold]
    #[inline(never)]
    fn precise(&self, b: usize, l: usize, o: [f32; 3]) -> PreciseTriangle {
        let block = &self.blocks[b];
        PreciseTriangle::new(&block.tris[l], o, block.prim[l])
    }
}

#[cfg(feature = "unit-tests")]
#[deny(dead_code)]
pub(crate) mod tests {
    use super::*;
    use crate::accel::layout::any;
    use crate::accel::packet::{PacketNearest, ShadowPacket};
    use crate::accel::reference::InOrder;

    fn a_layout_without_a_packet_walk_leaves_every_lane_to_the_per_ray_queries() {
        // One triangle ahead of 8 rays from the origin: the reference loop (no packet walk of
        // its own) leaves every lane undecided, the flat loop's walk decides them all.
        let v = [[-1.0, -1.0, 2.0], [1.0, -1.0, 2.0], [0.0, 1.0, 2.0]];
        let d: [f32x8; 3] = [
            f32x8::from([-0.2, -0.1, 0.0, 0.1, 0.2, 0.0, 0.05, -0.05]),
            f32x8::splat(-0.1),
            f32x8::splat(1.0),
        ];
        let in_order = InOrder(vec![(Shape::from(v), 0)]);
        let flat = FlatLoop::new(&[(v, 0)]);
        let o = [0.0; 3];

        let mut nearest = PacketNearest::<f32x8>::seeded(&d, 1.0, None);
        in_order.packet_into(&mut nearest, o, Prepared::AsMet, d);
        assert_eq!(nearest.finish().ambiguous, 0xff);
        let mut nearest = PacketNearest::<f32x8>::seeded(&d, 1.0, None);
        flat.packet_into(&mut nearest, o, Prepared::AsMet, d);
        let found = nearest.finish();
        assert_eq!((found.ambiguous, found.prim), (0, [0; 8]));

        // Shadow segments to z = 4: blocked by the triangle at t = 1/2.
        let d = d.map(|c| c * f32x8::splat(4.0));
        let mut shadow = ShadowPacket::<f32x8>::new(&d, 4.0, &[u32::MAX; 8], 0b1011_0110);
        in_order.packet_into(&mut shadow, o, Prepared::AsMet, d);
        let hits = shadow.finish();
        assert_eq!((hits.blocked, hits.unsure), (0, 0b1011_0110));
        let mut shadow = ShadowPacket::<f32x8>::new(&d, 4.0, &[u32::MAX; 8], 0b1011_0110);
        flat.packet_into(&mut shadow, o, Prepared::AsMet, d);
        let hits = shadow.finish();
        assert_eq!((hits.blocked, hits.unsure), (0b1011_0110, 0));
        // The per-ray queries answer the reference loop's lanes.
        let ray = Ray::new(o, [0.1, -0.4, 4.0]);
        assert!(any(
            &[&in_order],
            &ray,
            Method::Adaptive,
            0.0,
            1.0,
            u32::MAX
        ));
    }

    /// This module's tests, for tests/unit.rs to run.
    pub(crate) const TESTS: &[(&str, fn())] = &[(
        "a_layout_without_a_packet_walk_leaves_every_lane_to_the_per_ray_queries",
        a_layout_without_a_packet_walk_leaves_every_lane_to_the_per_ray_queries,
    )];
}
