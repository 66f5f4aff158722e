//! Triangles prepared for one origin in f64: one at a time ([`OriginTriangle::new`];
//! [`PreciseTriangle`] keeps the f64 quantities for the lanes the f32 rounding leaves
//! undecided), four at a time in f64 lanes ([`OriginTriangle::new4`], [`OriginQuad`]), and a
//! frame's lists of them ([`OriginTriangles`]). Apart from the queries: this is where the
//! bounds they rely on are derived.

use super::{cross, sub, OriginTriangle, MAX_MAGNITUDE, TINY64, U32, U64};
use crate::accel::IndexedTriangle;
use crate::geometry::adaptive::{round_down, round_up};
use crate::geometry::exact::on_plane;
use crate::math::lanes::{Lanes, Lanes64};
use crate::math::simd::{avx512_avx2_or_baseline, each3, with_cpu_isa, with_isa, Chosen, Isa};
use rayon::prelude::*;

/// A frame's triangles prepared for its camera position.
#[derive(Clone, Debug, Default)]
pub struct OriginTriangles {
    /// In the order given.
    pub tris: Vec<OriginTriangle>,
    /// The origin they were prepared for.
    pub origin: [f32; 3],
}

impl OriginTriangle {
    /// Prepares triangle `v` for rays from `o` (about 365 instructions; the frame's lists
    /// prepare four at a time with `OriginTriangle::new4`, the BVH leaves eight at a time in
    /// f32 with `OriginTriangle::new8`).
    ///
    /// The edge functions are taken as eᵢ = d·(pⱼ × Eᵢ) with the edge Eᵢ = vₖ − vⱼ (exactly
    /// d·(pⱼ × pₖ), as pₖ = pⱼ + Eᵢ), the normal as N = E₁ × E₂ (= (v₁ − v₀) × (v₂ − v₀)) and
    /// det[p₀, p₁, p₂] as p₀·N, all in f64. Bounds, with u = 2⁻⁵³, U = 2⁻²⁴, m ≥ every |pᵢₖ|
    /// and e ≥ every |Eᵢₖ|: p and E are within u of exact per component, so each component
    /// of a cross product pⱼ × Eᵢ is within 2·3.0001u·m·e + 2.0001u·m·e ≤ 8.0004u·m·e of
    /// exact (8.0004u·e² for N); rounding it to f32 adds 1.0001U·|ñ| + 2⁻¹⁴⁹ and the f32 dot
    /// product with d adds γ₃·Σ|dₖ||ñₖ|, so |ẽᵢ − eᵢ| ≤ Kᵢ·max|dₖ| with
    /// Kᵢ = 4.0002U·Σₖ|ñᵢₖ| + 3·8.0004u·m·e + 3·2⁻¹⁴⁹. p₀·N is within
    /// 4.0002u·m·|N|₁ + 3m·8.0004u·e² of exact before its rounding to f32. The bounds' own
    /// roundings are covered by a factor 1 + 10⁻⁶. The rounding of p and E scales with the
    /// triangle's size and distance (m·e), not the distance squared: small far triangles
    /// keep tight bounds.
    #[inline]
    pub fn new(v: &[[f32; 3]; 3], o: [f32; 3], prim: u32) -> Self {
        PreciseTriangle::new(v, o, prim).rounded
    }
}

/// A triangle prepared for one origin as [`OriginTriangle::new`] prepares it (which rounds
/// this to f32), its f64 quantities kept with their bounds: for the lanes that rounding
/// leaves undecided ([`PacketNearest::offer_precise`]). The nᵢ rounded to f32 bound each eᵢ
/// to about 4U·|nᵢ|·|d|; for a triangle small and far from the origin, eᵢ is small against
/// |nᵢ|·|d| (about (offset from the edge) / distance), so rays of a far bunny's pixels fell
/// within that bound of some edge, 0.5% of a field frame's camera rays, and were traced per
/// ray (5% of the frame). In f64 the bound is about 2⁻²⁹ as wide.
///
/// [`PacketNearest::offer_precise`]: super::PacketNearest::offer_precise
#[derive(Clone, Copy, Debug)]
pub(crate) struct PreciseTriangle {
    /// nᵢ = pⱼ × Eᵢ in f64.
    n: [[f64; 3]; 3],
    /// The bound on each component of `n`'s error (8.0004u·m·e, see [`OriginTriangle::new`]).
    n_err: f64,
    /// N = E₁ × E₂ in f64.
    normal: [f64; 3],
    /// The bound on each component of `normal`'s error (8.0004u·e²).
    normal_err: f64,
    /// det[p₀, p₁, p₂] = p₀·N in f64.
    num: f64,
    /// The bound on `num`'s error.
    num_err: f64,
    /// Whether the f64 test can be used: `num`'s sign certain, magnitudes finite.
    pub(super) usable: bool,
    /// The same triangle rounded to f32 ([`OriginTriangle::new`]).
    pub(crate) rounded: OriginTriangle,
}

