//! The adaptive method's fast paths for the renderer: camera rays in packets of 8 against
//! triangles prepared for the camera's position ([`closest`]; per ray in BVH leaves:
//! [`OriginTriangle::estimate`]), and shadow rays in packets of 8 ([`shadow_x8`]).
//!
//! All camera rays of a frame leave the same origin o. With pᵢ = vᵢ − o, the exact
//! predicates of the adaptive method are the signs of eᵢ = d·(pⱼ × pₖ) ((i, j, k) cyclic; eᵢ
//! weighs vertex i) and t = det[p₀, p₁, p₂] / (e₀ + e₁ + e₂). The cross products and the
//! determinant depend on the triangle alone, so they are computed once per frame in f64
//! with bounds on their error ([`OriginTriangles::new`]); per ray and triangle there remain
//! three f32 dot products, whose rounding error is at most Kᵢ·max|dₖ| with Kᵢ fixed per
//! triangle. An eᵢ beyond that bound has a certain sign, t comes with a certain interval,
//! and a lane keeps the nearest candidate only while its interval lies wholly below the
//! others'. Every lane that cannot be decided so (a ray within rounding of an edge, two hits
//! too close to order, a degenerate case) is reported `ambiguous`, and the caller traces it
//! with the per-ray adaptive search, which decides exactly. So a decided lane's primitive is
//! exactly the one the per-ray search returns.

use super::IndexedTriangle;
use crate::geometry::adaptive::{Approx, Estimate};
use rayon::prelude::*;
use wide::f32x8;

/// Calls `body(args)` (an `#[inline(always)]` kernel) through a copy compiled with AVX2 and
/// FMA where the CPU has them ([`has_avx2`]), else as compiled for the baseline: the one place
/// the crate uses unsafe code.
macro_rules! avx2_or_baseline {
    ($body:path => ($($arg:ident: $ty:ty),*) -> $ret:ty) => {{
        #[cfg(target_arch = "x86_64")]
        if $crate::accel::packet::has_avx2() {
            #[target_feature(enable = "avx2,fma")]
            fn avx2($($arg: $ty),*) -> $ret {
                $body($($arg),*)
            }
            // SAFETY: the CPU has AVX2 and FMA (checked at run time).
            #[allow(unsafe_code)]
            return unsafe { avx2($($arg),*) };
        }
        $body($($arg),*)
    }};
}
pub(crate) use avx2_or_baseline;

/// Unit roundoff of f32 and f64.
const U32: f64 = 1.0 / (1u64 << 24) as f64;
const U64: f64 = 1.0 / (1u64 << 53) as f64;

/// Largest |nₖ| sum (and |det|) prepared: larger ones make every ray ambiguous.
const MAX_MAGNITUDE: f64 = 1e36;

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

impl OriginTriangle {
    /// Prepares triangle `v` for rays from `o`; cheap enough (about 150 instructions) to make
    /// each time a packet meets a triangle, which is how the BVH's packets use it.
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
        const TINY: f64 = 3.0 * 1.5e-45;
        const MARGIN: f64 = 1.0 + 1e-6;
        let w = v.map(|vi| vi.map(f64::from));
        let o = o.map(f64::from);
        let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
        let cross = |a: [f64; 3], b: [f64; 3]| {
            [
                a[1] * b[2] - a[2] * b[1],
                a[2] * b[0] - a[0] * b[2],
                a[0] * b[1] - a[1] * b[0],
            ]
        };
        let abs_max = |x: &[[f64; 3]; 3]| {
            x.iter()
                .flatten()
                .fold(0f64, |acc, c| if c.abs() > acc { c.abs() } else { acc })
        };
        let p = [sub(w[0], o), sub(w[1], o), sub(w[2], o)];
        let e = [sub(w[2], w[1]), sub(w[0], w[2]), sub(w[1], w[0])];
        let n64 = [cross(p[1], e[0]), cross(p[2], e[1]), cross(p[0], e[2])];
        let normal64 = cross(e[1], e[2]);
        let m = abs_max(&p) * (1.0 + 2.0 * U64);
        let me = abs_max(&e) * (1.0 + 2.0 * U64);
        let n = n64.map(|ni| ni.map(|x| x as f32));
        let normal = normal64.map(|x| x as f32);
        let abs_sum = |x: [f32; 3]| x[0].abs() as f64 + x[1].abs() as f64 + x[2].abs() as f64;
        let s = n.map(abs_sum);
        let n_err = 3.0 * 8.0004 * U64 * m * me + TINY;
        let k = s.map(|si| ((4.0002 * U32 * si + n_err) * MARGIN) as f32);
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
        Self {
            n,
            k,
            k_sum,
            n_max: n_max as f32,
            num,
            c_t,
            normal,
            k_det,
            prim,
            usable,
        }
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

