//! Instances are only a way of storing: a scene with meshes placed as instances must answer
//! every query, and render every image, exactly as the same scene flattened into world
//! triangles ([`Scene::flattened`]), on random placements and on the hard-case suite.
//!
//! "Exactly": the same primitive (or miss) for every method, the same t and barycentrics for
//! the inexact methods; the adaptive method's t is the f32 t where that is certain, and which
//! f32 computation is certain depends on the box bounds the path uses (as between the flat
//! loop and the BVH, tests/library/accel.rs), so there it is held to the same hit point within f32
//! rounding of its inputs.

use crate::common;

use common::suite;
use common::{check_instance_packets, icosphere, same_hit, Rng};
use glam::{DMat4, DVec3};
use raylab::accel::{self, Accel, AccelChoice};
use raylab::geometry::{Method, Ray, Shape, Sphere, Triangle};
use raylab::render::{render_image, LabStep, RenderSettings, Stage};
use raylab::scene::{cornell, Instance, Mesh, Scene};
use raylab::Camera;
use std::sync::Arc;

/// The structure raylab chooses for `scene`.
pub(crate) fn auto(scene: &Scene) -> Accel {
    Accel::for_scene(scene, AccelChoice::Auto)
}

pub(crate) fn triangles(shapes: &[Shape<f32>]) -> Vec<[[f32; 3]; 3]> {
    shapes
        .iter()
        .map(|s| match s {
            Shape::Triangle(Triangle(v)) => *v,
            _ => panic!("a mesh holds triangles"),
        })
        .collect()
}

pub(crate) fn mesh(name: &str, shapes: &[Shape<f32>], rng: &mut Rng) -> Arc<Mesh> {
    let tris = triangles(shapes);
    // Every fifth face without a colour of its own (the placing colour applies).
    let colors = (0..tris.len())
        .map(|i| (i % 5 != 0).then(|| [0, 1, 2].map(|_| rng.range(0.1, 0.9) as f32)))
        .collect();
    Arc::new(Mesh::new(name.into(), tris, colors))
}

/// A random placement: T·R·S with any angles (a quarter turn now and then), scales uniform or
/// not, sometimes mirrored.
pub(crate) fn placement(rng: &mut Rng) -> DMat4 {
    let t = DVec3::new(
        rng.range(-3.0, 3.0),
        rng.range(-3.0, 3.0),
        rng.range(-3.0, 3.0),
    );
    let angle = |rng: &mut Rng| match rng.below(3) {
        0 => 90.0 * rng.below(4) as f64,
        _ => rng.range(-180.0, 180.0),
    };
    let r = raylab::math::transform::rotation_xyz(DVec3::new(
        angle(rng).to_radians(),
        angle(rng).to_radians(),
        angle(rng).to_radians(),
    ));
    let s = match rng.below(3) {
        0 => DVec3::splat(rng.range(0.3, 2.0)),
        1 => DVec3::new(
            rng.range(0.3, 2.0),
            rng.range(0.3, 2.0),
            rng.range(0.3, 2.0),
        ),
        _ => DVec3::new(
            -rng.range(0.3, 2.0),
            rng.range(0.3, 2.0),
            rng.range(0.3, 2.0),
        ),
    };
    DMat4::from_translation(t) * r * DMat4::from_scale(s)
}

/// A scene of explicit triangles and spheres with `count` placements of `mesh` between them.
pub(crate) fn scene_with(mesh: &Arc<Mesh>, placements: &[DMat4], rng: &mut Rng) -> Scene {
    let mut shapes = Vec::new();
    let mut instances = Vec::new();
    let mut prim = 0u32;
    for (k, m) in placements.iter().enumerate() {
        // Some explicit shapes before each instance (a sphere now and then).
        for _ in 0..rng.below(3) {
            let c = [0, 1, 2].map(|_| rng.range(-3.0, 3.0) as f32);
            shapes.push(match rng.below(4) {
                0 => Shape::Sphere(Sphere {
                    centre: c,
                    radius: rng.range(0.1, 0.6) as f32,
                }),
                _ => Shape::from(
                    [0, 1, 2].map(|_| [0, 1, 2].map(|j| c[j] + rng.range(-0.8, 0.8) as f32)),
                ),
            });
            prim += 1;
        }
        instances.push(Instance {
            mesh: mesh.clone(),
            world_from_object: *m,
            first_prim: prim,
            color: [0.2, 0.3, 0.1 * k as f32],
            tint: (k == 1).then_some([1.0, 0.0, 0.0]),
        });
        prim += mesh.triangles.len() as u32;
    }
    // One instance's triangle copied exactly as an explicit one: a tie at equal t.
    if let Some(first) = instances.first() {
        shapes.push(Shape::from(first.world_triangle(3)));
    }
    let colors = shapes.iter().map(|_| [0.5, 0.6, 0.7]).collect();
    Scene::new(
        "instanced",
        shapes,
        colors,
        cornell::LIGHT,
        cornell::AMBIENT,
    )
    .with_instances(instances)
    .expect("fits")
}