impl PreciseTriangle {
    /// Where the ray from the origin along `d` (f32 components) meets the triangle, decided
    /// in f64 (`tri` usable): `Some(None)` where it certainly misses it or meets it behind
    /// the origin, `Some(Some((lo, hi)))` where it certainly crosses it in front with the
    /// exact t in [lo, hi] (f32), `None` where f64 cannot tell (within rounding of an edge,
    /// or det too uncertain).
    ///
    /// With u = 2⁻⁵³: eᵢ = d·ñᵢ in f64 is within 3.0001u·Σₖ|dₖñᵢₖ| (the dot product) plus
    /// `n_err`·Σₖ|dₖ| (ñ's own error) of d·nᵢ, d being exact in f64; det = d·Ñ likewise with
    /// `normal_err`, so r_det = its bound / |det̃|, kept ≤ 1/4; num's relative error is
    /// r_num = `num_err`/|ñum|. Then t̃ = ñum/det̃ is within
    /// |t̃|·(1.4·(r_num + r_det) + 4u) of t (as [`PacketNearest`] derives it, with u for U),
    /// and 2u more covers the rounding of t̃ ± that before it is rounded outward to f32.
    ///
    /// [`PacketNearest`]: super::PacketNearest
    #[cold]
    #[inline(never)]
    pub(super) fn crossing(&self, d: [f32; 3]) -> Option<Option<(f32, f32)>> {
        const MARGIN: f64 = 1.0 + 1e-6;
        let d = d.map(f64::from);
        let d_sum = d[0].abs() + d[1].abs() + d[2].abs();
        // The dot product with d and its bound (`err`: each component's).
        let dot = |n: &[f64; 3], err: f64| {
            let value = d[0] * n[0] + d[1] * n[1] + d[2] * n[2];
            let size = (d[0] * n[0]).abs() + (d[1] * n[1]).abs() + (d[2] * n[2]).abs();
            (value, (3.0001 * U64 * size + err * d_sum) * MARGIN + TINY64)
        };
        let (mut pos, mut neg) = (0, 0);
        for (i, n) in self.n.iter().enumerate() {
            let (e, bound) = dot(n, self.n_err);
            pos |= ((e > bound) as u32) << i;
            neg |= ((e < -bound) as u32) << i;
        }
        if pos != 0 && neg != 0 {
            return Some(None);
        }
        if pos | neg != 0b111 {
            return None;
        }
        // In front where the eᵢ's sign (det's) is the numerator's.
        if (pos == 0b111) != (self.num > 0.0) {
            return Some(None);
        }
        let (det, det_err) = dot(&self.normal, self.normal_err);
        let r_det = det_err / det.abs();
        if r_det.is_nan() || r_det > 0.25 {
            return None;
        }
        let r_num = self.num_err / self.num.abs();
        let t = self.num / det;
        let err = t.abs() * (1.4 * (r_num + r_det) + 6.0 * U64) * MARGIN + TINY64;
        Some(Some((round_down(t - err), round_up(t + err))))
    }

