use raylab::accel::soa::TriangleBlocks;
use raylab::geometry::adaptive::Search;
use raylab::geometry::triangle::WatertightRay;
use raylab::geometry::Shape;
use std::time::Instant;
fn main() {
    let scene = raylab::Scene::cornell();
    let (w, h) = (1280u32, 720u32);
    let cam = raylab::Camera::cornell(w);
    let tris: Vec<_> = scene
        .shapes
        .iter()
        .enumerate()
        .filter_map(|(i, s)| match s {
            Shape::Triangle(v) => Some((*v, i as u32)),
            _ => None,
        })
        .collect();
    let blocks = TriangleBlocks::new(&tris);
    let rays: Vec<_> = (0..h)
        .flat_map(|j| (0..w).map(move |i| (i, j)))
        .map(|(i, j)| cam.ray_for_pixel(i, j, w, h))
        .collect();
    for round in 0..3 {
        let t0 = Instant::now();
        let mut s1 = 0u64;
        for r in &rays {
            let wr = WatertightRay::new(r.o, r.d).unwrap();
            s1 += blocks
                .closest_hit(&wr, 0.0, f32::INFINITY)
                .map_or(0, |h| h.prim as u64);
        }
        let t1 = Instant::now();
        let mut s2 = 0u64;
        for r in &rays {
            let wr = WatertightRay::new(r.o, r.d).unwrap();
            let mut s = Search::new(r, 0.0, f32::INFINITY);
            blocks.closest_hit_adaptive(&wr, &mut s);
            s2 += s.hit().map_or(0, |h| h.prim as u64);
        }
        let t2 = Instant::now();
        println!(
            "round {round}: watertight {:.1} ms, adaptive {:.1} ms  ({s1} {s2})",
            (t1 - t0).as_secs_f64() * 1e3,
            (t2 - t1).as_secs_f64() * 1e3
        );
    }
}
