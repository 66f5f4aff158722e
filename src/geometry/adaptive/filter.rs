//! Level 1, the f32 filter: the watertight test with a conservative bound on its edge
//! functions' rounding ([`classify_f32`], from [`box_extent`] and [`edge_error`]), its hits
//! as t intervals, the loose per-ray t bound of the SIMD loop, and f64 rounded outwards to
//! f32 ([`round_up`], [`round_down`]).

use super::estimate::{Approx, Estimate};
use crate::geometry::triangle::{t_error_bound, WatertightRay};

/// Smallest and largest box extents for which the f32 filter's bound holds (no underflow in
/// the products, no overflow of the square). Outside them the filter defers.
const MIN_EXTENT: f32 = 1.0 / (1u64 << 40) as f32;
const MAX_EXTENT: f32 = (1u64 << 60) as f32;

/// M for the f32 filter's error bound: 2·max|v − o| over the box [lo, hi] (a bound on the
/// magnitudes |pₓ| + |Sₓ·p_z| that the sheared coordinates of its vertices are computed
/// from, as |Sₓ|, |S_y| ≤ 1), or `f32::INFINITY` where the bound would not hold.
#[inline]
pub fn box_extent(o: [f32; 3], lo: [f32; 3], hi: [f32; 3]) -> f32 {
    let mut m = 0.0f32;
    for k in 0..3 {
        m = m.max((hi[k] - o[k]).abs()).max((o[k] - lo[k]).abs());
    }
    let m = 2.0 * m * (1.0 + 1.0 / (1 << 20) as f32);
    if (MIN_EXTENT..=MAX_EXTENT).contains(&m) {
        m
    } else {
        f32::INFINITY
    }
}

/// γ(n) for f32, at compile time.
const fn gamma32(n: f32) -> f32 {
    let nu = n * (f32::EPSILON * 0.5);
    nu / (1.0 - nu)
}

/// The constants of [`edge_error`]: E = C1·M·m + C2·M² + tiny.
const EDGE_C1: f32 = 2.0 * gamma32(10.0);
const EDGE_C2: f32 = 4.0 * gamma32(4.0) * gamma32(4.0);

/// A bound E on the rounding error of a watertight f32 edge function x_j·y_k − y_j·x_k, from
/// M ([`box_extent`]) and m = the largest |x|, |y| of the three computed sheared vertices.
///
/// Each sheared coordinate x = pₓ + Sₓ·p_z is computed with error ≤ γ₄·(|pₓ| + |Sₓ·p_z|)
/// ≤ γ₄·M (one rounding each for p, S, the product and the sum), so
/// |x̃ⱼỹₖ − xⱼyₖ| ≤ γ₄·M·|ỹₖ| + (|x̃ⱼ| + γ₄·M)·γ₄·M ≤ 2γ₄·M·m + γ₄²·M², twice, plus the
/// rounding of the two products and the difference (≤ 4u·m², m ≤ M·(1 + γ₄)): in all at
/// most γ₉·M·m + 2γ₄²·M². E doubles that (margin for the rounding of E itself), and adds
/// 1e-37 for products that fall into the subnormal range.
#[inline]
pub fn edge_error(m_box: f32, m_lane: f32) -> f32 {
    EDGE_C1 * m_box * m_lane + EDGE_C2 * m_box * m_box + 1e-37
}