    /// [`OriginTriangle::new`], its f64 quantities kept.
    #[inline]
    pub(crate) fn new(v: &[[f32; 3]; 3], o: [f32; 3], prim: u32) -> Self {
        const TINY: f64 = 3.0 * 1.5e-45;
        const MARGIN: f64 = 1.0 + 1e-6;
        // (Helpers as always-inlined items without iterators: as closures over iterators
        // their code came and went with unrelated changes elsewhere, +21% instructions once.)
        #[inline(always)]
        fn widen(x: [f32; 3]) -> [f64; 3] {
            [f64::from(x[0]), f64::from(x[1]), f64::from(x[2])]
        }
        /// The largest |xᵢₖ| (a NaN never replaces the maximum so far).
        #[inline(always)]
        fn abs_max(x: &[[f64; 3]; 3]) -> f64 {
            let mut acc = 0f64;
            for row in x {
                for c in row {
                    if c.abs() > acc {
                        acc = c.abs();
                    }
                }
            }
            acc
        }
        let w = [widen(v[0]), widen(v[1]), widen(v[2])];
        let o = widen(o);
        let p = [sub(w[0], o), sub(w[1], o), sub(w[2], o)];
        let e = [sub(w[2], w[1]), sub(w[0], w[2]), sub(w[1], w[0])];
        let n64 = [cross(p[1], e[0]), cross(p[2], e[1]), cross(p[0], e[2])];
        let normal64 = cross(e[1], e[2]);
        let m = abs_max(&p) * (1.0 + 2.0 * U64);
        let me = abs_max(&e) * (1.0 + 2.0 * U64);
        // (`each3`, not array `map`: in the AVX2 build, where the packets prepare triangles as
        // they meet them, `map` stayed a call.)
        let n = each3(|i| each3(|k| n64[i][k] as f32));
        let normal = each3(|k| normal64[k] as f32);
        let abs_sum = |x: [f32; 3]| x[0].abs() as f64 + x[1].abs() as f64 + x[2].abs() as f64;
        let s = each3(|i| abs_sum(n[i]));
        let n_err = 3.0 * 8.0004 * U64 * m * me + TINY;
        let k = each3(|i| ((4.0002 * U32 * s[i] + n_err) * MARGIN) as f32);
        let k_sum = ((k[0] as f64 + k[1] as f64 + k[2] as f64) * MARGIN) as f32;
        let k_det = ((4.0002 * U32 * abs_sum(normal) + 3.0 * 8.0004 * U64 * me * me + TINY)
            * MARGIN) as f32;
        let num64 = p[0][0] * normal64[0] + p[0][1] * normal64[1] + p[0][2] * normal64[2];
        let normal_abs = normal64[0].abs() + normal64[1].abs() + normal64[2].abs();
        let num = num64 as f32;
        let num_err = (4.0002 * U64 * m * normal_abs + 3.0 * 8.0004 * U64 * m * me * me) * MARGIN
            + U32 * num64.abs()
            + 1.5e-45;
        let r_num = num_err / (num as f64).abs();
        // See `PacketNearest`: |t̃ − t| ≤ |t̃|·(1.4·(r_num + 2.1·u) + 4u + 1.4·ΣK·max|d|/|det̃|),
        // and 2u more for the rounding of t̃ ± that.
        let c_t = (1.4 * (r_num + 2.1 * U32) + 6.0 * U32) as f32;
        let n_max = s[0].max(s[1]).max(s[2]);
        // The sign of det must be certain and its relative error at most 1/2; magnitudes far
        // from overflow. A NaN anywhere reaches num64 (p₀·N involves every vertex and the
        // origin) and fails the comparisons.
        let usable = (num as f64).abs() > 2.0 * num_err
            && num64.abs() < MAX_MAGNITUDE
            && m < MAX_MAGNITUDE
            && me < MAX_MAGNITUDE
            && n_max < MAX_MAGNITUDE
            && k_sum.is_finite()
            && k_det.is_finite();
        let rounded = OriginTriangle {
            n,
            k,
            k_sum,
            det_from_normal: k_sum > 4.0 * k_det,
            n_max: n_max as f32,
            num,
            c_t,
            normal,
            k_det,
            prim,
            usable,
            in_plane: false,
        };
        let num_err64 =
            (4.0002 * U64 * m * normal_abs + 3.0 * 8.0004 * U64 * m * me * me) * MARGIN + TINY64;
        let mut precise = Self {
            n: n64,
            n_err: 8.0004 * U64 * m * me * MARGIN + TINY64,
            normal: normal64,
            normal_err: 8.0004 * U64 * me * me * MARGIN + TINY64,
            num: num64,
            num_err: num_err64,
            // (NaN anywhere reaches num64 and fails the first comparison.)
            usable: num64.abs() > 2.0 * num_err64
                && num64.abs() < MAX_MAGNITUDE
                && m < MAX_MAGNITUDE
                && me < MAX_MAGNITUDE,
            rounded,
        };
        if !precise.usable {
            precise.rounded.in_plane = in_plane(v, o);
        }
        precise
    }
}

