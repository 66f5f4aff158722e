//! The adaptive method's fast paths for the renderer: camera rays in packets of 8 against
//! triangles prepared for the camera's position ([`closest`]; per ray in BVH leaves:
//! [`OriginTriangle::estimate`]), and shadow rays from the light in packets of 8
//! ([`shadow_from_origin`]: the same test for the light's position).
//!
//! All camera rays of a frame leave the same origin o. With pᵢ = vᵢ − o, the exact
//! predicates of the adaptive method are the signs of eᵢ = d·(pⱼ × pₖ) ((i, j, k) cyclic; eᵢ
//! weighs vertex i) and t = det[p₀, p₁, p₂] / (e₀ + e₁ + e₂). The cross products and the
//! determinant depend on the triangle alone, so they are computed once per frame with bounds
//! on their error: in f64 for a frame's lists ([`OriginTriangles::new`]), in f32 for a BVH's
//! leaves (`OriginTriangle::new8`, bounds about twice as loose; a triangle those leave
//! undecided for a live lane is prepared again in f64, [`PacketNearest::offer_decided`]);
//! per ray and triangle there remain three f32 dot products, whose rounding error is at most
//! Kᵢ·max|dₖ| with Kᵢ fixed per triangle. An eᵢ beyond that bound has a certain sign, t
//! comes with a certain interval, and a lane keeps the nearest candidate only while its
//! interval lies wholly below the others'. Every lane that cannot be decided so (a ray
//! within rounding of an edge, two hits too close to order, a degenerate case) is reported
//! `ambiguous`, and the caller traces it with the per-ray adaptive search, which decides
//! exactly. So a decided lane's primitive is exactly the one the per-ray search returns.

use super::IndexedTriangle;
use crate::geometry::adaptive::{round_down, round_up, Approx, Estimate};
use crate::geometry::exact;
use crate::math::lanes::{f32x8, LaneOps, Lanes, Lanes64};
use crate::math::simd::{avx2_or_baseline, each3};
use rayon::prelude::*;
use std::cmp::Ordering;
use std::ops::{Mul, Sub};

/// Unit roundoff of f32 and f64.
const U32: f64 = 1.0 / (1u64 << 24) as f64;
const U64: f64 = 1.0 / (1u64 << 53) as f64;

/// Largest |nₖ| sum (and |det|) prepared: larger ones make every ray ambiguous.
const MAX_MAGNITUDE: f64 = 1e36;

/// Absolute slack of the f64 bounds ([`PreciseTriangle`]): products in f64's subnormal range
/// and the bounds' own roundings there (far below any value they decide).
const TINY64: f64 = 1e-300;

/// Largest max|dₖ|·Σ|nₖ| a packet may reach (far from f32 overflow).
const MAX_PRODUCT: f32 = 1e37;

/// Absolute part of each edge bound: the dot product's products in the subnormal range
/// (2^-150 each) and the rounding of Kᵢ·max|d| there.
const EDGE_ABS: f32 = 1e-44;

/// One triangle seen from the shared origin.
#[derive(Clone, Copy, Debug)]
pub struct OriginTriangle {
    /// nᵢ = pⱼ × pₖ rounded to f32, so that eᵢ = d·nᵢ.
    n: [[f32; 3]; 3],
    /// Kᵢ: |computed eᵢ − exact eᵢ| ≤ Kᵢ·max|dₖ| + [`EDGE_ABS`] (rounding up included).
    k: [f32; 3],
    /// K₀ + K₁ + K₂.
    k_sum: f32,
    /// Whether t's determinant is taken as d·normal (bound `k_det`) rather than as
    /// e₀ + e₁ + e₂ (bound `k_sum`): where the sum's bound is the looser by more than 4×,
    /// a small triangle far from the origin (see [`t_interval`]).
    det_from_normal: bool,
    /// The largest Σₖ|nᵢₖ|, for the overflow check.
    n_max: f32,
    /// det[p₀, p₁, p₂] rounded to f32 (its sign is certain).
    num: f32,
    /// Relative error coefficient of t apart from the determinant's part.
    c_t: f32,
    /// The normal (v₁ − v₀) × (v₂ − v₀) rounded to f32: d·n is the determinant of t without
    /// the cancellation of e₀ + e₁ + e₂ (for a small triangle far from the origin the eᵢ are
    /// large and their sum small).
    normal: [f32; 3],
    /// |computed d·normal − exact| ≤ k_det·max|dₖ| + [`EDGE_ABS`].
    k_det: f32,
    /// Primitive index in the scene.
    pub prim: u32,
    /// False where the bounds cannot be used (the origin within rounding of the triangle's
    /// plane, huge magnitudes, non-finite input): every ray is then ambiguous.
    usable: bool,
}

/// A frame's triangles prepared for its camera position.
#[derive(Clone, Debug, Default)]
pub struct OriginTriangles {
    /// In the order given.
    pub tris: Vec<OriginTriangle>,
    /// The origin they were prepared for.
    pub origin: [f32; 3],
}

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

/// a − b, for the preparations' f64, f64-lane and f32-lane arithmetic alike (always inlined:
/// in the AVX2 kernels a call would leave the lane operations as calls too).
#[inline(always)]
fn sub<T: Copy + Sub<Output = T>>(a: [T; 3], b: [T; 3]) -> [T; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// a × b, as [`sub`].
#[inline(always)]
fn cross<T: Copy + Sub<Output = T> + Mul<Output = T>>(a: [T; 3], b: [T; 3]) -> [T; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
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
    usable: bool,
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
    #[cold]
    #[inline(never)]
    fn crossing(&self, d: [f32; 3]) -> Option<Option<(f32, f32)>> {
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
        };
        let num_err64 =
            (4.0002 * U64 * m * normal_abs + 3.0 * 8.0004 * U64 * m * me * me) * MARGIN + TINY64;
        Self {
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
        }
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

/// The ids a block's lanes record in [`PacketNearest::offer_block_to_lane`].
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
#[derive(Clone, Copy, Debug, Default)]
#[repr(C, align(32))]
pub(crate) struct OriginBlock {
    n: [[[f32; 8]; 3]; 3],
    k: [[f32; 8]; 3],
    k_sum: [f32; 8],
    k_det: [f32; 8],
    n_max: [f32; 8],
    num: [f32; 8],
    c_t: [f32; 8],
    normal: [[f32; 8]; 3],
    prim: [u32; 8],
    det_from_normal: u32,
    usable: u32,
}

/// Lane `l`'s triangle of an [`OriginQuad`] or [`OriginBlock`] (`l` masked to the width:
/// no bounds check per field).
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
        }
    }};
}

impl OriginQuad {
    /// Lane `l`'s triangle (`l` < 4).
    #[inline(always)]
    pub(crate) fn get(&self, l: usize) -> OriginTriangle {
        debug_assert!(l < 4);
        lane_of!(self, l, 4)
    }
}

impl OriginBlock {
    /// Lane `l`'s triangle (`l` < 8).
    #[inline(always)]
    pub(crate) fn get(&self, l: usize) -> OriginTriangle {
        debug_assert!(l < 8);
        lane_of!(self, l, 8)
    }

    /// The lanes' primitive indices.
    #[cfg(test)]
    pub(crate) fn prims(&self) -> [u32; 8] {
        self.prim
    }