/// Rays from around the scene aimed at the world vertices and edge midpoints of its
/// triangles (where neighbouring triangles meet), and at random points.
pub(crate) fn rays_at(flat: &Scene, rng: &mut Rng, n: usize) -> Vec<Ray> {
    (0..n)
        .map(|_| {
            let o = [0, 1, 2].map(|_| rng.range(-7.0, 7.0) as f32);
            let target = match flat.shapes[rng.below(flat.shapes.len())] {
                Shape::Triangle(Triangle(v)) if rng.below(3) == 0 => v[rng.below(3)],
                Shape::Triangle(Triangle(v)) if rng.below(2) == 0 => {
                    [0, 1, 2].map(|k| (v[0][k] + v[1][k]) * 0.5)
                }
                _ => [0, 1, 2].map(|_| rng.range(-3.0, 3.0) as f32),
            };
            Ray::new(o, [0, 1, 2].map(|k| target[k] - o[k]))
        })
        .collect()
}

#[test]
fn instanced_queries_equal_the_flattened_scene() {
    let mut rng = Rng(0x1257);
    let mut compared = 0usize;
    let mut hits = 0usize;
    for round in 0..12 {
        let mesh_shapes = icosphere(1 + round % 2, 0.7, [0.1, -0.2, 0.3]);
        let mesh = mesh("ball", &mesh_shapes, &mut rng);
        let placements: Vec<DMat4> = (0..2 + rng.below(4)).map(|_| placement(&mut rng)).collect();
        let scene = scene_with(&mesh, &placements, &mut rng);
        let flat = scene.flattened();
        assert_eq!(scene.len(), flat.len());
        for p in 0..scene.len() as u32 {
            assert_eq!(scene.shape(p), flat.shapes[p as usize], "primitive {p}");
            assert_eq!(scene.color(p), flat.colors()[p as usize], "colour of {p}");
        }
        for choice in [AccelChoice::Auto, AccelChoice::Flat] {
            let inst = Accel::for_scene(&scene, choice);
            assert!(inst.instances().is_some());
            let reference = auto(&flat);
            for ray in rays_at(&flat, &mut rng, 150) {
                for method in Method::ALL {
                    let want = accel::closest_hit(&flat.shapes, &ray, method, 0.0, f32::INFINITY);
                    let got = inst.closest_hit(&ray, method, 0.0, f32::INFINITY);
                    let flat_got = reference.closest_hit(&ray, method, 0.0, f32::INFINITY);
                    let what = format!("round {round} {choice:?}: {method} {ray:?}");
                    same_hit(method, &ray, flat_got, want, &what);
                    same_hit(method, &ray, got, want, &what);
                    compared += 1;
                    hits += got.is_some() as usize;
                }
                // Shadow queries: segments towards the nearest hit's point, skipping it. (The
                // flattened structure keeps one of exact copies, so skipping it skips them
                // all; copies in different instances, or of an instance's triangle stored on
                // its own, are kept: such a skip is not compared. Shadow segments from a
                // surface never meet its plane, so renders agree: see the image test.)
                let skip = inst
                    .closest_hit(&ray, Method::Adaptive, 0.0, f32::INFINITY)
                    .map_or(u32::MAX, |h| h.prim);
                let copied = skip != u32::MAX && {
                    let own = flat.shapes[skip as usize];
                    flat.shapes.iter().filter(|s| **s == own).count() > 1
                };
                if copied {
                    continue;
                }
                for tmax in [0.5, 1.0, 2.0] {
                    let want = reference.any_hit(&ray, Method::Adaptive, 0.0, tmax, skip);
                    let got = inst.any_hit(&ray, Method::Adaptive, 0.0, tmax, skip);
                    assert_eq!(got, want, "round {round}: any hit to {tmax} {ray:?}");
                }
            }
        }
    }
    assert!(hits > compared / 3, "{hits} of {compared} rays hit");
}

