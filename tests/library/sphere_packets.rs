//! Spheres in the packets: a tile a sphere may show in keeps its camera packets,
//! the sphere tested four lanes (or four (sphere, lane) pairs) at a time through its f64
//! interval level (`sphere::interval_x4_of`, `interval_x4_gathered`), and shadow segments near a sphere test it lane by lane before
//! the triangle packets. Every answer must be the per-ray search's.

use crate::common;

use common::{icosphere, Rng};
use raylab::accel::{AccelChoice, FrameSetup, TileScratch, NO_HIT};
use raylab::camera::Camera;
use raylab::geometry::adaptive::{closest_hit_reference, Estimate};
use raylab::geometry::sphere::{DirectionLanes, DirectionsX4, LanesX4};
use raylab::geometry::{sphere, Method, Ray, Shape, Sphere};
use raylab::render::{render_image, LabStep, RenderSettings, Stage};
use raylab::scene::Scene;
use std::cmp::Ordering;
use wide::{f32x8, f64x4};

fn sphere(centre: [f32; 3], radius: f32) -> Shape<f32> {
    Shape::Sphere(Sphere { centre, radius })
}

/// The Cornell box with `spheres` added (primitives 30 on).
fn cornell_plus(spheres: &[Shape<f32>]) -> Scene {
    let mut scene = Scene::cornell();
    for (i, s) in spheres.iter().enumerate() {
        scene.shapes.push(*s);
        scene.colors_mut().push([0.9, 0.3 + 0.2 * i as f32, 0.2]);
    }
    scene
}

/// [`cornell_plus`] with the structure `choice` built over it.
fn cornell_with(spheres: &[Shape<f32>], choice: AccelChoice) -> Stage {
    Stage::new(cornell_plus(spheres), choice)
}

/// What the exact level says of o + t·d on the sphere for tmin < t < tmax: the nearest root,
/// if any, compared with the interval [lo, hi] (`Some(true)`: inside it).
fn exact_root_in(
    o: [f64; 3],
    d: [f64; 3],
    (c, r): ([f64; 3], f64),
    (tmin, tmax): (f64, f64),
    lo: f64,
    hi: f64,
) -> Option<bool> {
    let t = sphere::exact(o, d, c, r, tmin, tmax)?;
    Some(t.cmp_f(lo) != Ordering::Less && t.cmp_f(hi) != Ordering::Greater)
}

