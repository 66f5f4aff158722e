//! The hard-case suite against exact references: every f32 input is an exact rational, and
//! each answer is decided in exact arithmetic (`num-rational`, written here independently of
//! the library's own exact level): hit or miss for the closed triangle or sphere, the nearest
//! primitive (exact ties to the lower index), and t.
//!
//! Families (fixed seeds, several hundred rays each): closed meshes hit exactly at shared edges
//! and vertices from inside and outside, grazing rays, far triangles and spheres, tiny and huge
//! meshes, large offsets (meshes, and the Cornell box with its camera), small far spheres,
//! origins exactly on a sphere, inside and just outside it, near-tangent rays,
//! near-coincident surfaces (parallel and crossing triangles, a triangle just in front of a
//! sphere), the Cornell box's primary rays and rays at its edges and vertices. Per family and
//! method it counts leaks (exact hit, answered miss), false hits, wrong nearest primitive (an
//! exact tie not resolved to the lower index, or a primitive the exact ray does not meet),
//! pass-throughs (a miss, or a primitive exactly behind the nearest surface: the ray slipped
//! through it) and the median and largest relative t error, and prints the table
//! (`cargo test --test library hard_cases:: -- --nocapture --test-threads 1`; docs/hard_cases.md).
//!
//! Asserted: the default (adaptive) method, through its six fast paths (the flat SIMD loop,
//! the BVH, the renderer's camera-ray packets, the BVH with triangles prepared for the
//! camera's origin per ray, and BVH packets with triangles prepared per frame or as the
//! packet meets them), answers every ray of every family correctly: zero leaks, false hits, wrong nearest
//! and pass-throughs. The plain watertight f32 method is held to no leaks from inside closed
//! meshes; the other methods' counts are reported, not asserted.

use crate::common;

use common::suite::{self, exact_nearest, Counts, Family};
use raylab::accel::testing::{self as packet, OriginTriangles};
use raylab::accel::{self, Accel, AccelChoice, IndexedTriangle};
use raylab::geometry::{adaptive, Method, Ray, Shape, Triangle};
use rayon::prelude::*;
use std::collections::HashMap;
use wide::f32x8;

const VARIANTS: [&str; 12] = [
    "adaptive f32 (SIMD loop)",
    "adaptive f32 (BVH)",
    "adaptive f32 (camera packets)",
    "adaptive f32 (BVH, camera origin)",
    "adaptive f32 (BVH packets, prepared)",
    "adaptive f32 (BVH packets, as met)",
    "watertight f32",
    "moller f32",
    "cramer f32",
    "watertight f64",
    "moller f64",
    "cramer f64",
];

/// The renderer's camera-ray path: the packet kernel from the ray's origin (this ray in
/// every lane), the exact-edge resolver where it is ambiguous, t as `lane_answer` gives it,
/// and the per-ray search (the flat loop) where neither decides. `None`
/// for scenes with spheres (the renderer uses packets for triangle scenes only).
/// Returns the answer and whether it came from the per-ray search.
fn camera_packet(
    shapes: &[Shape<f32>],
    cache: &mut HashMap<[u32; 3], OriginTriangles>,
    ray: &Ray<f32>,
    per_ray: Option<(f64, u32)>,
) -> Option<(Option<(f64, u32)>, bool)> {
    let tris: Vec<IndexedTriangle> = shapes
        .iter()
        .enumerate()
        .map(|(i, s)| match s {
            Shape::Triangle(Triangle(v)) => Some((*v, i as u32)),
            Shape::Sphere(_) => None,
        })
        .collect::<Option<_>>()?;
    let prepared = cache
        .entry(ray.o.map(f32::to_bits))
        .or_insert_with(|| OriginTriangles::new(&tris, ray.o));
    let d = ray.d.map(f32x8::splat);
    let found = packet::closest(&prepared.tris, &d, packet::max_component(&d));
    if found.ambiguous & 1 != 0 {
        // The renderer's next step: exact edge signs over the same triangles. It names the
        // primitive only (the renderer shades from it); t is the per-ray search's, so that
        // a wrong primitive shows as a wrong nearest.
        let vertices = |p: u32| tris[p as usize].0;
        return match packet::closest_exact_lane(&prepared.tris, vertices, ray.o, ray.d) {
            Some(Some(prim)) => Some((per_ray.map(|(t, _)| (t, prim)), false)),
            Some(None) => Some((None, false)),
            None => Some((per_ray, true)),
        };
    }
    let prim = found.prim[0];
    if prim == u32::MAX {
        return Some((None, false));
    }
    Some((lane_answer(shapes, ray, prim), false))
}