#[test]
fn tiles_off_the_instances_box_render_as_the_flattened_scene() {
    // Balls alone, no box around them: tiles off the instances' screen rectangle are filled
    // as background without tracing. One ball sits at the image's left edge, part off it.
    let mut rng = Rng(78);
    let mesh = mesh("ball", &icosphere(2, 0.3, [0.0, 0.0, 0.0]), &mut rng);
    let at = |x: f64, y: f64| DMat4::from_translation(DVec3::new(x, y, 0.0));
    let placements = [at(-1.25, 0.0), at(0.0, 0.1), at(0.5, -0.3)];
    let instances: Vec<Instance> = (placements.iter().enumerate())
        .map(|(k, &m)| Instance {
            mesh: mesh.clone(),
            world_from_object: m,
            first_prim: (k * mesh.triangles.len()) as u32,
            color: [0.2, 0.5, 0.9],
            tint: None,
        })
        .collect();
    let scene = Scene::new(
        "balls",
        Vec::new(),
        Vec::new(),
        cornell::LIGHT,
        cornell::AMBIENT,
    )
    .with_instances(instances)
    .unwrap();
    let flat = Stage::from(scene.flattened());
    let cam = Camera::from_yaw_pitch(DVec3::new(0.0, 0.0, -2.5), 0.0, 0.0, 100.0).unwrap();
    let (w, h) = (120, 90);
    let gen = cam.ray_generator(w, h);
    let stage = Stage::from(scene.clone());
    let queries = stage.accel().for_frame(&accel::FrameSetup {
        eye: gen.origin(),
        light: scene.light.position,
        projection: Some(cam.projection(w, h)),
        method: Method::Adaptive,
        camera_rays: (w * h) as usize,
        shadows: false,
        per_ray: false,
    });
    let mut scratch = accel::TileScratch::default();
    let empty = (0..h)
        .step_by(16)
        .flat_map(|y0| {
            (0..w)
                .step_by(8)
                .map(move |x0| [x0, y0, (x0 + 8).min(w), (y0 + 16).min(h)])
        })
        .filter(|&tile| queries.tile(tile, &mut scratch).shows_nothing())
        .count();
    // Above and below the row of balls.
    assert!(empty >= 30, "{empty} empty tiles");
    for step in [LabStep::Flat, LabStep::Shadows] {
        for tile_culling in [true, false] {
            let settings = RenderSettings {
                width: w,
                height: h,
                step,
                tile_culling,
                ..Default::default()
            };
            let (a, sa) = render_image(&stage, &cam, &settings).unwrap();
            let (b, sb) = render_image(&flat, &cam, &settings).unwrap();
            assert!(a == b, "{step} culling {tile_culling}: images differ");
            assert_eq!((sa.hits, sa.shadow_rays), (sb.hits, sb.shadow_rays));
            assert!(sa.hits > 1000, "{} hits", sa.hits);
        }
    }
}

