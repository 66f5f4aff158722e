//! The hard-case suite against exact references: every f32 input is an exact rational, and
//! each ray/triangle answer is decided in exact rational arithmetic (`num-rational`): hit or
//! miss for the closed triangle, the nearest primitive (exact ties to the lower index), and t.
//!
//! Families (fixed seeds, several hundred rays each): closed meshes hit exactly at shared edges
//! and vertices from inside and outside, grazing rays, far geometry, tiny and huge triangles,
//! large offsets, near-coincident surfaces, the Cornell box. Per family and method it counts
//! leaks (exact hit, answered miss), false hits, wrong nearest primitive, and the relative t
//! error, and prints the table (`cargo test --release --test hard_cases -- --nocapture`).
//!
//! Asserted today for the default (watertight, f32): no leaks and no false hits from inside
//! closed meshes (unit, tiny, huge, offset), and none on the Cornell box. "Wrong nearest" is
//! counted against the exact rule that an exact tie goes to the lower index: rays aimed exactly
//! at a shared edge hit both triangles at the same t, and the float methods pick either. Those
//! counts, silhouette grazes from outside and near-coincident surfaces are reported, not
//! asserted: making them zero is the adaptive-precision work of issue 5.

mod common;

use common::{cube, icosphere, vertices_and_edge_midpoints, Rng};
use num_rational::BigRational;
use num_traits::{ToPrimitive, Zero};
use raylab::accel;
use raylab::geometry::{Method, Ray, Shape};

type Q = BigRational;

fn q(x: f32) -> Q {
    Q::from_float(x).expect("finite")
}

/// Exact nearest hit: (t as a rational, primitive), ties to the lower index.
fn exact_nearest(shapes: &[Shape<f32>], ray: &Ray<f32>, tmin: f32, tmax: f32) -> Option<(Q, u32)> {
    let o = ray.o.map(q);
    let d = ray.d.map(q);
    let (tmin, tmax) = (
        q(tmin),
        if tmax.is_finite() {
            Some(q(tmax))
        } else {
            None
        },
    );
    let sub = |a: &[Q; 3], b: &[Q; 3]| [&a[0] - &b[0], &a[1] - &b[1], &a[2] - &b[2]];
    let cross = |a: &[Q; 3], b: &[Q; 3]| {
        [
            &a[1] * &b[2] - &a[2] * &b[1],
            &a[2] * &b[0] - &a[0] * &b[2],
            &a[0] * &b[1] - &a[1] * &b[0],
        ]
    };
    let dot = |a: &[Q; 3], b: &[Q; 3]| &a[0] * &b[0] + &a[1] * &b[1] + &a[2] * &b[2];
    let mut best: Option<(Q, u32)> = None;
    for (i, s) in shapes.iter().enumerate() {
        let Shape::Triangle(v) = s else { continue };
        let v = v.map(|p| p.map(q));
        let e1 = sub(&v[1], &v[0]);
        let e2 = sub(&v[2], &v[0]);
        let p = cross(&d, &e2);
        let det = dot(&e1, &p);
        if det.is_zero() {
            continue; // in the plane or degenerate: a miss by convention
        }
        let s0 = sub(&o, &v[0]);
        let qv = cross(&s0, &e1);
        let b1 = dot(&s0, &p) / &det;
        let b2 = dot(&d, &qv) / &det;
        let t = dot(&e2, &qv) / &det;
        let inside = b1 >= Q::zero() && b2 >= Q::zero() && &b1 + &b2 <= Q::from_integer(1.into());
        let in_range = t > tmin && tmax.as_ref().is_none_or(|m| &t < m);
        if inside && in_range && best.as_ref().is_none_or(|(bt, _)| &t < bt) {
            best = Some((t, i as u32));
        }
    }
    best
}

#[derive(Default)]
struct Counts {
    rays: usize,
    leaks: usize,
    false_hits: usize,
    wrong_nearest: usize,
    rel_errors: Vec<f64>,
}

impl Counts {
    fn median_rel(&self) -> f64 {
        let mut e = self.rel_errors.clone();
        e.sort_by(f64::total_cmp);
        e.get(e.len() / 2).copied().unwrap_or(0.0)
    }
}