/// A packet lane's answer: the primitive it decided, with the exact t correctly rounded
/// (`adaptive::rounded_t`, what `raylab trace` prints for a lane; the renderer takes only the
/// primitive). NaN where the primitive's t does not exist (the ray misses its plane): that
/// shows as an error.
fn lane_answer(shapes: &[Shape<f32>], ray: &Ray<f32>, prim: u32) -> Option<(f64, u32)> {
    let t = adaptive::rounded_t(&shapes[prim as usize], ray, 0.0, f32::INFINITY);
    Some((t.map_or(f64::NAN, f64::from), prim))
}

/// Runs every variant on `rays` (t > 0); returns the counts in the order of `VARIANTS`, and
/// how many rays the packet kernel left to the per-ray search.
fn evaluate(shapes: &[Shape<f32>], rays: &[Ray<f32>]) -> (Vec<Counts>, usize) {
    let shapes64: Vec<Shape<f64>> = shapes.iter().map(adaptive::widen).collect();
    let flat = Accel::build(shapes, AccelChoice::Flat);
    let bvh = Accel::build(shapes, AccelChoice::Bvh);
    let inf = f32::INFINITY;
    let plain = [Method::Watertight, Method::Moller, Method::Cramer];
    let mut out: Vec<Counts> = VARIANTS.iter().map(|_| Counts::default()).collect();
    let mut cache = HashMap::new();
    let mut bvh_cache = HashMap::new();
    let mut ambiguous = 0;
    // The exact references on every core.
    let exacts: Vec<_> = rays.par_iter().map(|r| exact_nearest(shapes, r)).collect();
    for (ray, exact) in rays.iter().zip(exacts) {
        let ray64 = Ray::new(ray.o.map(f64::from), ray.d.map(f64::from));
        let mut answers: Vec<Option<(f64, u32)>> = Vec::new();
        for acc in [&flat, &bvh] {
            let h = acc.closest_hit(ray, Method::Adaptive, 0.0, inf);
            answers.push(h.map(|h| (h.t as f64, h.prim)));
        }
        let (packet, was_ambiguous) =
            camera_packet(shapes, &mut cache, ray, answers[0]).unwrap_or((answers[0], true));
        ambiguous += was_ambiguous as usize;
        answers.push(packet);
        // The renderer's camera rays through a BVH: triangles prepared for the origin.
        let prepared = bvh_cache
            .entry(ray.o.map(f32::to_bits))
            .or_insert_with(|| bvh.prepare_origin(ray.o));
        let h = packet::closest_from_origin(&bvh, ray, prepared, 0.0, inf);
        answers.push(h.map(|h| (h.t as f64, h.prim)));
        // And 8 at a time through the BVH (this ray in every lane), t as `lane_answer` gives
        // it; ambiguous lanes and scenes with spheres go per ray, as in the renderer.
        let d = ray.d.map(f32x8::splat);
        for prepared in [Some(&*prepared), None] {
            let found = bvh.closest_packet(ray.o, prepared, &d, packet::max_component(&d));
            let answer = match found {
                Some(f) if f.ambiguous & 1 == 0 && f.prim[0] == u32::MAX => None,
                Some(f) if f.ambiguous & 1 == 0 => lane_answer(shapes, ray, f.prim[0]),
                _ => h.map(|h| (h.t as f64, h.prim)),
            };
            answers.push(answer);
        }
        for m in plain {
            let h = accel::closest_hit(shapes, ray, m, 0.0, inf);
            answers.push(h.map(|h| (h.t as f64, h.prim)));
        }
        for m in plain {
            let h = accel::closest_hit(&shapes64, &ray64, m, 0.0, f64::INFINITY);
            answers.push(h.map(|h| (h.t, h.prim)));
        }
        for (c, got) in out.iter_mut().zip(answers) {
            c.add(shapes, ray, &exact, got);
        }
    }
    (out, ambiguous)
}