#[test]
fn the_four_lane_sphere_interval_never_contradicts_the_exact_roots() {
    // Random rays at spheres of radii 2^-20..2^20, origins far, near, on and inside the
    // surface, directions of any length, tangent rays and zero directions; both ranges the
    // packets use (camera: 0 < t < ∞, shadow: 0 < t < 1). A hit's interval must hold the exact
    // nearest root, a miss must have none, and the lanes must agree with the scalar level
    // wherever both decide.
    let mut rng = Rng(14);
    let (mut hits, mut misses, mut undecided) = ([0; 3], [0; 3], [0; 3]);
    let mut earlier = Vec::new();
    for case in 0..4000 {
        let scale = 2f64.powi(rng.below(41) as i32 - 20);
        let c = [0, 1, 2].map(|_| (rng.range(-4.0, 4.0) * scale) as f32 as f64);
        let r = (rng.range(0.05, 2.0) * scale) as f32 as f64;
        let o = match case % 4 {
            // On the surface (rounded to f32: a hair inside or outside).
            0 => {
                let u = [0, 1, 2].map(|_| rng.range(-1.0, 1.0));
                let n = (u[0] * u[0] + u[1] * u[1] + u[2] * u[2]).sqrt();
                [0, 1, 2].map(|k| (c[k] + r * u[k] / n) as f32 as f64)
            }
            // Inside.
            1 => [0, 1, 2].map(|k| (c[k] + 0.3 * r * rng.range(-1.0, 1.0)) as f32 as f64),
            _ => [0, 1, 2].map(|_| (rng.range(-20.0, 20.0) * scale) as f32 as f64),
        };
        let (from, tmin, tmax) = (
            sphere::FromOrigin::new(o, c, r),
            0.0,
            if case % 2 == 0 { f64::INFINITY } else { 1.0 },
        );
        let dirs: [[f64; 3]; 4] = std::array::from_fn(|lane| {
            let aim = match (case + lane) % 5 {
                // Tangent: at a point on the sphere's rim seen from o.
                0 => {
                    let to_c = [0, 1, 2].map(|k| c[k] - o[k]);
                    let side = [to_c[1], -to_c[0], 0.0];
                    let n = (side[0] * side[0] + side[1] * side[1]).sqrt().max(1e-300);
                    [0, 1, 2].map(|k| c[k] + r * side[k] / n)
                }
                1 if lane == 3 => o, // zero direction
                _ => [0, 1, 2].map(|k| c[k] + r * rng.range(-1.3, 1.3)),
            };
            let len = 2f64.powi(rng.below(9) as i32 - 4);
            [0, 1, 2].map(|k| ((aim[k] - o[k]) * len) as f32 as f64)
        });
        let d = [0, 1, 2].map(|k| f64x4::new(dirs.map(|v| v[k])));
        // Three forms: one sphere's (the shading point's), the packets' (1/a once), and the
        // packets' with the sphere as the frame prepares it (`FromOrigin::for_packets`).
        let dirs_x4 = DirectionsX4::new(d);
        let per_sphere = sphere::interval_x4(&from, &d, tmin, tmax);
        let per_packet = sphere::interval_x4_of(&from, &dirs_x4, tmin, tmax);
        let framed = sphere::FromOrigin::for_packets(o, c, r);
        let per_frame = sphere::interval_x4_of(&framed, &dirs_x4, tmin, tmax);
        // The packets' pairs: lanes of two packets (this case's and the one two before, with
        // the same range), each against its own sphere, gathered in a shuffled order, give
        // each lane the bits of `per_frame`.
        earlier.push((framed, dirs_x4, per_frame));
        if case >= 2 {
            let (a, b) = (&earlier[case - 2], &earlier[case]);
            let eight = DirectionLanes::new(&[a.1, b.1]);
            let lanes = [
                (case + 1) % 4,
                4 + case % 4,
                4 + (case + 2) % 4,
                (case + 3) % 4,
            ];
            let spheres = lanes.map(|l| if l < 4 { &a.0 } else { &b.0 });
            let pairs: LanesX4 = sphere::interval_x4_gathered(spheres, &eight, lanes, tmin, tmax);
            for (i, l) in lanes.into_iter().enumerate() {
                let want = if l < 4 { a.2 } else { b.2 };
                let bits = |x: &LanesX4, l: usize| {
                    [x.hit, x.miss, x.lo, x.hi].map(|v| v.to_array()[l].to_bits())
                };
                assert_eq!(bits(&pairs, i), bits(&want, l % 4), "case {case} lane {l}");
            }
        }
        for (f, lanes) in [per_sphere, per_packet, per_frame].into_iter().enumerate() {
            let form = ["per sphere", "per packet", "per frame"][f];
            let (hit, miss) = (lanes.hit.to_bitmask(), lanes.miss.to_bitmask());
            assert_eq!(
                hit & miss,
                0,
                "case {case} {form}: a lane both hit and missed"
            );
            for (l, dl) in dirs.iter().enumerate() {
                let exact = exact_root_in(
                    o,
                    *dl,
                    (c, r),
                    (tmin, tmax),
                    lanes.lo.to_array()[l],
                    lanes.hi.to_array()[l],
                );
                let scalar = sphere::interval(o, *dl, c, r, tmin, tmax);
                let what = format!("case {case} lane {l} {form}: o {o:?} d {dl:?} c {c:?} r {r}");
                if hit & (1 << l) != 0 {
                    hits[f] += 1;
                    assert_eq!(exact, Some(true), "{what}: hit interval misses the root");
                    assert!(
                        !matches!(scalar, Estimate::Miss),
                        "{what}: scalar says miss"
                    );
                } else if miss & (1 << l) != 0 {
                    misses[f] += 1;
                    assert_eq!(exact, None, "{what}: a root where the lanes say miss");
                    assert!(
                        !matches!(scalar, Estimate::Hit(_)),
                        "{what}: scalar says hit"
                    );
                } else {
                    undecided[f] += 1;
                }
            }
        }
    }
    for f in 0..3 {
        let (hits, misses, undecided) = (hits[f], misses[f], undecided[f]);
        println!("form {f} (0: per sphere, 1: per packet, 2: per frame): {hits} hits, {misses} misses, {undecided} undecided of 16,000 lanes");
        assert!(hits > 4000 && misses > 4000, "{hits} hits, {misses} misses");
        assert!(undecided < 1200, "{undecided} lanes undecided");
    }
}

