//! The sphere's f64 interval test for four rays from one origin at once ([`interval_x4`],
//! [`interval_x4_of`]), or for four (sphere, ray) pairs ([`interval_x4_gathered`]): the
//! packets' test, in the f64 lanes of the caller's build, with what it needs of the sphere
//! ([`FromOrigin`]) and of the rays ([`DirectionsX4`], [`DirectionLanes`]).

use crate::math::interval::{idot, idot_x4, isub, iv3, Interval, IntervalX4};
use crate::math::lanes::{f64x4, Lanes64};

/// What [`interval_x4`] found per lane: masks (all bits set in a lane where true) of the
/// lanes certainly hitting with tmin < t < tmax, t in [`lo`, `hi`], and of the lanes
/// certainly missing in that range; the rest are undecided.
///
/// [`lo`]: LanesX4::lo
/// [`hi`]: LanesX4::hi
#[derive(Clone, Copy, Debug)]
pub struct LanesX4<F = f64x4> {
    pub hit: F,
    pub miss: F,
    pub lo: F,
    pub hi: F,
}

/// The sphere seen from a ray origin o, what [`interval_x4`] needs of it: f = o − c and
/// k = f·f − r² as intervals, computed once for every ray from o.
#[derive(Clone, Copy, Debug)]
pub struct FromOrigin {
    f: [Interval; 3],
    k: Interval,
}

impl FromOrigin {
    /// With scalar intervals widened by one ulp. A lit pixel's shading point takes its t
    /// from the root this gives (`Sphere::surface_point`), so its bits are the pixels':
    /// keep it as it is.
    pub fn new(o: [f64; 3], centre: [f64; 3], radius: f64) -> Self {
        let f = isub(iv3(o), iv3(centre));
        Self {
            f,
            k: idot(f, f) - Interval::point(radius).square(),
        }
    }

    /// f and k in every lane.
    #[inline(always)]
    fn splat<F: Lanes64>(&self) -> ([IntervalX4<F>; 3], IntervalX4<F>) {
        let f = [
            IntervalX4::splat(self.f[0]),
            IntervalX4::splat(self.f[1]),
            IntervalX4::splat(self.f[2]),
        ];
        (f, IntervalX4::splat(self.k))
    }

    /// The packets' own, made for every sphere of the scene once a frame, for finite f32
    /// inputs: f and k with each end widened as [`IntervalX4`] widens
    /// ([`Interval::loosely_widened`]: at least one ulp, no branches) and f·f as a sum of
    /// squares, a third of [`FromOrigin::new`]'s cost. The intervals differ from its by ulps
    /// and enclose the same exact values: every lane the packets decide is decided correctly,
    /// and a lane a few ulps from a tie or a tangent may go to the per-ray search instead.
    pub fn for_packets(o: [f64; 3], centre: [f64; 3], radius: f64) -> Self {
        let loose = Interval::loosely_widened;
        let f = [0, 1, 2].map(|k| {
            let x = o[k] - centre[k];
            loose(x, x)
        });
        let [x, y, z] = f.map(Interval::loosely_squared);
        let xy = loose(x.lo + y.lo, x.hi + y.hi);
        let ff = loose(xy.lo + z.lo, xy.hi + z.hi);
        let r2 = Interval::point(radius).loosely_squared();
        Self {
            f,
            k: loose(ff.lo - r2.hi, ff.hi - r2.lo),
        }
    }
}

/// [`interval`](super::interval) for four rays from one origin at once (directions `d`,
/// lanes): the same steps in [`IntervalX4`] arithmetic, whose ends are a little wider, so a
/// lane it decides [`interval`](super::interval) decides the same way (both enclose the
/// exact roots). For f32 inputs (every magnitude within 2^±150, so nothing over- or
/// underflows in f64); lanes with non-finite ends come out undecided.
#[inline(always)]
pub fn interval_x4<F: Lanes64>(
    sphere: &FromOrigin,
    d: &[F; 3],
    tmin: f64,
    tmax: f64,
) -> LanesX4<F> {
    let (a, finite) = squared_length_x4(d);
    let (f, k) = sphere.splat();
    roots_x4(f, k, d, a, finite, OverA::Divide, tmin, tmax)
}