fn report(family: &str, counts: &[Counts]) {
    for (name, c) in VARIANTS.iter().zip(counts) {
        println!(
            "| {family} | {name} | {} | {} | {} | {} | {} | {:.1e} | {:.1e} |",
            c.rays,
            c.leaks,
            c.false_hits,
            c.wrong_nearest,
            c.pass_through,
            c.rel(0.5),
            c.rel(1.0)
        );
    }
}

/// Reports, and asserts the adaptive method got every ray right.
fn check(family: &Family) -> Vec<Counts> {
    let name = family.name.as_str();
    let (counts, ambiguous) = evaluate(&family.shapes, &family.rays);
    report(name, &counts);
    println!(
        "{name}: the camera packets left {ambiguous} of {} rays to the per-ray search",
        family.rays.len()
    );
    for c in &counts[..6] {
        assert_eq!(
            (c.leaks, c.false_hits, c.wrong_nearest, c.pass_through),
            (0, 0, 0, 0),
            "{name}: the adaptive method must answer every ray exactly"
        );
        // t: the f32 rounding of a value within the f32 filter's bound of the exact t.
        assert!(
            c.rel(1.0) < 1e-5,
            "{name}: adaptive t error {:e}",
            c.rel(1.0)
        );
    }
    counts
}

/// Checks every family; the plain watertight f32 method must not leak from inside a closed
/// mesh or on the Cornell box either.
fn check_all(families: Vec<Family>) {
    for family in &families {
        let counts = check(family);
        let closed = family.name.contains("inside")
            || family.name.starts_with("tiny cube")
            || family.name.starts_with("huge cube")
            || family.name.starts_with("cube at")
            || family.name.starts_with("Cornell primary");
        if closed && !family.name.contains("ulp") {
            assert_eq!(
                counts[6].leaks + counts[6].false_hits,
                0,
                "{}: watertight f32 leaked",
                family.name
            );
        }
    }
}

#[test]
fn closed_meshes_at_shared_edges_and_vertices() {
    check_all(suite::closed_meshes());
}

#[test]
fn tiny_huge_and_offset_meshes() {
    check_all(suite::tiny_huge_and_offset());
}

#[test]
fn grazing_and_far() {
    check_all(suite::grazing_and_far());
}

#[test]
fn near_coincident_surfaces() {
    check_all(suite::near_coincident());
}

#[test]
fn spheres() {
    check_all(suite::spheres());
}

#[test]
fn cornell_primary_rays_and_its_edges() {
    check_all(suite::cornell());
}

#[test]
fn cornell_box_and_camera_translated() {
    check_all(suite::cornell_translated());
}

#[test]
fn round_two_fans_junctions_in_plane_copies_subnormal_vertices_zeros_slivers() {
    check_all(suite::round_two());
}

