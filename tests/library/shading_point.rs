//! The shading point's two bounds (`geometry::SurfacePoint`, made by
//! `render::shade::shading_point`, the bits every path shades with) held against exact
//! rational points on every family of the hard-case suite: the point lies within `hit_error`
//! of the exact hit point per axis, within `p_error` of the primitive's surface, and the shadow
//! ray offset from it ends strictly on the light's side of the surface.

use crate::common;

use common::suite::{self, cross, dot, exact_nearest, q, sub, RefT, Q};
use num_traits::{Signed, Zero};
use raylab::accel;
use raylab::geometry::{Hit, Method, Ray, Shape, Sphere, Triangle};
use raylab::render::shade::{shading_point, Lit};
use raylab::scene::{cornell, Scene};
use rayon::prelude::*;
use std::cmp::Ordering;

/// The exact hit point's coordinate k, as an interval (an irrational sphere root is known
/// within 2⁻²⁵⁶ relative).
fn hit_coordinate(ray: &Ray, t: &RefT, k: usize) -> (Q, Q) {
    let (lo, hi) = match t {
        RefT::Exact(x) => (x.clone(), x.clone()),
        RefT::Between(lo, hi) => (lo.clone(), hi.clone()),
    };
    let at = |t: &Q| q(ray.o[k]) + t * q(ray.d[k]);
    let (a, b) = (at(&lo), at(&hi));
    if a <= b {
        (a, b)
    } else {
        (b, a)
    }
}

fn exact(v: [f32; 3]) -> [Q; 3] {
    v.map(q)
}

/// Whether the box p ± e holds a point of the plane through v0 with normal n.
fn box_meets_plane(n: &[Q; 3], v0: &[Q; 3], p: &[Q; 3], e: &[Q; 3]) -> bool {
    let at_p = dot(n, &sub(p, v0));
    let reach = &n[0].abs() * &e[0] + &n[1].abs() * &e[1] + &n[2].abs() * &e[2];
    at_p.abs() <= reach
}

/// Whether the box p ± e holds a point at distance r from `centre`.
fn box_meets_sphere(centre: &[Q; 3], r: &Q, p: &[Q; 3], e: &[Q; 3]) -> bool {
    let (mut near, mut far) = (Q::zero(), Q::zero());
    for k in 0..3 {
        let (lo, hi) = (&p[k] - &e[k], &p[k] + &e[k]);
        let c = &centre[k];
        let gap = if c < &lo {
            &lo - c
        } else if c > &hi {
            c - &hi
        } else {
            Q::zero()
        };
        let reach = (c - &lo).abs().max((&hi - c).abs());
        near += &gap * &gap;
        far += &reach * &reach;
    }
    let r2 = r * r;
    near <= r2 && r2 <= far
}

/// Which side of the primitive's exact surface x is on: the sign of n·(x − v₀) for a
/// triangle, of |x − c|² − r² for a sphere.
fn side(shape: &Shape, x: &[Q; 3]) -> Ordering {
    let value = match shape {
        Shape::Triangle(Triangle(v)) => {
            let v = v.map(exact);
            let n = cross(&sub(&v[1], &v[0]), &sub(&v[2], &v[0]));
            dot(&n, &sub(x, &v[0]))
        }
        Shape::Sphere(Sphere { centre, radius }) => {
            let rel = sub(x, &exact(*centre));
            dot(&rel, &rel) - q(*radius) * q(*radius)
        }
    };
    value.cmp(&Q::zero())
}

#[derive(Default)]
struct Tally {
    hits: usize,
    hit_bound_broken: usize,
    surface_bound_broken: usize,
    shadow_ends: usize,
    shadow_end_wrong_side: usize,
    /// Spheres seen from the other side than the light (not skipped by their shadow test).
    self_blocked: usize,
    /// hit_error / (max |xₖ| + 1e-30) per hit, and the actual |p − x| on the same scale.
    bound_rel: Vec<f64>,
    actual_rel: Vec<f64>,
}

impl Tally {
    /// Both tallies' counts and samples.
    fn and(mut self, other: Tally) -> Tally {
        self.hits += other.hits;
        self.hit_bound_broken += other.hit_bound_broken;
        self.surface_bound_broken += other.surface_bound_broken;
        self.shadow_ends += other.shadow_ends;
        self.shadow_end_wrong_side += other.shadow_end_wrong_side;
        self.self_blocked += other.self_blocked;
        self.bound_rel.extend(other.bound_rel);
        self.actual_rel.extend(other.actual_rel);
        self
    }
}