impl OriginTriangle {
    /// [`OriginTriangle::new`] for four triangles at once, lane by lane in `D` (the same
    /// operations in the same order: the same bits, as this file's unit tests check).
    #[inline(always)]
    pub(crate) fn new4<D: Lanes64>(
        v: [&[[f32; 3]; 3]; 4],
        o: [f32; 3],
        prim: [u32; 4],
    ) -> OriginQuad {
        const TINY: f64 = 3.0 * 1.5e-45;
        const MARGIN: f64 = 1.0 + 1e-6;
        // (Helpers as always-inlined items, not closures: a closure is compiled apart from
        // the AVX2 kernel that calls it, and its lane operations stayed calls.)
        #[inline(always)]
        fn c<D: Lanes64>(x: f64) -> D {
            D::splat(x)
        }
        #[inline(always)]
        fn vertex<D: Lanes64>(v: &[&[[f32; 3]; 3]; 4], j: usize) -> [D; 3] {
            [
                coordinate(v, j, 0),
                coordinate(v, j, 1),
                coordinate(v, j, 2),
            ]
        }
        #[inline(always)]
        fn coordinate<D: Lanes64>(v: &[&[[f32; 3]; 3]; 4], j: usize, k: usize) -> D {
            D::from_array([
                f64::from(v[0][j][k]),
                f64::from(v[1][j][k]),
                f64::from(v[2][j][k]),
                f64::from(v[3][j][k]),
            ])
        }
        #[inline(always)]
        fn f32s<D: Lanes64>(x: [D; 3]) -> [[f32; 4]; 3] {
            [x[0].to_f32(), x[1].to_f32(), x[2].to_f32()]
        }
        #[inline(always)]
        fn k_of<D: Lanes64>(s: D, n_err: D) -> D {
            ((c::<D>(4.0002 * U32) * s + n_err) * c(MARGIN)).round_f32()
        }
        /// As `abs_max` in `new`: a lane's maximum so far is replaced only by a larger |x|.
        #[inline(always)]
        fn abs_max<D: Lanes64>(x: &[[D; 3]; 3]) -> D {
            let mut acc = D::splat(0.0);
            for row in x {
                for x in row {
                    acc = x.abs().fast_max(acc);
                }
            }
            acc
        }
        #[inline(always)]
        fn round3<D: Lanes64>(x: [D; 3]) -> [D; 3] {
            [x[0].round_f32(), x[1].round_f32(), x[2].round_f32()]
        }
        #[inline(always)]
        fn abs_sum<D: Lanes64>(x: [D; 3]) -> D {
            x[0].abs() + x[1].abs() + x[2].abs()
        }
        let w = [vertex::<D>(&v, 0), vertex(&v, 1), vertex(&v, 2)];
        let o = [c::<D>(o[0].into()), c(o[1].into()), c(o[2].into())];
        let p = [sub(w[0], o), sub(w[1], o), sub(w[2], o)];
        let e = [sub(w[2], w[1]), sub(w[0], w[2]), sub(w[1], w[0])];
        let n64 = [cross(p[1], e[0]), cross(p[2], e[1]), cross(p[0], e[2])];
        let normal64 = cross(e[1], e[2]);
        let m = abs_max(&p) * c(1.0 + 2.0 * U64);
        let me = abs_max(&e) * c(1.0 + 2.0 * U64);
        // n and normal rounded to f32 (and back: the sums below are of the f32 values).
        let n = [round3(n64[0]), round3(n64[1]), round3(n64[2])];
        let normal = round3(normal64);
        let s = [abs_sum(n[0]), abs_sum(n[1]), abs_sum(n[2])];
        let n_err = c::<D>(3.0 * 8.0004 * U64) * m * me + c(TINY);
        let k = [k_of(s[0], n_err), k_of(s[1], n_err), k_of(s[2], n_err)];
        let k_sum = ((k[0] + k[1] + k[2]) * c(MARGIN)).to_f32();
        let k_det = ((c::<D>(4.0002 * U32) * abs_sum(normal)
            + c::<D>(3.0 * 8.0004 * U64) * me * me
            + c(TINY))
            * c(MARGIN))
        .to_f32();
        let num64 = p[0][0] * normal64[0] + p[0][1] * normal64[1] + p[0][2] * normal64[2];
        let normal_abs = abs_sum(normal64);
        let num = num64.round_f32();
        let num_err = (c::<D>(4.0002 * U64) * m * normal_abs
            + c::<D>(3.0 * 8.0004 * U64) * m * me * me)
            * c(MARGIN)
            + c::<D>(U32) * num64.abs()
            + c(1.5e-45);
        let r_num = num_err / num.abs();
        let c_t = (c::<D>(1.4) * (r_num + c(2.1 * U32)) + c(6.0 * U32)).to_f32();
        let n_max = s[0].max(s[1]).max(s[2]);
        let big = c::<D>(MAX_MAGNITUDE);
        let fits = num.abs().simd_gt(c::<D>(2.0) * num_err)
            & num64.abs().simd_lt(big)
            & m.simd_lt(big)
            & me.simd_lt(big)
            & n_max.simd_lt(big);
        let fits = fits.to_bitmask();
        let mut det_from_normal = 0;
        let mut usable = 0;
        for l in 0..4 {
            det_from_normal |= ((k_sum[l] > 4.0 * k_det[l]) as u32) << l;
            let finite = k_sum[l].is_finite() && k_det[l].is_finite();
            usable |= ((fits & (1 << l) != 0 && finite) as u32) << l;
        }
        OriginQuad {
            n: [f32s(n[0]), f32s(n[1]), f32s(n[2])],
            k: f32s(k),
            k_sum,
            k_det,
            n_max: n_max.to_f32(),
            num: num.to_f32(),
            c_t,
            normal: f32s(normal),
            prim,
            det_from_normal,
            usable,
        }
    }
}