/// How [`roots_x4`] takes x to x/a. (An enum, not a closure: a closure is compiled without
/// the AVX build's features, and its AVX lanes' operations stay calls.)
#[derive(Clone, Copy)]
enum OverA<F> {
    /// Divided by the interval a.
    Divide,
    /// Multiplied by the interval 1/a.
    ByInverse(IntervalX4<F>),
}

impl<F: Lanes64> OverA<F> {
    #[inline(always)]
    fn apply(self, x: IntervalX4<F>, a: IntervalX4<F>) -> IntervalX4<F> {
        match self {
            OverA::Divide => x.div_positive(a),
            OverA::ByInverse(inv_a) => x.mul_positive(inv_a),
        }
    }
}

/// Four directions as a packet's sphere tests need them ([`interval_x4_of`]): with
/// a = d·d and 1/a, the same for every sphere the packet meets, computed once.
#[derive(Clone, Copy, Debug)]
pub struct DirectionsX4<F = f64x4> {
    d: [F; 3],
    a: IntervalX4<F>,
    inv_a: IntervalX4<F>,
    finite: F,
}

/// Four intervals as lanes.
#[inline(always)]
fn gathered<F: Lanes64>(x: [Interval; 4]) -> IntervalX4<F> {
    IntervalX4 {
        lo: F::from_array([x[0].lo, x[1].lo, x[2].lo, x[3].lo]),
        hi: F::from_array([x[0].hi, x[1].hi, x[2].hi, x[3].hi]),
    }
}

/// Four and four lanes as eight.
#[inline(always)]
fn joined<F: Lanes64>(a: F, b: F) -> [f64; 8] {
    let (a, b) = (a.to_array(), b.to_array());
    [a[0], a[1], a[2], a[3], b[0], b[1], b[2], b[3]]
}

/// Lanes `lanes` of eight.
#[inline(always)]
fn picked<F: Lanes64>(x: &[f64; 8], lanes: [usize; 4]) -> F {
    F::from_array([x[lanes[0]], x[lanes[1]], x[lanes[2]], x[lanes[3]]])
}

/// Eight directions prepared as [`DirectionsX4`] (lanes 0–3 and 4–7), kept lane by lane,
/// so that any four of them can be tested at once ([`interval_x4_gathered`]).
#[derive(Clone, Copy, Debug)]
pub struct DirectionLanes {
    d: [[f64; 8]; 3],
    a: [[f64; 8]; 2],
    inv_a: [[f64; 8]; 2],
    finite: [f64; 8],
}

impl DirectionLanes {
    /// Lanes 0–3 from `halves[0]`, 4–7 from `halves[1]`.
    #[inline(always)]
    pub fn new<F: Lanes64>(halves: &[DirectionsX4<F>; 2]) -> Self {
        // (No closure around the lanes: see `math::interval::idot_x4`.)
        let [h0, h1] = halves;
        Self {
            d: [
                joined(h0.d[0], h1.d[0]),
                joined(h0.d[1], h1.d[1]),
                joined(h0.d[2], h1.d[2]),
            ],
            a: [joined(h0.a.lo, h1.a.lo), joined(h0.a.hi, h1.a.hi)],
            inv_a: [
                joined(h0.inv_a.lo, h1.inv_a.lo),
                joined(h0.inv_a.hi, h1.inv_a.hi),
            ],
            finite: joined(h0.finite, h1.finite),
        }
    }

    /// Lanes `lanes` (each 0–7), as four directions.
    #[inline(always)]
    fn gather<F: Lanes64>(&self, lanes: [usize; 4]) -> DirectionsX4<F> {
        let d = &self.d;
        DirectionsX4 {
            d: [
                picked(&d[0], lanes),
                picked(&d[1], lanes),
                picked(&d[2], lanes),
            ],
            a: IntervalX4 {
                lo: picked(&self.a[0], lanes),
                hi: picked(&self.a[1], lanes),
            },
            inv_a: IntervalX4 {
                lo: picked(&self.inv_a[0], lanes),
                hi: picked(&self.inv_a[1], lanes),
            },
            finite: picked(&self.finite, lanes),
        }
    }
}