fn check_family(family: &suite::Family, tally: &mut Tally) {
    let colors = vec![[0.5; 3]; family.shapes.len()];
    let scene = Scene::new(
        "family",
        family.shapes.clone(),
        colors,
        cornell::LIGHT,
        cornell::AMBIENT,
    );
    let light = exact(scene.light.position);
    for ray in &family.rays {
        let Some((t, prim)) = exact_nearest(&family.shapes, ray) else {
            continue;
        };
        let shape = family.shapes[prim as usize];
        let sp = shading_point(&scene, ray, prim);
        tally.hits += 1;
        let p = exact(sp.p);
        // |pₖ − xₖ| ≤ hit_error at both ends of x's interval.
        let (mut scale, mut actual) = (1e-30f64, 0f64);
        for (k, pk) in p.iter().enumerate() {
            let (lo, hi) = hit_coordinate(ray, &t, k);
            let bound = q(sp.hit_error[k]);
            if (pk - &lo).abs() > bound || (&hi - pk).abs() > bound {
                tally.hit_bound_broken += 1;
                eprintln!(
                    "{}: hit bound broken, axis {k}: p {:?} hit_error {:?} x ≈ {}",
                    family.name,
                    sp.p,
                    sp.hit_error,
                    num_traits::ToPrimitive::to_f64(&lo).unwrap()
                );
            }
            let x = num_traits::ToPrimitive::to_f64(&lo).unwrap();
            scale = scale.max(x.abs());
            actual = actual.max((sp.p[k] as f64 - x).abs());
        }
        let worst = sp.hit_error.iter().fold(0f32, |m, e| m.max(*e)) as f64;
        tally.bound_rel.push(worst / scale);
        tally.actual_rel.push(actual / scale);
        // The box p ± p_error meets the exact surface.
        let e = exact(sp.p_error);
        let meets = match shape {
            Shape::Triangle(Triangle(v)) => {
                let v = v.map(exact);
                let n = cross(&sub(&v[1], &v[0]), &sub(&v[2], &v[0]));
                box_meets_plane(&n, &v[0], &p, &e)
            }
            Shape::Sphere(Sphere { centre, radius }) => {
                box_meets_sphere(&exact(centre), &q(radius), &p, &e)
            }
        };
        if !meets {
            tally.surface_bound_broken += 1;
            eprintln!(
                "{}: surface bound broken: p {:?} p_error {:?}",
                family.name, sp.p, sp.p_error
            );
        }
        // The shadow ray from the light ends on the light's side of the exact surface.
        let hit = Hit {
            t: t.f64() as f32,
            prim,
            b1: 0.0,
            b2: 0.0,
        };
        let lit = Lit::new(&scene, ray, &hit);
        if let Some(shadow) = lit.shadow {
            let end: [Q; 3] = [0, 1, 2].map(|k| q(shadow.o[k]) + q(shadow.d[k]));
            let light_side = side(&shape, &light);
            tally.shadow_ends += 1;
            if lit.skip == prim {
                // Skipped by the shadow test: the end must be on the light's side.
                if light_side == Ordering::Equal || side(&shape, &end) != light_side {
                    tally.shadow_end_wrong_side += 1;
                    eprintln!("{}: shadow ray ends off the light's side", family.name);
                }
            } else {
                // A sphere seen from the other side than the light: it blocks its own
                // shadow ray.
                tally.self_blocked += 1;
                let blocked = accel::any_hit(
                    &family.shapes,
                    &shadow,
                    Method::Adaptive,
                    0.0,
                    1.0,
                    u32::MAX,
                );
                assert!(
                    matches!(shape, Shape::Sphere(_)) && blocked,
                    "{}",
                    family.name
                );
            }
        }
    }
}

fn quantile(xs: &mut [f64], f: f64) -> f64 {
    xs.sort_by(f64::total_cmp);
    xs[((xs.len() - 1) as f64 * f) as usize]
}

