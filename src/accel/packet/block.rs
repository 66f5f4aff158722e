//! Eight triangles prepared for one origin in f32 lanes ([`OriginTriangle::new8`] into an
//! [`OriginBlock`]): the preparation of a hierarchy's leaves as the rays reach them. Apart
//! from `prepare.rs`: f32 throughout, with its own derivation of the bounds.

use super::prepare::lane_of;
use super::{cross, sub, OriginTriangle};
use crate::math::lanes::Lanes;

/// The ids a block's lanes record in [`PacketNearest::offer_block_to_lane`].
///
/// [`PacketNearest::offer_block_to_lane`]: super::PacketNearest::offer_block_to_lane
#[derive(Clone, Copy, Debug)]
pub(crate) enum BlockIds {
    /// Lane j records `base + j` (a BVH's positions).
    From(u32),
    /// Lane j records its triangle's primitive index (instances).
    Prims,
}

/// Eight triangles' coordinates, for [`OriginTriangle::new8_from`]: lane l's vertex j,
/// coordinate k. (Read where the lanes are gathered: a leaf's shared vertices are not
/// triangles in memory.)
pub(crate) trait TriangleLanes {
    fn coordinate(&self, l: usize, j: usize, k: usize) -> f32;
}

impl TriangleLanes for [&[[f32; 3]; 3]; 8] {
    #[inline(always)]
    fn coordinate(&self, l: usize, j: usize, k: usize) -> f32 {
        self[l][j][k]
    }
}

/// Eight triangles prepared for one origin in f32 ([`OriginTriangle::new8`]), field by field
/// as [`OriginQuad`]: a frame's cache keeps a BVH's triangles in blocks of 8.
///
/// [`OriginQuad`]: super::prepare::OriginQuad
#[derive(Clone, Copy, Debug, Default)]
#[repr(C, align(32))]
pub(crate) struct OriginBlock {
    pub(super) n: [[[f32; 8]; 3]; 3],
    pub(super) k: [[f32; 8]; 3],
    pub(super) k_sum: [f32; 8],
    pub(super) k_det: [f32; 8],
    pub(super) n_max: [f32; 8],
    pub(super) num: [f32; 8],
    pub(super) c_t: [f32; 8],
    pub(super) normal: [[f32; 8]; 3],
    pub(super) prim: [u32; 8],
    pub(super) det_from_normal: u32,
    pub(super) usable: u32,
}

impl OriginBlock {
    /// Lane `l`'s triangle (`l` < 8).
    #[inline(always)]
    pub(crate) fn get(&self, l: usize) -> OriginTriangle {
        debug_assert!(l < 8);
        lane_of!(self, l, 8)
    }

    /// The lanes' primitive indices.
    #[cfg(feature = "unit-tests")]
    pub(crate) fn prims(&self) -> [u32; 8] {
        self.prim
    }

    #[cfg(feature = "unit-tests")]
    pub(crate) fn set_prims(&mut self, prims: [u32; 8]) {
        self.prim = prims;
    }
}

