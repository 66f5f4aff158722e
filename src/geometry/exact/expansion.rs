//! Shewchuk's floating-point expansions: exact sums and products of f64s, and [`orient`],
//! the exact sign of det[d, a − o, b − o] (a plain f64 filter first, then distillation,
//! then expansions).

use std::cmp::Ordering;

/// x + y = a + b exactly (Knuth's two-sum).
#[inline]
pub fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let x = a + b;
    let bv = x - a;
    let av = x - bv;
    (x, (a - av) + (b - bv))
}

/// x + y = a·b exactly: the fused multiply-add gives the rounding error where the CPU has it
/// (compiled in); otherwise Dekker's product with Veltkamp's split (exact for products clear
/// of overflow and underflow, which [`in_safe_range`] ensures), since software `fma` is slow.
#[inline]
pub(super) fn two_prod(a: f64, b: f64) -> (f64, f64) {
    let x = a * b;
    if cfg!(target_feature = "fma") {
        return (x, a.mul_add(b, -x));
    }
    let split = |v: f64| {
        let c = 134_217_729.0 * v; // 2^27 + 1
        let hi = c - (c - v);
        (hi, v - hi)
    };
    let ((ah, al), (bh, bl)) = (split(a), split(b));
    let err = ((ah * bh - x) + ah * bl + al * bh) + al * bl;
    (x, err)
}

/// A nonoverlapping expansion in increasing magnitude, on the stack: the sum of its terms
/// is the exact value. 32 terms hold everything [`orient`] builds (at most 24).
#[derive(Clone, Copy)]
struct Expansion {
    t: [f64; 32],
    n: usize,
}

impl Expansion {
    fn of(terms: &[f64]) -> Self {
        let mut e = Self {
            t: [0.0; 32],
            n: terms.len(),
        };
        e.t[..terms.len()].copy_from_slice(terms);
        e
    }

    fn terms(&self) -> &[f64] {
        &self.t[..self.n]
    }

    /// self + b in place (Shewchuk's GROW-EXPANSION with zero elimination; each output
    /// term is written at or before the input term it came from).
    fn grow(&mut self, b: f64) {
        let mut q = b;
        let mut k = 0;
        for i in 0..self.n {
            let (s, err) = two_sum(q, self.t[i]);
            if err != 0.0 {
                self.t[k] = err;
                k += 1;
            }
            q = s;
        }
        if q != 0.0 || k == 0 {
            self.t[k] = q;
            k += 1;
        }
        self.n = k;
    }

    /// self + f.
    fn add(mut self, f: &Expansion) -> Self {
        for &x in f.terms() {
            self.grow(x);
        }
        self
    }

    /// self·b (Shewchuk's SCALE-EXPANSION with zero elimination).
    fn scale(&self, b: f64) -> Self {
        let mut h = Self::of(&[]);
        let push = |h: &mut Self, x: f64| {
            if x != 0.0 {
                h.t[h.n] = x;
                h.n += 1;
            }
        };
        let e = self.terms();
        let (mut q, err) = two_prod(e[0], b);
        push(&mut h, err);
        for &x in &e[1..] {
            let (p1, p0) = two_prod(x, b);
            let (s, err) = two_sum(q, p0);
            push(&mut h, err);
            // |p1| ≥ |s| here, so a fast two-sum would do; the plain one is as exact.
            let (s2, err) = two_sum(p1, s);
            push(&mut h, err);
            q = s2;
        }
        if q != 0.0 || h.n == 0 {
            h.t[h.n] = q;
            h.n += 1;
        }
        h
    }

    /// The sign of the exact value (the largest term's).
    fn sign(&self) -> Ordering {
        let top = self.terms().last().copied().unwrap_or(0.0);
        top.partial_cmp(&0.0).unwrap_or(Ordering::Equal)
    }
}

/// The exact sign of Σ aᵢ·bᵢ over at most 16 `pairs`, each product clear of f64 underflow
/// and overflow (factors 0 or of magnitude in [10⁻¹²⁰, 10¹²⁰]): every product as its
/// two-product, summed as an expansion.
pub(super) fn sum_of_products_sign(pairs: &[(f64, f64)]) -> Ordering {
    assert!(pairs.len() <= 16, "an expansion holds 32 terms");
    let mut e = Expansion::of(&[]);
    for &(a, b) in pairs {
        let (x, err) = two_prod(a, b);
        e.grow(err);
        e.grow(x);
    }
    e.sign()
}

/// a·b − c·d as an expansion.
fn cross_term(a: f64, b: f64, c: f64, d: f64) -> Expansion {
    let (x1, x0) = two_prod(a, b);
    let (y1, y0) = two_prod(c, d);
    let mut e = Expansion::of(&[x0]);
    e.grow(x1);
    e.grow(-y0);
    e.grow(-y1);
    e
}

/// Inputs whose products of three stay clear of f64 underflow and overflow (every f32 is).
fn in_safe_range(x: f64) -> bool {
    x == 0.0 || (1e-90..=1e90).contains(&x.abs())
}

/// Shewchuk's `o3derrboundA`, (7 + 56ε)ε with ε = 2⁻⁵³: |computed − exact| of a 3×3
/// determinant is below it times the permanent.
const ORIENT_BOUND: f64 = (7.0 + 56.0 * f64::EPSILON / 2.0) * (f64::EPSILON / 2.0);

