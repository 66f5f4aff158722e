//! Rays the f32 filters cannot decide, against the reference through every layout
//! (`accel::check_all`): from origins 2⁴⁰ away from a small scene, and shadow segments to a far
//! light nearly parallel to a wall, starting on it or just off it.

use crate::accel::check_all;
use crate::common::Rng;
use raylab::accel;
use raylab::geometry::{Method, Ray, Shape, Sphere, Triangle};

/// Rays from origins 2⁴⁰ away from the Cornell box: along each axis towards it and away from
/// it (over t ∈ (−∞, ∞) those reach it behind), diagonally, and aimed at it in f32, whose
/// rounding misses it by far: every layout answers as the reference does, over every interval.
/// From such an origin the flat loop's f32 filter decides no triangle, and its f64 test of the
/// box around them all decides instead which rays go on to the exact tests.
#[test]
fn rays_from_origins_far_from_a_small_scene_are_answered_as_the_reference_does() {
    let shapes = raylab::scene::Scene::cornell().shapes;
    let far = 2.0f32.powi(40);
    let (lo, hi) = shapes.iter().fold(
        ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]),
        |(lo, hi), s| {
            let Shape::Triangle(Triangle(v)) = s else {
                unreachable!("the Cornell box holds triangles")
            };
            let lo = [0, 1, 2].map(|k| lo[k].min(v[0][k]).min(v[1][k]).min(v[2][k]));
            let hi = [0, 1, 2].map(|k| hi[k].max(v[0][k]).max(v[1][k]).max(v[2][k]));
            (lo, hi)
        },
    );
    let mut rays = Vec::new();
    for f in [0.0f32, 0.3, 0.5, 1.0] {
        let p = [0, 1, 2].map(|k| lo[k] + (hi[k] - lo[k]) * f);
        for axis in 0..3 {
            for side in [-1.0f32, 1.0] {
                let mut o = p;
                o[axis] = side * far;
                let mut d = [0.0; 3];
                d[axis] = -side;
                rays.push(Ray::new(o, d));
                rays.push(Ray::new(o, d.map(|c| -c)));
            }
        }
    }
    rays.push(Ray::new([far, far, 0.5], [-1.0, -1.0, 0.0]));
    rays.push(Ray::new([far, far, 0.5], [1.0, 1.0, 0.0]));
    let mut rng = Rng(0xfa7_0e1e);
    for _ in 0..16 {
        let o = [0, 1, 2].map(|_| rng.range(-1.0, 1.0) as f32 * far);
        let target = [0, 1, 2].map(|k| rng.range(lo[k].into(), hi[k].into()) as f32);
        rays.push(Ray::new(o, [0, 1, 2].map(|k| target[k] - o[k])));
    }
    let reference = |ray: &Ray, tmin, tmax| {
        accel::closest_hit(&shapes, ray, Method::Adaptive, tmin, tmax).is_some()
    };
    let axis_rays = rays.iter().step_by(2).take(24);
    assert!(
        axis_rays.clone().all(|r| reference(r, 0.0, f32::INFINITY)),
        "the rays along an axis towards the box hit it"
    );
    assert!(
        rays.iter()
            .skip(1)
            .step_by(2)
            .take(24)
            .all(|r| !reference(r, 0.0, f32::INFINITY) && reference(r, f32::NEG_INFINITY, 0.0)),
        "the rays along an axis away from it hit it behind"
    );
    for (tmin, tmax) in [
        (0.0, f32::INFINITY),
        (f32::NEG_INFINITY, f32::INFINITY),
        (f32::NEG_INFINITY, 0.0),
        (0.0, far - 4.0),
        (far - 4.0, f32::INFINITY),
    ] {
        check_all(&shapes, &rays, tmin, tmax);
    }
}

