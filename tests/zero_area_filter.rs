//! The exact zero-area test ([`raylab::geometry::triangle::zero_area`]): a triangle with area
//! is decided by an f64 filter whatever its coordinates' binary expansions (0.1 as well as
//! 0.5), so f64 scenes of decimal coordinates never reach rationals; triangles of zero area,
//! or nearly, are decided exactly. One test: the counts it reads are global.

use raylab::geometry::adaptive::levels::{self, Event};
use raylab::geometry::exact::{orient_rational, two_sum};
use raylab::geometry::triangle::{self, zero_area};
use raylab::geometry::{Method, Ray, Shape, Triangle};
use raylab::scene::ObjFrame;
use std::cmp::Ordering;
use std::path::Path;

/// Zero area in rationals: every component of (v₁ − v₀) × (v₂ − v₀), the determinant
/// det[e_k, v₁ − v₀, v₂ − v₀], is 0.
fn zero_area_rational(v: &[[f64; 3]; 3]) -> bool {
    (0..3).all(|k| {
        let mut e = [0.0; 3];
        e[k] = 1.0;
        orient_rational(e, v[0], v[1], v[2]) == Ordering::Equal
    })
}

fn next(x: &mut u64) -> f64 {
    *x = x
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (*x >> 11) as f64 / (1u64 << 53) as f64
}

fn no_meshes(p: &Path, _: ObjFrame, _: [f32; 3]) -> Result<raylab::Scene, String> {
    Err(format!("no mesh {}", p.display()))
}

/// One ulp up.
fn up(x: f64) -> f64 {
    x.next_up()
}

#[test]
fn triangles_with_area_are_decided_by_the_filter_and_zero_area_exactly() {
    levels::count_levels(true);
    levels::reset();
    let exact = || levels::count(Event::ZeroAreaExact);
    let rational = || levels::count(Event::ZeroAreaRational);

    // A stack of 400 triangles of decimal coordinates (differences not exact in f64), parsed
    // in f64 and traced by Möller–Trumbore through their middle: every hit is Möller's own,
    // and no zero-area question reaches the exact levels.
    let mut seed = 7;
    let mut text = String::new();
    for k in 0..400 {
        let mut c = |base: f64| format!("{:.13}", base + 0.01 * next(&mut seed));
        let z = 1000.0 - k as f64;
        text += &format!(
            "tri {} {} {} {} {} {} {} {} {}\n",
            c(-10.09),
            c(-10.29),
            c(z),
            c(10.7),
            c(-10.12),
            c(z),
            c(0.11),
            c(10.9),
            c(z)
        );
    }
    let d =
        raylab::scene::file::parse::<f64>("stack.scene", &text, Path::new(""), &no_meshes).unwrap();
    assert!(d.warnings.is_empty(), "{:?}", d.warnings);
    let shapes = d.shapes;
    let Shape::Triangle(Triangle(v)) = shapes[0] else {
        panic!("a triangle")
    };
    assert_ne!(two_sum(v[1][0], -v[0][0]).1, 0.0, "an inexact difference");
    let mut hits = 0;
    for i in 0..200 {
        let o = [next(&mut seed) - 0.5, next(&mut seed) - 0.5, -5.0];
        let ray = Ray::new(o, [0.0, 0.0, 1.0]);
        for s in &shapes {
            let Shape::Triangle(Triangle(v)) = s else {
                panic!("triangles")
            };
            let plain = triangle::moller(ray.o, ray.d, v, 0.0, f64::INFINITY);
            let hit = s.intersect(&ray, Method::Moller, 0.0, f64::INFINITY);
            assert_eq!(hit, plain, "ray {i}");
            hits += hit.is_some() as usize;
        }
    }
    assert_eq!(hits, 200 * 400);
    assert_eq!((exact(), rational()), (0, 0), "the filter decides them all");

    // Exactly collinear, with differences not exact in f64: on x = y = z, and on y = 2x
    // (doubling is exact) at a height of 0.3.
    let diagonal = [0.1, 3.7, 12345.678].map(|x| [x, x, x]);
    let doubled = [0.1, 0.7, 1.3e5].map(|x| [x, 2.0 * x, 0.3]);
    let far = [1e-3, 0.3, 7e4].map(|x| [x, -3.0 * x, 5.0 * x]);
    for v in [diagonal, doubled] {
        assert_ne!(two_sum(v[2][0], -v[0][0]).1, 0.0, "an inexact difference");
        assert!(zero_area(&v), "{v:?}");
        assert!(zero_area_rational(&v), "{v:?}");
    }
    // (Not collinear after all where −3x or 5x rounds: the exact answer stands.)
    assert_eq!(zero_area(&far), zero_area_rational(&far));
    // Each coordinate of each vertex one ulp off: area, however little.
    for v in [diagonal, doubled] {
        for (p, k) in (0..3).flat_map(|p| (0..3).map(move |k| (p, k))) {
            let mut w = v;
            w[p][k] = up(w[p][k]);
            assert!(!zero_area_rational(&w), "{w:?}");
            assert!(!zero_area(&w), "{w:?}");
        }
    }
    // At random, compared with rationals: exactly collinear (dyadic points o + t·d, exact),
    // and nearly (decimal o and d: each point rounded), some rounded to f32 and widened.
    let (mut zero, mut area) = (0, 0);
    for i in 0..3000 {
        let mut r = || next(&mut seed) * 2.0 - 1.0;
        let scale = [1e-3, 1.0, 1e3, 1e9][i % 4];
        let dyadic = |x: f64, n: f64| (x * n).round() / n;
        let (o, d) = match i % 2 {
            0 => (
                [0, 1, 2].map(|_| dyadic(r() * scale, 1024.0)),
                [0, 1, 2].map(|_| dyadic(r(), 64.0)),
            ),
            _ => ([r() * scale, r() * scale, r() * scale], [r(), r(), r()]),
        };
        let ts = [r(), r(), r()].map(|t| dyadic(t, 8.0));
        let mut v = ts.map(|t| [0, 1, 2].map(|k| o[k] + t * d[k]));
        if i % 5 == 0 {
            v = v.map(|p| p.map(|c| c as f32 as f64));
        }
        let expected = zero_area_rational(&v);
        assert_eq!(zero_area(&v), expected, "{v:?}");
        match expected {
            true => zero += 1,
            false => area += 1,
        }
    }
    assert!(
        zero > 100 && area > 100,
        "{zero} of zero area, {area} with area"
    );
    assert!(exact() > 0, "near-degenerate ones reach the exact level");
    assert_eq!(rational(), 0, "the expansions decide every one in range");
    // Past the expansions' range: rationals, exactly.
    let huge = [1e200, 3e200, -7e200].map(|x| [x, x, 0.5 * x]);
    assert!(zero_area(&huge));
    let mut tilted = huge;
    tilted[2][1] = up(tilted[2][1]);
    assert!(!zero_area(&tilted));
    assert_eq!(rational(), 2);
    levels::count_levels(false);
}