/// Level 1: the f32 watertight test with a certain sign for every edge function, or `Unsure`.
/// `m_box` comes from [`box_extent`] for a box holding the triangle.
#[inline]
pub fn classify_f32(r: &WatertightRay<f32>, v: &[[f32; 3]; 3], m_box: f32) -> Estimate {
    let [kx, ky, kz] = r.k;
    let [sx, sy, sz] = r.s;
    let sheared = |p: [f32; 3]| {
        let (x, y, z) = (p[kx] - r.o[kx], p[ky] - r.o[ky], p[kz] - r.o[kz]);
        [x + sx * z, y + sy * z, z]
    };
    let [a, b, c] = v.map(sheared);
    let u = c[0] * b[1] - c[1] * b[0];
    let w = b[0] * a[1] - b[1] * a[0];
    let vv = a[0] * c[1] - a[1] * c[0];
    // max|x|, |y| with plain compares (f32::max's NaN rules cost more; a NaN coordinate
    // makes the edge functions NaN, which decide nothing anyway).
    let big = |m: f32, x: f32| if x.abs() > m { x.abs() } else { m };
    let m = big(
        big(big(a[0].abs(), a[1]), big(b[0].abs(), b[1])),
        big(c[0].abs(), c[1]),
    );
    let e = edge_error(m_box, m);
    if (u < -e || vv < -e || w < -e) && (u > e || vv > e || w > e) {
        return Estimate::Miss;
    }
    let all_pos = u > e && vv > e && w > e;
    let all_neg = u < -e && vv < -e && w < -e;
    if !(all_pos || all_neg) {
        return Estimate::Unsure;
    }
    let det = u + vv + w;
    let rcp = 1.0 / det;
    let t = (u * a[2] + vv * b[2] + w * c[2]) * sz * rcp;
    let bound = t_error_bound(&[a, b, c], sz, [u, vv, w], rcp);
    approx_f32(t, bound, vv * rcp, w * rcp, 1)
}

/// The smallest f32 ≥ x.
#[inline]
pub fn round_up(x: f64) -> f32 {
    let y = x as f32;
    if (y as f64) < x {
        y.next_up()
    } else {
        y
    }
}

/// The largest f32 ≤ x.
#[inline]
pub fn round_down(x: f64) -> f32 {
    let y = x as f32;
    if (y as f64) > x {
        y.next_down()
    } else {
        y
    }
}

/// The f32 filter's hit as an interval (the t bound doubled for margin); `level` 0 for the
/// loose bound of [`loose_t_bound`], 1 for pbrt's.
#[inline]
pub fn approx_f32(t: f32, bound: f32, b1: f32, b2: f32, level: u8) -> Estimate {
    if !(t.is_finite() && bound.is_finite()) {
        return Estimate::Unsure;
    }
    let (t, slack) = (t as f64, 2.0 * bound as f64);
    Estimate::Hit(Approx {
        t,
        lo: t - slack,
        hi: t + slack,
        b1: b1 as f64,
        b2: b2 as f64,
        level,
    })
}

/// Coefficients (A, B) of a per-ray bound A + B·|1/det| on pbrt's t error bound, valid for
/// every triangle inside a box of extent `m_box` ([`box_extent`]) whose edge signs are all
/// certain. It costs two operations per lane instead of about thirty; where it is too loose
/// to order two hits, the search recomputes pbrt's bound for just those two.
///
/// Derivation: with all edge functions of one sign, |det| ≥ max|e|, so max|e|·|1/det| ≤ 1;
/// every sheared |x|, |y| is ≤ M and |z| ≤ M/2 (see [`box_extent`]). Substituted into
/// pbrt's 3·(γ₃·max|e|·Zₜ + δₑ·Zₜ + δ_z·max|e|)·|1/det| with Zₜ = max|z|·|S_z|:
/// ≤ |S_z|·M·(3γ₃ + 3(γ₂ + 3γ₅)·M²·|1/det|), and 1% on top for the rounding of this; plus
/// twice pbrt's bound's underflow term U·(1 + |1/det|·(1 + 3|S_z|)) (and U·M² for its `Zₜ`
/// starting at U), which the products above lose where they underflow.
#[inline]
pub fn loose_t_bound(m_box: f32, sz: f32) -> (f32, f32) {
    let k = 1.01 * m_box * sz.abs();
    let u = 2.0 * <f32 as crate::math::Real>::UNDERFLOW;
    (
        k * 3.0003 * gamma32(3.0) + u,
        k * 3.0 * (gamma32(2.0) + 3.0 * gamma32(5.0)) * m_box * m_box
            + u * (1.0 + 3.0 * sz.abs() + m_box * m_box),
    )
}

/// The f32 test with pbrt's t bound, from f32 inputs (level 1), for a triangle found by the
/// loose level.
pub(crate) fn precise_f32(o: [f32; 3], d: [f32; 3], v: &[[f32; 3]; 3]) -> Estimate {
    let Some(r) = WatertightRay::new(o, d) else {
        return Estimate::Unsure;
    };
    let (mut lo, mut hi) = (v[0], v[0]);
    for p in &v[1..] {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    classify_f32(&r, v, box_extent(o, lo, hi))
}