    fn prepare<'a>(
        n: usize,
        get: impl Fn(usize) -> (&'a [[f32; 3]; 3], u32) + Sync,
        origin: [f32; 3],
    ) -> Self {
        let prepare = |i| {
            let (v, prim) = get(i);
            OriginTriangle::new(v, origin, prim)
        };
        Self {
            tris: if n >= 4096 {
                (0..n).into_par_iter().map(prepare).collect()
            } else {
                (0..n).map(prepare).collect()
            },
            origin,
        }
    }
}

impl OriginTriangle {
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
        let e = self.n.map(|n| d[0] * n[0] + d[1] * n[1] + d[2] * n[2]);
        let bound = self.k.map(|k| k * dm + EDGE_ABS);
        let pos = [0, 1, 2].map(|i| e[i] > bound[i]);
        let neg = [0, 1, 2].map(|i| e[i] < -bound[i]);
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
    if [d[0], d[1], d[2]].iter().any(|v| v.simd_ne(*v).any()) {
        return f32::NAN;
    }
    let m = d[0].abs().max(d[1].abs()).max(d[2].abs()).to_array();
    let half = [
        m[0].max(m[4]),
        m[1].max(m[5]),
        m[2].max(m[6]),
        m[3].max(m[7]),
    ];
    half[0].max(half[1]).max(half[2].max(half[3]))
}

/// The nearest of `tris` along each of 8 directions from their shared origin, for
/// 0 < t < ∞. `d_max` ≥ every |dₖ| of the packet ([`max_component`]); lanes that could
/// overflow (or a NaN direction) are ambiguous. See [`PacketNearest`].
pub fn closest(tris: &[OriginTriangle], d: &[f32x8; 3], d_max: f32) -> PacketHits {
    avx2_or_baseline!(closest_body => (tris: &[OriginTriangle], d: &[f32x8; 3], d_max: f32) -> PacketHits)
}

/// Whether the CPU has AVX2 and FMA, for the kernels compiled twice: for the baseline x86-64
/// (SSE2, f32x8 as two 4-lane halves) and with AVX2 and FMA enabled (VEX-encoded
/// three-operand instructions: 18% fewer instructions in `closest`, callgrind). The
/// answer is cached by the standard library.
#[cfg(target_arch = "x86_64")]
#[inline]
pub(crate) fn has_avx2() -> bool {
    !BASELINE_ONLY.load(std::sync::atomic::Ordering::Relaxed)
        && std::arch::is_x86_feature_detected!("avx2")
        && std::arch::is_x86_feature_detected!("fma")
}

static BASELINE_ONLY: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Runs the kernels' baseline build even where AVX2 is present (for tests and comparisons:
/// both builds of a kernel must give the same bits, as neither contracts to FMA).
pub fn use_baseline_simd(on: bool) {
    BASELINE_ONLY.store(on, std::sync::atomic::Ordering::Relaxed);
}

#[inline(always)]
fn closest_body(tris: &[OriginTriangle], d: &[f32x8; 3], d_max: f32) -> PacketHits {
    let mut nearest = PacketNearest::new(d, d_max);
    for tri in tris {
        nearest.offer(tri, tri.prim);
    }
    nearest.finish()
}