/// Shadow segments to a far light, nearly parallel to a wall (the plane x = 0), starting on
/// it, just off it on either side (10⁻³⁰ to 10⁻³) and moving towards it, away from it or
/// along it: every layout's any-hit answer (which first asks whether a segment stays on one
/// side of a triangle's plane, in f64) is the reference's, over (0, 1) and shorter intervals.
#[test]
fn segments_along_a_wall_to_a_far_light_are_answered_as_the_reference_does() {
    let mut shapes: Vec<Shape<f32>> = vec![
        Shape::from([[0.0, -1.0, -1.0], [0.0, 1.0, -1.0], [0.0, 0.0, 1.0]]),
        Shape::from([[0.0, -3.0, -2.0], [0.0, -3.0, 2.0], [0.0, -1e9, 0.0]]),
        Shape::from([[-1.0, -0.5, 0.0], [1.0, -0.5, 0.0], [0.0, -0.5, 1.0]]),
    ];
    for k in 0..64 {
        let x = 100.0 + k as f32;
        shapes.push(Shape::from([
            [x, 0.0, 5.0],
            [x + 0.5, 0.0, 5.0],
            [x, 0.5, 5.5],
        ]));
    }
    let mut rays = Vec::new();
    for offset in [
        0.0f32, 1e-30, -1e-30, 1e-12, -1e-12, 1e-7, -1e-7, 1e-3, -1e-3,
    ] {
        for o in [
            [offset, 0.2, 0.1],
            [offset, -0.4, -0.3],
            [offset, 0.9, -0.9],
        ] {
            for dx in [0.0f32, 1.0, -1.0, 1e-3, -1e-3, 2e-9] {
                rays.push(Ray::new(o, [dx, -1e9, 3e8]));
                rays.push(Ray::new(o, [dx, 1e9, -2e7]));
            }
        }
    }
    for (tmin, tmax) in [(0.0, 1.0), (0.0, 1e-9), (1e-12, 1.0), (0.0, f32::INFINITY)] {
        check_all(&shapes, &rays, tmin, tmax);
    }
}

/// Spheres seen from 2³⁰ away: rays along an axis at a sphere's rim (a tangent touch hits),
/// just inside and just outside it, rays aimed at centres in f32 (their rounding misses by
/// far), and rays away: every layout answers as the reference does, over every interval. From
/// so far the hierarchy's boxes pass many spheres, each of which an f64 test of the ray's line
/// against it refuses before the exact search.
#[test]
fn spheres_seen_from_far_away_are_answered_as_the_reference_does() {
    let mut rng = Rng(0x5fe7e);
    let mut shapes: Vec<Shape<f32>> = (0..100)
        .map(|_| {
            Shape::Sphere(Sphere {
                centre: [0, 1, 2].map(|_| rng.range(-4.0, 4.0) as f32),
                radius: rng.range(0.05, 0.3) as f32,
            })
        })
        .collect();
    shapes.push(Shape::from([
        [-5.0, -5.0, 6.0],
        [5.0, -5.0, 6.0],
        [0.0, 5.0, 6.0],
    ]));
    let far = 2.0f32.powi(30);
    let mut rays = Vec::new();
    for s in shapes.iter().take(10) {
        let Shape::Sphere(Sphere {
            centre: c,
            radius: r,
        }) = *s
        else {
            continue;
        };
        for x in [
            c[0] + r,
            c[0] + r * (1.0 - 1e-6),
            c[0] + r * (1.0 + 1e-6),
            c[0],
        ] {
            rays.push(Ray::new([x, c[1], -far], [0.0, 0.0, 1.0]));
            rays.push(Ray::new([x, c[1], -far], [0.0, 0.0, -1.0]));
        }
        let o = [0, 1, 2].map(|_| rng.range(-1.0, 1.0) as f32 * far);
        rays.push(Ray::new(o, [0, 1, 2].map(|k| c[k] - o[k])));
    }
    assert!(
        rays.iter().step_by(2).take(8).any(|r| {
            accel::closest_hit(&shapes, r, Method::Adaptive, 0.0, f32::INFINITY).is_some()
        }),
        "some rays meet their sphere"
    );
    for (tmin, tmax) in [(0.0, f32::INFINITY), (f32::NEG_INFINITY, f32::INFINITY)] {
        check_all(&shapes, &rays, tmin, tmax);
    }
}

