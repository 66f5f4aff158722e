use raylab::geometry::adaptive::{classify_f32, edge_bound, triangle_interval, Estimate};
use raylab::geometry::triangle::WatertightRay;
use raylab::geometry::Shape;
fn main() {
    let scene = raylab::Scene::cornell();
    let (w, h) = (1280u32, 720u32);
    let cam = raylab::Camera::cornell(w);
    let (mut lo, mut hi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
    for s in &scene.shapes {
        if let Shape::Triangle(v) = s {
            for p in v {
                for k in 0..3 {
                    lo[k] = lo[k].min(p[k]);
                    hi[k] = hi[k].max(p[k]);
                }
            }
        }
    }
    let (mut unsure32, mut unsure64, mut sure, mut total) = (0, 0, 0, 0);
    let mut rays_unsure64 = 0;
    for j in 0..h {
        for i in 0..w {
            let r = cam.ray_for_pixel(i, j, w, h);
            let wr = WatertightRay::new(r.o, r.d).unwrap();
            let e = edge_bound(r.o, lo, hi);
            total += 1;
            let mut ray_u = false;
            for s in &scene.shapes {
                if let Shape::Triangle(v) = s {
                    match classify_f32(&wr, v, e) {
                        Estimate::Unsure => {
                            unsure32 += 1;
                            if triangle_interval(
                                r.o.map(f64::from),
                                r.d.map(f64::from),
                                &v.map(|p| p.map(f64::from)),
                            ) == Estimate::Unsure
                            {
                                unsure64 += 1;
                                ray_u = true;
                            }
                        }
                        Estimate::Hit(_) => sure += 1,
                        _ => {}
                    }
                }
            }
            rays_unsure64 += ray_u as u32;
        }
    }
    println!("rays {total} sure-hit lanes {sure} unsure32 {unsure32} unsure64 {unsure64} rays needing exact {rays_unsure64} E={:e}", edge_bound(cam.ray_for_pixel(0,0,w,h).o, lo, hi));
}
