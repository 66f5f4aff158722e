//! Instanced answers at every scale the scene format accepts. A mesh stored at 2⁻¹⁰⁰ and placed
//! by a scale of 2¹⁰⁰ (or the reverse, or at 2⁻⁸⁰, or among f32's subnormals at 2⁻¹³⁰) is an
//! ordinary unit-sized object in the world, but a ray's direction carried into its frame is
//! scaled by the inverse: with directions from 2⁻¹⁰⁰ to 2¹⁰⁰ long it leaves f32's normal range
//! (underflows, overflows or loses its relative precision). Every query must still answer as
//! the same scene flattened, per ray and 8 rays at a time, for every method.

use crate::common;

use common::{check_instance_packets, icosphere, same_hit, Rng};
use glam::{DMat4, DVec3};
use raylab::accel::{self, Accel, AccelChoice};
use raylab::geometry::{Method, Ray, Shape, Triangle};
use raylab::scene::{cornell, Instance, Mesh, Scene};
use std::sync::Arc;

/// Two placements of a ball of radius 0.7 about (2, 2, 2) stored scaled by 2^`stored`, each
/// placed by a scale of 2^-`stored` (turned and moved), so that the world holds two
/// unit-sized balls. (About (2, 2, 2), no coordinate of the ball's boxes is near 0: at 2⁻⁸⁰
/// they are all within the range the f32 slab tests trust.)
fn balls_stored_at(stored: i32) -> Scene {
    let s = 2f64.powi(stored);
    let centre = DVec3::splat(2.0);
    let ball: Vec<[[f32; 3]; 3]> = icosphere(2, 0.7, centre.as_vec3().to_array())
        .iter()
        .map(|shape| match shape {
            Shape::Triangle(Triangle(v)) => v.map(|p| p.map(|c| (c as f64 * s) as f32)),
            Shape::Sphere(_) => unreachable!("an icosphere holds triangles"),
        })
        .collect();
    let n = ball.len() as u32;
    let mesh = Arc::new(Mesh::new("ball".into(), ball, vec![None; n as usize]));
    let rotation = raylab::math::transform::rotation_xyz(DVec3::new(0.4, -1.1, 0.7));
    let instances = [[-0.9, 0.1, 0.2], [0.8, -0.2, 0.9]]
        .iter()
        .enumerate()
        .map(|(k, t)| {
            let at = DVec3::from_array(*t) - rotation.transform_vector3(centre);
            Instance {
                mesh: mesh.clone(),
                world_from_object: DMat4::from_translation(at)
                    * rotation
                    * DMat4::from_scale(DVec3::splat(1.0 / s)),
                first_prim: n * k as u32,
                color: [0.5; 3],
                tint: None,
            }
        })
        .collect();
    Scene::new("balls", vec![], vec![], cornell::LIGHT, cornell::AMBIENT)
        .with_instances(instances)
        .expect("fits")
}

/// A ray from around the balls towards a world vertex, an edge midpoint or a random point
/// near them, its direction scaled by 2^`scale`.
fn ray_towards(flat: &Scene, rng: &mut Rng, scale: i32) -> Ray {
    let o = [0, 1, 2].map(|_| rng.range(-4.0, 4.0) as f32);
    Ray::new(o, direction_from(o, flat, rng, scale))
}

/// A direction from `o` towards a world vertex, an edge midpoint or a random point near the
/// balls, scaled by 2^`scale`.
fn direction_from(o: [f32; 3], flat: &Scene, rng: &mut Rng, scale: i32) -> [f32; 3] {
    let target = match flat.shapes[rng.below(flat.shapes.len())] {
        Shape::Triangle(Triangle(v)) if rng.below(3) == 0 => v[rng.below(3)],
        Shape::Triangle(Triangle(v)) if rng.below(2) == 0 => {
            [0, 1, 2].map(|k| (v[0][k] + v[1][k]) * 0.5)
        }
        _ => [0, 1, 2].map(|_| rng.range(-1.5, 1.5) as f32),
    };
    let f = 2f64.powi(scale);
    [0, 1, 2].map(|k| ((target[k] - o[k]) as f64 * f) as f32)
}

/// The scales (powers of two) the ball is stored at.
const STORED: [i32; 5] = [-100, -80, -30, 100, -130];

/// The scales (powers of two) of the rays' directions.
fn direction_scales() -> impl Iterator<Item = i32> {
    (-125..=100).step_by(5)
}

#[test]
fn per_ray_queries_answer_as_flattened_whatever_the_scale_of_the_carried_direction() {
    let mut rng = Rng(0x5ca1e);
    let (mut compared, mut hits) = (0, 0);
    for stored in STORED {
        let scene = balls_stored_at(stored);
        let flat = scene.flattened();
        for choice in [AccelChoice::Auto, AccelChoice::Flat] {
            let inst = Accel::for_scene(&scene, choice);
            assert!(inst.instances().is_some());
            for scale in direction_scales() {
                for _ in 0..12 {
                    let ray = ray_towards(&flat, &mut rng, scale);
                    let what = format!("stored 2^{stored}, {choice:?}, |d| 2^{scale}: {ray:?}");
                    let mut nearest = None;
                    for method in Method::ALL {
                        let want =
                            accel::closest_hit(&flat.shapes, &ray, method, 0.0, f32::INFINITY);
                        let got = inst.closest_hit(&ray, method, 0.0, f32::INFINITY);
                        same_hit(method, &ray, got, want, &format!("{method} {what}"));
                        compared += 1;
                        hits += got.is_some() as usize;
                        if method == Method::Adaptive {
                            nearest = want;
                        }
                    }
                    // Shadow queries: up to half way to the exact nearest hit, and just past it.
                    if let Some(h) = nearest {
                        for tmax in [h.t * 0.5, h.t * 1.01] {
                            let want = accel::reference::any_hit(
                                &flat.shapes,
                                &ray,
                                Method::Adaptive,
                                0.0,
                                tmax,
                                u32::MAX,
                            );
                            let got = inst.any_hit(&ray, Method::Adaptive, 0.0, tmax, u32::MAX);
                            assert_eq!(got, want, "any hit to {tmax}: {what}");
                        }
                    }
                }
            }
        }
    }
    assert!(hits * 3 > compared, "{hits} of {compared} rays hit");
}

#[test]
fn packets_answer_as_flattened_whatever_the_scale_of_the_carried_directions() {
    let mut rng = Rng(0xba11);
    let (mut decided, mut lanes) = (0, 0);
    for stored in STORED {
        let scene = balls_stored_at(stored);
        let flat_scene = scene.flattened();
        let (inst, flat) = (
            Accel::for_scene(&scene, AccelChoice::Auto),
            Accel::for_scene(&flat_scene, AccelChoice::Auto),
        );
        for scale in direction_scales() {
            for _ in 0..8 {
                let o = [0, 1, 2].map(|_| rng.range(-4.0, 4.0) as f32);
                let dirs: [[f32; 3]; 8] =
                    std::array::from_fn(|_| direction_from(o, &flat_scene, &mut rng, scale));
                let what = format!("stored 2^{stored}, |d| 2^{scale}");
                let (d, l) = check_instance_packets(&inst, &flat, o, &dirs, &what);
                decided += d;
                lanes += l;
            }
        }
    }
    assert!(decided * 2 > lanes, "{decided} of {lanes} lanes decided");
}