#[test]
fn camera_packets_keep_the_tiles_a_sphere_shows_in_and_name_the_per_ray_primitive() {
    // The lab's Cornell box with two spheres, one resting exactly on the floor (its lowest
    // point is the floor's plane) and one through the left wall, through the small scene's
    // culled packets and through the BVH's packets: every tile runs packets, and every lane
    // names the primitive of the per-ray search (exact), on and off the spheres.
    let spheres = [
        sphere([0.25, 0.5, -0.2], 0.5),
        sphere([-1.0, 0.1, 0.3], 0.35),
    ];
    for choice in [AccelChoice::Auto, AccelChoice::Bvh] {
        let stage = cornell_with(&spheres, choice);
        let (scene, accel) = (stage.scene(), stage.accel());
        let (w, h) = (96, 72);
        let camera = Camera::cornell(w);
        let gen = camera.ray_generator(w, h);
        let frame = accel.for_frame(&FrameSetup {
            eye: gen.origin(),
            light: scene.light.position,
            projection: Some(camera.projection(w, h)),
            method: Method::Adaptive,
            camera_rays: (w * h) as usize,
            shadows: false,
            per_ray: false,
        });
        let mut scratch = TileScratch::default();
        let mut on_spheres = 0;
        for y in 0..h {
            for x0 in (0..w).step_by(8) {
                let mut tile = frame.tile([x0, y, x0 + 8, y + 1], &mut scratch);
                assert!(tile.packets(), "{choice:?}: tile ({x0}, {y}) goes per ray");
                let xs: [f32; 8] = std::array::from_fn(|l| (x0 + l as u32) as f32 + 0.5);
                let d = gen.directions_x8(f32x8::from(xs), f32x8::splat(y as f32 + 0.5));
                let prims = tile.closest_x8(&d, 0xff);
                for (l, &prim) in prims.iter().enumerate() {
                    let ray = Ray::new(gen.origin(), d.map(|c| c.to_array()[l]));
                    let want = accel.closest_hit(&ray, Method::Adaptive, 0.0, f32::INFINITY);
                    let reference = closest_hit_reference(&scene.shapes, &ray, 0.0, f32::INFINITY);
                    let want = want.map_or(NO_HIT, |h| h.prim);
                    assert_eq!(reference.map_or(NO_HIT, |h| h.prim), want);
                    assert_eq!(prim, want, "{choice:?}: pixel ({}, {y})", x0 + l as u32);
                    on_spheres += (prim >= 30 && prim != NO_HIT) as usize;
                }
            }
        }
        assert!(
            on_spheres > 800,
            "{choice:?}: {on_spheres} lanes on the spheres"
        );
    }
}

/// Renders `scene` through the packets and through the per-ray path (the cracks view traces
/// every ray one at a time; with the adaptive method it marks nothing) and requires the same
/// bits and counts.
fn packets_render_as_per_ray(what: &str, scene: &Stage, camera: &Camera, w: u32, h: u32) {
    for step in [
        LabStep::Flat,
        LabStep::Direct,
        LabStep::Shadows,
        LabStep::Indirect,
    ] {
        for spp in [1, 2] {
            for tile_culling in [true, false] {
                let packets = RenderSettings {
                    width: w,
                    height: h,
                    step,
                    spp,
                    tile_culling,
                    ..Default::default()
                };
                let per_ray = RenderSettings {
                    cracks: true,
                    ..packets
                };
                let (a, sa) = render_image(scene, camera, &packets).unwrap();
                let (b, sb) = render_image(scene, camera, &per_ray).unwrap();
                let off = (a.chunks_exact(4).zip(b.chunks_exact(4)))
                    .filter(|(p, q)| p != q)
                    .count();
                let tag = format!("{what}, {step} spp {spp} culling {tile_culling}");
                assert_eq!(off, 0, "{tag}: {off} pixels differ");
                assert_eq!(
                    (sa.hits, sa.shadow_rays),
                    (sb.hits, sb.shadow_rays),
                    "{tag}"
                );
            }
        }
    }
}