/// Four triangles prepared for one origin ([`OriginTriangle::new4`]) field by field, as
/// their lanes leave them: one store per field rather than one per field and lane (for these
/// f64 quads about 1% of a frame, against 4/5 of the f32 preparation's instructions, see
/// `new8`). Read a triangle at a time ([`OriginQuad::get`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct OriginQuad {
    n: [[[f32; 4]; 3]; 3],
    k: [[f32; 4]; 3],
    k_sum: [f32; 4],
    k_det: [f32; 4],
    n_max: [f32; 4],
    num: [f32; 4],
    c_t: [f32; 4],
    normal: [[f32; 4]; 3],
    prim: [u32; 4],
    /// Bit l: lane l's `det_from_normal`.
    det_from_normal: u32,
    /// Bit l: lane l's `usable`.
    usable: u32,
}

/// Lane `l`'s triangle of an [`OriginQuad`] or [`OriginBlock`] (`l` masked to the width:
/// no bounds check per field).
///
/// [`OriginBlock`]: super::OriginBlock
macro_rules! lane_of {
    ($s:expr, $l:expr, $width:expr) => {{
        let (s, l) = ($s, $l & ($width - 1));
        let n = &s.n;
        OriginTriangle {
            n: [
                [n[0][0][l], n[0][1][l], n[0][2][l]],
                [n[1][0][l], n[1][1][l], n[1][2][l]],
                [n[2][0][l], n[2][1][l], n[2][2][l]],
            ],
            k: [s.k[0][l], s.k[1][l], s.k[2][l]],
            k_sum: s.k_sum[l],
            det_from_normal: s.det_from_normal & (1 << l) != 0,
            n_max: s.n_max[l],
            num: s.num[l],
            c_t: s.c_t[l],
            normal: [s.normal[0][l], s.normal[1][l], s.normal[2][l]],
            k_det: s.k_det[l],
            prim: s.prim[l],
            usable: s.usable & (1 << l) != 0,
            in_plane: false,
        }
    }};
}

pub(super) use lane_of;

impl OriginQuad {
    /// Lane `l`'s triangle (`l` < 4).
    #[inline(always)]
    pub(crate) fn get(&self, l: usize) -> OriginTriangle {
        debug_assert!(l < 4);
        lane_of!(self, l, 4)
    }
}

impl OriginTriangles {
    /// Prepares `tris` for rays from `origin` (in parallel for large meshes).
    pub fn new(tris: &[IndexedTriangle], origin: [f32; 3]) -> Self {
        Self::new_in(Chosen::now(), tris, origin)
    }