/// The exact sign of det[d, a − o, b − o]: which side of the edge (a, b) the line o + t·d
/// passes. `None` where a − o or b − o is not exact in f64 or an input is outside the safe
/// range (then the caller falls back to rationals).
pub fn orient(d: [f64; 3], o: [f64; 3], a: [f64; 3], b: [f64; 3]) -> Option<Ordering> {
    let mut pa = [0.0; 3];
    let mut pb = [0.0; 3];
    for k in 0..3 {
        let (x, ex) = two_sum(a[k], -o[k]);
        let (y, ey) = two_sum(b[k], -o[k]);
        if ex != 0.0 || ey != 0.0 {
            return None;
        }
        if ![x, y, d[k]].into_iter().all(in_safe_range) {
            return None;
        }
        (pa[k], pb[k]) = (x, y);
    }
    // The plain f64 determinant decides where it is clear of its rounding (Shewchuk's
    // orient3d bound, from entries that are exact here; no product can underflow or
    // overflow in the safe range): ~40 instructions against ~1,200 for the expansions.
    let (m0, m1, m2) = (pa[1] * pb[2], pa[2] * pb[1], pa[2] * pb[0]);
    let (m3, m4, m5) = (pa[0] * pb[2], pa[0] * pb[1], pa[1] * pb[0]);
    let det = d[0] * (m0 - m1) + d[1] * (m2 - m3) + d[2] * (m4 - m5);
    let permanent = d[0].abs() * (m0.abs() + m1.abs())
        + d[1].abs() * (m2.abs() + m3.abs())
        + d[2].abs() * (m4.abs() + m5.abs());
    let bound = ORIENT_BOUND * permanent;
    if det > bound {
        return Some(Ordering::Greater);
    }
    if -det > bound {
        return Some(Ordering::Less);
    }
    if let Some(sign) = orient_distilled(d, &pa, &pb) {
        return Some(sign);
    }
    let terms = [
        cross_term(pa[1], pb[2], pa[2], pb[1]).scale(d[0]),
        cross_term(pa[2], pb[0], pa[0], pb[2]).scale(d[1]),
        cross_term(pa[0], pb[1], pa[1], pb[0]).scale(d[2]),
    ];
    // Nonoverlapping, increasing magnitude, zeros removed: the last term carries the sign.
    Some(terms[0].add(&terms[1]).add(&terms[2]).sign())
}

/// The exact sign of det[d, pa, pb] (entries in the safe range) as the sign of a sum of at
/// most 24 exact products, by distillation ([`sum_sign`]); `None` where that does not settle
/// within its sweeps. Rays exactly through a wall's diagonal or a box's edge give exact zeros,
/// which the filter never decides: the Cornell box's 640×360 frame has ~850 of them, and this
/// takes ~630 instructions for each against ~1,700 for the expansions (callgrind).
pub(super) fn orient_distilled(d: [f64; 3], pa: &[f64; 3], pb: &[f64; 3]) -> Option<Ordering> {
    let mut terms = [0.0; 24];
    let mut n = 0;
    for (k, &dk) in d.iter().enumerate() {
        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
        // pa_i·pb_j − pa_j·pb_i = (p − q) + p_err − q_err exactly, p − q as a two-sum.
        let (p, p_err) = two_prod(pa[i], pb[j]);
        let (q, q_err) = two_prod(pa[j], pb[i]);
        let (s, s_err) = two_sum(p, -q);
        for c in [s, s_err, p_err, -q_err] {
            if c != 0.0 {
                let (h, l) = two_prod(dk, c);
                for x in [h, l] {
                    if x != 0.0 {
                        terms[n] = x;
                        n += 1;
                    }
                }
            }
        }
    }
    sum_sign(&mut terms, n)
}

/// Distillation sweeps before [`sum_sign`] gives up (exact zeros of a few terms settle in 1–3).
const SWEEPS: usize = 6;

/// The exact sign of `terms[..n]`'s sum (no term overflowing): each sweep adds the terms in
/// turn, keeping every two-sum's rounding error as a term (the exact sum never changes), until
/// no error is left or the running sum outweighs them all. `None` after [`SWEEPS`] sweeps.
pub(super) fn sum_sign(terms: &mut [f64; 24], mut n: usize) -> Option<Ordering> {
    for _ in 0..SWEEPS {
        let mut sum = 0.0;
        let mut kept = 0;
        for i in 0..n {
            let (s, err) = two_sum(sum, terms[i]);
            if err != 0.0 {
                terms[kept] = err;
                kept += 1;
            }
            sum = s;
        }
        // (The first two-sum, 0 + x, is exact: a sweep keeps at most n − 1 errors.)
        if kept == 0 {
            return sum.partial_cmp(&0.0);
        }
        // Σ|errors| computed in f64 is below the exact one by at most a relative (kept − 1)·ε
        // (ε = 2⁻⁵³, kept ≤ 24): the margin covers it and the product's rounding.
        let rest: f64 = terms[..kept].iter().map(|t| t.abs()).sum();
        if sum.abs() > rest * (1.0 + 64.0 * f64::EPSILON) {
            return sum.partial_cmp(&0.0);
        }
        terms[kept] = sum;
        n = kept + 1;
    }
    None
}
