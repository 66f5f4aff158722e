//! What correctly rounded t costs: on the Cornell box's camera rays (400×400
//! from (0.01, 0.02, −3), one thread), the adaptive query through the BVH per ray beside
//! `adaptive::rounded_t` per hit in f32 and in f64, three interleaved rounds, one run.
//! `cargo run --release --example t_rounding_cost`
use raylab::geometry::{adaptive, Method, Ray, Shape};
use std::time::Instant;
fn main() {
    let shapes32: Vec<Shape<f32>> = raylab::tracefile::parse_scene::<f32>("c", "cornell\n")
        .unwrap()
        .0;
    let shapes64: Vec<Shape<f64>> = raylab::tracefile::parse_scene::<f64>("c", "cornell\n")
        .unwrap()
        .0;
    let scene = raylab::tracefile::parse_scene_instanced("c", "cornell\n").unwrap();
    let accel = &raylab::accel::Accel::for_scene(&scene, raylab::accel::AccelChoice::Auto);
    let rays: Vec<[f64; 6]> = (0..160_000)
        .map(|i| {
            let (x, y) = (
                (i % 400) as f64 / 200.0 - 1.0,
                (i / 400) as f64 / 200.0 - 1.0,
            );
            [0.01, 0.02, -3.0, x * 0.37, y * 0.37, 1.0]
        })
        .collect();
    let r32: Vec<Ray<f32>> = rays
        .iter()
        .map(|r| {
            Ray::new(
                [r[0], r[1], r[2]].map(|x| x as f32),
                [r[3], r[4], r[5]].map(|x| x as f32),
            )
        })
        .collect();
    let r64: Vec<Ray<f64>> = rays
        .iter()
        .map(|r| Ray::new([r[0], r[1], r[2]], [r[3], r[4], r[5]]))
        .collect();
    let h32: Vec<u32> = r32
        .iter()
        .map(|r| {
            accel
                .closest_hit(r, Method::Adaptive, 0.0, f32::INFINITY)
                .unwrap()
                .prim
        })
        .collect();
    let h64: Vec<u32> = r64
        .iter()
        .map(|r| {
            raylab::accel::closest_hit(&shapes64, r, Method::Adaptive, 0.0, f64::INFINITY)
                .unwrap()
                .prim
        })
        .collect();
    println!(
        "CPU: {}, SIMD: {}",
        raylab::machine::cpu_model(),
        raylab::machine::simd_level()
    );
    for round in 0..3 {
        let mut sink = 0.0f64;
        let t = Instant::now();
        for r in &r32 {
            sink += accel
                .closest_hit(r, Method::Adaptive, 0.0, f32::INFINITY)
                .unwrap()
                .t as f64;
        }
        let query32 = t.elapsed().as_secs_f64() * 1e9 / rays.len() as f64;
        let t = Instant::now();
        for (r, p) in r32.iter().zip(&h32) {
            sink +=
                adaptive::rounded_t(&shapes32[*p as usize], r, 0.0, f32::INFINITY).unwrap() as f64;
        }
        let round32 = t.elapsed().as_secs_f64() * 1e9 / rays.len() as f64;
        let t = Instant::now();
        for (r, p) in r64.iter().zip(&h64) {
            sink += adaptive::rounded_t(&shapes64[*p as usize], r, 0.0, f64::INFINITY).unwrap();
        }
        let round64 = t.elapsed().as_secs_f64() * 1e9 / rays.len() as f64;
        println!("round {round}: f32 BVH query {query32:.0} ns/ray, rounded_t f32 {round32:.0} ns/hit, rounded_t f64 {round64:.0} ns/hit ({sink:.0})");
    }
}