    /// [`OriginTriangles::new`] in the build a frame chose ([`Chosen`]) (one copy of the
    /// preparation for both, each of whose three builds holds a parallel loop).
    pub(crate) fn new_in(build: Chosen, tris: &[IndexedTriangle], origin: [f32; 3]) -> Self {
        let get = |i: usize| (&tris[i].0, tris[i].1);
        with_isa!(build, |isa| Self::prepare_in(isa, tris.len(), &get, origin))
    }

    /// [`OriginTriangles::new`] for vertices and primitive indices held apart (a BVH's).
    pub fn from_parts(vertices: &[[[f32; 3]; 3]], prims: &[u32], origin: [f32; 3]) -> Self {
        assert_eq!(vertices.len(), prims.len());
        Self::prepare(vertices.len(), |i| (&vertices[i], prims[i]), origin)
    }

    /// Four at a time ([`OriginTriangle::new4`] in the build's f64 lanes: about 145
    /// instructions per triangle under AVX2 with the collection, against 365 one by one,
    /// callgrind), in parallel for large meshes.
    pub(crate) fn prepare<'a>(
        n: usize,
        get: impl Fn(usize) -> (&'a [[f32; 3]; 3], u32) + Sync,
        origin: [f32; 3],
    ) -> Self {
        with_cpu_isa!(|isa| Self::prepare_in(isa, n, &get, origin))
    }

    /// [`OriginTriangles::prepare`] in the build `isa` names.
    fn prepare_in<'a, I: Isa>(
        isa: I,
        n: usize,
        get: &(impl Fn(usize) -> (&'a [[f32; 3]; 3], u32) + Sync),
        origin: [f32; 3],
    ) -> Self {
        let quad = |q: usize| {
            let [i0, i1, i2, i3] = quad_indices(4 * q, n);
            let (a, b, c, d) = (get(i0), get(i1), get(i2), get(i3));
            let v = [a.0, b.0, c.0, d.0];
            let mut quad = prepare4_in(isa, v, origin, [a.1, b.1, c.1, d.1]);
            for (tri, v) in quad.iter_mut().zip(v) {
                if !tri.usable {
                    tri.in_plane = in_plane(v, origin.map(f64::from));
                }
            }
            quad
        };
        let quads: Vec<[OriginTriangle; 4]> = if n >= 4096 {
            (0..n.div_ceil(4)).into_par_iter().map(quad).collect()
        } else {
            (0..n.div_ceil(4)).map(quad).collect()
        };
        let mut tris = quads.into_flattened();
        tris.truncate(n);
        Self { tris, origin }
    }
}

/// Whether `o` lies exactly in the plane of triangle `v` (false where that cannot be told:
/// coordinates whose differences f64 does not hold exactly).
#[cold]
#[inline(never)]
fn in_plane(v: &[[f32; 3]; 3], o: [f64; 3]) -> bool {
    on_plane(v, o) == Some(true)
}

/// The four positions `start..start + 4` of a quad of triangles ending at `end` (exclusive,
/// > `start`): a short quad repeats its last triangle, which is prepared and never used.
#[inline(always)]
pub(crate) fn quad_indices(start: usize, end: usize) -> [usize; 4] {
    let last = end - 1;
    [
        start,
        (start + 1).min(last),
        (start + 2).min(last),
        (start + 3).min(last),
    ]
}

/// Four triangles prepared for `o` ([`OriginTriangle::new4`]) in the f64 lanes of the build
/// `isa` names.
#[inline(always)]
fn prepare4_in<I: Isa>(
    isa: I,
    v: [&[[f32; 3]; 3]; 4],
    o: [f32; 3],
    prim: [u32; 4],
) -> [OriginTriangle; 4] {
    avx512_avx2_or_baseline!(token isa, lanes prepare4_body => (
        v: [&[[f32; 3]; 3]; 4],
        o: [f32; 3],
        prim: [u32; 4]
    ) -> [OriginTriangle; 4])
}

#[inline(always)]
fn prepare4_body<V: Lanes>(
    v: [&[[f32; 3]; 3]; 4],
    o: [f32; 3],
    prim: [u32; 4],
) -> [OriginTriangle; 4] {
    let quad = OriginTriangle::new4::<V::F64>(v, o, prim);
    [quad.get(0), quad.get(1), quad.get(2), quad.get(3)]
}