    #[cfg(test)]
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

impl OriginTriangles {
    /// Prepares `tris` for rays from `origin` (in parallel for large meshes).
    pub fn new(tris: &[IndexedTriangle], origin: [f32; 3]) -> Self {
        Self::prepare(tris.len(), |i| (&tris[i].0, tris[i].1), origin)
    }

    /// [`OriginTriangles::new`] for vertices and primitive indices held apart (a BVH's).
    pub fn from_parts(vertices: &[[[f32; 3]; 3]], prims: &[u32], origin: [f32; 3]) -> Self {
        assert_eq!(vertices.len(), prims.len());
        Self::prepare(vertices.len(), |i| (&vertices[i], prims[i]), origin)
    }

    /// Four at a time ([`OriginTriangle::new4`] in the build's f64 lanes: about 145
    /// instructions per triangle under AVX2 with the collection, against 365 one by one,
    /// callgrind), in parallel for large meshes.
    fn prepare<'a>(
        n: usize,
        get: impl Fn(usize) -> (&'a [[f32; 3]; 3], u32) + Sync,
        origin: [f32; 3],
    ) -> Self {
        let quad = |q: usize| {
            let [i0, i1, i2, i3] = quad_indices(4 * q, n);
            let (a, b, c, d) = (get(i0), get(i1), get(i2), get(i3));
            prepare4([a.0, b.0, c.0, d.0], origin, [a.1, b.1, c.1, d.1])
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

/// Four triangles prepared for `o` ([`OriginTriangle::new4`]) in the CPU's widest lanes.
pub(crate) fn prepare4(v: [&[[f32; 3]; 3]; 4], o: [f32; 3], prim: [u32; 4]) -> [OriginTriangle; 4] {
    avx2_or_baseline!(lanes prepare4_body => (
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

/// The nearest of `tris` along each of 8 directions from their shared origin, for
/// 0 < t < ∞. `d_max` ≥ every |dₖ| of the packet ([`max_component`]); lanes that could
/// overflow (or a NaN direction) are ambiguous. See [`PacketNearest`].
pub fn closest(tris: &[OriginTriangle], d: &[f32x8; 3], d_max: f32) -> PacketHits {
    closest_seeded(tris, d, d_max, None)
}

/// [`closest`] starting from `seed` ([`PacketNearest::seeded`]).
pub fn closest_seeded(
    tris: &[OriginTriangle],
    d: &[f32x8; 3],
    d_max: f32,
    seed: Option<&PacketSeed>,
) -> PacketHits {
    avx2_or_baseline!(lanes closest_body => (
        tris: &[OriginTriangle],
        d: &[f32x8; 3],
        d_max: f32,
        seed: Option<&PacketSeed>
    ) -> PacketHits)
}

/// The exact nearest of `tris` (prepared for origin `o`) along direction `d` for
/// 0 < t < ∞, for a ray the packet kernel left ambiguous: `Some(None)` for a miss,
/// `Some(Some(prim))`, or `None` where this cannot tell (the per-ray search then does).
/// `vertices(prim)` gives a triangle's vertices.
///
/// The kernel's f32 edge tests and t intervals stand where they are certain; an edge sign
/// they leave unsure is computed exactly (expansions, [`exact::orient`]), which settles rays
/// exactly through an edge or vertex. Candidates are ordered by their t intervals where
/// those do not overlap, else by exact plane sides (`nearer`): a quad's two halves (one
/// plane) are hit at the same t, where the lower index wins, as in the per-ray search; of
/// two walls meeting at an edge, the one whose plane the other's crossing point lies behind
/// is nearer. Most ambiguous camera rays of a box-like scene are of those kinds: whole lines
/// of pixel centres run exactly along a wall's diagonal or into the box's corner edges, and
/// the per-ray search costs ~30 times more for each (Cornell box, 1280×720: 160 rays a frame
/// went per ray before the walls' edges were settled here, none now).
///
/// [`exact::orient`]: crate::geometry::exact::orient
pub fn nearest_exact_lane(
    tris: &[OriginTriangle],
    vertices: impl Fn(u32) -> [[f32; 3]; 3],
    o: [f32; 3],
    d: [f32; 3],
) -> Option<Option<u32>> {
    let lane = ExactLane::new(o, d)?;
    // Each triangle certainly hit in front, with its t interval.
    let mut hits: Vec<LaneHit> = Vec::new();
    for tri in tris {
        let v = vertices(tri.prim);
        let (crossing, weighs) = lane.crossing_where(tri, &v)?;
        if crossing != Crossing::Front {
            continue;
        }
        let (lo, hi) = lane.t_interval(tri)?;
        hits.push(LaneHit {
            prim: tri.prim,
            lo,
            hi,
            v,
            weighs,
        });
    }
    let Some(first) = hits.iter().min_by(|a, b| a.hi.total_cmp(&b.hi)) else {
        return Some(None);
    };
    // The nearest of those that may be as near as `first` (the others are certainly
    // farther), ties to the lower index: (t, prim) is a total order, so one pass does.
    let mut best = first;
    for hit in &hits {
        if hit.prim == first.prim || hit.lo > first.hi {
            continue;
        }
        best = match nearer(&lane.o, best, hit)? {
            Ordering::Less => best,
            Ordering::Greater => hit,
            Ordering::Equal if hit.prim < best.prim => hit,
            Ordering::Equal => best,
        };
    }
    Some(Some(best.prim))
}

/// A triangle an ambiguous lane certainly crosses in front ([`nearest_exact_lane`]).
struct LaneHit {
    prim: u32,
    /// Bounds on t.
    lo: f32,
    hi: f32,
    v: [[f32; 3]; 3],
    /// Which vertices weigh in the crossing point ([`ExactLane::crossing_where`]).
    weighs: [bool; 3],
}

/// How `a`'s t compares with `b`'s along the lane from `o` (both crossed in front), exactly,
/// without computing t: `None` where this cannot tell.
///
/// The lane crosses a's plane once, at t_a, with `o` strictly on one side; a point of the
/// lane is on `o`'s side exactly when its t is below t_a. b's crossing point is a mix of
/// b's weighing vertices, so where those lie on one side of a's plane (or on it) so does
/// the point: on `o`'s side, t_b < t_a; on the other, t_b > t_a; on the plane, the same t
/// (a coplanar pair, or a ray through the edge two triangles share). Where b's vertices
/// straddle a's plane, the same with the roles swapped.
fn nearer(o: &[f64; 3], a: &LaneHit, b: &LaneHit) -> Option<Ordering> {
    if let Some(side) = side_of_crossing(b, &a.v)? {
        return Some(compare_from(o, &a.v, side)?.reverse());
    }
    compare_from(o, &b.v, side_of_crossing(a, &b.v)??)
}

/// t of the lane's crossing point on `hit` against t of its crossing with plane `v`, given
/// the side of `v`'s plane that point lies on: `Less` where it is nearer.
fn compare_from(o: &[f64; 3], v: &[[f32; 3]; 3], side: Ordering) -> Option<Ordering> {
    let own = exact::plane_side(v, *o)?;
    match (side, own) {
        (_, Ordering::Equal) => None,
        (Ordering::Equal, _) => Some(Ordering::Equal),
        _ if side == own => Some(Ordering::Less),
        _ => Some(Ordering::Greater),
    }
}

/// The side of plane `v` that `hit`'s crossing point lies on: `Some(None)` where its
/// weighing vertices straddle the plane (the point may lie either side).
fn side_of_crossing(hit: &LaneHit, v: &[[f32; 3]; 3]) -> Option<Option<Ordering>> {
    let mut side = Ordering::Equal;
    for (p, weighs) in hit.v.iter().zip(hit.weighs) {
        if !weighs {
            continue;
        }
        // (A shared vertex is on the plane: the usual case, and the expansions' slowest.)
        let on = match v.contains(p) {
            true => Ordering::Equal,
            false => exact::plane_side(v, p.map(f64::from))?,
        };
        match (side, on) {
            (_, Ordering::Equal) => {}
            (Ordering::Equal, s) => side = s,
            (s, t) if s != t => return Some(None),
            _ => {}
        }
    }
    Some(Some(side))
}

/// Whether the segment from `o` (the origin `tris` were prepared for) to o + d is blocked
/// for 0 < t < 1 by one of `tris` other than `skip`, for a shadow ray
/// [`shadow_from_origin`] left unsure; `None` where this cannot tell (the per-ray search then
/// does). Edge signs as in [`nearest_exact_lane`]; t against 1 by the f32 interval where it
/// decides, else exactly: the end o + d (exact in f64) lies strictly on the other side of
/// the triangle's plane than o. That settles the usual case, the other half of the quad a
/// shadow ray's end point was offset from (t within rounding of 1).
pub fn blocked_exact_lane(
    tris: &[OriginTriangle],
    vertices: impl Fn(u32) -> [[f32; 3]; 3],
    o: [f32; 3],
    d: [f32; 3],
    skip: u32,
) -> Option<bool> {
    let lane = ExactLane::new(o, d)?;
    let mut end = [0.0; 3];
    for ((end, o), d) in end.iter_mut().zip(lane.o).zip(lane.d) {
        let (sum, err) = exact::two_sum(o, d);
        if err != 0.0 {
            return None;
        }
        *end = sum;
    }
    for tri in tris.iter().filter(|t| t.prim != skip) {
        let v = vertices(tri.prim);
        if lane.crossing(tri, &v)? != Crossing::Front {
            continue;
        }
        match lane.t_interval(tri) {
            Some((_, hi)) if hi < 1.0 => return Some(true),
            Some((lo, _)) if lo >= 1.0 => continue,
            _ => {}
        }
        let side = |x| exact::plane_side(&v, x);
        let (from, to) = (side(lane.o)?, side(end)?);
        if from == Ordering::Equal {
            return None;
        }
        if to != Ordering::Equal && to != from {
            return Some(true);
        }
    }
    Some(false)
}

/// How the line o + t·d meets a triangle, decided exactly.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Crossing {
    /// Misses it, or crosses its plane at t < 0.
    Away,
    /// Crosses it (interior, edge or vertex) at t > 0.
    Front,
}

/// One ray of a packet, for the exact edge tests of the ambiguous lanes.
struct ExactLane {
    d32: [f32; 3],
    /// max|dₖ| rounded up.
    dm: f32,
    o: [f64; 3],
    d: [f64; 3],
}

impl ExactLane {
    fn new(o: [f32; 3], d: [f32; 3]) -> Option<Self> {
        let dm = d.iter().fold(0f32, |m, c| m.max(c.abs())) * (1.0 + 1e-6);
        if !dm.is_finite() || d.iter().any(|c| c.is_nan()) || o.iter().any(|c| !c.is_finite()) {
            return None;
        }
        Some(Self {
            d32: d,
            dm,
            o: o.map(f64::from),
            d: d.map(f64::from),
        })
    }

    /// The kernel's edge tests where certain, exact signs ([`exact::orient`]) where not.
    fn crossing(&self, tri: &OriginTriangle, v: &[[f32; 3]; 3]) -> Option<Crossing> {
        self.crossing_where(tri, v).map(|(crossing, _)| crossing)
    }

    /// [`ExactLane::crossing`] with which of the triangle's vertices weigh in the crossing
    /// point (barycentric weight > 0: the edge opposite vertex i has a nonzero sign; on an
    /// edge or at a vertex the others weigh nothing).
    fn crossing_where(
        &self,
        tri: &OriginTriangle,
        v: &[[f32; 3]; 3],
    ) -> Option<(Crossing, [bool; 3])> {
        if !tri.usable || tri.n_max * self.dm >= MAX_PRODUCT {
            return None;
        }
        let d = self.d32;
        let mut sign = [0i8; 3];
        for i in 0..3 {
            let n = &tri.n[i];
            let e = d[0] * n[0] + d[1] * n[1] + d[2] * n[2];
            let bound = tri.k[i] * self.dm + EDGE_ABS;
            sign[i] = if e > bound {
                1
            } else if e < -bound {
                -1
            } else {
                let (a, b) = (v[(i + 1) % 3].map(f64::from), v[(i + 2) % 3].map(f64::from));
                match exact::orient(self.d, self.o, a, b)? {
                    Ordering::Greater => 1,
                    Ordering::Less => -1,
                    Ordering::Equal => 0,
                }
            };
        }
        let weighs = sign.map(|s| s != 0);
        if sign.contains(&1) && sign.contains(&-1) {
            return Some((Crossing::Away, weighs));
        }
        let s = sign.iter().sum::<i8>().signum();
        if s == 0 {
            return None; // all three zero: the line lies in the triangle's plane
        }
        // In front where det (of the eᵢ's sign) and the numerator agree.
        let crossing = match (tri.num > 0.0) == (s > 0) {
            true => Crossing::Front,
            false => Crossing::Away,
        };
        Some((crossing, weighs))
    }

    /// t's interval for a triangle crossed in front, as `PacketNearest::offer` bounds it
    /// (`None` where that bound is loose).
    fn t_interval(&self, tri: &OriginTriangle) -> Option<(f32, f32)> {
        let d = self.d32;
        let e = tri.n.map(|n| d[0] * n[0] + d[1] * n[1] + d[2] * n[2]);
        let n = tri.normal;
        let (det, bound) = match tri.det_from_normal {
            false => (e[0] + e[1] + e[2], tri.k_sum * self.dm + 3.0 * EDGE_ABS),
            true => (
                d[0] * n[0] + d[1] * n[1] + d[2] * n[2],
                tri.k_det * self.dm + EDGE_ABS,
            ),
        };
        let rcp = 1.0 / det;
        let t = tri.num * rcp;
        let r_det = (bound * 1.0001) * rcp.abs();
        if r_det.is_nan() || r_det > 0.25 {
            return None;
        }
        let err = t.abs() * (tri.c_t + 1.4 * r_det) + 1e-37;
        Some((t - err, t + err))
    }
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

/// The edge tests of one prepared triangle for 8 directions from its origin: the edge
/// functions eᵢ = d·nᵢ, and the lanes that certainly miss it (edges of both signs beyond
/// their bounds), certainly cross it in front (all three of the numerator's sign: t > 0) or
/// behind (t < 0). Other lanes are undecided.
struct EdgeTests<V> {
    e: [V; 3],
    miss: V,
    front: V,
    behind: V,
}

impl<V: LaneOps> EdgeTests<V> {
    /// `dm`: max|dₖ| rounded up.
    #[inline(always)]
    fn new(tri: &OriginTriangle, d: &[V; 3], dm: f32) -> Self {
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
#[inline(always)]
fn t_interval<V: LaneOps>(tri: &OriginTriangle, e: &[V; 3], d: &[V; 3], dm: f32) -> (V, V, V) {
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
#[inline(always)]
fn block_crossings<W: LaneOps>(
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

/// A field of an [`OriginBlock`] as lanes.
#[inline(always)]
fn load<V: Lanes>(field: &[f32; 8]) -> V {
    V::from_array(*field)
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
    best_lo: V,
    best_hi: V,
    /// The nearest's ids as bit patterns (only ever moved bitwise); u32::MAX for none.
    best_prim: V,
    ambiguous: V,
}

impl<V: LaneOps> PacketNearest<V> {
    /// [`PacketNearest::new`] inside a kernel already in lanes `V`.
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
    #[inline(always)]
    pub fn new(d: &[f32x8; 3], d_max: f32) -> Self {
        Self::new_in(each3(|k| V::from_wide(d[k])), d_max)
    }

    /// [`PacketNearest::new`] holding `seed`'s candidates and ambiguous lanes, if any.
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
    #[cfg(test)]
    fn finish_ref(&self) -> PacketHits {
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

/// Eight shadow rays from the origin `tris` were prepared for (the light), directions `d`
/// (`d_max` ≥ every |dₖ|, [`max_component`]): whether each lane in `valid` is blocked for
/// 0 < t < 1 by one of `tris` other than its `skip` primitive, decided as [`PacketNearest`]
/// decides a candidate (certain edge signs, t in a certain interval), or left to the per-ray
/// adaptive search (`unsure`) where the bounds cannot tell. A lane is blocked when some
/// triangle certainly crosses it with its whole t interval below 1; it is clear of a
/// triangle that it certainly misses, that lies certainly behind the origin, or whose t
/// interval starts at 1 or beyond.
pub fn shadow_from_origin(
    tris: &[OriginTriangle],
    d: &[f32x8; 3],
    d_max: f32,
    skip: &[u32; 8],
    valid: u32,
) -> ShadowHits {
    avx2_or_baseline!(lanes shadow_from_origin_body => (
        tris: &[OriginTriangle],
        d: &[f32x8; 3],
        d_max: f32,
        skip: &[u32; 8],
        valid: u32
    ) -> ShadowHits)
}

#[inline(always)]
fn shadow_from_origin_body<V: Lanes>(
    tris: &[OriginTriangle],
    d: &[f32x8; 3],
    d_max: f32,
    skip: &[u32; 8],
    valid: u32,
) -> ShadowHits {
    let mut packet = ShadowPacket::<V>::new(d, d_max, skip, valid);
    for tri in tris {
        if packet.live() == 0 {
            break;
        }
        packet.offer(tri);
    }
    packet.finish()
}

/// Eight shadow segments from the origin triangles are prepared for, as triangles are offered
/// in any order (all of a small scene's, or a BVH's leaves as the segments reach them): per
/// lane, blocked for certain, or unsure. See [`shadow_from_origin`].
pub struct ShadowPacket<V = f32x8> {
    d: [V; 3],
    /// max|dₖ| rounded up.
    dm: f32,
    /// Each lane's own primitive (bit patterns; u32::MAX, a NaN, equals nothing).
    skip: V,
    valid: u32,
    blocked: u32,
    unsure: u32,
}

impl<V: Lanes> ShadowPacket<V> {
    #[inline(always)]
    pub fn new(d: &[f32x8; 3], d_max: f32, skip: &[u32; 8], valid: u32) -> Self {
        let dm = d_max * (1.0 + 1e-6);
        Self {
            d: each3(|k| V::from_wide(d[k])),
            dm,
            skip: V::from_bits(*skip),
            valid,
            blocked: 0,
            // Every lane, where max|d| is not finite.
            unsure: if dm.is_finite() { 0 } else { valid },
        }
    }

    /// The lanes still to be decided: valid, not yet blocked (an unsure lane may still be
    /// found blocked by another triangle).
    #[inline(always)]
    pub fn live(&self) -> u32 {
        match self.dm.is_finite() {
            true => self.valid & !self.blocked,
            false => 0,
        }
    }

    /// Tests one triangle on every live lane but those it belongs to.
    #[inline(always)]
    pub fn offer(&mut self, tri: &OriginTriangle) {
        self.offer_as::<false>(tri);
    }

    /// [`ShadowPacket::offer`] unless the triangle would leave a live lane unsure: then
    /// nothing changes and the answer is false (see [`PacketNearest::offer_decided`]).
    #[inline(always)]
    pub fn offer_decided(&mut self, tri: &OriginTriangle) -> bool {
        self.offer_as::<true>(tri)
    }

    #[inline(always)]
    fn offer_as<const DECIDED: bool>(&mut self, tri: &OriginTriangle) -> bool {
        let (d, dm) = (&self.d, self.dm);
        let own = self
            .skip
            .simd_eq(V::splat(f32::from_bits(tri.prim)))
            .to_bitmask();
        let live = self.live() & !own;
        if live == 0 {
            return true;
        }
        if !tri.usable || tri.n_max * dm >= MAX_PRODUCT {
            if DECIDED {
                return false;
            }
            self.unsure |= live;
            return true;
        }
        let one = V::one();
        let EdgeTests {
            e,
            miss,
            front,
            behind,
        } = EdgeTests::new(tri, d, dm);
        let (front_bits, clear_bits) = (front.to_bitmask(), (miss | behind).to_bitmask());
        if front_bits & live == 0 {
            let unsure = live & !clear_bits;
            if DECIDED && unsure != 0 {
                return false;
            }
            self.unsure |= unsure;
            return true;
        }
        let (lo, hi, tight) = t_interval(tri, &e, d, dm);
        let before_end = (front & tight & hi.simd_lt(one)).to_bitmask();
        let past_end = (front & tight & lo.simd_ge(one)).to_bitmask();
        let unsure = live & !(clear_bits | before_end | past_end);
        if DECIDED && unsure != 0 {
            return false;
        }
        self.blocked |= live & before_end;
        self.unsure |= unsure;
        true
    }

    pub fn finish(self) -> ShadowHits {
        ShadowHits {
            blocked: self.blocked,
            unsure: self.unsure & !self.blocked,
        }
    }
}

/// Shadow lanes: blocked for certain, and undecided (traced per ray).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ShadowHits {
    pub blocked: u32,
    pub unsure: u32,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::lanes::f64x4;

    /// Values in [−0.5, 0.5) from the crate's test generator seeded with `seed`.
    fn unit_steps(mut seed: u64) -> impl FnMut() -> f32 {
        move || (crate::xorshift(&mut seed) >> 40) as f32 / (1u64 << 24) as f32 - 0.5
    }

    /// Every field's bits.
    fn bits(t: &OriginTriangle) -> Vec<u32> {
        let mut b: Vec<u32> = t.n.iter().flatten().map(|x| x.to_bits()).collect();
        b.extend(t.k.map(f32::to_bits));
        b.extend(t.normal.map(f32::to_bits));
        b.extend([t.k_sum, t.n_max, t.num, t.c_t, t.k_det].map(f32::to_bits));
        b.extend([t.det_from_normal as u32, t.prim, t.usable as u32]);
        b
    }

    /// Triangles of every kind the preparation meets: random ones at all scales, slivers,
    /// degenerate and tiny ones, ones through the origin's plane, huge and non-finite
    /// coordinates.
    fn triangles() -> Vec<[[f32; 3]; 3]> {
        let mut next = unit_steps(0x9e37_79b9_7f4a_7c15);
        let mut tris = Vec::new();
        for scale in [1e-30f32, 1e-6, 1.0, 1e3, 1e12, 1e30] {
            for _ in 0..64 {
                tris.push([(); 3].map(|_| [(); 3].map(|_| next() * scale)));
            }
        }
        let v = [1.0f32, 2.0, 3.0];
        tris.extend([
            [v, v, v],
            [[0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]],
            [[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], // the origin on its plane
            [
                [1.0, 1.0, 5.0],
                [1.0 + f32::EPSILON, 1.0, 5.0],
                [1.0, 1.0 + 1e-7, 5.0],
            ],
            [[3e38, 0.0, 1.0], [-3e38, 1.0, 1.0], [0.0, 3e38, 1.0]],
            [[f32::NAN, 0.0, 1.0], [1.0, 0.0, 1.0], [0.0, 1.0, 1.0]],
            [[f32::INFINITY, 0.0, 1.0], [1.0, 0.0, 1.0], [0.0, 1.0, 1.0]],
            [
                [1e-45, 0.0, 1e-45],
                [0.0, 1e-45, 1e-45],
                [1e-45, 1e-45, 2e-45],
            ],
        ]);
        tris
    }

    #[allow(unsafe_code)]
    #[test]
    fn four_at_a_time_prepares_the_same_bits_as_one_by_one() {
        #[target_feature(enable = "avx2,fma")]
        fn avx(v: [&[[f32; 3]; 3]; 4], o: [f32; 3], prim: [u32; 4]) -> [OriginTriangle; 4] {
            let quad = OriginTriangle::new4::<crate::math::lanes::Avx4d>(v, o, prim);
            [0, 1, 2, 3].map(|l| quad.get(l))
        }
        #[target_feature(enable = "avx512f,avx512vl,avx512bw,avx512dq,avx512cd,avx2,fma")]
        fn avx512(v: [&[[f32; 3]; 3]; 4], o: [f32; 3], prim: [u32; 4]) -> [OriginTriangle; 4] {
            let quad = OriginTriangle::new4::<crate::math::lanes::Avx4d>(v, o, prim);
            [0, 1, 2, 3].map(|l| quad.get(l))
        }
        let tris = triangles();
        for o in [[0.0f32, 0.0, 0.0], [0.3, -0.2, -3.0], [1e6, 2.0, -1e-3]] {
            for (q, quad) in tris.chunks_exact(4).enumerate() {
                let v = [&quad[0], &quad[1], &quad[2], &quad[3]];
                let prim = [0, 1, 2, 3].map(|j| (4 * q + j) as u32);
                let one = (0..4).map(|j| bits(&OriginTriangle::new(v[j], o, prim[j])));
                let quad = OriginTriangle::new4::<f64x4>(v, o, prim);
                let wide = [0, 1, 2, 3].map(|l| bits(&quad.get(l)));
                for (j, one) in one.enumerate() {
                    assert_eq!(one, wide[j], "{:?} from {o:?}", v[j]);
                    if crate::math::simd::has_avx2() {
                        // SAFETY: the CPU has AVX2 and FMA.
                        let avx = unsafe { avx(v, o, prim) }.map(|t| bits(&t));
                        assert_eq!(one, avx[j], "{:?} from {o:?}", v[j]);
                    }
                    if crate::math::simd::detected() == crate::math::simd::SimdLevel::Avx512 {
                        // SAFETY: the CPU has AVX-512 F, VL, BW, DQ and CD.
                        let avx = unsafe { avx512(v, o, prim) }.map(|t| bits(&t));
                        assert_eq!(one, avx[j], "{:?} from {o:?}", v[j]);
                    }
                }
            }
        }
    }

    /// The bounds the kernels rely on, against exact rational arithmetic: for every usable
    /// triangle and direction d, |ẽᵢ − eᵢ| ≤ Kᵢ·max|dₖ| + EDGE_ABS (ẽᵢ computed as the kernels
    /// compute it), |d·Ñ − d·N| ≤ k_det·max|dₖ| + EDGE_ABS, Σ Kᵢ ≤ k_sum, and det[p₀, p₁, p₂]
    /// within the relative error c_t allows of num (so its sign is num's). Returns how many
    /// edge functions came within 4 bounds of zero (the test must reach the hard cases).
    fn check_bounds(tri: &OriginTriangle, v: &[[f32; 3]; 3], o: [f32; 3], d: [f32; 3]) -> usize {
        use crate::geometry::exact::{dot, q, qv, sub, Q, QV};
        use num_traits::Signed;
        const U: f64 = 1.0 / (1u64 << 24) as f64;
        let cross = |a: &QV, b: &QV| -> QV {
            [
                &a[1] * &b[2] - &a[2] * &b[1],
                &a[2] * &b[0] - &a[0] * &b[2],
                &a[0] * &b[1] - &a[1] * &b[0],
            ]
        };
        let wide = |x: [f32; 3]| x.map(f64::from);
        let (oq, dq) = (qv(wide(o)), qv(wide(d)));
        let p: Vec<QV> = v.iter().map(|v| sub(&qv(wide(*v)), &oq)).collect();
        let dm = d.iter().fold(0f32, |m, c| m.max(c.abs())) * (1.0 + 1e-6);
        let within = |computed: f32, exact: &Q, bound: f32, what: &str| {
            let err = (q(f64::from(computed)) - exact).abs();
            assert!(
                err <= q(f64::from(bound)),
                "{what}: {computed} off by {err} > {bound} for {v:?} from {o:?} along {d:?}"
            );
        };
        let mut close = 0;
        for i in 0..3 {
            let exact = dot(&dq, &cross(&p[(i + 1) % 3], &p[(i + 2) % 3]));
            let n = &tri.n[i];
            let e = d[0] * n[0] + d[1] * n[1] + d[2] * n[2];
            let bound = tri.k[i] * dm + EDGE_ABS;
            within(e, &exact, bound, "edge function");
            close += (e.abs() <= 4.0 * bound) as usize;
        }
        assert!(tri.k.iter().map(|&k| f64::from(k)).sum::<f64>() <= f64::from(tri.k_sum));
        let normal = cross(&sub(&p[1], &p[0]), &sub(&p[2], &p[0]));
        let n = &tri.normal;
        let det = d[0] * n[0] + d[1] * n[1] + d[2] * n[2];
        within(
            det,
            &dot(&dq, &normal),
            tri.k_det * dm + EDGE_ABS,
            "determinant",
        );
        let num = dot(&p[0], &normal);
        let r_num = (f64::from(tri.c_t) / (1.0 + 1e-6) - 6.0 * U) / 1.4 - 2.1 * U;
        within(
            tri.num,
            &num,
            (r_num * f64::from(tri.num).abs()) as f32,
            "numerator",
        );
        close
    }

    /// Directions at the triangle's edges and vertices (and a little off them) and random
    /// ones, from `o`.
    fn directions(v: &[[f32; 3]; 3], o: [f32; 3], next: &mut impl FnMut() -> f32) -> Vec<[f32; 3]> {
        let mut out = Vec::new();
        for j in 0..3 {
            let (a, b) = (v[j], v[(j + 1) % 3]);
            for s in [0.0f32, 0.5, next() + 0.5, 1.0] {
                let at = each3(|k| a[k] + s * (b[k] - a[k]));
                let d = each3(|k| at[k] - o[k]);
                out.push(d);
                out.push(each3(|k| d[k] * (1.0 + 1e-6 * next())));
            }
        }
        out.push([next(), next(), next()]);
        out
    }

    #[test]
    fn both_preparations_bound_their_errors_exactly() {
        let mut next = unit_steps(0x2545_f491_4f6c_dd1d);
        let tris = triangles();
        let (mut usable, mut close) = ([0usize; 2], 0);
        for o in [
            [0.0f32, 0.0, 0.0],
            [0.3, -0.2, -3.0],
            [1e6, 2.0, -1e-3],
            [0.01, 0.02, 40.0],
        ] {
            for block in tris.chunks(8) {
                let v: [&[[f32; 3]; 3]; 8] =
                    std::array::from_fn(|j| &block[j.min(block.len() - 1)]);
                let prim = std::array::from_fn(|j| j as u32);
                let mut f32s = OriginBlock::default();
                OriginTriangle::new8::<f32x8>(v, o, prim, &mut f32s);
                for (j, v) in v.iter().enumerate().take(block.len()) {
                    let kinds = [OriginTriangle::new(v, o, 0), f32s.get(j)];
                    for (kind, tri) in kinds.iter().enumerate() {
                        if !tri.usable {
                            continue;
                        }
                        usable[kind] += 1;
                        for d in directions(v, o, &mut next) {
                            close += check_bounds(tri, v, o, d);
                        }
                    }
                }
            }
        }
        // Most of the suite is usable in f32 too (not the 1e30 scale, not the non-finite).
        assert!(usable[1] * 10 >= usable[0] * 7, "usable: {usable:?}");
        assert!(close > 1000, "{close} edge functions near zero");
    }

    /// Triangles about 10⁻³ across, about 5 units from `o` in every direction: a far
    /// bunny's, whose edge functions are small against their f32 rounding bounds.
    fn far_small(o: [f32; 3], next: &mut impl FnMut() -> f32) -> Vec<[[f32; 3]; 3]> {
        (0..48)
            .map(|_| {
                let c = each3(|k| o[k] + 10.0 * next());
                [(); 3].map(|_| each3(|k| c[k] + 2e-3 * next()))
            })
            .collect()
    }

    /// How the line o + t·d meets triangle `v`, in exact arithmetic alone (`None`: the line
    /// lies in its plane, or the input is not finite).
    fn exact_crossing(v: &[[f32; 3]; 3], o: [f32; 3], d: [f32; 3]) -> Option<Crossing> {
        use num_traits::Zero;
        let wide = |x: [f32; 3]| x.map(f64::from);
        let mut sign = [Ordering::Equal; 3];
        for (i, s) in sign.iter_mut().enumerate() {
            *s = exact::orient(wide(d), wide(o), wide(v[(i + 1) % 3]), wide(v[(i + 2) % 3]))?;
        }
        if sign.contains(&Ordering::Greater) && sign.contains(&Ordering::Less) {
            return Some(Crossing::Away);
        }
        if sign.iter().all(|s| *s == Ordering::Equal) {
            return None;
        }
        let t = exact_t(v, o, d)?;
        Some(match t > Zero::zero() {
            true => Crossing::Front,
            false => Crossing::Away,
        })
    }

    /// [`PreciseTriangle::crossing`] against exact arithmetic: a certain miss is one, a
    /// certain crossing is one in front with the exact t in its interval; and it decides
    /// most of the rays the f32 rounding leaves within its bounds of an edge.
    #[test]
    fn f64_crossings_hold_the_exact_answer_and_decide_what_f32_cannot() {
        use crate::geometry::exact::q;
        let mut next = unit_steps(0x5851_f42d_4c95_7f2d);
        let (mut f32_unsure, mut rescued, mut f64_unsure, mut fronts) = (0, 0, 0, 0);
        for o in [
            [0.0f32, 0.0, 0.0],
            [0.3, -0.2, -3.0],
            [1e6, 2.0, -1e-3],
            [4.0, 1.0, 5.0],
        ] {
            let mut tris = triangles();
            tris.extend(far_small(o, &mut next));
            for v in &tris {
                let tri = PreciseTriangle::new(v, o, 7);
                if !tri.usable {
                    continue;
                }
                for d in directions(v, o, &mut next) {
                    let (Some(lane), Some(exact)) = (ExactLane::new(o, d), exact_crossing(v, o, d))
                    else {
                        continue;
                    };
                    let exact = Some(exact);
                    let got = tri.crossing(d);
                    let f32_sure = tri.rounded.usable
                        && (0..3).all(|i| {
                            let n = &tri.rounded.n[i];
                            let e = d[0] * n[0] + d[1] * n[1] + d[2] * n[2];
                            e.abs() > tri.rounded.k[i] * lane.dm + EDGE_ABS
                        });
                    f32_unsure += !f32_sure as usize;
                    rescued += (!f32_sure && got.is_some()) as usize;
                    match got {
                        None => f64_unsure += 1,
                        Some(None) => {
                            assert_eq!(exact, Some(Crossing::Away), "{v:?} from {o:?} along {d:?}")
                        }
                        Some(Some((lo, hi))) => {
                            fronts += 1;
                            assert_eq!(
                                exact,
                                Some(Crossing::Front),
                                "{v:?} from {o:?} along {d:?}"
                            );
                            let t = exact_t(v, o, d).expect("crossed, so not parallel");
                            assert!(
                                q(f64::from(lo)) <= t && t <= q(f64::from(hi)),
                                "t {t} outside [{lo}, {hi}] for {v:?} from {o:?} along {d:?}"
                            );
                        }
                    }
                }
            }
        }
        assert!(fronts > 500, "{fronts} crossings");
        assert!(f32_unsure > 200, "{f32_unsure} rays near an edge for f32");
        // (Here about 90%: the rest pass exactly through a vertex or along an edge.)
        assert!(
            rescued * 10 > f32_unsure * 8,
            "{rescued} of {f32_unsure} decided in f64"
        );
        assert!(
            f64_unsure * 4 < f32_unsure,
            "{f64_unsure} left undecided in f64"
        );
    }

    /// The exact t of the line o + t·d in the plane of `v` (None if parallel).
    fn exact_t(v: &[[f32; 3]; 3], o: [f32; 3], d: [f32; 3]) -> Option<crate::geometry::exact::Q> {
        use crate::geometry::exact::{dot, qv, sub};
        use num_traits::Zero;
        let wide = |x: [f32; 3]| qv(x.map(f64::from));
        let p: Vec<_> = v.iter().map(|v| sub(&wide(*v), &wide(o))).collect();
        let (a, b) = (sub(&p[1], &p[0]), sub(&p[2], &p[0]));
        let normal = [
            &a[1] * &b[2] - &a[2] * &b[1],
            &a[2] * &b[0] - &a[0] * &b[2],
            &a[0] * &b[1] - &a[1] * &b[0],
        ];
        let det = dot(&wide(d), &normal);
        (!det.is_zero()).then(|| dot(&p[0], &normal) / det)
    }

    /// Triangles for the block passes' tests: three triangulated sheets one behind the other
    /// (shared edges and vertices, two candidates along most rays; the third lies within the
    /// t intervals' width of the first: their order is uncertain), interleaved so that each
    /// run of 8 (or leaf of 4) holds triangles of every sheet; then some of the
    /// preparation's hard suite.
    fn layered_triangles() -> Vec<[[f32; 3]; 3]> {
        let sheet = |z: f32, shift: f32| {
            let mut tris = Vec::new();
            for i in 0..4 {
                for j in 0..4 {
                    let (x, y) = (i as f32 * 0.1 - 0.2 + shift, j as f32 * 0.1 - 0.2);
                    let c = [
                        [x, y, z],
                        [x + 0.1, y, z],
                        [x, y + 0.1, z],
                        [x + 0.1, y + 0.1, z],
                    ];
                    tris.push([c[0], c[1], c[2]]);
                    tris.push([c[2], c[1], c[3]]);
                }
            }
            tris
        };
        let sheets = [
            sheet(2.0, 0.0),
            sheet(2.0 + 1e-4, 0.013),
            sheet(f32::from_bits(2.0f32.to_bits() + 1), 0.029),
        ];
        let mut tris: Vec<_> = (0..32)
            .flat_map(|i| sheets.each_ref().map(|s| s[i]))
            .collect();
        tris.extend(triangles().into_iter().step_by(5));
        tris
    }

    /// Directions from `o` at the edges and vertices of `tris` and between
    /// ([`directions`]), and through their insides (where the sheets overlap).
    fn rays_at(
        tris: &[[[f32; 3]; 3]],
        o: [f32; 3],
        next: &mut impl FnMut() -> f32,
    ) -> Vec<[f32; 3]> {
        let mut dirs = Vec::new();
        for t in tris {
            dirs.extend(directions(t, o, next));
            for _ in 0..4 {
                let (a, b) = (next() + 0.5, next() + 0.5);
                let (a, b) = if a + b > 1.0 {
                    (1.0 - a, 1.0 - b)
                } else {
                    (a, b)
                };
                dirs.push(each3(|k| {
                    t[0][k] + a * (t[1][k] - t[0][k]) + b * (t[2][k] - t[0][k]) - o[k]
                }));
            }
        }
        dirs
    }

    /// The exact nearest front crossing of the ray from `o` along `d` among `ids` of
    /// `block` (vertices `v`): its id and whether another front one was crossed, or None.
    fn exact_nearest(
        block: &OriginBlock,
        v: &[&[[f32; 3]; 3]; 8],
        o: [f32; 3],
        d: [f32; 3],
        ids: &[usize],
    ) -> Option<(usize, bool)> {
        let exact = ExactLane::new(o, d).unwrap();
        let fronts: Vec<(usize, _)> = (ids.iter().copied())
            .filter(|&j| exact.crossing(&block.get(j), v[j]) == Some(Crossing::Front))
            .map(|j| (j, exact_t(v[j], o, d).unwrap()))
            .collect();
        let (j, t) = fronts.iter().min_by(|a, b| a.1.cmp(&b.1))?;
        assert!(
            fronts.iter().all(|(k, u)| k == j || u > t),
            "a tie at {d:?}"
        );
        Some((*j, fronts.len() > 1))
    }

    #[test]
    fn one_lane_offers_of_a_block_decide_as_offers_one_by_one() {
        // Blocks of 8 from two triangulated sheets one behind the other (shared edges and
        // vertices, two candidates along most rays) and from the preparation's hard suite;
        // rays at their edges and vertices and between; every leaf-sized run of lanes, from
        // an empty lane and from one holding a candidate. Where the one-lane pass decides,
        // its answer is the exact nearest (rational t, exact edge signs), and the one of
        // offers one by one wherever those decide; where it does not, nothing changed.
        let mut next = unit_steps(0x5851_f42d_4c95_7f2d);
        let tris = layered_triangles();
        let o = [0.01f32, -0.02, 0.0];
        let (mut decided, mut taken, mut declined, mut ordered) = (0, 0, 0, 0);
        for block_tris in tris.chunks(8).filter(|b| b.len() == 8) {
            let v: [&[[f32; 3]; 3]; 8] = std::array::from_fn(|j| &block_tris[j]);
            let mut block = OriginBlock::default();
            OriginTriangle::new8::<f32x8>(v, o, [0; 8], &mut block);
            let dirs = rays_at(block_tris, o, &mut next);
            for (k, d) in dirs.iter().enumerate() {
                let l = k % 8;
                let mut lanes = [[0f32; 8]; 3];
                for (c, lane) in lanes.iter_mut().enumerate() {
                    for (m, x) in lane.iter_mut().enumerate() {
                        *x = match m == l {
                            true => d[c],
                            false => dirs[(k + m * 7) % dirs.len()][c],
                        };
                    }
                }
                let dw = lanes.map(f32x8::from);
                let d_max = lanes.iter().flatten().fold(0f32, |m, x| m.max(x.abs()));
                for (start, len) in [(0, 4), (4, 4), (2, 3), (5, 3), (0, 8), (7, 1)] {
                    let mask = ((1u32 << len) - 1) << start;
                    for seeded in [None, Some((start + len) % 8)] {
                        let mut one = PacketNearest::<f32x8>::new(&dw, d_max);
                        if let Some(s) = seeded {
                            one.offer(&block.get(s), 100 + s as u32);
                        }
                        if one.ambiguous() & (1 << l) != 0 {
                            continue;
                        }
                        let mut each = PacketNearest::<f32x8>::new(&dw, d_max);
                        if let Some(s) = seeded {
                            each.offer(&block.get(s), 100 + s as u32);
                        }
                        let before = format!("{:?}", one.finish_ref());
                        let lo_before = one.best_lo.to_array()[l];
                        if !one.offer_block_to_lane(&block, mask, BlockIds::From(0), l) {
                            assert_eq!(format!("{:?}", one.finish_ref()), before);
                            assert_eq!(one.best_lo.to_array()[l].to_bits(), lo_before.to_bits());
                            declined += 1;
                            continue;
                        }
                        decided += 1;
                        assert_eq!(one.ambiguous() & (1 << l), 0);
                        for j in (start..start + len).filter(|j| *j < 8) {
                            each.offer(&block.get(j), j as u32);
                        }
                        let got = one.finish_ref().prim[l];
                        if each.ambiguous() & (1 << l) == 0 {
                            assert_eq!(got, each.finish_ref().prim[l], "block lane {l}, {d:?}");
                        }
                        // Exact: the nearest front crossing among the run and the seed.
                        let mut ids: Vec<usize> = (start..start + len).filter(|j| *j < 8).collect();
                        ids.extend(seeded);
                        match exact_nearest(&block, &v, o, *d, &ids) {
                            None => assert_eq!(got, u32::MAX, "{d:?}"),
                            Some((j, others)) => {
                                let from_seed = Some(j) == seeded && got == 100 + j as u32;
                                assert!(got == j as u32 || from_seed, "{got} for {j}, {d:?}");
                                taken += (got < 100) as usize;
                                ordered += others as usize;
                            }
                        }
                    }
                }
            }
        }
        // (Most rays here are aimed at edges and vertices: many lanes stay undecided.)
        println!("decided {decided}, taken {taken}, ordered {ordered}, declined {declined}");
        assert!(decided > 10_000 && taken > 1_000 && ordered > 200 && declined > 1_000);
    }

    /// A leaf's offers to two to four lanes at once ([`PacketNearest::offer_leaf_to_lanes`]),
    /// in 8 lanes (two passes for three or four rays) and, where the CPU has AVX-512, in 16
    /// (one pass), on the triangles and rays of the one-lane test: where they decide, each
    /// ray's answer is the exact nearest of the leaf and its seed, and that of offers one by
    /// one wherever those decide, and no other lane changed; where they do not, nothing did.
    #[test]
    fn leaf_offers_to_a_few_lanes_decide_as_offers_one_by_one() {
        let check = |[decided, taken, ordered, declined]: [usize; 4]| {
            println!("decided {decided}, taken {taken}, ordered {ordered}, declined {declined}");
            assert!(decided > 5_000 && taken > 1_000 && ordered > 200 && declined > 500);
        };
        check(leaf_offers::<f32x8>());
        use crate::math::lanes::Avx16;
        use crate::math::simd::{detected, SimdLevel};
        if detected() >= SimdLevel::Avx512 {
            #[target_feature(enable = "avx512f,avx512vl,avx512bw,avx512dq,avx512cd,avx2,fma")]
            fn in_16_lanes() -> [usize; 4] {
                leaf_offers::<Avx16>()
            }
            // SAFETY: the CPU has AVX-512 F, VL, BW, DQ and CD (checked above).
            #[allow(unsafe_code)]
            check(unsafe { in_16_lanes() });
        }
    }

    /// The body of `leaf_offers_to_a_few_lanes_decide_as_offers_one_by_one` in lanes `V`:
    /// the counts of leaf offers decided, rays that took a leaf triangle, rays that crossed
    /// more than one, and offers declined.
    #[inline(always)]
    fn leaf_offers<V: LaneOps>() -> [usize; 4] {
        /// The lanes' bits.
        #[inline(always)]
        fn bits<V: LaneOps>(x: V) -> [u32; 16] {
            let mut a = [0f32; 16];
            x.store(&mut a);
            a.map(f32::to_bits)
        }
        #[inline(always)]
        fn state<V: LaneOps>(p: &PacketNearest<V>) -> ([u32; 16], u32, [u32; 16], [u32; 16]) {
            let mut prims = [0u32; 16];
            let ambiguous = p.finish_into(&mut prims);
            (prims, ambiguous, bits(p.best_lo), bits(p.best_hi))
        }
        let mut next = unit_steps(0x2545_f491_4f6c_dd1d);
        let tris = layered_triangles();
        let o = [0.01f32, -0.02, 0.0];
        let width = V::WIDTH;
        let (mut decided, mut taken, mut declined, mut ordered) = (0, 0, 0, 0);
        for leaf_tris in tris.chunks(4).filter(|b| b.len() == 4) {
            // As `Bvh::prepare_leaf` prepares a leaf: lanes 4–7 repeat lanes 0–3.
            let v: [&[[f32; 3]; 3]; 8] = std::array::from_fn(|j| &leaf_tris[j % 4]);
            let mut block = OriginBlock::default();
            OriginTriangle::new8::<f32x8>(v, o, [0; 8], &mut block);
            let dirs = rays_at(leaf_tris, o, &mut next);
            for k in 0..dirs.len() {
                let mut lanes = [[0f32; 16]; 3];
                for (c, lane) in lanes.iter_mut().enumerate() {
                    for (m, x) in lane.iter_mut().enumerate() {
                        *x = dirs[(k + m * 7) % dirs.len()][c];
                    }
                }
                let d = [0, 1, 2].map(|c| V::load(&lanes[c]));
                let d_max = (lanes.iter())
                    .flat_map(|lane| &lane[..width])
                    .fold(0f32, |m, x| m.max(x.abs()));
                for rays in [0b11, 0x22, 0xc8, 0xb1, 0x8421, 0xe002] {
                    let rays = rays & V::full();
                    for len in 1..=4 {
                        // A seed outside the leaf, offered to every lane first.
                        for seeded in [None, (len < 4).then_some(len)] {
                            let mut one = PacketNearest::<V>::new_in(d, d_max);
                            if let Some(s) = seeded {
                                one.offer(&block.get(s), 100 + s as u32);
                            }
                            let live = rays & !one.ambiguous();
                            if live.count_ones() < 2 {
                                continue;
                            }
                            let before = state(&one);
                            if !one.offer_leaf_to_lanes(&block, len, 0, live) {
                                assert_eq!(state(&one), before);
                                declined += 1;
                                continue;
                            }
                            decided += 1;
                            let after = state(&one);
                            assert_eq!(after.1, before.1, "no lane left ambiguous");
                            for m in (0..width).filter(|m| live & (1 << m) == 0) {
                                let lane = |s: &([u32; 16], u32, [u32; 16], [u32; 16])| {
                                    (s.0[m], s.2[m], s.3[m])
                                };
                                assert_eq!(lane(&after), lane(&before), "lane {m} untouched");
                            }
                            let mut each = PacketNearest::<V>::new_in(d, d_max);
                            if let Some(s) = seeded {
                                each.offer(&block.get(s), 100 + s as u32);
                            }
                            for j in 0..len {
                                each.offer(&block.get(j), j as u32);
                            }
                            let each = state(&each);
                            let mut ids: Vec<usize> = (0..len).collect();
                            ids.extend(seeded);
                            for l in (0..width).filter(|l| live & (1 << l) != 0) {
                                let got = after.0[l];
                                if each.1 & (1 << l) == 0 {
                                    assert_eq!(got, each.0[l], "lane {l} of {rays:#x}");
                                }
                                let dl = [lanes[0][l], lanes[1][l], lanes[2][l]];
                                match exact_nearest(&block, &v, o, dl, &ids) {
                                    None => assert_eq!(got, u32::MAX, "{dl:?}"),
                                    Some((j, others)) => {
                                        let want = match Some(j) == seeded {
                                            true => 100 + j as u32,
                                            false => j as u32,
                                        };
                                        assert_eq!(got, want, "{dl:?}");
                                        taken += (got < 100) as usize;
                                        ordered += others as usize;
                                    }
                                }
                            }
                        }
                    }
                }
            }
        }
        [decided, taken, ordered, declined]
    }

    #[test]
    fn prepared_lists_keep_order_and_length() {
        let tris = triangles();
        for n in [0, 1, 3, 4, 5, 4099] {
            let list: Vec<IndexedTriangle> = (0..n)
                .map(|i| (tris[i % tris.len()], 7 * i as u32))
                .collect();
            let o = [0.1, 0.2, -2.0];
            let prepared = OriginTriangles::new(&list, o);
            assert_eq!(prepared.tris.len(), n);
            for (t, (v, prim)) in prepared.tris.iter().zip(&list) {
                assert_eq!(bits(t), bits(&OriginTriangle::new(v, o, *prim)));
            }
        }
    }
}