/// Runs every method in f32 and f64 on `rays`; returns the counts in the order of `VARIANTS`.
fn evaluate(shapes: &[Shape<f32>], rays: &[Ray<f32>]) -> Vec<Counts> {
    let shapes64: Vec<Shape<f64>> = shapes
        .iter()
        .map(|s| match s {
            Shape::Triangle(v) => Shape::Triangle(v.map(|p| p.map(f64::from))),
            Shape::Sphere { centre, radius } => Shape::Sphere {
                centre: centre.map(f64::from),
                radius: *radius as f64,
            },
        })
        .collect();
    let mut out: Vec<Counts> = (0..6).map(|_| Counts::default()).collect();
    for ray in rays {
        let exact = exact_nearest(shapes, ray, 0.0, f32::INFINITY);
        let ray64 = Ray::new(ray.o.map(f64::from), ray.d.map(f64::from));
        for (k, method) in Method::ALL.into_iter().enumerate() {
            let got32 = accel::closest_hit(shapes, ray, method, 0.0, f32::INFINITY)
                .map(|h| (h.t as f64, h.prim));
            let got64 = accel::closest_hit(&shapes64, &ray64, method, 0.0, f64::INFINITY)
                .map(|h| (h.t, h.prim));
            for (idx, got) in [(k, got32), (3 + k, got64)] {
                let c = &mut out[idx];
                c.rays += 1;
                match (&exact, got) {
                    (Some(_), None) => c.leaks += 1,
                    (None, Some(_)) => c.false_hits += 1,
                    (Some((t, prim)), Some((gt, gprim))) => {
                        if *prim != gprim {
                            c.wrong_nearest += 1;
                        } else {
                            let t = t.to_f64().unwrap();
                            c.rel_errors.push(((gt - t) / t).abs());
                        }
                    }
                    (None, None) => {}
                }
            }
        }
    }
    out
}

const VARIANTS: [&str; 6] = [
    "watertight f32",
    "moller f32",
    "cramer f32",
    "watertight f64",
    "moller f64",
    "cramer f64",
];

fn report(family: &str, counts: &[Counts]) {
    for (name, c) in VARIANTS.iter().zip(counts) {
        println!(
            "| {family} | {name} | {} | {} | {} | {} | {:.1e} |",
            c.rays,
            c.leaks,
            c.false_hits,
            c.wrong_nearest,
            c.median_rel()
        );
    }
}

/// Rays from `origins` at every vertex and edge midpoint of `mesh`.
fn aimed_rays(mesh: &[Shape<f32>], origins: &[[f32; 3]]) -> Vec<Ray<f32>> {
    let targets = vertices_and_edge_midpoints(mesh);
    origins
        .iter()
        .flat_map(|o| {
            targets
                .iter()
                .map(move |p| Ray::new(*o, [0, 1, 2].map(|k| p[k] - o[k])))
        })
        .collect()
}

fn random_points(rng: &mut Rng, n: usize, lo: f64, hi: f64) -> Vec<[f32; 3]> {
    (0..n)
        .map(|_| [0, 1, 2].map(|_| rng.range(lo, hi) as f32))
        .collect()
}

#[test]
fn closed_meshes_at_shared_edges_and_vertices() {
    let mut rng = Rng(101);
    let cube_mesh = cube(2, 2.0, [-1.0; 3]);
    let inside = evaluate(
        &cube_mesh,
        &aimed_rays(&cube_mesh, &random_points(&mut rng, 3, -0.9, 0.9)),
    );
    report("cube, from inside", &inside);
    assert_eq!(
        inside[0].leaks + inside[0].false_hits,
        0,
        "watertight f32: no ray leaves the closed cube"
    );
    // From outside, rays aimed at silhouette edges touch the mesh only at the edge, where
    // rounding decides (the f32 methods call some near-touches hits, and miss some exact
    // touches): reported, not asserted.
    let outside = evaluate(
        &cube_mesh,
        &aimed_rays(&cube_mesh, &random_points(&mut rng, 2, 2.0, 4.0)),
    );
    report("cube, from outside", &outside);

    let ico = icosphere(1, 1.0, [0.0; 3]);
    let rays = aimed_rays(&ico, &random_points(&mut rng, 3, -0.5, 0.5));
    let counts = evaluate(&ico, &rays);
    report("icosphere, from inside", &counts);
    assert_eq!(
        counts[0].leaks + counts[0].false_hits,
        0,
        "no ray slips through the closed icosphere"
    );
}