#[test]
fn instanced_images_equal_the_flattened_scene() {
    let mut rng = Rng(77);
    let mesh = mesh("ball", &icosphere(2, 0.35, [0.0, 0.0, 0.0]), &mut rng);
    // Balls on the Cornell box's floor, one squashed, one turned.
    let mut shapes = cornell::scene().shapes;
    let mut colors = cornell::scene().colors().to_vec();
    let at = |x: f64, z: f64| DMat4::from_translation(DVec3::new(x, 0.65, z));
    let placements = [
        at(-0.55, -0.55),
        at(0.05, -0.75) * DMat4::from_scale(DVec3::new(1.0, 0.5, 1.3)),
        at(0.62, -0.6) * DMat4::from_rotation_y(0.7),
    ];
    let mut instances = Vec::new();
    for m in placements {
        instances.push(Instance {
            mesh: mesh.clone(),
            world_from_object: m,
            first_prim: (shapes.len() + instances.len() * mesh.triangles.len()) as u32,
            color: [0.2, 0.5, 0.9],
            tint: None,
        });
    }
    shapes.push(Shape::Sphere(Sphere {
        centre: [0.5, 0.7, 0.5],
        radius: 0.2,
    }));
    colors.push([0.9, 0.9, 0.2]);
    // The sphere comes after the instances in primitive order.
    let n_inst = (instances.len() * mesh.triangles.len()) as u32;
    let scene = Scene::new("balls", shapes, colors, cornell::LIGHT, cornell::AMBIENT)
        .with_instances(instances)
        .unwrap();
    assert_eq!(scene.len() as u32, 30 + n_inst + 1);
    // The explicit triangles in the BVH (auto), and in the flat loop: both walk the
    // camera and shadow packets beside the instances.
    let in_flat_loop = Stage::new(scene.clone(), AccelChoice::Flat);
    let (scene, flat) = (Stage::from(scene.clone()), Stage::from(scene.flattened()));
    let cam = Camera::cornell(100);
    for step in LabStep::ALL {
        for cracks in [false, true] {
            let settings = RenderSettings {
                width: 100,
                height: 75,
                step,
                cracks,
                ..Default::default()
            };
            let (b, sb) = render_image(&flat, &cam, &settings).unwrap();
            for (layout, stage) in [("bvh", &scene), ("flat loop", &in_flat_loop)] {
                let (a, sa) = render_image(stage, &cam, &settings).unwrap();
                assert!(a == b, "{layout} {step} cracks={cracks}: images differ");
                assert_eq!(
                    (sa.hits, sa.shadow_rays),
                    (sb.hits, sb.shadow_rays),
                    "{layout} {step}"
                );
            }
        }
    }
    // The balls show: the flat image differs from the box alone.
    let settings = RenderSettings {
        width: 100,
        height: 75,
        ..Default::default()
    };
    let boxed = render_image(&Scene::cornell().into(), &cam, &settings)
        .unwrap()
        .0;
    let balls = render_image(&scene, &cam, &settings).unwrap().0;
    let differ = boxed
        .chunks(4)
        .zip(balls.chunks(4))
        .filter(|(a, b)| a != b)
        .count();
    assert!(differ > 500, "{differ} pixels show the balls");
}