impl<F: Lanes64> DirectionsX4<F> {
    /// The directions `d` (lanes), prepared.
    #[inline(always)]
    pub fn new(d: [F; 3]) -> Self {
        let (a, finite) = squared_length_x4(&d);
        Self {
            d,
            a,
            inv_a: IntervalX4::point(F::splat(1.0)).div_positive(a),
            finite,
        }
    }
}

/// [`interval_x4`] with the directions prepared once per packet: the roots scaled by the
/// interval 1/a instead of divided by a (one rounding more, so the ends are a few ulps
/// wider; both enclose the exact roots).
#[inline(always)]
pub fn interval_x4_of<F: Lanes64>(
    sphere: &FromOrigin,
    dirs: &DirectionsX4<F>,
    tmin: f64,
    tmax: f64,
) -> LanesX4<F> {
    let over_a = OverA::ByInverse(dirs.inv_a);
    let (f, k) = sphere.splat();
    roots_x4(f, k, &dirs.d, dirs.a, dirs.finite, over_a, tmin, tmax)
}

/// [`interval_x4_of`] for four (sphere, ray) pairs at once: lane i tests `spheres[i]`
/// against the packet's lane `lanes[i]` (directions `dirs`), with the same steps on the same
/// values, so each lane's answer is the same bits as in [`interval_x4_of`]. For a packet whose
/// lanes each meet a different sphere, where [`interval_x4_of`] would test one lane of four.
#[inline(always)]
pub fn interval_x4_gathered<F: Lanes64>(
    spheres: [&FromOrigin; 4],
    dirs: &DirectionLanes,
    lanes: [usize; 4],
    tmin: f64,
    tmax: f64,
) -> LanesX4<F> {
    let d = dirs.gather::<F>(lanes);
    let [s0, s1, s2, s3] = spheres;
    let f = [
        gathered([s0.f[0], s1.f[0], s2.f[0], s3.f[0]]),
        gathered([s0.f[1], s1.f[1], s2.f[1], s3.f[1]]),
        gathered([s0.f[2], s1.f[2], s2.f[2], s3.f[2]]),
    ];
    let k = gathered([s0.k, s1.k, s2.k, s3.k]);
    let over_a = OverA::ByInverse(d.inv_a);
    roots_x4(f, k, &d.d, d.a, d.finite, over_a, tmin, tmax)
}

/// a = d·d per lane, as an interval, and the lanes where d is finite.
#[inline(always)]
fn squared_length_x4<F: Lanes64>(d: &[F; 3]) -> (IntervalX4<F>, F) {
    let a = IntervalX4::point(d[0]).square()
        + IntervalX4::point(d[1]).square()
        + IntervalX4::point(d[2]).square();
    (a, d[0].is_finite() & d[1].is_finite() & d[2].is_finite())
}

/// The roots' lanes, for the sphere's f = o − c and k = f·f − r² per lane, given a = d·d,
/// the lanes where d is finite, and x ↦ x/a (`over_a`, for lanes with a.lo > 0).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn roots_x4<F: Lanes64>(
    f: [IntervalX4<F>; 3],
    k: IntervalX4<F>,
    d: &[F; 3],
    a: IntervalX4<F>,
    finite: F,
    over_a: OverA<F>,
    tmin: f64,
    tmax: f64,
) -> LanesX4<F> {
    let b = idot_x4(&f, d);
    let disc = b.square() - a * k;
    let zero = F::splat(0.0);
    let miss_line = finite & disc.hi.simd_lt(zero);
    let crosses = finite & disc.lo.simd_gt(zero) & a.lo.simd_gt(zero);
    let root = disc.sqrt();
    let t0 = over_a.apply(-b - root, a);
    let t1 = over_a.apply(-b + root, a);
    let (tmin, tmax) = (F::splat(tmin), F::splat(tmax));
    let ok = crosses & t0.finite() & t1.finite();
    // As `interval`: the near root unless it is certainly at or before tmin.
    let near_before = t0.hi.simd_le(tmin);
    let hit0 = !near_before & t0.lo.simd_gt(tmin) & t0.hi.simd_lt(tmax);
    let hit1 = near_before & t1.lo.simd_gt(tmin) & t1.hi.simd_lt(tmax);
    let miss = (!near_before & t0.lo.simd_ge(tmax))
        | (near_before & (t1.hi.simd_le(tmin) | t1.lo.simd_ge(tmax)));
    LanesX4 {
        hit: ok & (hit0 | hit1),
        miss: miss_line | (ok & miss),
        lo: near_before.bitselect(t1.lo, t0.lo),
        hi: near_before.bitselect(t1.hi, t0.hi),
    }
}