/// A 5,120-triangle ball in the Cornell box seen from 10⁶ units away, the view filled with the
/// box: the packets' triangles, prepared for that eye in f32, are rounded by some 0.06 units,
/// more than the ball's sides (~0.03), so a frame without shadows traces its camera rays one
/// at a time (the per-ray walk moves each up to the box in f64 first); from 10 units, or with
/// shadows, they go in packets.
/// Every pixel and count is the per-ray path's (the cracks view, which marks nothing with the
/// adaptive method), with shadows and with supersampling.
#[test]
fn a_mesh_seen_from_far_away_renders_as_the_per_ray_path() {
    use raylab::accel::{AccelChoice, FrameSetup};
    use raylab::render::{LabStep, RenderSettings};
    let ball = crate::common::icosphere(4, 0.3, [0.2, 0.4, 0.2]);
    assert_eq!(ball.len(), 5120);
    let stage = crate::common::cornell_with_blue(ball, AccelChoice::Auto);
    let setup = |z: f32, shadows: bool| FrameSetup {
        eye: [0.0, 0.0, z],
        light: [0.0, -0.5, -0.7],
        projection: None,
        method: Method::Adaptive,
        camera_rays: 64 * 48,
        shadows,
        per_ray: false,
    };
    let accel = stage.accel();
    assert!(!accel.for_frame(&setup(-1e6, false)).packets(), "from 10⁶");
    assert!(accel.for_frame(&setup(-10.0, false)).packets(), "from 10");
    // (With shadows the camera rays stay in packets: their segments would go per ray too.)
    assert!(
        accel.for_frame(&setup(-1e6, true)).packets(),
        "from 10⁶, shadows"
    );
    for (z, focal) in [(-1e6, 64.0 * 1e6 / 2.2), (-10.0, 64.0 * 10.0 / 2.2)] {
        let pos = glam::DVec3::new(0.0, 0.0, z);
        let cam = raylab::Camera::from_yaw_pitch(pos, 0.0, 0.0, focal).unwrap();
        for (step, spp) in [(LabStep::Flat, 1), (LabStep::Shadows, 2)] {
            let frame = RenderSettings {
                width: 64,
                height: 48,
                step,
                spp,
                ..Default::default()
            };
            let at = format!("from {z}, {step}, spp {spp}");
            let (a, _) = crate::common::renders_as_per_ray(&stage, &cam, &frame, &at);
            // The ball is in view: some pixels are its blue.
            let blue = (a.chunks_exact(4)).filter(|p| u32::from(p[2]) > u32::from(p[0]) + 40);
            let blue = blue.count();
            assert!(blue > 50, "{at}: {blue} blue pixels");
        }
    }
}

