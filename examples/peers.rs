//! Peers in the same run (issue 4): raylab against the lecture's naive loop and the `obvhs`
//! crate's BVH, on the same scenes, cameras (1280x720 primary rays) and thread counts.
//!
//! `cargo run --release --example peers [FRAMES]`; the meshes come from ../shared/scenes when
//! it exists, the 1M-triangle mesh from target/igea_1m.obj when `benches/readme_table.sh` has
//! made it (the Cornell box always runs). Rows, per scene and thread count, best of FRAMES:
//! - raylab render: a whole flat frame through the renderer (default adaptive method: exact),
//! - raylab closest_hit: the per-ray query (adaptive), one call per camera ray,
//! - obvhs cwbvh: its 8-wide compressed BVH and its triangle test (f32, not exact), closest hit,
//! - lecture loop: every ray against every triangle with x = A⁻¹b (scalar); for the meshes on
//!   every Nth ray (about 2e8 tests per frame; the full loop would take minutes per frame),
//!   scaled to the frame.
//!
//! Mrays/s counts primary rays only; the ratio column is the row's time over raylab render's.

use glam_obvhs::Vec3A;
use obvhs::cwbvh::builder::build_cwbvh_from_tris;
use obvhs::ray::{Ray as ORay, RayHit};
use obvhs::triangle::Triangle;
use obvhs::BvhBuildParams;
use raylab::controller::CameraController;
use raylab::geometry::{Method, Ray, Shape};
use raylab::render::{render_image, LabStep, RenderSettings};
use raylab::{Camera, Scene};
use rayon::prelude::*;
use std::path::Path;
use std::time::{Duration, Instant};

const W: u32 = 1280;
const H: u32 = 720;

fn best_of<T>(frames: usize, mut f: impl FnMut() -> T) -> Duration {
    (0..frames)
        .map(|_| {
            let start = Instant::now();
            std::hint::black_box(f());
            start.elapsed()
        })
        .min()
        .unwrap_or_default()
}

/// The lecture's closest hit: every triangle, x = (t, u, v) = A⁻¹b with A = [−d, e1, e2].
fn lecture_closest(tris: &[[[f32; 3]; 3]], ray: &Ray) -> Option<u32> {
    let mut best = (f32::INFINITY, None);
    for (i, v) in tris.iter().enumerate() {
        if let Some((t, _, _)) = Shape::Triangle(*v).intersect(ray, Method::Cramer, 0.0, best.0) {
            best = (t, Some(i as u32));
        }
    }
    best.1
}

fn main() -> anyhow::Result<()> {
    let frames: usize = std::env::args()
        .nth(1)
        .map(|s| s.parse())
        .transpose()?
        .unwrap_or(5);
    let cpu = raylab::machine::cpu_model();
    println!(
        "machine: {cpu}, {} cores; {W}x{H} primary rays, best of {frames} frames",
        std::thread::available_parallelism().map_or(1, |n| n.get())
    );
    let mut scenes: Vec<(String, Scene, Camera)> =
        vec![("cornell".into(), Scene::cornell(), Camera::cornell(W))];
    // The 1M-triangle mesh (igea subdivided 1:4) where benches/readme_table.sh has made it.
    let meshes = [
        Path::new("../shared/scenes/bunny.obj"),
        Path::new("../shared/scenes/igea.obj"),
        Path::new("target/igea_1m.obj"),
    ];
    for path in meshes {
        let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("mesh");
        if path.exists() {
            let scene = raylab::scene::obj::load_obj_file(path, Default::default())?;
            let cam = CameraController::framing(scene.bounds().expect("non-empty"), W, H).camera(W);
            scenes.push((name.into(), scene, cam));
        }
    }
    println!();
    println!(
        "| scene | threads | method | build ms | best frame ms | Mrays/s | time / raylab render |"
    );
    println!("|---|---|---|---|---|---|---|");
    for (name, scene, cam) in &scenes {
        let tris: Vec<[[f32; 3]; 3]> = scene
            .shapes
            .iter()
            .filter_map(|s| match s {
                Shape::Triangle(v) => Some(*v),
                Shape::Sphere { .. } => None,
            })
            .collect();
        let gen = cam.ray_generator(W, H);
        let rays: Vec<Ray> = (0..H)
            .flat_map(|j| (0..W).map(move |i| (i, j)))
            .map(|(i, j)| gen.ray_through(i as f32 + 0.5, j as f32 + 0.5))
            .collect();
        let start = Instant::now();
        let accel = scene.accel();
        let raylab_build = start.elapsed();
        let otris: Vec<Triangle> = tris
            .iter()
            .map(|v| {
                let p = |k: usize| Vec3A::from_array(v[k]);
                Triangle {
                    v0: p(0),
                    v1: p(1),
                    v2: p(2),
                }
            })
            .collect();
        let start = Instant::now();
        let cwbvh = build_cwbvh_from_tris(
            &otris,
            BvhBuildParams::medium_build(),
            &mut Duration::default(),
        );
        let obvhs_build = start.elapsed();
        // About 2e8 ray-triangle tests per lecture-loop frame.
        let stride = (rays.len() * tris.len() / 200_000_000).max(1);
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()?;
            let settings = RenderSettings {
                width: W,
                height: H,
                step: LabStep::Flat,
                ..Default::default()
            };
            let render = pool.install(|| {
                best_of(frames, || {
                    render_image(scene, cam, &settings).map(|r| r.1.hits)
                })
            });
            let per_ray = pool.install(|| {
                best_of(frames, || {
                    rays.par_iter()
                        .filter(|r| {
                            accel
                                .closest_hit(r, Method::Adaptive, 0.0, f32::INFINITY)
                                .is_some()
                        })
                        .count()
                })
            });
            let obvhs = pool.install(|| {
                best_of(frames, || {
                    rays.par_iter()
                        .filter(|r| {
                            let ray = ORay::new_inf(Vec3A::from_array(r.o), Vec3A::from_array(r.d));
                            let mut hit = RayHit::none();
                            cwbvh.ray_traverse(ray, &mut hit, |ray, id| {
                                otris[cwbvh.primitive_indices[id] as usize].intersect(ray)
                            })
                        })
                        .count()
                })
            });
            let lecture = pool.install(|| {
                best_of(frames.min(2), || {
                    rays.par_iter()
                        .step_by(stride)
                        .filter(|r| lecture_closest(&tris, r).is_some())
                        .count()
                })
            }) * stride as u32;
            let base = render.as_secs_f64();
            let lecture_name = if stride > 1 {
                format!("lecture loop A⁻¹b (every {stride}th ray, scaled)")
            } else {
                "lecture loop A⁻¹b".to_string()
            };
            let rows = [
                (
                    "raylab render (adaptive, exact)".to_string(),
                    raylab_build,
                    render,
                ),
                (
                    "raylab closest_hit per ray (adaptive)".to_string(),
                    raylab_build,
                    per_ray,
                ),
                ("obvhs cwbvh (f32)".to_string(), obvhs_build, obvhs),
                (lecture_name, Duration::ZERO, lecture),
            ];
            for (method, build, time) in rows {
                let s = time.as_secs_f64();
                println!(
                    "| {name} | {threads} | {method} | {:.1} | {:.1} | {:.1} | {:.2} |",
                    build.as_secs_f64() * 1e3,
                    s * 1e3,
                    (W * H) as f64 / s / 1e6,
                    s / base
                );
            }
        }
    }
    Ok(())
}