#[cfg(feature = "unit-tests")]
#[deny(dead_code)]
pub(crate) mod tests {
    use super::FromOrigin;
    use crate::math::interval::Interval;
    use num_rational::BigRational;

    fn exact(x: f64) -> BigRational {
        BigRational::from_float(x).expect("finite")
    }

    fn encloses(x: Interval, want: &BigRational) -> bool {
        exact(x.lo) <= *want && *want <= exact(x.hi)
    }

    /// The packets' preparation of a sphere encloses the exact f = o − c and k = f·f − r², and
    /// k's interval stays within 2⁻⁴⁵ of the terms' size: on f32 values from 2⁻⁶⁰ to 2⁶⁰ of
    /// both signs, with a coordinate equal to the origin's (f's 0 exactly) or all three (f =
    /// 0), the origin exactly on the sphere (k = 0) or rounded onto it (k a few ulps of r²
    /// either side), radii 2³⁰ smaller than the distance (r² vanishes in f·f's rounding), and
    /// the extremes of f32: subnormals and values near 2¹²⁷.
    fn packets_preparation_encloses_the_exact_values() {
        let mut x = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = move || crate::math::xorshift(&mut x);
        let mut value = move || {
            let bits = next();
            let e = (bits % 121) as i32 - 60;
            let m = 1.0 + (bits >> 8) as f64 / (1u64 << 56) as f64;
            let sign = if bits & 0x80 == 0 { 1.0 } else { -1.0 };
            (sign * m * 2f64.powi(e)) as f32
        };
        for i in 0..20_000 {
            let mut o = [value(), value(), value()];
            let mut c = [value(), value(), value()];
            let mut r = value().abs();
            match i % 8 {
                0 => c[i % 3] = o[i % 3],
                1 => (o, c) = ([r, 0.0, 0.0], [0.0; 3]),
                2 => r = o[0].abs().max(c[0].abs()) * 2f32.powi(-30),
                3 => c = o,
                4 => {
                    // On the sphere as far as f32 goes: o = c + r·(0.6, 0.8, 0), rounded.
                    o = [c[0] + r * 0.6, c[1] + r * 0.8, c[2]];
                }
                5 => {
                    let tiny = f32::from_bits(1 + (i as u32 % 1000));
                    (o, c, r) = ([tiny, -tiny, 0.0], [-tiny, 0.0, tiny], tiny);
                }
                6 => {
                    let big = f32::MAX / (1 + i % 5) as f32;
                    (o, c, r) = ([big, -big, big], [-big, big, 0.0], big);
                }
                _ => {}
            }
            let (o64, c64, r64) = (o.map(f64::from), c.map(f64::from), f64::from(r));
            let from = FromOrigin::for_packets(o64, c64, r64);
            let f = [0, 1, 2].map(|k| exact(o64[k]) - exact(c64[k]));
            for (k, (got, want)) in from.f.iter().zip(&f).enumerate() {
                assert!(encloses(*got, want), "{o:?} {c:?}: f{k} {got:?}");
            }
            let ff = &f[0] * &f[0] + &f[1] * &f[1] + &f[2] * &f[2];
            let want = &ff - exact(r64) * exact(r64);
            assert!(encloses(from.k, &want), "{o:?} {c:?} {r}: k {:?}", from.k);
            let size = f.iter().map(|x| x * x).sum::<BigRational>() + exact(r64 * r64);
            let width = exact(from.k.hi) - exact(from.k.lo);
            assert!(
                width <= size * exact(2f64.powi(-45)) + exact(1e-300),
                "{o:?} {c:?} {r}: k {:?}",
                from.k
            );
        }
    }

    /// This module's tests, for tests/unit.rs to run.
    pub(crate) const TESTS: &[(&str, fn())] = &[(
        "packets_preparation_encloses_the_exact_values",
        packets_preparation_encloses_the_exact_values,
    )];
}