/// A hard-case family's triangles as one mesh, placed twice: as it is, and turned a quarter
/// about z and scaled by 2 (exact); with the number of triangles. `None` for a family with
/// other shapes (spheres are not meshes).
fn family_placed_twice(family: &suite::Family, rng: &mut Rng) -> Option<(Scene, u32)> {
    let tris: Vec<Shape<f32>> = (family.shapes.iter())
        .filter(|s| matches!(s, Shape::Triangle(_)))
        .copied()
        .collect();
    if tris.len() != family.shapes.len() || tris.is_empty() {
        return None;
    }
    let quarter = DMat4::from_cols_array_2d(&[
        [0.0, 2.0, 0.0, 0.0],
        [-2.0, 0.0, 0.0, 0.0],
        [0.0, 0.0, 2.0, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ]);
    let mesh = mesh(&family.name, &tris, rng);
    let n = tris.len() as u32;
    let place = |m: DMat4, first: u32| Instance {
        mesh: mesh.clone(),
        world_from_object: m,
        first_prim: first,
        color: [0.5; 3],
        tint: None,
    };
    let scene = Scene::new("suite", vec![], vec![], cornell::LIGHT, cornell::AMBIENT)
        .with_instances(vec![place(DMat4::IDENTITY, 0), place(quarter, n)])
        .unwrap();
    Some((scene, n))
}

#[test]
fn hard_cases_through_instances_answer_as_flattened() {
    // Every family's triangles as one mesh, placed twice: as it is (the family's own rays)
    // and turned a quarter about z and scaled by 2 (exact: the turned family's rays must
    // name the same primitives, offset by the first placement's size).
    let mut rng = Rng(5);
    let turn = |p: [f32; 3]| [-2.0 * p[1], 2.0 * p[0], 2.0 * p[2]];
    let mut rays = 0;
    for family in suite::all() {
        let Some((scene, n)) = family_placed_twice(&family, &mut rng) else {
            continue; // (the spheres family: spheres are not meshes)
        };
        let own = Scene::new(
            "own",
            family.shapes.clone(),
            vec![[0.5; 3]; n as usize],
            cornell::LIGHT,
            cornell::AMBIENT,
        );
        let (own, flat, scene) = (auto(&own), auto(&scene.flattened()), auto(&scene));
        for ray in &family.rays {
            let want = own.closest_hit(ray, Method::Adaptive, 0.0, f32::INFINITY);
            let got = scene.closest_hit(ray, Method::Adaptive, 0.0, f32::INFINITY);
            let flat_got = flat.closest_hit(ray, Method::Adaptive, 0.0, f32::INFINITY);
            same_hit(Method::Adaptive, ray, got, flat_got, &family.name);
            // The second placement lies elsewhere only where the family is not centred on
            // the z axis; where the first placement is hit, it is the family's own answer.
            if let (Some(g), Some(w)) = (got, want) {
                if g.prim < n {
                    assert_eq!(g.prim, w.prim, "{}: {ray:?}", family.name);
                }
            }
            let turned = Ray::new(turn(ray.o), turn(ray.d));
            let got = scene.closest_hit(&turned, Method::Adaptive, 0.0, f32::INFINITY);
            let flat_got = flat.closest_hit(&turned, Method::Adaptive, 0.0, f32::INFINITY);
            same_hit(Method::Adaptive, &turned, got, flat_got, &family.name);
            rays += 1;
        }
    }
    assert!(rays > 2000, "{rays} rays");
}

#[test]
fn instanced_packets_decide_as_the_flattened_scene() {
    // The mesh leaves prepare their triangles in f32, go to a lone lane in one pass, and
    // are prepared again in f64 where the f32 bounds leave a lane undecided: every lane
    // decided must be the flattened answer. (1) The hard-case suite placed twice (as it is
    // and turned a quarter, scaled by 2), each family ray as lane 0 beside seven other
    // families' directions from the same origin. (2) Small balls placed far away in a row
    // (the bunny field's far rows, where the f32 bounds are loosest), rays through random
    // points of the row: most leaves are reached by one lane. (The suite's rays are hard on
    // purpose: about a third of its lanes go to the per-ray search, as before the f32
    // preparation.)
    let mut rng = Rng(9);
    let (mut decided, mut lanes) = (0, 0);
    let mut all_dirs: Vec<[f32; 3]> = Vec::new();
    for family in suite::all() {
        all_dirs.extend(family.rays.iter().map(|r| r.d));
    }
    for family in suite::all() {
        let Some((scene, _)) = family_placed_twice(&family, &mut rng) else {
            continue;
        };
        let (scene, flat) = (auto(&scene), auto(&scene.flattened()));
        for ray in family.rays.iter().step_by(3) {
            let mut dirs = [ray.d; 8];
            for d in &mut dirs[1..] {
                *d = all_dirs[rng.below(all_dirs.len())];
            }
            let (d, l) = check_instance_packets(&scene, &flat, ray.o, &dirs, &family.name);
            decided += d;
            lanes += l;
        }
    }
    assert!(
        lanes > 2000 && decided * 5 > lanes * 3,
        "{decided} of {lanes} lanes decided"
    );

    let ball = mesh("ball", &icosphere(3, 0.05, [0.0; 3]), &mut rng);
    let n = ball.triangles.len() as u32;
    let placements: Vec<Instance> = (0..40)
        .map(|i| Instance {
            mesh: ball.clone(),
            world_from_object: DMat4::from_translation(DVec3::new(
                i as f64 * 0.13 - 2.6,
                0.0,
                40.0,
            )),
            first_prim: n * i,
            color: [0.5; 3],
            tint: None,
        })
        .collect();
    let scene = Scene::new("row", vec![], vec![], cornell::LIGHT, cornell::AMBIENT)
        .with_instances(placements)
        .unwrap();
    let (scene, flat) = (auto(&scene), auto(&scene.flattened()));
    let (mut decided, mut lanes, mut hits) = (0, 0, 0);
    for _ in 0..400 {
        let o = [
            rng.range(-0.5, 0.5) as f32,
            rng.range(-0.1, 0.1) as f32,
            -1.0,
        ];
        let dirs: [[f32; 3]; 8] = std::array::from_fn(|_| {
            let p = [rng.range(-2.7, 2.6), rng.range(-0.06, 0.06), 40.0];
            [p[0] as f32 - o[0], p[1] as f32 - o[1], p[2] as f32 - o[2]]
        });
        let (d, l) = check_instance_packets(&scene, &flat, o, &dirs, "row");
        decided += d;
        lanes += l;
        hits += dirs
            .iter()
            .filter(|d| {
                flat.closest_hit(&Ray::new(o, **d), Method::Adaptive, 0.0, f32::INFINITY)
                    .is_some()
            })
            .count();
    }
    assert!(
        decided * 10 > lanes * 9,
        "{decided} of {lanes} lanes decided"
    );
    assert!(
        hits > lanes / 4,
        "the rays meet the balls: {hits} of {lanes}"
    );
}