#[test]
fn tiny_huge_and_offset_meshes() {
    let mut rng = Rng(102);
    for (family, size, offset) in [
        ("tiny cube 2^-17", 2f32.powi(-17), [0.0f32; 3]),
        ("huge cube 2^17", 2f32.powi(17), [0.0; 3]),
        ("cube at 1e4", 64.0, [1e4, -1e4, 2e4]),
        ("cube at 1e6", 4096.0, [1e6, 1e6, -1e6]),
    ] {
        let mesh = cube(2, size, offset);
        let origins: Vec<[f32; 3]> = (0..4)
            .map(|_| [0, 1, 2].map(|k| offset[k] + size * rng.range(0.1, 0.9) as f32))
            .collect();
        let counts = evaluate(&mesh, &aimed_rays(&mesh, &origins));
        report(family, &counts);
        assert_eq!(
            counts[0].leaks + counts[0].false_hits,
            0,
            "{family}: watertight leaked"
        );
    }
}

#[test]
fn grazing_far_and_near_coincident() {
    let mut rng = Rng(103);
    // Grazing: a big triangle in z = 0, rays at 1e-1..1e-6 rad aimed near its edge x = 0.
    let tri = vec![Shape::Triangle([
        [0.0, -4.0, 0.0],
        [0.0, 4.0, 0.0],
        [8.0, 0.0, 0.0],
    ])];
    let mut rays = Vec::new();
    for e in 1..=6 {
        let a = 10f64.powi(-e);
        for _ in 0..60 {
            let az = rng.range(0.0, std::f64::consts::TAU);
            let x = rng.range(-1e-3, 1e-3);
            let dir = [a.cos() * az.cos(), a.cos() * az.sin(), a.sin()];
            let target = [x, rng.range(-1.0, 1.0), 0.0];
            let o = [0, 1, 2].map(|k| (target[k] - 2.0 * dir[k]) as f32);
            rays.push(Ray::new(o, dir.map(|c| c as f32)));
        }
    }
    report("grazing 1e-1..1e-6 rad", &evaluate(&tri, &rays));

    // Far: unit-ish triangles at 1e3..1e6 seen from the origin.
    let mut shapes = Vec::new();
    let mut rays = Vec::new();
    for e in 3..=6 {
        let dist = 10f32.powi(e);
        let c = [dist * 0.6, dist * 0.8, rng.range(-1.0, 1.0) as f32];
        let s = dist * 1e-3;
        shapes.push(Shape::Triangle([
            [c[0] - s, c[1], c[2] - s],
            [c[0] + s, c[1], c[2] - s],
            [c[0], c[1], c[2] + s],
        ]));
        for _ in 0..100 {
            let p = [
                c[0] + s * rng.range(-1.2, 1.2) as f32,
                c[1],
                c[2] + s * rng.range(-1.2, 1.2) as f32,
            ];
            rays.push(Ray::new([0.0; 3], p));
        }
    }
    report("far 1e3..1e6", &evaluate(&shapes, &rays));

    // Near-coincident: parallel triangles 1e-3..1e-7 apart; which is nearer?
    let mut shapes = Vec::new();
    let mut rays = Vec::new();
    for (k, gap) in [1e-3f32, 1e-5, 1e-6, 1e-7].into_iter().enumerate() {
        let x = 10.0 * k as f32;
        let z = 1.0f32;
        shapes.push(Shape::Triangle([
            [x - 1.0, -1.0, z + gap],
            [x + 1.0, -1.0, z + gap],
            [x, 1.0, z + gap],
        ]));
        shapes.push(Shape::Triangle([
            [x - 1.0, -1.0, z],
            [x + 1.0, -1.0, z],
            [x, 1.0, z],
        ]));
        for _ in 0..100 {
            let p = [
                x + rng.range(-0.4, 0.4) as f32,
                rng.range(-0.8, 0.2) as f32,
                z,
            ];
            let o = [x, 0.0, -1.0];
            rays.push(Ray::new(o, [0, 1, 2].map(|c| p[c] - o[c])));
        }
    }
    report("parallel 1e-3..1e-7 apart", &evaluate(&shapes, &rays));
}

#[test]
fn cornell_primary_rays_and_its_edges() {
    let scene = raylab::Scene::cornell();
    let cam = raylab::Camera::cornell(64);
    let mut rays: Vec<Ray<f32>> = (0..48)
        .flat_map(|j| (0..64).map(move |i| (i, j)))
        .map(|(i, j)| cam.ray_for_pixel(i, j, 64, 48))
        .collect();
    let o = cam.ray_for_pixel(0, 0, 64, 48).o;
    rays.extend(
        vertices_and_edge_midpoints(&scene.shapes)
            .into_iter()
            .map(|p| Ray::new(o, [0, 1, 2].map(|k| p[k] - o[k]))),
    );
    let counts = evaluate(&scene.shapes, &rays);
    report("Cornell primary + edges/vertices", &counts);
    assert_eq!(counts[0].leaks + counts[0].false_hits, 0);
}
