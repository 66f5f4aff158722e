//! The f64 plane t bound holds the exact t; the f64 filter's answers are the exact ones;
//! [`rounded_t`] agrees with the exact rounding.

use super::rounded::plane_t_f64;
use super::*;
use crate::geometry::exact;
use proptest::prelude::*;
use std::cmp::Ordering;

/// A float of any magnitude from 2⁻¹⁹⁵ to 2¹⁹⁵ (the bound's range), either sign.
fn wide() -> impl Strategy<Value = f64> {
    (-1.0f64..1.0, -195i32..195).prop_map(|(m, e)| m * 2f64.powi(e))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(3000))]
    /// plane_t_f64's bound holds the exact t, for grazing rays (d nearly in the plane)
    /// and for coordinates of any magnitude in its range.
    fn the_f64_plane_t_bound_holds_the_exact_t(
        v in prop::array::uniform3(prop::array::uniform3(-4.0f64..4.0)),
        o in prop::array::uniform3(-8.0f64..8.0),
        b in (0.0f64..1.0, 0.0f64..1.0),
        tilt in -60i32..0,
        scale in -190i32..190,
        wild in prop::array::uniform3(wide()),
    ) {
        let s = 2f64.powi(scale);
        let v = v.map(|p| p.map(|x| x * s));
        let o = o.map(|x| x * s);
        // Aim at a point of the plane, then tilt d into the plane by 2^tilt.
        let target = [0, 1, 2].map(|k| v[0][k] + b.0 * (v[1][k] - v[0][k]) + b.1 * (v[2][k] - v[0][k]));
        let along = [0, 1, 2].map(|k| v[1][k] - v[0][k]);
        let w = 2f64.powi(tilt);
        for d in [
            [0, 1, 2].map(|k| target[k] - o[k]),
            [0, 1, 2].map(|k| along[k] + w * (target[k] - o[k])),
            wild,
        ] {
            let Some((t, err)) = plane_t_f64(o, d, &v) else { continue };
            let exact = exact::plane_t(o, d, &v).expect("not parallel where the bound holds");
            prop_assert_ne!(exact.cmp_f(t - err), Ordering::Less, "t {} err {}", t, err);
            prop_assert_ne!(exact.cmp_f(t + err), Ordering::Greater, "t {} err {}", t, err);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(3000))]
    /// Whatever the f64 filter decides is exact: a miss has edge signs of both kinds (or the
    /// line lies in the plane), a hit has them all alike and its interval holds the exact t;
    /// for rays aimed at an edge or a vertex (most left unsure), rays from 10⁻⁶ to 10¹⁰
    /// triangle sizes away, and coordinates of any magnitude in its range.
    fn the_f64_filter_decides_exactly(
        v in prop::array::uniform3(prop::array::uniform3(-4.0f64..4.0)),
        o in prop::array::uniform3(-1.0f64..1.0),
        b in (0.0f64..1.0, 0.0f64..1.0),
        away in -6i32..10,
        scale in -80i32..80,
        snap in 0usize..4,
        wild in prop::array::uniform3(wide()),
    ) {
        let s = 2f64.powi(scale);
        let v = v.map(|p| p.map(|x| (x * s) as f32 as f64));
        let o = o.map(|x| (x * s * 10f64.powi(away)) as f32 as f64);
        // Aim inside, at edge v0–v1, at vertex v2, or at random.
        let (b1, b2) = match snap {
            0 => b,
            1 => (b.0, 0.0),
            _ => (0.0, 1.0),
        };
        let target = [0, 1, 2].map(|k| v[0][k] + b1 * (v[1][k] - v[0][k]) + b2 * (v[2][k] - v[0][k]));
        for d in [[0, 1, 2].map(|k| ((target[k] - o[k]) as f32) as f64), wild] {
            let est = triangle_f64(o, d, &v);
            if est == Estimate::Unsure {
                continue;
            }
            let signs = [(1, 2), (2, 0), (0, 1)].map(|(i, j)| {
                exact::orient(d, o, v[i], v[j])
                    .unwrap_or_else(|| exact::orient_rational(d, o, v[i], v[j]))
            });
            let both = signs.contains(&Ordering::Less) && signs.contains(&Ordering::Greater);
            let flat = signs.iter().all(|s| *s == Ordering::Equal);
            match est {
                Estimate::Miss => prop_assert!(both || flat, "a miss with signs {:?}", signs),
                Estimate::Hit(a) => {
                    prop_assert!(!both && !flat && !signs.contains(&Ordering::Equal),
                        "a hit with signs {:?}", signs);
                    let t = exact::plane_t(o, d, &v).expect("a hit is not parallel");
                    prop_assert_ne!(t.cmp_f(a.lo), Ordering::Less, "{:?}", a);
                    prop_assert_ne!(t.cmp_f(a.hi), Ordering::Greater, "{:?}", a);
                }
                Estimate::Unsure => unreachable!(),
            }
        }
    }
}

fn rounded_t_agrees_with_the_exact_rounding_on_both_levels() {
    // A grazing ray: the f64 bound cannot decide the f32 rounding of a t whose
    // d·n cancels this far, so the integer level gives it (exactly 1/4).
    let v = [
        [0.0, 0.0, 0.0],
        [1.4742268323898315, 0.0, 1.9907678365707397],
        [0.0, 1.0, 0.0],
    ];
    let o = [0.4116266369819641, 0.25, 0.5558527708053589];
    let d = [1.3019471168518066, 0.0, 1.758124589920044];
    let tri32 = Shape::from(v.map(|p| p.map(|x| x as f32)));
    let ray32 = Ray::new(o.map(|x| x as f32), d.map(|x| x as f32));
    assert_eq!(rounded_t(&tri32, &ray32, 0.0, f32::INFINITY), Some(0.25));
    // A plain ray: decided by the f64 bound, equal to the exact rounding.
    let ray = Ray::new([0.1f32, 0.2, -3.0], [0.013, -0.02, 1.0]);
    let tri = [[-1.0f32, -1.0, 1.0], [1.0, -1.0, 1.0], [0.0, 1.0, 1.0]];
    let wide = tri.map(|p| p.map(f64::from));
    let (o, d) = (ray.o.map(f64::from), ray.d.map(f64::from));
    let (t, err) = plane_t_f64(o, d, &wide).unwrap();
    assert_eq!((t - err) as f32, (t + err) as f32);
    let exact: f32 = exact::plane_t(o, d, &wide).unwrap().rounded();
    assert_eq!(
        rounded_t(&Shape::from(tri), &ray, 0.0, f32::INFINITY),
        Some(exact)
    );
    assert_eq!(exact::plane_t_rounded::<f32>(o, d, &wide), Some(exact));
}

/// This module's tests, for tests/unit.rs to run.
pub(crate) const TESTS: &[(&str, fn())] = &[
    (
        "the_f64_plane_t_bound_holds_the_exact_t",
        the_f64_plane_t_bound_holds_the_exact_t,
    ),
    (
        "the_f64_filter_decides_exactly",
        the_f64_filter_decides_exactly,
    ),
    (
        "rounded_t_agrees_with_the_exact_rounding_on_both_levels",
        rounded_t_agrees_with_the_exact_rounding_on_both_levels,
    ),
];