#[test]
fn scenes_with_spheres_render_through_the_packets_as_per_ray() {
    let light = Scene::cornell().light.position;
    let touching = [
        sphere([0.25, 0.5, -0.2], 0.5),
        sphere([-1.0, 0.1, 0.3], 0.35),
        sphere([0.6, -0.6, 0.6], 0.001),
    ];
    let cam = Camera::cornell(72);
    packets_render_as_per_ray(
        "spheres on the floor, through a wall, tiny",
        &cornell_with(&touching, AccelChoice::Auto),
        &cam,
        72,
        54,
    );
    // Around the light: everything but the sphere's inside is in its shadow, and the inside
    // is lit (the sphere's own skip).
    let lamp = sphere(light, 0.2);
    packets_render_as_per_ray(
        "a sphere around the light",
        &cornell_with(&[lamp, touching[0]], AccelChoice::Auto),
        &cam,
        64,
        48,
    );
    // The camera inside a sphere with the light outside: the sphere blocks its own inside.
    let inside = Camera::from_yaw_pitch(glam::DVec3::new(0.1, 0.2, 0.0), 0.4, 0.2, 40.0).unwrap();
    packets_render_as_per_ray(
        "the camera inside a sphere",
        &cornell_with(
            &[sphere([0.1, 0.2, 0.05], 0.3), touching[1]],
            AccelChoice::Auto,
        ),
        &inside,
        48,
        36,
    );
    // Spheres alone (the flat loop holds no triangle): packets still, through the spheres'
    // hierarchy.
    let alone = Scene::new(
        "spheres",
        touching.to_vec(),
        vec![[0.8, 0.3, 0.2]; 3],
        Scene::cornell().light,
        [0.1; 3],
    );
    let alone = Stage::new(alone, AccelChoice::Auto);
    let frame = alone.accel().for_frame(&FrameSetup {
        eye: cam.ray_generator(64, 48).origin(),
        light,
        projection: Some(cam.projection(64, 48)),
        method: Method::Adaptive,
        camera_rays: 64 * 48,
        shadows: true,
        per_ray: false,
    });
    assert!(frame.packets(), "spheres alone go in packets");
    drop(frame);
    packets_render_as_per_ray("spheres alone", &alone, &cam, 64, 48);
    // A meshed ball beside real spheres: the BVH's packets (1,280 triangles, prepared per
    // frame and as met), a sphere inside the mesh's box.
    let mut mixed = cornell_plus(&touching);
    let ball = icosphere(3, 0.35, [-0.3, 0.55, 0.2]);
    let n = ball.len();
    mixed.shapes.extend(ball);
    mixed
        .colors_mut()
        .extend(std::iter::repeat_n([0.2, 0.5, 0.9], n));
    mixed.shapes.push(sphere([-0.3, 0.55, 0.2], 0.1));
    mixed.colors_mut().push([1.0, 1.0, 0.0]);
    let mixed = Stage::new(mixed, AccelChoice::Bvh);
    packets_render_as_per_ray("a meshed ball beside spheres", &mixed, &cam, 64, 48);
}

#[test]
fn many_small_balls_render_through_the_packets_as_per_ray() {
    // 1,500 balls of radius 0.01–0.03 in the box, a pixel or two each at 64×48, so a
    // packet's lanes part at the leaves and meet their balls in (sphere, lane) pairs; with
    // 150 twins 10⁻⁶ from a ball (lanes too close to order, left to the per-ray search
    // midway through a leaf) and balls that overlap. Colours differ from ball to ball.
    let mut rng = Rng(65);
    let mut balls = Vec::new();
    for i in 0..1500 {
        let c = [0, 1, 2].map(|_| rng.range(-0.9, 0.9) as f32);
        balls.push(sphere(c, rng.range(0.01, 0.03) as f32));
        if i % 10 == 0 {
            balls.push(sphere([c[0] + 1e-6, c[1], c[2] - 1e-6], 0.02));
        }
    }
    let mut scene = cornell_plus(&[]);
    for (i, b) in balls.iter().enumerate() {
        scene.shapes.push(*b);
        let hue = (i % 97) as f32 / 97.0;
        scene
            .colors_mut()
            .push([hue, 1.0 - hue, (i % 7) as f32 / 7.0]);
    }
    let stage = Stage::new(scene, AccelChoice::Auto);
    packets_render_as_per_ray("1,650 small balls", &stage, &Camera::cornell(64), 64, 48);
}

#[test]
fn the_spheres_cast_shadows_in_the_packets() {
    // The shadow of the sphere on the floor: against the same scene without it, shadowed
    // pixels appear (and both paths above agree on every one of them).
    let ball = sphere([0.25, 0.5, -0.2], 0.5);
    let with = cornell_with(&[ball], AccelChoice::Auto);
    let without = cornell_with(&[], AccelChoice::Auto);
    let cam = Camera::cornell(80);
    let settings = |step| RenderSettings {
        width: 80,
        height: 60,
        step,
        ..Default::default()
    };
    let (shadowed, stats) = render_image(&with, &cam, &settings(LabStep::Shadows)).unwrap();
    let direct = render_image(&with, &cam, &settings(LabStep::Direct))
        .unwrap()
        .0;
    let darker = (shadowed.chunks_exact(4).zip(direct.chunks_exact(4)))
        .filter(|(s, d)| s[..3] != d[..3])
        .count();
    let box_only = render_image(&without, &cam, &settings(LabStep::Shadows))
        .unwrap()
        .0;
    let changed = (shadowed.chunks_exact(4).zip(box_only.chunks_exact(4)))
        .filter(|(s, d)| s != d)
        .count();
    assert!(darker > 300, "{darker} pixels in shadow");
    assert!(changed > darker, "{changed} pixels changed by the sphere");
    assert!(
        stats.shadow_rays > 4000,
        "{} shadow rays",
        stats.shadow_rays
    );
}