/// The nearest candidate so far of each of 8 rays from the shared origin, as triangles are
/// offered in any order (all of a small scene's, or a BVH's leaves as the rays reach them).
///
/// Error bound of t, for a lane whose three eᵢ have one certain sign: the computed
/// det̃ = ẽ₀ + ẽ₁ + ẽ₂ is within ΣK·max|d| + γ₂|det̃|/(1 − γ₂) of the exact one, i.e. a
/// relative r_det ≤ ΣK·max|d|·|1/det̃|·(1 + u) + 2.1u, kept ≤ 1/4 (else ambiguous); the
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
pub struct PacketNearest {
    d: [f32x8; 3],
    /// max|dₖ| rounded up.
    dm: f32,
    best_lo: f32x8,
    best_hi: f32x8,
    /// The nearest's ids as bit patterns (only ever moved bitwise); u32::MAX for none.
    best_prim: f32x8,
    ambiguous: f32x8,
}

impl PacketNearest {
    pub fn new(d: &[f32x8; 3], d_max: f32) -> Self {
        let inf = f32x8::splat(f32::INFINITY);
        let none = f32x8::ZERO.simd_ne(f32x8::ZERO);
        Self {
            d: *d,
            dm: d_max * (1.0 + 1e-6),
            best_lo: inf,
            best_hi: inf,
            best_prim: f32x8::splat(f32::from_bits(u32::MAX)),
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
    pub fn reach(&self) -> f32x8 {
        self.best_hi
    }

    /// Offers one triangle to every lane; a lane that takes it as its nearest records `id`.
    #[inline(always)]
    pub fn offer(&mut self, tri: &OriginTriangle, id: u32) {
        let (d, dm) = (&self.d, self.dm);
        if !tri.usable || tri.n_max * dm >= MAX_PRODUCT || !dm.is_finite() {
            self.ambiguous = f32x8::ZERO.simd_eq(f32x8::ZERO);
            return;
        }
        let e = tri.n.map(|n| {
            d[0] * f32x8::splat(n[0]) + d[1] * f32x8::splat(n[1]) + d[2] * f32x8::splat(n[2])
        });
        let bound = tri.k.map(|k| f32x8::splat(k * dm + EDGE_ABS));
        let pos = [0, 1, 2].map(|i| e[i].simd_gt(bound[i]));
        let neg = [0, 1, 2].map(|i| e[i].simd_lt(-bound[i]));
        let any_pos = pos[0] | pos[1] | pos[2];
        let any_neg = neg[0] | neg[1] | neg[2];
        let miss = any_pos & any_neg;
        if miss.all() {
            return;
        }
        let all_pos = pos[0] & pos[1] & pos[2];
        let all_neg = neg[0] & neg[1] & neg[2];
        // In front: the sign of det (that of the eᵢ) is the numerator's.
        let front = if tri.num > 0.0 { all_pos } else { all_neg };
        let behind = if tri.num > 0.0 { all_neg } else { all_pos };
        self.ambiguous |= !(miss | front | behind);
        if front.none() {
            return;
        }
        let det = e[0] + e[1] + e[2];
        let rcp = f32x8::ONE / det;
        let t = f32x8::splat(tri.num) * rcp;
        let r_det = f32x8::splat((tri.k_sum * dm + 3.0 * EDGE_ABS) * 1.0001) * rcp.abs();
        let tight = r_det.simd_le(f32x8::splat(0.25));
        let err =
            t.abs() * (f32x8::splat(tri.c_t) + f32x8::splat(1.4) * r_det) + f32x8::splat(1e-37);
        let (lo, hi) = (t - err, t + err);
        let nearer = hi.simd_lt(self.best_lo);
        let farther = lo.simd_gt(self.best_hi);
        // Overlapping intervals, or a loose one: the per-ray search orders them.
        self.ambiguous |= front & !(tight & (nearer | farther));
        let take = front & tight & nearer;
        self.best_lo = take.bitselect(lo, self.best_lo);
        self.best_hi = take.bitselect(hi, self.best_hi);
        self.best_prim = take.bitselect(f32x8::splat(f32::from_bits(id)), self.best_prim);
    }

    /// Per lane the id of the nearest (u32::MAX for none), and the ambiguous lanes.
    pub fn finish(self) -> PacketHits {
        PacketHits {
            prim: self.best_prim.to_array().map(f32::to_bits),
            ambiguous: self.ambiguous.to_bitmask(),
        }
    }
}

/// Eight shadow rays (any origin, any direction) against a few triangles at once, rays in the
/// lanes: whether each is blocked for 0 < t < 1 by a triangle other than its `skip`
/// primitive, decided from f32 arithmetic with a bound on its error, or left to the per-ray
/// adaptive search (`unsure`) where the bound cannot tell.
///
/// The bound: with m ≥ |vₖ − oₖ| for every vertex and axis (from the box `lo`..`hi` around
/// the triangles), each p = fl(v − o) is within u·m of the exact difference, each component
/// of a computed cross product pⱼ × pₖ within 8.0001·u·m² of the exact one and at most
/// 2m²(1 + 3u) in size, so an edge function eᵢ = d·(pⱼ × pₖ) computed in f32 is within
/// E = 14.1·u·|d|₁·m² of exact (8.0001 + 2·3.0001, plus margin), and det[p₀, p₁, p₂] within
/// 48.5·u·m³ (three terms of m·(γ₃·2m² + 8u·m² + 2u·m²)). t = det/Σeᵢ lies certainly in
/// (0, 1) when the signs agree and |det| + its error < |Σeᵢ| − its error (3E + 2.1u·|Σẽ|).
/// Lanes with m below 1e-15 (products could underflow) or bounds beyond 1e30 are unsure.
pub fn shadow_x8(
    tris: &[Occluder],
    bounds: ([f32; 3], [f32; 3]),
    rays: &[([f32; 3], [f32; 3], u32); 8],
    valid: u32,
) -> ShadowHits {
    avx2_or_baseline!(shadow_x8_body => (
        tris: &[Occluder],
        bounds: ([f32; 3], [f32; 3]),
        rays: &[([f32; 3], [f32; 3], u32); 8],
        valid: u32
    ) -> ShadowHits)
}

#[inline(always)]
fn shadow_x8_body(
    tris: &[Occluder],
    (lo, hi): ([f32; 3], [f32; 3]),
    rays: &[([f32; 3], [f32; 3], u32); 8],
    valid: u32,
) -> ShadowHits {
    const U: f32 = 1.0 / (1u32 << 24) as f32;
    let (mut oa, mut da) = ([[0.0f32; 8]; 3], [[0.0f32; 8]; 3]);
    // The box around the valid lanes' segments (as `Occluder::meets` wants it).
    let (mut seg_lo, mut seg_hi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
    for (l, (o, d, _)) in rays.iter().enumerate() {
        for k in 0..3 {
            (oa[k][l], da[k][l]) = (o[k], d[k]);
        }
        if valid & (1 << l) != 0 {
            grow_by_segment((&mut seg_lo, &mut seg_hi), *o, *d);
        }
    }
    let (o, d) = (oa.map(f32x8::from), da.map(f32x8::from));
    // m per lane, rounded up past the f32 subtractions' rounding.
    let mut m = f32x8::ZERO;
    for k in 0..3 {
        let (l, h) = (f32x8::splat(lo[k]), f32x8::splat(hi[k]));
        m = m.max((h - o[k]).abs()).max((o[k] - l).abs());
    }
    let m = m * f32x8::splat(1.0 + 1.0 / (1 << 20) as f32);
    // Skip primitives as bit patterns, compared as floats (never NaN below 2^24; u32::MAX,
    // a NaN, equals nothing).
    let skip = f32x8::from(rays.map(|r| f32::from_bits(r.2)));
    let d1 = d[0].abs() + d[1].abs() + d[2].abs();
    let edge_bound = f32x8::splat(14.1 * U) * d1 * m * m + f32x8::splat(1e-37);
    let num_bound = f32x8::splat(48.5 * U) * m * m * m + f32x8::splat(1e-37);
    // Lanes whose bounds would overflow (or NaN inputs) are left to the per-ray search.
    let finite = |x: f32x8| x.simd_lt(f32x8::splat(1e30));
    // And lanes so close to every triangle that the products could underflow.
    let big = m.simd_gt(f32x8::splat(1e-15));
    let usable = (finite(edge_bound) & finite(num_bound) & finite(d1) & big).to_bitmask() & valid;
    let mut blocked = 0u32;
    let mut unsure = valid & !usable;
    let zero = f32x8::ZERO;
    for occ in tris {
        if usable & !blocked == 0 {
            break;
        }
        if !occ.meets(seg_lo, seg_hi) {
            continue; // no segment of the packet comes near
        }
        let (v, prim) = (&occ.v, &occ.prim);
        let own = skip
            .simd_eq(f32x8::splat(f32::from_bits(*prim)))
            .to_bitmask();
        let live = usable & !blocked & !own;
        if live == 0 {
            continue;
        }
        let p = v.map(|vi| [0, 1, 2].map(|k| f32x8::splat(vi[k]) - o[k]));
        let cross = |a: &[f32x8; 3], b: &[f32x8; 3]| {
            [
                a[1] * b[2] - a[2] * b[1],
                a[2] * b[0] - a[0] * b[2],
                a[0] * b[1] - a[1] * b[0],
            ]
        };
        let c0 = cross(&p[1], &p[2]);
        let c1 = cross(&p[2], &p[0]);
        let c2 = cross(&p[0], &p[1]);
        let dot = |c: &[f32x8; 3], w: &[f32x8; 3]| c[0] * w[0] + c[1] * w[1] + c[2] * w[2];
        let e = [dot(&c0, &d), dot(&c1, &d), dot(&c2, &d)];
        let pos = e[0].simd_gt(edge_bound) & e[1].simd_gt(edge_bound) & e[2].simd_gt(edge_bound);
        let neg = e[0].simd_lt(-edge_bound) & e[1].simd_lt(-edge_bound) & e[2].simd_lt(-edge_bound);
        let any_pos =
            e[0].simd_gt(edge_bound) | e[1].simd_gt(edge_bound) | e[2].simd_gt(edge_bound);
        let any_neg =
            e[0].simd_lt(-edge_bound) | e[1].simd_lt(-edge_bound) | e[2].simd_lt(-edge_bound);
        let miss = (any_pos & any_neg).to_bitmask();
        let crosses = (pos | neg).to_bitmask();
        let mut undecided = live & !miss & !crosses;
        let cand = live & crosses;
        if cand == 0 && undecided == 0 {
            continue;
        }
        if cand != 0 {
            let det = e[0] + e[1] + e[2];
            let num = dot(&c0, &p[0]);
            let det_err = f32x8::splat(3.0001) * edge_bound + f32x8::splat(2.1 * U) * det.abs();
            let (an, ad) = (num.abs(), det.abs());
            // Same sign as det (t > 0) with the numerator's sign certain.
            let same = (num.simd_gt(zero) & pos) | (num.simd_lt(zero) & neg);
            let num_sure = an.simd_gt(num_bound);
            // a < b for the exact sums: 2^-20 (16 roundings) of margin on each side.
            let margin = 1.0 / (1 << 20) as f32;
            let (up, down) = (f32x8::splat(1.0 + margin), f32x8::splat(1.0 - margin));
            let below = |a: f32x8, b: f32x8| (a * up).simd_lt(b * down);
            let inside = same & num_sure & below(an + num_bound, ad - det_err);
            let before = !same & num_sure;
            let beyond = below(ad + det_err, an - num_bound);
            let inside = inside.to_bitmask() & cand;
            blocked |= inside;
            undecided |= cand & !inside & !(before | beyond).to_bitmask();
        }
        // The same test in f64 for the lanes f32 cannot decide (an origin within rounding of
        // the triangle's plane: the other half of the quad a shadow ray leaves, say).
        while undecided != 0 {
            let l = undecided.trailing_zeros() as usize;
            undecided &= undecided - 1;
            let mf = m.to_array()[l] as f64;
            match shadow_f64(v, rays[l].0, rays[l].1, mf) {
                Some(true) => blocked |= 1 << l,
                Some(false) => {}
                None => unsure |= 1 << l,
            }
        }
    }
    ShadowHits {
        blocked,
        unsure: unsure & !blocked,
    }
}

/// One shadow ray against one triangle in f64 with the bounds of [`shadow_x8`] for f64
/// (u = 2^-53; every f32 input is exact in f64): blocked for 0 < t < 1, not blocked, or
/// `None` where even f64 cannot tell (an exact tie: the per-ray search decides it exactly).
#[inline(never)]
#[cold]
fn shadow_f64(v: &[[f32; 3]; 3], o: [f32; 3], d: [f32; 3], m: f64) -> Option<bool> {
    let u = 1.0 / (1u64 << 53) as f64;
    let d = d.map(f64::from);
    let p = v.map(|vi| [0, 1, 2].map(|k| vi[k] as f64 - o[k] as f64));
    let cross = |a: &[f64; 3], b: &[f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let dot = |a: &[f64; 3], b: &[f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let c = [
        cross(&p[1], &p[2]),
        cross(&p[2], &p[0]),
        cross(&p[0], &p[1]),
    ];
    let e = c.map(|ci| dot(&ci, &d));
    let d1 = d[0].abs() + d[1].abs() + d[2].abs();
    let edge = 14.1 * u * d1 * m * m + 1e-300;
    let num_bound = 48.5 * u * m * m * m + 1e-300;
    if !(edge < 1e290 && num_bound < 1e290 && m > 1e-90) {
        return None;
    }
    let pos = e.iter().all(|x| *x > edge);
    let neg = e.iter().all(|x| *x < -edge);
    if e.iter().any(|x| *x > edge) && e.iter().any(|x| *x < -edge) {
        return Some(false);
    }
    if !(pos || neg) {
        return None;
    }
    let det = e[0] + e[1] + e[2];
    let num = dot(&c[0], &p[0]);
    let det_err = 3.0001 * edge + 2.1 * u * det.abs();
    let (an, ad) = (num.abs(), det.abs());
    if an <= num_bound {
        return None;
    }
    if (num > 0.0) != pos {
        return Some(false); // t < 0
    }
    let margin = 1.0 / (1u64 << 40) as f64;
    let below = |a: f64, b: f64| a * (1.0 + margin) < b * (1.0 - margin);
    if below(an + num_bound, ad - det_err) {
        Some(true)
    } else if below(ad + det_err, an - num_bound) {
        Some(false)
    } else {
        None
    }
}

/// Shadow lanes: blocked for certain, and undecided (traced per ray).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ShadowHits {
    pub blocked: u32,
    pub unsure: u32,
}

/// Grows the box [lo, hi] by the segment from `o` to o + d as computed in f32 (whose rounding
/// [`Occluder::meets`] allows for). NaN coordinates are left out.
#[inline]
pub fn grow_by_segment((lo, hi): (&mut [f32; 3], &mut [f32; 3]), o: [f32; 3], d: [f32; 3]) {
    for k in 0..3 {
        let end = o[k] + d[k];
        let (a, b) = if end < o[k] { (end, o[k]) } else { (o[k], end) };
        lo[k] = if a < lo[k] { a } else { lo[k] };
        hi[k] = if b > hi[k] { b } else { hi[k] };
    }
}

/// A triangle that may block shadow rays, with its bounding box.
#[derive(Clone, Copy, Debug)]
pub struct Occluder {
    pub v: [[f32; 3]; 3],
    pub prim: u32,
    pub lo: [f32; 3],
    pub hi: [f32; 3],
}

impl Occluder {
    pub fn new((v, prim): &IndexedTriangle) -> Self {
        Self {
            v: *v,
            prim: *prim,
            lo: [0, 1, 2].map(|k| v[0][k].min(v[1][k]).min(v[2][k])),
            hi: [0, 1, 2].map(|k| v[0][k].max(v[1][k]).max(v[2][k])),
        }
    }

    /// Whether the box meets [lo, hi] widened by 1e-6 relative (plus 1e-30): a box built
    /// from segment ends computed in f32 (origin + direction, rounded) then holds the exact
    /// segments.
    pub fn meets(&self, lo: [f32; 3], hi: [f32; 3]) -> bool {
        let slack = |x: f32| x.abs() * 1e-6 + 1e-30;
        (0..3).all(|k| !(self.hi[k] < lo[k] - slack(lo[k]) || self.lo[k] > hi[k] + slack(hi[k])))
    }
}