impl OriginTriangle {
    /// Eight triangles prepared for `o` in f32, lane by lane in `V`: the BVH's preparation
    /// as its leaves are reached (f32 lanes, twice as many as f64's and no conversions: about
    /// 65 instructions a triangle with its gather and the cache, against about 160 for
    /// [`OriginTriangle::new4`] with its per-lane stores, callgrind, Igea 640×360), with
    /// edge bounds about twice [`OriginTriangle::new`]'s. Alone, those sent 2.7 times as
    /// many lanes of the 1M-triangle mesh to the per-ray search (906 against 339 in two
    /// frames at 640×360, 16k instructions each); the walks therefore offer a triangle that
    /// leaves a live lane undecided again as `new` prepares it.
    ///
    /// The same quantities as `new`, each rounded in f32, with U = 2⁻²⁴: p̃ = fl(v − o) and
    /// Ẽ = fl(vₖ − vⱼ) are within U' = U/(1 − U) of exact relative to themselves, so each
    /// component a·b − c·d of ñᵢ = fl(p̃ⱼ × Ẽᵢ) is within
    /// (2U + U² + 2U' + U'²)·(|a||b| + |c||d|) ≤ 4.0001U·(|a||b| + |c||d|) of exact (the two
    /// products' input errors and three roundings), and all three together within
    /// 4.0001U·‖p̃ⱼ‖₁‖Ẽᵢ‖₁ (plus 2⁻¹⁵⁰ per product in the subnormal range). The f32 dot
    /// product with d adds γ₃·Σₖ|dₖ||ñᵢₖ|, so |ẽᵢ − eᵢ| ≤ Kᵢ·max|dₖ| with
    /// Kᵢ = 4.0002U·Σₖ|ñᵢₖ| + 4.002U·‖p̃ⱼ‖₁‖Ẽᵢ‖₁ + 3·10⁻⁴⁴. Ñ = fl(Ẽ₁ × Ẽ₂) likewise
    /// (k_det), and ñum = fl(p̃₀·Ñ) is within
    /// 5.0003U·Σₖ|p̃₀ₖÑₖ| + max|p̃₀ₖ|·(4.002U·‖Ẽ₁‖₁‖Ẽ₂‖₁ + 3·10⁻⁴⁴) + 10⁻⁴³ of
    /// det[p₀, p₁, p₂]. The bounds' own roundings (at most 7 in a chain, all of positive
    /// terms) are covered by the factor 1 + 10⁻⁶. Coordinates of p̃ and Ẽ must stay below
    /// 10¹⁸ (every product within f32's range), else the triangle is unusable.
    ///
    /// Written into `out`: a frame's cache has its blocks written in place
    /// ([`super::prepared::Claim`]).
    ///
    /// [`super::prepared::Claim`]: crate::accel::prepared::Claim
    #[inline(always)]
    pub(crate) fn new8<V: Lanes>(
        v: [&[[f32; 3]; 3]; 8],
        o: [f32; 3],
        prim: [u32; 8],
        out: &mut OriginBlock,
    ) {
        Self::new8_from::<V>(&v, o, prim, out)
    }

    /// [`OriginTriangle::new8`] of the triangles `v` holds.
    #[inline(always)]
    pub(crate) fn new8_from<V: Lanes>(
        v: &impl TriangleLanes,
        o: [f32; 3],
        prim: [u32; 8],
        out: &mut OriginBlock,
    ) {
        #[inline(always)]
        fn coordinate<V: Lanes>(v: &impl TriangleLanes, j: usize, k: usize) -> V {
            V::from_array([
                v.coordinate(0, j, k),
                v.coordinate(1, j, k),
                v.coordinate(2, j, k),
                v.coordinate(3, j, k),
                v.coordinate(4, j, k),
                v.coordinate(5, j, k),
                v.coordinate(6, j, k),
                v.coordinate(7, j, k),
            ])
        }
        #[inline(always)]
        fn vertex<V: Lanes>(v: &impl TriangleLanes, j: usize) -> [V; 3] {
            [
                coordinate(v, j, 0),
                coordinate(v, j, 1),
                coordinate(v, j, 2),
            ]
        }
        let w = [vertex::<V>(v, 0), vertex(v, 1), vertex(v, 2)];
        Self::new8_from_lanes(w, o, prim, out)
    }

