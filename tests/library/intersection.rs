//! Ray/triangle and ray/sphere on hard cases: shared edges and vertices of closed meshes,
//! grazing rays, tiny and huge triangles, small far spheres, origins on a sphere.
//!
//! The default (adaptive) and the plain watertight method are held to zero failures; what the lecture's method and
//! Möller–Trumbore get on the same rays is printed (run with `--nocapture`), not asserted.

use crate::common;

use common::{cube, icosphere, vertices_and_edge_midpoints, Rng};
use raylab::accel::closest_hit;
use raylab::geometry::{sphere, Method, Ray, Shape, Sphere, Triangle};

fn sub(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// Rays from `origins` aimed at every vertex and edge midpoint of a closed mesh; each must hit
/// (from inside a closed mesh there is no way out). Returns the number of leaks per method,
/// and checks the t of every watertight hit: the target is on the first surface met, so the
/// hit lies within a few f32 ulps of the largest coordinate from it (the midpoints and the
/// direction are rounded to f32): |t − 1|·|d| ≤ 8·ulp.
fn leaks_from(mesh: &[Shape<f32>], origins: &[[f32; 3]]) -> [usize; 4] {
    let max_coord = mesh
        .iter()
        .flat_map(|s| match s {
            Shape::Triangle(Triangle(v)) => v.iter().flatten().map(|c| c.abs()).collect::<Vec<_>>(),
            Shape::Sphere(_) => vec![],
        })
        .fold(0.0f32, f32::max);
    let dist_tol = 8.0 * max_coord * f32::EPSILON;
    let targets = vertices_and_edge_midpoints(mesh);
    let mut leaks = [0usize; 4];
    for o in origins {
        for p in &targets {
            let ray = Ray::new(*o, sub(*p, *o));
            for (m, method) in Method::ALL.into_iter().enumerate() {
                match closest_hit(mesh, &ray, method, 0.0, f32::INFINITY) {
                    None => leaks[m] += 1,
                    Some(h) if matches!(method, Method::Watertight | Method::Adaptive) => {
                        let len = ray.d.iter().map(|c| c * c).sum::<f32>().sqrt();
                        let miss_by = (h.t - 1.0).abs() * len;
                        assert!(
                            miss_by <= dist_tol,
                            "t = {} aiming at {p:?} from {o:?}",
                            h.t
                        )
                    }
                    Some(_) => {}
                }
            }
        }
    }
    leaks
}

fn report(name: &str, rays: usize, leaks: [usize; 4]) {
    println!(
        "{name}: {rays} rays, leaks adaptive={} watertight={} moller={} cramer={}",
        leaks[0], leaks[1], leaks[2], leaks[3]
    );
    assert_eq!(leaks[0], 0, "{name}: the adaptive method leaked");
    assert_eq!(leaks[1], 0, "{name}: the watertight method leaked");
}

#[test]
fn closed_cube_has_no_cracks_from_inside() {
    let mesh = cube(8, 2.0, [-1.0, -1.0, -1.0]);
    assert_eq!(mesh.len(), 6 * 8 * 8 * 2);
    let mut rng = Rng(1);
    let mut origins: Vec<[f32; 3]> = (0..6)
        .map(|_| [0, 1, 2].map(|_| rng.range(-0.9, 0.9) as f32))
        .collect();
    origins.push([0.0, 0.0, 0.0]);
    origins.push([0.25, -0.5, 0.75]); // on the vertex grid's lines
    let n = origins.len() * vertices_and_edge_midpoints(&mesh).len();
    report("cube, inside", n, leaks_from(&mesh, &origins));
}

#[test]
fn closed_icosphere_has_no_cracks_from_inside() {
    let mesh = icosphere(3, 1.0, [0.0, 0.0, 0.0]);
    let mut rng = Rng(2);
    let origins: Vec<[f32; 3]> = (0..4)
        .map(|_| [0, 1, 2].map(|_| rng.range(-0.5, 0.5) as f32))
        .chain([[0.0; 3]])
        .collect();
    let n = origins.len() * vertices_and_edge_midpoints(&mesh).len();
    report("icosphere, inside", n, leaks_from(&mesh, &origins));
}

#[test]
fn closed_meshes_far_away_and_offset_have_no_cracks() {
    // The same cube translated by 1e4 (f32 spacing there is 1e-3) and an icosphere at 1e5.
    let mesh = cube(4, 64.0, [10_000.0, -10_240.0, 20_480.0]);
    let origins = [
        [10_017.25, -10_200.5, 20_500.125],
        [10_032.0, -10_208.0, 20_512.0],
    ];
    let n = origins.len() * vertices_and_edge_midpoints(&mesh).len();
    report("cube at 1e4, inside", n, leaks_from(&mesh, &origins));

    let mesh = icosphere(2, 100.0, [1e5, 2e5, -1e5]);
    let origins = [[1e5, 2e5, -1e5], [1e5 + 20.0, 2e5 - 30.0, -1e5 + 10.0]];
    let n = origins.len() * vertices_and_edge_midpoints(&mesh).len();
    report("icosphere at 1e5, inside", n, leaks_from(&mesh, &origins));
}

#[test]
fn tiny_closed_mesh_has_no_cracks() {
    // A cube of side 2^-17 ≈ 7.6e-6 near the origin: an |det| < 1e-8 test would drop it whole.
    let s = 2f32.powi(-17);
    let mesh = cube(4, s, [0.0, 0.0, 0.0]);
    let origins = [[s * 0.5, s * 0.25, s * 0.75], [s * 0.3, s * 0.6, s * 0.1]];
    let n = origins.len() * vertices_and_edge_midpoints(&mesh).len();
    report("tiny cube, inside", n, leaks_from(&mesh, &origins));
}

#[test]
fn rays_from_outside_hit_shared_edges_and_vertices_of_faces() {
    // Aim from outside at every interior vertex and edge midpoint of the front face (z = −1):
    // all lie on the first surface, none on a silhouette.
    let mesh = cube(8, 2.0, [-1.0, -1.0, -1.0]);
    let mut rng = Rng(3);
    let targets: Vec<[f32; 3]> = vertices_and_edge_midpoints(&mesh)
        .into_iter()
        .filter(|p| p[2] == -1.0 && p[0].abs() < 1.0 && p[1].abs() < 1.0)
        .collect();
    assert!(targets.len() > 200);
    let mut leaks = [0usize; 4];
    let mut wrong_t = 0;
    for p in &targets {
        let o = [
            rng.range(-3.0, 3.0) as f32,
            rng.range(-3.0, 3.0) as f32,
            -4.0,
        ];
        let ray = Ray::new(o, sub(*p, o));
        for (m, method) in Method::ALL.into_iter().enumerate() {
            match closest_hit(&mesh, &ray, method, 0.0, f32::INFINITY) {
                None => leaks[m] += 1,
                Some(h)
                    if matches!(method, Method::Watertight | Method::Adaptive)
                        && (h.t - 1.0).abs() > 1e-6 =>
                {
                    wrong_t += 1
                }
                Some(_) => {}
            }
        }
    }
    report("cube front face, outside", targets.len(), leaks);
    assert_eq!(wrong_t, 0);
}

/// The exact t where the f32 ray o + t·d meets the plane z = 0, in f64 (o, d exact inputs).
fn t_plane_z0(ray: &Ray<f32>) -> f64 {
    -(ray.o[2] as f64) / ray.d[2] as f64
}

#[test]
fn grazing_rays_inside_and_just_outside_an_edge() {
    // Triangle in z = 0 with an edge along x = 0 (from (0,-1) to (0,1)), extending to x = 2.
    let tri = Shape::from([[0.0, -1.0, 0.0], [0.0, 1.0, 0.0], [2.0, 0.0, 0.0]]);
    let mut bad = [0usize; 4];
    let mut worst_rel_t = 0.0f64;
    let mut rays = 0;
    for exp in 1..=6 {
        let angle = 10f64.powi(-exp);
        for k in 0..40 {
            let azimuth = k as f64 * std::f64::consts::TAU / 40.0;
            // Aim at points inside (x = +0.05, well inside) and outside (x = −0.05) the edge.
            for (x, inside) in [(0.05f64, true), (-0.05, false), (0.5, true), (-0.5, false)] {
                let target = [x, 0.1, 0.0];
                let dir = [
                    angle.cos() * azimuth.cos(),
                    angle.cos() * azimuth.sin(),
                    angle.sin(),
                ];
                let o = [0, 1, 2].map(|c| (target[c] - 3.0 * dir[c]) as f32);
                let d = dir.map(|c| c as f32);
                let ray = Ray::new(o, d);
                // Where the f32 ray really crosses z = 0, decided in f64.
                let t_ref = t_plane_z0(&ray);
                let px = o[0] as f64 + t_ref * d[0] as f64;
                let py = o[1] as f64 + t_ref * d[1] as f64;
                let really_inside = px >= 0.0 && py.abs() <= 1.0 - px / 2.0;
                assert_eq!(really_inside, inside, "test geometry");
                rays += 1;
                for (m, method) in Method::ALL.into_iter().enumerate() {
                    let hit = tri.intersect(&ray, method, 0.0, f32::INFINITY);
                    if hit.is_some() != inside {
                        bad[m] += 1;
                    }
                    if let (Some((t, _, _)), Method::Watertight) = (hit, method) {
                        worst_rel_t = worst_rel_t.max((t as f64 - t_ref).abs() / t_ref);
                    }
                }
            }
        }
    }
    println!(
        "grazing: {rays} rays, wrong answers adaptive={} watertight={} moller={} cramer={}; worst watertight relative t error {worst_rel_t:e}",
        bad[0], bad[1], bad[2], bad[3]
    );
    assert_eq!(bad[0], 0);
    assert_eq!(bad[1], 0);
    // Relative t error bound for the watertight method on these rays (a few ulps of f32).
    assert!(worst_rel_t < 1e-6, "{worst_rel_t}");
}

#[test]
fn tiny_and_huge_triangles_hit_inside_miss_outside_with_every_method() {
    // No method may use an absolute epsilon: a 1e-5 triangle must be hit like a 1e5 one.
    for size in [1e-5f32, 1e-3, 1.0, 1e3, 1e5] {
        for distance in [size * 10.0, size * 1e3] {
            let tri = Shape::from([[-size, -size, 0.0], [size, -size, 0.0], [0.0, size, 0.0]]);
            let o = [0.0, 0.0, -distance];
            let centre = Ray::new(o, [0.0, -0.2 * size, distance]);
            let outside = Ray::new(o, [1.2 * size, 0.0, distance]);
            for method in Method::ALL {
                let h = tri.intersect(&centre, method, 0.0, f32::INFINITY);
                let (t, _, _) =
                    h.unwrap_or_else(|| panic!("{method} missed a {size} triangle at {distance}"));
                assert!((t - 1.0).abs() < 1e-6, "{method}: t = {t}");
                assert!(
                    tri.intersect(&outside, method, 0.0, f32::INFINITY)
                        .is_none(),
                    "{method} hit outside a {size} triangle"
                );
            }
        }
    }
}

#[test]
fn edges_and_vertices_belong_to_the_triangle() {
    // Exactly on an edge, exactly on a vertex: closed triangles report a hit (every method).
    let tri = Shape::from([[0.0f32, 0.0, 0.0], [4.0, 0.0, 0.0], [0.0, 4.0, 0.0]]);
    for target in [
        [2.0f32, 0.0, 0.0],
        [0.0, 2.0, 0.0],
        [2.0, 2.0, 0.0],
        [0.0, 0.0, 0.0],
        [4.0, 0.0, 0.0],
    ] {
        let ray = Ray::new([target[0], target[1], -1.0], [0.0, 0.0, 1.0]);
        for method in Method::ALL {
            let hit = tri.intersect(&ray, method, 0.0, f32::INFINITY);
            assert_eq!(
                hit.map(|h| h.0),
                Some(1.0),
                "{method} at {target:?}: {hit:?}"
            );
        }
        // Back side too: two-sided.
        let back = Ray::new([target[0], target[1], 1.0], [0.0, 0.0, -2.0]);
        assert_eq!(
            tri.intersect(&back, Method::Watertight, 0.0, f32::INFINITY)
                .map(|h| h.0),
            Some(0.5)
        );
    }
    // Just beyond an edge is outside: by 2^-20 for every method, and by the smallest
    // subnormal for the watertight one (whose products underflow to 0 and are re-decided in
    // f64; Möller–Trumbore's underflow to 0 and call it a hit on the edge).
    let ray = Ray::new([2.0, -(2f32.powi(-20)), -1.0], [0.0, 0.0, 1.0]);
    for method in Method::ALL {
        assert!(
            tri.intersect(&ray, method, 0.0, f32::INFINITY).is_none(),
            "{method}"
        );
    }
    let ray = Ray::new([2.0, (0.0f32).next_down(), -1.0], [0.0, 0.0, 1.0]);
    assert!(tri
        .intersect(&ray, Method::Watertight, 0.0, f32::INFINITY)
        .is_none());
}

#[test]
fn tmin_and_tmax_are_exclusive() {
    let tri = Shape::from([[-1.0f32, -1.0, 0.0], [1.0, -1.0, 0.0], [0.0, 1.0, 0.0]]);
    let ray = Ray::new([0.0, 0.0, -2.0], [0.0, 0.0, 1.0]);
    for method in Method::ALL {
        assert_eq!(
            tri.intersect(&ray, method, 0.0, f32::INFINITY).map(|h| h.0),
            Some(2.0)
        );
        assert!(tri.intersect(&ray, method, 2.0, 3.0).is_none());
        assert!(tri.intersect(&ray, method, 1.0, 2.0).is_none());
        assert!(tri.intersect(&ray, method, 1.0, 2.0f32.next_up()).is_some());
        // A ray in the triangle's plane is a miss, not a division by zero.
        let inplane = Ray::new([-5.0, 0.0, 0.0], [1.0, 0.0, 0.0]);
        assert!(tri
            .intersect(&inplane, method, 0.0, f32::INFINITY)
            .is_none());
    }
}

/// Exact-enough sphere reference in f64 for f32 inputs: nearest root > 0, or None.
fn sphere_ref(o: [f32; 3], d: [f32; 3], c: [f32; 3], r: f32) -> Option<f64> {
    let f: [f64; 3] = [0, 1, 2].map(|k| o[k] as f64 - c[k] as f64);
    let d: [f64; 3] = d.map(f64::from);
    let a = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    let b = f[0] * d[0] + f[1] * d[1] + f[2] * d[2];
    let l: [f64; 3] = [0, 1, 2].map(|k| f[k] - b / a * d[k]);
    let l2 = l[0] * l[0] + l[1] * l[1] + l[2] * l[2];
    let disc = a * (r as f64 * r as f64 - l2);
    if disc < 0.0 {
        return None;
    }
    let roots = [(-b - disc.sqrt()) / a, (-b + disc.sqrt()) / a];
    roots.into_iter().find(|&t| t > 0.0)
}

#[test]
fn small_far_spheres() {
    // Radius / distance from 1e-3 to 1e-5 in f32: the textbook discriminant cancels to noise.
    let mut naive_wrong = 0;
    let mut rays = 0;
    let mut rng = Rng(5);
    for (r, dist) in [
        (1.0f32, 1e3f32),
        (1.0, 1e4),
        (1.0, 1e5),
        (1e-3, 1.0),
        (0.01, 1e3),
    ] {
        for _ in 0..50 {
            let c = [dist * 0.6, -dist * 0.8, rng.range(-1.0, 1.0) as f32 * r];
            // Aim at offsets from the centre of 0..0.9 r (hit) and 1.1..2 r (miss), across.
            for (lo, hi, should_hit) in [(0.0, 0.9, true), (1.1, 2.0, false)] {
                let off = rng.range(lo, hi) as f32 * r;
                let target = [c[0], c[1], c[2] + off];
                let o = [0.0f32, 0.0, c[2] + off];
                let d = sub(target, o);
                rays += 1;
                let got = sphere::intersect(o, d, c, r, 0.0, f32::INFINITY);
                let expected = sphere_ref(o, d, c, r);
                assert_eq!(expected.is_some(), should_hit, "test geometry");
                assert_eq!(got.is_some(), should_hit, "r={r} dist={dist} off={off}");
                if let (Some(t), Some(t_ref)) = (got, expected) {
                    // t errors: the far distance costs relative precision of the near root;
                    // bound by a few ulps of the distance relative to the depth 2r.
                    let abs_err = (t as f64 - t_ref).abs() * dist as f64;
                    assert!(
                        abs_err < 8.0 * f32::EPSILON as f64 * dist as f64 + 1e-3 * r as f64,
                        "t={t} ref={t_ref} r={r} dist={dist}"
                    );
                }
                if sphere::intersect_naive(o, d, c, r, 0.0, f32::INFINITY).is_some() != should_hit {
                    naive_wrong += 1;
                }
            }
        }
    }
    println!("small far spheres: {rays} rays, textbook discriminant wrong on {naive_wrong}");
}

#[test]
fn origins_on_a_sphere() {
    // Radius 5 with (3,4,0)-type offsets: the origins lie exactly on the sphere in f32.
    let c = [10.0f32, -20.0, 7.0];
    let r = 5.0;
    let on = |p: [f32; 3]| [c[0] + p[0], c[1] + p[1], c[2] + p[2]];
    for p in [
        [3.0, 4.0, 0.0],
        [0.0, -3.0, 4.0],
        [5.0, 0.0, 0.0],
        [-4.0, 0.0, -3.0],
    ] {
        let o = on(p);
        // Inward: the far side at t = 2 (not the root t = 0 at the origin itself).
        let inward = [-p[0], -p[1], -p[2]];
        assert_eq!(
            sphere::intersect(o, inward, c, r, 0.0, f32::INFINITY),
            Some(2.0),
            "{p:?}"
        );
        // Outward: nothing ahead.
        assert_eq!(
            sphere::intersect(o, p, c, r, 0.0, f32::INFINITY),
            None,
            "{p:?}"
        );
        // Tangent: touches only at the origin, which tmin = 0 excludes.
        let k = (0..3).find(|&k| p[k] == 0.0).unwrap();
        let mut tangent = [0.0f32; 3];
        tangent[k] = 1.0;
        assert_eq!(
            sphere::intersect(o, tangent, c, r, 0.0, f32::INFINITY),
            None,
            "{p:?}"
        );
        // f64 agrees.
        let o64 = o.map(f64::from);
        let in64 = inward.map(f64::from);
        assert_eq!(
            sphere::intersect(o64, in64, c.map(f64::from), 5.0, 0.0, f64::INFINITY),
            Some(2.0)
        );
    }
    // Inside: exactly one root ahead; outside, missing, and a ray starting past the sphere.
    assert_eq!(
        sphere::intersect(c, [0.0, 0.0, 1.0], c, r, 0.0, f32::INFINITY),
        Some(5.0)
    );
    let o = [c[0], c[1], c[2] - 10.0];
    assert_eq!(
        sphere::intersect(o, [0.0, 0.0, 1.0], c, r, 0.0, f32::INFINITY),
        Some(5.0)
    );
    assert_eq!(
        sphere::intersect(o, [0.0, 0.0, 1.0], c, r, 5.0, f32::INFINITY),
        Some(15.0)
    );
    assert_eq!(
        sphere::intersect(o, [0.0, 1.0, 0.0], c, r, 0.0, f32::INFINITY),
        None
    );
    assert_eq!(
        sphere::intersect(o, [0.0, 0.0, -1.0], c, r, 0.0, f32::INFINITY),
        None
    );
}

#[test]
fn near_tangent_sphere_rays() {
    // Rays passing the sphere at 1 ± 1e-4 radii: hit inside, miss outside, and never a NaN.
    let c = [0.0f32, 0.0, 10.0];
    for k in 0..200 {
        let a = k as f64 * 0.0314;
        let (s, co) = a.sin_cos();
        for (scale, should_hit) in [(1.0 - 1e-4, true), (1.0 + 1e-4, false)] {
            let o = [(co * scale) as f32, (s * scale) as f32, 0.0];
            let got = sphere::intersect(o, [0.0, 0.0, 1.0], c, 1.0, 0.0, f32::INFINITY);
            assert_eq!(got.is_some(), should_hit, "angle {a} scale {scale}");
            if let Some(t) = got {
                assert!((t - 10.0).abs() < 0.02, "t = {t}");
            }
        }
    }
}

#[test]
fn nearest_of_several_and_ties_to_lower_index() {
    let a = Shape::from([[-1.0f32, -1.0, 2.0], [1.0, -1.0, 2.0], [0.0, 1.0, 2.0]]);
    let b = Shape::from([[-1.0f32, -1.0, 1.0], [1.0, -1.0, 1.0], [0.0, 1.0, 1.0]]);
    let s = Shape::Sphere(Sphere {
        centre: [0.0, 0.0, 3.0],
        radius: 0.5,
    });
    let ray = Ray::new([0.0, 0.0, 0.0], [0.0, 0.0, 1.0]);
    let shapes = [a, s, b];
    let h = closest_hit(&shapes, &ray, Method::Watertight, 0.0, f32::INFINITY).unwrap();
    assert_eq!((h.t, h.prim), (1.0, 2));
    let h = closest_hit(&shapes, &ray, Method::Watertight, 1.5, f32::INFINITY).unwrap();
    assert_eq!((h.t, h.prim), (2.0, 0));
    let twins = [b, a, b];
    let h = closest_hit(&twins, &ray, Method::Watertight, 0.0, f32::INFINITY).unwrap();
    assert_eq!(h.prim, 0, "an exact tie goes to the lower index");
}

#[test]
fn methods_agree_away_from_edges() {
    // Random triangles and rays aimed at barycentric points at least 1% inside or outside:
    // every method answers the same, with t agreeing to a relative 1e-4.
    let mut rng = Rng(7);
    for _ in 0..2000 {
        let v: [[f32; 3]; 3] = [0, 1, 2].map(|_| [0, 1, 2].map(|_| rng.range(-1.0, 1.0) as f32));
        let tri = Shape::from(v);
        let mut b = [rng.range(0.0, 1.0), rng.range(0.0, 1.0)];
        let inside = rng.below(2) == 0;
        if inside {
            if b[0] + b[1] > 1.0 {
                b = [1.0 - b[0], 1.0 - b[1]];
            }
            b = [0.01 + 0.97 * b[0], 0.01 + 0.97 * b[1]];
            if 1.0 - b[0] - b[1] < 0.01 {
                continue;
            }
        } else {
            b = [-0.02 - b[0], b[1]];
        }
        let p: [f32; 3] = [0, 1, 2].map(|k| {
            ((1.0 - b[0] - b[1]) * v[0][k] as f64 + b[0] * v[1][k] as f64 + b[1] * v[2][k] as f64)
                as f32
        });
        let o: [f32; 3] = [0, 1, 2].map(|_| rng.range(-3.0, 3.0) as f32);
        let ray = Ray::new(o, sub(p, o));
        // Skip near-grazing configurations, where "1% inside" is not a robust margin.
        let e1 = sub(v[1], v[0]);
        let e2 = sub(v[2], v[0]);
        let n = [
            e1[1] * e2[2] - e1[2] * e2[1],
            e1[2] * e2[0] - e1[0] * e2[2],
            e1[0] * e2[1] - e1[1] * e2[0],
        ];
        let d = ray.d;
        let cos = (n[0] * d[0] + n[1] * d[1] + n[2] * d[2]).abs()
            / ((n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt()
                * (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt());
        if cos < 0.05 {
            continue;
        }
        for method in Method::ALL {
            let hit = tri.intersect(&ray, method, 0.0, f32::INFINITY);
            assert_eq!(hit.is_some(), inside, "{method}");
            if let Some((t, _, _)) = hit {
                assert!((t - 1.0).abs() < 1e-4, "{method}: t = {t}");
            }
        }
    }
}
