//! The hot kernels, one at a time (`cargo bench -p peers --bench kernels`; the machine and thread
//! count are printed first): one ray against one triangle per method, 8 camera rays against a
//! prepared triangle (the packet kernel), 8 shadow rays, the sphere test, closest-hit through a
//! BVH, and the BVH build. Speed lives here and in `raylab bench`, never in tests.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use raylab::accel::testing::{self as packet, OriginTriangles};
use raylab::accel::{Accel, AccelChoice};
use raylab::geometry::adaptive::{box_extent, classify_f32};
use raylab::geometry::triangle::{cramer, moller, watertight_pre, WatertightRay};
use raylab::geometry::{sphere, Method, Ray, Shape};
use wide::f32x8;

/// A UV sphere of about `n` triangles around the origin, radius 1.
fn sphere_mesh(n: usize) -> Vec<Shape<f32>> {
    let rings = ((n / 2) as f64).sqrt() as usize;
    let p = |i: usize, j: usize| {
        let (th, ph) = (
            std::f64::consts::PI * i as f64 / rings as f64,
            2.0 * std::f64::consts::PI * j as f64 / rings as f64,
        );
        [th.sin() * ph.cos(), th.cos(), th.sin() * ph.sin()].map(|x| x as f32)
    };
    let mut tris = Vec::new();
    for i in 0..rings {
        for j in 0..rings {
            let (a, b, c, d) = (p(i, j), p(i + 1, j), p(i + 1, j + 1), p(i, j + 1));
            tris.push(Shape::from([a, b, c]));
            tris.push(Shape::from([a, c, d]));
        }
    }
    tris
}

/// Rays from z = −3 at a grid of points in the unit square.
fn rays(n: usize) -> Vec<Ray> {
    (0..n)
        .map(|k| {
            let (x, y) = (
                (k % 64) as f32 / 32.0 - 1.0,
                (k / 64 % 64) as f32 / 32.0 - 1.0,
            );
            Ray::new([0.01, 0.02, -3.0], [x * 0.3, y * 0.3, 1.0])
        })
        .collect()
}

fn kernels(c: &mut Criterion) {
    let cpu = raylab::machine::cpu_model();
    println!(
        "machine: {cpu}; {} cores; kernels run on 1 thread, the BVH build on {} (rayon)",
        std::thread::available_parallelism().map_or(1, |n| n.get()),
        rayon::current_num_threads()
    );
    let tri = [[-1.0f32, -1.0, 1.0], [1.0, -1.0, 1.0], [0.0, 1.0, 1.2]];
    let rs = rays(4096);
    let mut g = c.benchmark_group("ray-triangle (4096 rays)");
    g.bench_function("watertight", |b| {
        b.iter(|| {
            rs.iter()
                .filter(|r| {
                    WatertightRay::new(r.o, r.d)
                        .and_then(|w| watertight_pre(&w, &tri, 0.0, f32::INFINITY))
                        .is_some()
                })
                .count()
        })
    });
    g.bench_function("moller", |b| {
        b.iter(|| {
            rs.iter()
                .filter(|r| moller(r.o, r.d, &tri, 0.0, f32::INFINITY).is_some())
                .count()
        })
    });
    g.bench_function("cramer (lecture)", |b| {
        b.iter(|| {
            rs.iter()
                .filter(|r| cramer(r.o, r.d, &tri, 0.0, f32::INFINITY).is_some())
                .count()
        })
    });
    g.bench_function("adaptive f32 level", |b| {
        b.iter(|| {
            rs.iter()
                .filter(|r| {
                    WatertightRay::new(r.o, r.d).is_some_and(|w| {
                        let m = box_extent(r.o, [-1.0, -1.0, 1.0], [1.0, 1.0, 1.2]);
                        classify_f32(&w, &tri, m) != raylab::geometry::adaptive::Estimate::Miss
                    })
                })
                .count()
        })
    });
    let prepared = OriginTriangles::new(&[(tri, 0)], rs[0].o);
    g.bench_function("adaptive packet of 8 (shared origin)", |b| {
        b.iter(|| {
            rs.chunks(8)
                .map(|c| {
                    let d = [0, 1, 2].map(|k| f32x8::from(std::array::from_fn(|l| c[l].d[k])));
                    packet::closest(&prepared.tris, &d, packet::max_component(&d)).ambiguous
                })
                .sum::<u32>()
        })
    });
    g.bench_function("adaptive shadow packet of 8 (from the light)", |b| {
        b.iter(|| {
            rs.chunks(8)
                .map(|c| {
                    let d =
                        [0, 1, 2].map(|k| f32x8::from(std::array::from_fn(|l| c[l].d[k] * 4.0)));
                    let dm = packet::max_component(&d);
                    packet::any(&prepared.tris, &d, dm, &[u32::MAX; 8], 0xff).blocked
                })
                .sum::<u32>()
        })
    });
    g.finish();

    c.bench_function("ray-sphere, cancellation-free (4096 rays)", |b| {
        b.iter(|| {
            rs.iter()
                .filter(|r| {
                    sphere::intersect(r.o, r.d, [0.0, 0.0, 1.0], 0.5, 0.0, f32::INFINITY).is_some()
                })
                .count()
        })
    });

    let mesh = sphere_mesh(80_000);
    let bvh = Accel::build(&mesh, AccelChoice::Bvh);
    let mut g = c.benchmark_group(format!(
        "BVH closest hit, {} triangles (4096 rays)",
        mesh.len()
    ));
    for method in [Method::Adaptive, Method::Watertight] {
        g.bench_function(method.to_string(), |b| {
            b.iter(|| {
                rs.iter()
                    .filter(|r| bvh.closest_hit(r, method, 0.0, f32::INFINITY).is_some())
                    .count()
            })
        });
    }
    g.finish();
    let mut g = c.benchmark_group("BVH build");
    g.sample_size(10);
    g.bench_function(format!("{} triangles", mesh.len()), |b| {
        b.iter(|| black_box(Accel::build(&mesh, AccelChoice::Bvh)).memory_bytes())
    });
    g.finish();
}

criterion_group!(benches, kernels);
criterion_main!(benches);