#[test]
fn the_shading_point_keeps_its_bounds_on_the_hard_cases() {
    // (Families on every core: the exact reference is most of the test's time.)
    let mut tally = (suite::all().par_iter())
        .map(|family| {
            let mut tally = Tally::default();
            check_family(family, &mut tally);
            tally
        })
        .reduce(Tally::default, Tally::and);
    let Tally {
        hits,
        hit_bound_broken,
        surface_bound_broken,
        shadow_ends,
        shadow_end_wrong_side,
        self_blocked,
        ..
    } = tally;
    let (b50, b99) = (
        quantile(&mut tally.bound_rel, 0.5),
        quantile(&mut tally.bound_rel, 0.99),
    );
    let (a50, amax) = (
        quantile(&mut tally.actual_rel, 0.5),
        quantile(&mut tally.actual_rel, 1.0),
    );
    println!(
        "{hits} hits: hit_error / max|x| median {b50:.1e}, 99% {b99:.1e}; \
         actual |p − x| / max|x| median {a50:.1e}, max {amax:.1e}; {shadow_ends} shadow rays, \
         {self_blocked} blocked by their own sphere"
    );
    assert!(hits > 5_000, "{hits} hits");
    // The bound is worth stating: about 50 units in the last place at the median (grazing rays
    // make the tail).
    assert!(b50 < 1e-5, "median hit_error {b50:e} relative");
    assert_eq!(
        hit_bound_broken, 0,
        "points off the exact hit by more than hit_error"
    );
    assert_eq!(
        surface_bound_broken, 0,
        "points off the surface by more than p_error"
    );
    assert!(shadow_ends > 1_000, "{shadow_ends} shadow rays");
    assert_eq!(
        shadow_end_wrong_side, 0,
        "shadow rays ending off the light's side"
    );
}

#[test]
fn a_sphere_seen_from_inside_is_shadowed_by_itself_from_a_light_outside() {
    // A camera inside a sphere, the light outside: the lab's two-sided D lights the inside
    // wall facing the light, but every shadow ray must cross the sphere, so with shadows the
    // whole image is black (before, the sphere skipped itself and the wall was lit).
    use raylab::render::{render_image, LabStep, RenderSettings};
    use raylab::scene::PointLight;
    let scene = Scene::new(
        "inside",
        vec![Shape::Sphere(Sphere {
            centre: [0.0; 3],
            radius: 10.0,
        })],
        vec![[0.8; 3]],
        PointLight {
            position: [0.0, 0.0, -20.0],
            power: [4000.0; 3],
        },
        [0.5; 3],
    );
    let stage = raylab::render::Stage::from(scene);
    let camera = raylab::Camera::cornell(64);
    let lit_pixels = |step| {
        let settings = RenderSettings {
            width: 64,
            height: 48,
            step,
            ..Default::default()
        };
        let (rgba, _) = render_image(&stage, &camera, &settings).unwrap();
        rgba.chunks(4).filter(|p| p[..3] != [0, 0, 0]).count()
    };
    assert!(lit_pixels(LabStep::Direct) > 64 * 48 / 2);
    assert_eq!(lit_pixels(LabStep::Shadows), 0);
}

#[test]
fn a_tiny_faces_normal_is_its_unit_normal() {
    // The face's cross product below f32's range (edges of 2⁻⁸⁰ multiply to 2⁻¹⁶⁰): the normal
    // was 0, and a scene 10⁻²⁴ across shaded black while one 10⁻²² across shaded lit. Every
    // scale of one tilted face has one unit normal, whatever path shades it.
    let face = [[0.3f32, -0.7, 0.1], [1.1, 0.2, -0.4], [-0.5, 0.9, 0.8]];
    let unit = raylab::render::shade::unit_normal(&face);
    for k in [-20, -64, -80, -100, -120] {
        let s = 2f32.powi(k);
        let tiny = face.map(|p| p.map(|x| x * s));
        let n = raylab::render::shade::unit_normal(&tiny);
        let off = (0..3).map(|i| (n[i] - unit[i]).abs()).fold(0.0, f32::max);
        assert!(off < 1e-6, "2^{k}: {n:?} against {unit:?}");
        // As the shading point carries it, from a ray through the face's middle.
        let centre = [0, 1, 2].map(|i| (tiny[0][i] + tiny[1][i] + tiny[2][i]) / 3.0);
        let ray = Ray::new([centre[0], centre[1], centre[2] - 4.0 * s], [0.0, 0.0, 1.0]);
        let point = Shape::from(tiny).surface_point(&ray);
        assert_eq!(point.n, n, "2^{k}");
    }
}