#[test]
fn tmin_and_tmax_exactly_at_the_hit() {
    // Every suite ray whose exact nearest t is an f32, asked again with tmax = t (the hit
    // itself and any tie at t excluded: the open interval) and with tmin = t (what lies
    // beyond): the adaptive method through the reference loop, the flat SIMD loop and the BVH
    // gives the exact nearest in that interval, and `rounded_t` its exact t rounded.
    // The families on every core: (queries asked, hits, wrong answers) of each.
    let tally = |family: &Family| {
        let (mut asked, mut hits, mut wrong) = (0, 0, 0);
        let flat = Accel::build(&family.shapes, AccelChoice::Flat);
        let bvh = Accel::build(&family.shapes, AccelChoice::Bvh);
        for ray in &family.rays {
            let Some((suite::RefT::Exact(t), _)) = exact_nearest(&family.shapes, ray) else {
                continue;
            };
            let t32 = suite::round_q::<f32>(&t);
            if suite::q(t32) != t || !t32.is_finite() {
                continue;
            }
            for (tmin, tmax) in [(0.0, t32), (t32, f32::INFINITY)] {
                let qmax = tmax.is_finite().then(|| suite::q(tmax));
                let want = suite::exact_nearest_between(
                    &family.shapes,
                    ray,
                    &suite::q(tmin),
                    qmax.as_ref(),
                );
                let want = want.map(|(t, prim)| (t.rounded::<f32>(), prim));
                asked += 1;
                hits += want.is_some() as usize;
                let answers = [
                    accel::closest_hit(&family.shapes, ray, Method::Adaptive, tmin, tmax),
                    flat.closest_hit(ray, Method::Adaptive, tmin, tmax),
                    bvh.closest_hit(ray, Method::Adaptive, tmin, tmax),
                ];
                for got in answers {
                    let got = got.map(|h| {
                        let shape = &family.shapes[h.prim as usize];
                        (adaptive::rounded_t(shape, ray, tmin, tmax), h.prim)
                    });
                    if got != want {
                        wrong += 1;
                        eprintln!(
                            "{}: {ray:?} in ({tmin}, {tmax}): {got:?}, exact {want:?}",
                            family.name
                        );
                    }
                }
            }
        }
        (asked, hits, wrong)
    };
    let (asked, hits, wrong) = (suite::all().par_iter().map(tally))
        .reduce(|| (0, 0, 0), |a, b| (a.0 + b.0, a.1 + b.1, a.2 + b.2));
    println!("{asked} queries with tmin or tmax exactly at the hit, {hits} hits");
    assert!(
        asked > 5_000 && hits > 1_000,
        "{asked} queries, {hits} hits"
    );
    assert_eq!(wrong, 0);
}

#[test]
fn the_suite_in_f64_through_the_reference_loop() {
    // The adaptive method in f64 (the suite's f32 inputs are the same numbers in f64): every
    // family's nearest primitive exact, and `rounded_t` the exact t rounded to f64 (as
    // `raylab trace --precision f64` prints it).
    // The families on every core: (rays, hits, wrong primitives, t's off) of each.
    let tally = |family: &Family| {
        let (mut rays, mut hits, mut wrong, mut off) = (0, 0, 0, 0);
        let shapes: Vec<Shape<f64>> = family.shapes.iter().map(adaptive::widen).collect();
        for ray in &family.rays {
            let exact = exact_nearest(&family.shapes, ray);
            let r = Ray::new(ray.o.map(f64::from), ray.d.map(f64::from));
            let got = accel::closest_hit(&shapes, &r, Method::Adaptive, 0.0, f64::INFINITY);
            rays += 1;
            match (&exact, got) {
                (Some((t, prim)), Some(h)) if *prim == h.prim => {
                    hits += 1;
                    let shape = &shapes[h.prim as usize];
                    let printed = adaptive::rounded_t(shape, &r, 0.0, f64::INFINITY);
                    if t.rounded::<f64>() != printed {
                        off += 1;
                        eprintln!("{}: {ray:?}: t {printed:?}, exact {:?}", family.name, t);
                    }
                }
                (None, None) => {}
                _ => {
                    wrong += 1;
                    eprintln!("{}: {ray:?}: {got:?}, exact {exact:?}", family.name);
                }
            }
        }
        (rays, hits, wrong, off)
    };
    let (rays, hits, wrong, off) = (suite::all().par_iter().map(tally)).reduce(
        || (0, 0, 0, 0),
        |a, b| (a.0 + b.0, a.1 + b.1, a.2 + b.2, a.3 + b.3),
    );
    println!("f64: {rays} rays, {hits} hits");
    assert!(rays > 14_000 && hits > 12_000, "{rays} rays, {hits} hits");
    assert_eq!(
        (wrong, off),
        (0, 0),
        "wrong primitives, t's not the exact t rounded"
    );
}
