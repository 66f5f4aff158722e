//! t correctly rounded to f32 or f64 ([`rounded_t`]): from t in plain f64 with a proved
//! bound where that decides the rounding, else exactly.

use super::levels::{note, Event};
use super::widen;
use crate::geometry::{Ray, Shape};
use crate::math::Real;

/// The t at which `ray` meets `shape` (the plane of a triangle; a sphere's nearest root with
/// tmin < t < tmax), correctly rounded to T: the exact t rounded to the nearest value of T,
/// ties to even, overflowing to ±∞ and underflowing as IEEE 754 rounding does. `None` where
/// there is no such t (a line parallel to the plane, a sphere missed in the range).
///
/// It gives t for a primitive a query found; whether the ray meets the triangle inside its
/// edges is the query's business. Exact arithmetic only where t in f64 with its bound
/// (`plane_t_f64`; a sphere's f64 interval) cannot decide the rounding: for f32, nearly
/// never; for f64, nearly always (an f64 bound decides an f64 rounding only when it is 0).
pub fn rounded_t<T: Real>(shape: &Shape<T>, ray: &Ray<T>, tmin: T, tmax: T) -> Option<T> {
    let (o, d) = (ray.o.map(Real::f64), ray.d.map(Real::f64));
    let (tmin, tmax) = (tmin.f64(), tmax.f64());
    // (Both ends rounding to a zero decide nothing where they lie either side of 0: the exact
    // t 0 rounds to +0, a tiny negative one to −0, and −0 == +0. An f32 t of 0 printed −0.)
    let decides = |lo: f64, hi: f64| {
        let r = T::of(lo);
        let one_sign = (lo < 0.0) == (hi < 0.0);
        (lo > tmin && hi < tmax && r == T::of(hi) && one_sign).then_some(r)
    };
    let wide = widen(shape);
    if let Some((lo, hi)) = wide.t_in_f64(o, d, tmin, tmax) {
        if let Some(r) = decides(lo, hi) {
            note(Event::RoundedFromF64);
            return Some(r);
        }
    }
    note(Event::RoundedExactly);
    wide.t_rounded(o, d, tmin, tmax)
}

/// t = p₀·n / d·n of the plane of v in plain f64 (pᵢ = vᵢ − o, n = (p₁ − p₀) × (p₂ − p₀)),
/// with a bound on its error; `None` for inputs where over- or underflow could void it.
///
/// Every path through num and den is at most 7 roundings deep, so (Higham, ch. 3)
/// |fl(x) − x| ≤ γ₇·x_abs, with x_abs the same sums and products over absolute values; that
/// is computed in f64 too (rounding it adds at most γ₇ more), so err_x = 2γ₈·x_abs bounds it.
/// The quotient adds one rounding: |t̃ − t| ≤ (|t̃|·err_den + err_num)/(|den| − err_den) + u|t̃|.
/// About 40 ns; it decides an f32 rounding unless t lies within ~2⁻⁴⁰ of a midpoint.
pub(crate) fn plane_t_f64(o: [f64; 3], d: [f64; 3], v: &[[f64; 3]; 3]) -> Option<(f64, f64)> {
    use crate::math::real::{cross, dot, sub};
    // Inputs 0 or within 2^±200 (every f32 is): nothing overflows, and every nonzero
    // difference, edge and product of two is a multiple of 2⁻²⁵² and ≥ 2⁻⁷⁵⁶, normal. Only
    // the last products (into num and den) may underflow, each by < 2⁻¹⁰⁷⁴: the 8·2⁻¹⁰⁷⁴.
    let safe = |x: &f64| *x == 0.0 || (2f64.powi(-200)..=2f64.powi(200)).contains(&x.abs());
    if !o.iter().chain(&d).chain(v.iter().flatten()).all(safe) {
        return None;
    }
    // The same sums and products over absolute values.
    let add_abs = |a: [f64; 3], b: [f64; 3]| [0, 1, 2].map(|k| a[k].abs() + b[k].abs());
    let cross_abs = |a: [f64; 3], b: [f64; 3]| {
        [
            a[1] * b[2] + a[2] * b[1],
            a[2] * b[0] + a[0] * b[2],
            a[0] * b[1] + a[1] * b[0],
        ]
    };
    let p = v.map(|vi| sub(vi, o));
    let p_abs = v.map(|vi| add_abs(vi, o));
    let n = cross(sub(p[1], p[0]), sub(p[2], p[0]));
    let n_abs = cross_abs(add_abs(p_abs[1], p_abs[0]), add_abs(p_abs[2], p_abs[0]));
    let (num, den) = (dot(p[0], n), dot(d, n));
    let (num_abs, den_abs) = (dot(p_abs[0], n_abs), dot(d.map(f64::abs), n_abs));
    const G8: f64 = 8.0 * f64::EPSILON * 0.5 / (1.0 - 8.0 * f64::EPSILON * 0.5);
    const UNDERFLOW: f64 = 8.0 * f64::MIN_POSITIVE * f64::EPSILON; // 8·2⁻¹⁰⁷⁴
    let err_num = 2.0 * G8 * num_abs + UNDERFLOW;
    let err_den = 2.0 * G8 * den_abs + UNDERFLOW;
    if den.abs() <= 2.0 * err_den {
        return None;
    }
    let t = num / den;
    let err = (t.abs() * err_den + err_num) / (den.abs() - err_den) * (1.0 + 4.0 * f64::EPSILON)
        + t.abs() * f64::EPSILON;
    (t.is_finite() && err.is_finite()).then_some((t, err))
}