/// Hits whose t underflows f32 (a ray from the least subnormal above a triangle, 10¹⁰ long: t =
/// 1.4e-55), a tiny triangle whose t's products underflow, and two triangles a subnormal
/// apart: every layout answers as the reference does. (The f32 filters' t bound had no term
/// for underflow: t 0 ± 0 left the exact t out, and the layouts missed the first, took a hit
/// at tmin equal to the exact t for the second, and the farther triangle for the third.)
#[test]
fn hits_whose_t_underflows_are_answered_as_the_reference_does() {
    let tri = |s: f32, z: f32| Shape::Triangle(Triangle([[-s, -s, z], [s, -s, z], [0.0, s, z]]));
    let inf = f32::INFINITY;
    let nearest = |shapes: &[Shape], ray: &Ray, tmin| {
        accel::closest_hit(shapes, ray, Method::Adaptive, tmin, inf).map(|h| h.prim)
    };
    let one = [tri(1.0, 0.0)];
    let least = f32::from_bits(1);
    let rays =
        [1.0e10f32, 1.0, 1.0e-10, 1.0e18].map(|len| Ray::new([0.0, 0.0, least], [0.0, 0.0, -len]));
    assert_eq!(
        nearest(&one, &rays[0], 0.0),
        Some(0),
        "t = 1.4e-55 > 0: a hit"
    );
    check_all(&one, &rays, 0.0, inf);
    let small = [tri(2f32.powi(-30), 0.0)];
    let oz = 11.0 * 2f32.powi(-91);
    let down = [Ray::new([0.0, 0.0, oz], [0.0, 0.0, -1.0])];
    assert_eq!(nearest(&small, &down[0], oz), None, "t = tmin: no hit");
    assert_eq!(nearest(&small, &down[0], 0.95 * oz), Some(0));
    for tmin in [0.0, 0.95 * oz, oz, 1.05 * oz] {
        check_all(&small, &down, tmin, inf);
    }
    let two = [tri(1.5, 0.0), tri(1.2, -7.7e-41)];
    let mut rng = Rng(0x5ab_7e7a);
    let rays: Vec<Ray> = (0..200)
        .map(|_| {
            let o = [
                rng.range(-0.1, 0.1),
                rng.range(-0.1, 0.1),
                10f64.powf(rng.range(-44.0, -25.0)),
            ];
            let d = [0.0, 0.0, -10f64.powf(rng.range(0.0, 12.0))];
            Ray::new(o.map(|c| c as f32), d.map(|c| c as f32))
        })
        .collect();
    assert!(
        rays.iter().all(|r| nearest(&two, r, 0.0) == Some(0)),
        "the nearer triangle"
    );
    check_all(&two, &rays, 0.0, inf);
}

/// A ray that starts just inside a sphere far larger than the scene (radius 10¹⁰ to 10³⁷,
/// its surface through the scene) leaves it at t ≈ 1, beyond a unit ball it meets first: its
/// exact t, a + b·√s with a ≈ the radius, cancels in f64, and the adaptive search bounded
/// the best hit by that f64 value (off by 10¹⁴ at 10³⁰), so the hierarchies culled the
/// nearer ball (five spheres or more: with four, one leaf held them all). Every path answers
/// as the reference loop: per ray through each structure, and 8 rays a packet.
#[test]
fn a_sphere_far_larger_than_the_scene_hides_no_nearer_ball() {
    use raylab::accel::{Accel, AccelChoice};
    use raylab::tracefile::{self, Query, TraceRay};
    for radius in ["1e10", "1e15", "1e19", "1e30", "1e37"] {
        let text = format!(
            "sphere 0 0 0 1\nsphere 0 0 -{radius} {radius}\n\
             sphere 10 0 0 1\nsphere 20 0 0 1\nsphere 30 0 0 1\n"
        );
        // From (0, 0.8, -3), inside the big sphere, towards the unit ball and around it.
        let rays: String = (0..24)
            .map(|i| {
                format!(
                    "0 0.8 -3 {} {} 3 0 inf\n",
                    0.6 - 0.1 * (i % 6) as f64,
                    -0.2 * (i / 6) as f64
                )
            })
            .collect();
        let rays = tracefile::parse_rays::<f32>("f.rays", &rays).unwrap();
        let shapes = tracefile::parse_scene::<f32>("f.scene", &text).unwrap().0;
        let reference = tracefile::trace_all(&shapes, &rays, Method::Adaptive, Query::Nearest);
        let first = reference.lines().next().unwrap();
        assert_eq!(
            first, "hit 0.923077 0",
            "radius {radius}: the unit ball, at t = 12/13"
        );
        let scene = tracefile::parse_scene_instanced("f.scene", &text).unwrap();
        for choice in [AccelChoice::Flat, AccelChoice::Bvh, AccelChoice::Auto] {
            let structure = Accel::for_scene(&scene, choice);
            let through = |rays: &[TraceRay<f32>]| {
                tracefile::trace_all_through(
                    &scene,
                    &structure,
                    rays,
                    Method::Adaptive,
                    Query::Nearest,
                )
            };
            assert_eq!(through(&rays), reference, "radius {radius}, {choice:?}");
            let packets = tracefile::trace_all_packets(&scene, &structure, &rays, Query::Nearest);
            assert_eq!(packets, reference, "radius {radius}, {choice:?} packets");
        }
    }
}