    /// [`OriginTriangle::new8`] of the triangles whose vertex j, coordinate k, is lane l of
    /// `w[j][k]` (for vertices computed in lanes: instances' world triangles).
    #[inline(always)]
    pub(crate) fn new8_from_lanes<V: Lanes>(
        w: [[V; 3]; 3],
        o: [f32; 3],
        prim: [u32; 8],
        out: &mut OriginBlock,
    ) {
        const U: f32 = 1.0 / (1u32 << 24) as f32;
        const MARGIN: f32 = 1.0 + 1e-6;
        const BIG: f32 = 1e18;
        // (Helpers as always-inlined items, not closures: see `new4`.)
        #[inline(always)]
        fn c<V: Lanes>(x: f32) -> V {
            V::splat(x)
        }
        #[inline(always)]
        fn abs_sum<V: Lanes>(x: [V; 3]) -> V {
            x[0].abs() + x[1].abs() + x[2].abs()
        }
        /// The largest |xₖ| (a NaN may be dropped: it reaches `num` and fails there).
        #[inline(always)]
        fn abs_max<V: Lanes>(x: [V; 3]) -> V {
            x[0].abs().fast_max(x[1].abs()).fast_max(x[2].abs())
        }
        /// Kᵢ from Σₖ|ñᵢₖ| and the 1-norms of the cross product's factors.
        #[inline(always)]
        fn k_of<V: Lanes>(s: V, a: V, b: V) -> V {
            (c::<V>(4.0002 * U) * s + c::<V>(4.002 * U) * (a * b) + c(3e-44)) * c(MARGIN)
        }
        #[inline(always)]
        fn lanes3<V: Lanes>(x: [V; 3]) -> [[f32; 8]; 3] {
            [x[0].to_array(), x[1].to_array(), x[2].to_array()]
        }
        let o = [c::<V>(o[0]), c(o[1]), c(o[2])];
        let p = [sub(w[0], o), sub(w[1], o), sub(w[2], o)];
        let e = [sub(w[2], w[1]), sub(w[0], w[2]), sub(w[1], w[0])];
        let n = [cross(p[1], e[0]), cross(p[2], e[1]), cross(p[0], e[2])];
        let normal = cross(e[1], e[2]);
        let p1 = [abs_sum(p[0]), abs_sum(p[1]), abs_sum(p[2])];
        let e1 = [abs_sum(e[0]), abs_sum(e[1]), abs_sum(e[2])];
        let s = [abs_sum(n[0]), abs_sum(n[1]), abs_sum(n[2])];
        let k = [
            k_of(s[0], p1[1], e1[0]),
            k_of(s[1], p1[2], e1[1]),
            k_of(s[2], p1[0], e1[2]),
        ];
        let k_sum = (k[0] + k[1] + k[2]) * c(MARGIN);
        let k_det = k_of(abs_sum(normal), e1[1], e1[2]);
        let terms = [
            p[0][0] * normal[0],
            p[0][1] * normal[1],
            p[0][2] * normal[2],
        ];
        let num = terms[0] + terms[1] + terms[2];
        let p0_max = abs_max(p[0]);
        let num_err = (c::<V>(5.0003 * U) * abs_sum(terms)
            + p0_max * (c::<V>(4.002 * U) * (e1[1] * e1[2]) + c(3e-44))
            + c(1e-43))
            * c(MARGIN);
        let r_num = num_err / num.abs();
        // As in `new`: the bound of `PacketNearest`, and 2U for the rounding of t̃ ± it.
        let c_t = (c::<V>(1.4) * (r_num + c(2.1 * U)) + c(6.0 * U)) * c(MARGIN);
        let n_max = s[0].fast_max(s[1]).fast_max(s[2]);
        // det's sign certain and its relative error at most 1/2 (a NaN anywhere reaches num,
        // which involves every coordinate, and fails the comparison); p̃ and Ẽ below 10¹⁸.
        let big = c::<V>(BIG);
        let p_max = p0_max.fast_max(abs_max(p[1])).fast_max(abs_max(p[2]));
        let e_max = abs_max(e[0])
            .fast_max(abs_max(e[1]))
            .fast_max(abs_max(e[2]));
        #[inline(always)]
        fn finite<V: Lanes>(x: V) -> V {
            x.abs().simd_lt(c(f32::INFINITY))
        }
        let usable = num.abs().simd_gt(c::<V>(2.0) * num_err)
            & p_max.simd_lt(big)
            & e_max.simd_lt(big)
            & finite(k_sum)
            & finite(k_det);
        *out = OriginBlock {
            n: [lanes3(n[0]), lanes3(n[1]), lanes3(n[2])],
            k: lanes3(k),
            k_sum: k_sum.to_array(),
            k_det: k_det.to_array(),
            n_max: n_max.to_array(),
            num: num.to_array(),
            c_t: c_t.to_array(),
            normal: lanes3(normal),
            prim,
            det_from_normal: k_sum.simd_gt(c::<V>(4.0) * k_det).to_bitmask(),
            usable: usable.to_bitmask(),
        };
    }
}
