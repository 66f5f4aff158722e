//! Peers in the same run: raylab beside Embree 3, tinybvh and obvhs (and,
//! with `--lecture`, the lecture's naive loop), on the same scenes, camera rays, frame sizes
//! and thread counts, interleaved: each round times one frame of every method, in an order
//! that alternates from round to round; the best round is reported.
//!
//! `cargo run --release -p peers -- [--rounds N] [--sizes 1280x720,640x360]
//! [--threads 1,2] [--scenes cornell,bunny,igea,igea_1m,field] [--lecture]`
//!
//! - Embree 3 is loaded at run time (Debian: `apt-get install libembree3-3`); without it its
//!   rows are left out and the report says why. It builds at HIGH quality, with as many build
//!   threads as the largest thread count; rows: `rtcIntersect1` per ray, `rtcIntersect8` on
//!   4×2 pixel blocks and `rtcIntersect16` on 4×4 blocks, with a coherent context. On an
//!   AVX-512 CPU a second device, its kernels limited to AVX2 (Embree's `isa=avx2`), times the
//!   same three beside raylab's AVX2 build: the summary's "both at AVX2" columns are what a
//!   CPU without AVX-512 runs, both engines at that level.
//! - tinybvh (the `tinybvh-rs` crate, its C++ built with `-march=native`): its 8-wide
//!   `BVH8_CPU` layout needs the Rust side built with AVX2 as well, so run with
//!   `RUSTFLAGS="-C target-cpu=native" CARGO_TARGET_DIR=target/native` for that row; a
//!   baseline build times tinybvh's binary BVH instead, and the report says which.
//! - obvhs: its compressed 8-wide BVH (f32) and its triangle test.
//! - raylab: the renderer's whole flat frame (rays made, traced through packets, shaded and
//!   written; the default adaptive method, exact), and the per-ray query (`Accel::closest_hit`).
//!
//! The meshes come from ../shared/scenes when it exists, the 1M-triangle mesh from
//! target/igea_1m.obj when `benches/readme_table.sh` has made it, and the field of 1,000
//! bunnies from benches/scenes/bunny_field.scene (raylab and Embree, both placing one stored
//! bunny as 1,000 instances: Embree's `RTC_GEOMETRY_TYPE_INSTANCE` with the instances' f64
//! matrices rounded to f32); the Cornell box always runs. Every method gets the same rays
//! (the camera framing the mesh, or the lab's).
//!
//! Accuracy columns: against raylab's exact per-ray answer (the nearest triangle along the
//! f32 ray), the rays a method missed where the exact answer hits (a leak), hit where it
//! misses, or named another triangle: a tie where that one is hit at exactly the same t (on a
//! shared edge both are nearest), else wrong.

mod embree;

use anyhow::{anyhow, Context as _};
use clap::Parser;
use embree::{Embree, Placement, RayHitN, ValidN};
use glam_obvhs::Vec3A;
use obvhs::cwbvh::builder::build_cwbvh_from_tris;
use obvhs::cwbvh::CwBvh;
use obvhs::ray::{Ray as ORay, RayHit};
use obvhs::triangle::Triangle;
use obvhs::BvhBuildParams;
use raylab::camera::Camera;
use raylab::controller::CameraController;
use raylab::geometry::adaptive::closest_hit_reference;
use raylab::geometry::{Method, Ray, Shape};
use raylab::math::simd::{self, SimdLevel};
use raylab::render::{render_into, LabStep, RenderSettings, Stage};
use raylab::scene::Mesh;
use raylab::Scene;
use rayon::prelude::*;
use std::path::Path;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

#[derive(Parser)]
#[command(about = "raylab beside Embree, tinybvh and obvhs, interleaved in one run")]
struct Args {
    /// Rounds: each times one frame of every method; the best is reported.
    #[arg(long, default_value_t = 3)]
    rounds: usize,
    /// Frame sizes, WIDTHxHEIGHT.
    #[arg(long, value_delimiter = ',', default_value = "1280x720,640x360")]
    sizes: Vec<String>,
    /// Thread counts.
    #[arg(long, value_delimiter = ',', default_value = "1,2")]
    threads: Vec<usize>,
    /// Only these scenes (cornell, bunny, igea, igea_1m, field); all that exist by default.
    #[arg(long, value_delimiter = ',')]
    scenes: Vec<String>,
    /// Also time the lecture's loop (every ray against every triangle; strided on meshes).
    #[arg(long)]
    lecture: bool,
}

/// Lets a peer's BVH be shared by the rayon threads.
struct Shared<T>(T);
// SAFETY: only the peers' const queries run through it, which read the BVH and write nothing
// but the caller's ray (tinybvh's `Intersect` is a const member function).
unsafe impl<T> Sync for Shared<T> {}

/// One timed method: writes each ray's nearest primitive (row-major) where it answers per
/// ray, and returns the number of rays that hit something.
type Frame<'a> = Box<dyn Fn(&mut [Option<u32>]) -> u64 + Sync + 'a>;

/// What a timed method is, for the accuracy columns and the summaries.
#[derive(Clone, Copy, PartialEq)]
enum Role {
    /// raylab's whole frame at this lab step ("flat", "shadows"; ", AVX2" with the kernels
    /// limited to AVX2).
    Render(&'static str),
    /// raylab's exact per-ray query: the answers the others are checked against.
    Reference,
    /// One of Embree's modes.
    Embree,
    /// One of Embree's modes, its kernels limited to AVX2 (on an AVX-512 CPU).
    EmbreeAvx2,
    /// Another peer answering per ray (its answers are checked).
    Peer,
    /// The lecture's loop on every Nth ray (no answers kept).
    Lecture,
}

impl Role {
    /// Whether the method fills the primitive buffer (its accuracy is checked).
    fn answers_per_ray(self) -> bool {
        matches!(
            self,
            Role::Reference | Role::Embree | Role::EmbreeAvx2 | Role::Peer
        )
    }
}

struct Timed<'a> {
    name: String,
    role: Role,
    build: Option<Duration>,
    frame: Frame<'a>,
}

/// One scene of the run: its name, the raylab scene and its triangles for the peers (empty
/// for the instanced field, which only raylab and Embree render, as `instanced`).
struct Bench {
    name: String,
    scene: Scene,
    triangles: Vec<[[f32; 3]; 3]>,
    instanced: Option<Instanced>,
}

/// A scene's instances as Embree places them: the distinct meshes, the placements, and the
/// triangles outside any instance with their primitive numbers.
struct Instanced {
    meshes: Vec<Arc<Mesh>>,
    placements: Vec<Placement>,
    loose: Vec<([[f32; 3]; 3], u32)>,
}

impl Instanced {
    /// `scene`'s instances, or `None` if it has none. Spheres outside instances are left out
    /// (the field has none).
    fn of(scene: &Scene) -> Option<Self> {
        if scene.instances().is_empty() {
            return None;
        }
        let mut meshes: Vec<Arc<Mesh>> = Vec::new();
        let placements = (scene.instances().iter())
            .map(|inst| {
                let mesh = match meshes.iter().position(|m| Arc::ptr_eq(m, &inst.mesh)) {
                    Some(k) => k,
                    None => {
                        meshes.push(inst.mesh.clone());
                        meshes.len() - 1
                    }
                };
                let m = inst.world_from_object;
                let cols = [m.x_axis, m.y_axis, m.z_axis, m.w_axis];
                Placement {
                    mesh,
                    world_from_object: std::array::from_fn(|i| cols[i / 3][i % 3] as f32),
                    first_prim: inst.first_prim,
                }
            })
            .collect();
        let loose = (scene.explicit_with_prims().into_iter())
            .filter_map(|(shape, prim)| match shape {
                Shape::Triangle(v) => Some((v, prim)),
                Shape::Sphere { .. } => None,
            })
            .collect();
        Some(Instanced {
            meshes,
            placements,
            loose,
        })
    }
}

fn parse_size(s: &str) -> anyhow::Result<(u32, u32)> {
    let (w, h) = s
        .split_once('x')
        .ok_or_else(|| anyhow!("size '{s}' is not WIDTHxHEIGHT"))?;
    let size = (w.parse()?, h.parse()?);
    anyhow::ensure!(size.0 > 0 && size.1 > 0, "size '{s}' is empty");
    Ok(size)
}

fn load_benches(only: &[String]) -> anyhow::Result<Vec<Bench>> {
    let wanted = |name: &str| only.is_empty() || only.iter().any(|o| o == name);
    let mut benches = Vec::new();
    let sources = [
        ("cornell", None),
        ("bunny", Some("../shared/scenes/bunny.obj")),
        ("igea", Some("../shared/scenes/igea.obj")),
        ("igea_1m", Some("target/igea_1m.obj")),
        ("field", Some("benches/scenes/bunny_field.scene")),
    ];
    for (name, path) in sources {
        if !wanted(name) {
            continue;
        }
        let scene = match path {
            None => Scene::cornell(),
            Some(p)
                if Path::new(p).exists() && Path::new("../shared/scenes/bunny.obj").exists() =>
            {
                Scene::load(Path::new(p), Default::default())
                    .map_err(|e| anyhow!(e))
                    .with_context(|| format!("loading {p}"))?
            }
            Some(p) => {
                println!("({name}: {p} or ../shared/scenes not found, skipped)");
                continue;
            }
        };
        let triangles = match name {
            "field" => Vec::new(),
            _ => scene
                .shapes
                .iter()
                .filter_map(|s| match s {
                    Shape::Triangle(v) => Some(*v),
                    Shape::Sphere { .. } => None,
                })
                .collect(),
        };
        let instanced = Instanced::of(&scene);
        benches.push(Bench {
            name: name.into(),
            scene,
            triangles,
            instanced,
        });
    }
    Ok(benches)
}

/// The camera every method shares: the scene file's, the lab's, or one framing the mesh.
fn camera_for(bench: &Bench, w: u32, h: u32) -> anyhow::Result<Camera> {
    if bench.name == "cornell" {
        return Ok(Camera::cornell(w));
    }
    if let Some(c) = &bench.scene.camera {
        return Ok(CameraController::from_scene_camera(c, bench.scene.size()).camera(w));
    }
    let bounds = bench.scene.bounds().context("empty scene")?;
    Ok(CameraController::framing(bounds, w, h).camera(w))
}

fn timed<T>(f: impl FnOnce() -> T) -> (T, Duration) {
    let start = Instant::now();
    let out = f();
    (out, start.elapsed())
}

/// Embree's packets: blocks of `bw`×`bh` pixels (N = bw·bh rays), a row of blocks per task.
fn embree_packets<const N: usize>(
    rays: &[Ray],
    (w, h): (u32, u32),
    (bw, bh): (usize, usize),
    prims: &mut [Option<u32>],
    trace: impl Fn(&mut RayHitN<N>, &ValidN<N>) -> [Option<u32>; N] + Sync,
) -> u64 {
    let (w, h) = (w as usize, h as usize);
    prims
        .par_chunks_mut(w * bh)
        .enumerate()
        .map(|(by, out)| {
            let mut hits = 0;
            let rows = bh.min(h - by * bh);
            let mut lanes = [(0, 0); N];
            for bx in (0..w).step_by(bw) {
                let cols = bw.min(w - bx);
                let mut packet = RayHitN::<N>::empty();
                for (lane, slot) in lanes.iter_mut().enumerate().take(rows * cols) {
                    *slot = (lane / cols, bx + lane % cols);
                    let ray = &rays[(by * bh + slot.0) * w + slot.1];
                    packet.set(lane, ray.o, ray.d);
                }
                let valid = packet.valid();
                let prims = trace(&mut packet, &valid);
                for (&(r, x), prim) in lanes.iter().zip(prims).take(rows * cols) {
                    out[r * w + x] = prim;
                    hits += prim.is_some() as u64;
                }
            }
            hits
        })
        .sum()
}

/// Per-ray methods: each ray's answer into `prims`, the number that hit.
fn per_ray(
    rays: &[Ray],
    prims: &mut [Option<u32>],
    closest: impl Fn(&Ray) -> Option<u32> + Sync,
) -> u64 {
    prims
        .par_iter_mut()
        .zip(rays.par_iter())
        .map(|(out, ray)| {
            *out = closest(ray);
            out.is_some() as u64
        })
        .sum()
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

/// How a method's answers differ from the exact `reference` answers.
#[derive(Default)]
struct Disagreements {
    /// The exact answer hits, the method missed (a leak).
    missed: usize,
    /// The method hit where the exact answer misses.
    extra: usize,
    /// Another triangle, hit at exactly the same t (a shared edge: both are nearest).
    ties: usize,
    /// Another triangle, farther or not hit at all.
    wrong: usize,
}

/// Compares `got` with the exact `reference` answers for `rays` over `scene`. A different
/// triangle is a tie where the exact reference search over the two, in either order, names
/// the first (it breaks exact ties by the lower index).
fn disagreements(
    scene: &Scene,
    rays: &[Ray],
    reference: &[Option<u32>],
    got: &[Option<u32>],
) -> Disagreements {
    let mut d = Disagreements::default();
    for ((r, g), ray) in reference.iter().zip(got).zip(rays) {
        match (r, g) {
            (Some(_), None) => d.missed += 1,
            (None, Some(_)) => d.extra += 1,
            (Some(a), Some(b)) if a != b => {
                let pair = |x: u32, y: u32| {
                    let shapes = [scene.shape(x), scene.shape(y)];
                    closest_hit_reference(&shapes, ray, 0.0, f32::INFINITY).map(|h| h.prim)
                };
                match (pair(*a, *b), pair(*b, *a)) {
                    (Some(0), Some(0)) => d.ties += 1,
                    _ => d.wrong += 1,
                }
            }
            _ => {}
        }
    }
    d
}

/// tinybvh's C++ `Ray` as the bundled `tiny_bvh.h` (INST_IDX_BITS 32) lays it out: 128 bytes,
/// of which tinybvh-rs's `Ray` mirrors only the first 64 (the hit's t, u, v and prim at the same
/// offsets). Its `Ray::new` returns the 64-byte struct by value from C++, which writes all 128
/// and overruns the caller's stack, so the ray is made here, in a buffer of the full size.
#[repr(C, align(64))]
struct TinyRay {
    ray: tinybvh_rs::Ray,
    /// The C++ hit's auxData and user data.
    _rest: [u8; 64],
}

impl TinyRay {
    fn new(o: [f32; 3], d: [f32; 3]) -> Self {
        // As tinybvh's constructor: a unit direction, its reciprocal, every mask bit.
        let n = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        let dir = d.map(|x| x / n);
        let mut ray = tinybvh_rs::Ray {
            origin: o,
            dir,
            r_d: dir.map(|x| 1.0 / x),
            hit: tinybvh_rs::Intersection::new(),
            ..Default::default()
        };
        ray.padding_0 = 0xFFFF; // the C++ ray's mask
        ray.padding_2 = 0; // the C++ hit's instance
        TinyRay {
            ray,
            _rest: [0; 64],
        }
    }

    /// The nearest primitive, `None` where the ray missed.
    fn prim(&self) -> Option<u32> {
        (self.ray.hit.t < tinybvh_rs::INFINITE).then_some(self.ray.hit.prim)
    }
}

/// A peer's closest hit for one ray (origin, direction): its primitive, if any.
type ClosestFn<'a> = Box<dyn Fn([f32; 3], [f32; 3]) -> Option<u32> + 'a>;

/// tinybvh's fastest layout this build can call (see the module docs), borrowing the
/// vertices it was built on.
struct TinyBvh<'a> {
    name: &'static str,
    closest: Shared<ClosestFn<'a>>,
}

fn build_tinybvh(vertices: &[[f32; 4]]) -> anyhow::Result<TinyBvh<'_>> {
    use tinybvh_rs::Intersector;
    let bvh = tinybvh_rs::bvh::BVH::new(vertices.into()).map_err(|e| anyhow!("{e:?}"))?;
    #[cfg(target_feature = "avx2")]
    {
        let mut bvh = bvh;
        bvh.split_leaves(4);
        let mbvh = tinybvh_rs::mbvh::BVH::new(&bvh);
        // BVH8_CPU keeps its own copy of the triangles.
        let bvh8 = tinybvh_rs::bvh8_cpu::BVH::new(&mbvh).map_err(|e| anyhow!("{e:?}"))?;
        Ok(TinyBvh {
            name: "tinybvh BVH8_CPU (AVX2, f32)",
            closest: Shared(Box::new(move |o, d| {
                let mut ray = TinyRay::new(o, d);
                bvh8.intersect(&mut ray.ray);
                ray.prim()
            })),
        })
    }
    #[cfg(not(target_feature = "avx2"))]
    Ok(TinyBvh {
        name: "tinybvh BVH, binary (f32; BVH8_CPU needs target-cpu=native)",
        closest: Shared(Box::new(move |o, d| {
            let mut ray = TinyRay::new(o, d);
            bvh.intersect(&mut ray.ray);
            ray.prim()
        })),
    })
}

/// A row of the summary against the speed targets (docs/performance.md): raylab's render against the fastest of
/// Embree's three modes in that run (stricter than "Embree's best packet mode": on this
/// machine `rtcIntersect1` sometimes wins).
struct Versus {
    scene: String,
    size: String,
    threads: usize,
    raylab: Duration,
    /// The same frame with the kernels limited to AVX2 (on an AVX-512 CPU).
    raylab_avx2: Option<Duration>,
    embree_best: Duration,
    /// The fastest of Embree's modes with its kernels limited to AVX2 (on an AVX-512 CPU).
    embree_avx2_best: Option<Duration>,
}

/// A mesh's builds, best of the rounds (raylab's and Embree's alternating), and raylab's
/// structure's size.
struct Builds {
    scene: String,
    raylab: Duration,
    embree: Option<Duration>,
    raylab_bytes: usize,
}

/// What one run found, for the summaries.
#[derive(Default)]
struct Found {
    versus: Vec<Versus>,
    builds: Vec<Builds>,
    /// (scene, size, threads, step, best frame) of raylab's own renders.
    frames: Vec<(String, String, usize, &'static str, Duration)>,
}

fn main() -> anyhow::Result<()> {
    let args = Args::parse();
    let sizes: Vec<(u32, u32)> = args
        .sizes
        .iter()
        .map(|s| parse_size(s))
        .collect::<anyhow::Result<_>>()?;
    anyhow::ensure!(args.rounds > 0, "--rounds must be at least 1");
    anyhow::ensure!(
        args.threads.iter().all(|&t| t > 0),
        "--threads must be at least 1"
    );
    let max_threads = args.threads.iter().copied().max().unwrap_or(1);
    println!(
        "machine: {}, {} cores; raylab {}; Rust code built for {}",
        raylab::machine::cpu_model(),
        std::thread::available_parallelism().map_or(1, |n| n.get()),
        raylab::machine::simd_level(),
        if cfg!(target_feature = "avx512f") {
            "AVX-512 (target-cpu=native: the AVX2 row's kernels are not AVX2 alone; build with -C target-feature=+avx2,+fma)"
        } else if cfg!(target_feature = "avx2") {
            "AVX2 (-C target-feature=+avx2,+fma or target-cpu=native)"
        } else {
            "baseline x86-64 (raylab dispatches AVX2 or AVX-512 at run time)"
        }
    );
    let embree = Embree::load(max_threads, None);
    match &embree {
        Ok(_) => println!("Embree 3: loaded (HIGH build quality, {max_threads} build threads; its kernels the best the CPU has)"),
        Err(e) => println!("Embree 3: not timed: {e}"),
    }
    // On an AVX-512 CPU, Embree again with its kernels limited to AVX2 (its `isa=avx2`), beside
    // raylab's AVX2 build: what a CPU without AVX-512 runs, both engines at that level.
    let embree_avx2 = match (&embree, simd::detected() == SimdLevel::Avx512) {
        (Ok(_), true) => match Embree::load(max_threads, Some("avx2")) {
            Ok(e) => {
                println!("Embree 3, second device: kernels limited to AVX2 (isa=avx2)");
                Some(e)
            }
            Err(e) => {
                println!("Embree 3 at AVX2: not timed: {e}");
                None
            }
        },
        _ => None,
    };
    println!(
        "{} rounds, interleaved, order alternating; best round reported",
        args.rounds
    );
    let benches = load_benches(&args.scenes)?;
    println!();
    println!("| scene | size | threads | method | build ms | best frame ms | Mrays/s | time / raylab render | missed | extra hits | other triangle, a tie | other triangle, wrong |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    let mut found = Found::default();
    for bench in &benches {
        let embrees = [embree.as_ref().ok(), embree_avx2.as_ref()];
        run_bench(bench, &sizes, &args, embrees, &mut found)?;
    }
    let versus = &found.versus;
    if !versus.is_empty() {
        println!();
        println!("| scene | size | threads | raylab render ms | Embree's best mode ms | raylab / Embree speed | both at AVX2: raylab ms | Embree ms | raylab / Embree speed | target |");
        println!("|---|---|---|---|---|---|---|---|---|---|");
        for v in versus {
            let target = match v.scene.as_str() {
                "cornell" => "≥ 2.5",
                "bunny" => "≥ 1.5",
                "igea" => "≥ 1.3",
                "igea_1m" => "≥ 1.2",
                "field" => "none (≥ 15 frames/s at 1280x720)",
                _ => "",
            };
            let ms = |t: Option<Duration>| {
                t.map_or("–".into(), |t| format!("{:.2}", t.as_secs_f64() * 1e3))
            };
            let avx2 = match (v.raylab_avx2, v.embree_avx2_best) {
                (Some(r), Some(e)) => format!("{:.2}", e.as_secs_f64() / r.as_secs_f64()),
                _ => "–".into(),
            };
            println!(
                "| {} | {} | {} | {:.2} | {:.2} | {:.2} | {} | {} | {avx2} | {target} |",
                v.scene,
                v.size,
                v.threads,
                v.raylab.as_secs_f64() * 1e3,
                v.embree_best.as_secs_f64() * 1e3,
                v.embree_best.as_secs_f64() / v.raylab.as_secs_f64(),
                ms(v.raylab_avx2),
                ms(v.embree_avx2_best),
            );
        }
    }
    if !found.builds.is_empty() {
        println!();
        println!("| scene | raylab build ms (its structure) | Embree HIGH build ms | raylab / Embree build time | raylab structure MB | targets (1M mesh) |");
        println!("|---|---|---|---|---|---|");
        for b in &found.builds {
            let embree = b
                .embree
                .map_or("–".into(), |e| format!("{:.1}", e.as_secs_f64() * 1e3));
            let ratio = b.embree.map_or("–".into(), |e| {
                format!("{:.2}", b.raylab.as_secs_f64() / e.as_secs_f64())
            });
            let target = match b.scene.as_str() {
                "igea_1m" => "build ≤ 0.5× Embree's; ≤ 100 MB",
                _ => "",
            };
            println!(
                "| {} | {:.1} | {embree} | {ratio} | {:.1} | {target} |",
                b.scene,
                b.raylab.as_secs_f64() * 1e3,
                b.raylab_bytes as f64 / 1e6
            );
        }
    }
    let targets: Vec<_> = (found.frames.iter())
        .filter_map(|(scene, size, threads, step, t)| {
            let want = match (scene.as_str(), size.as_str(), step) {
                ("cornell", "1280x720", &("shadows" | "shadows, AVX2")) => 60.0,
                ("field", "1280x720", &("flat" | "flat, AVX2")) => 15.0,
                _ => return None,
            };
            Some((scene, size, threads, step, 1.0 / t.as_secs_f64(), want))
        })
        .collect();
    if !targets.is_empty() {
        println!();
        println!("| scene | size | threads | step | raylab frames/s | target |");
        println!("|---|---|---|---|---|---|");
        for (scene, size, threads, step, fps, want) in targets {
            println!("| {scene} | {size} | {threads} | {step} | {fps:.1} | ≥ {want} |");
        }
    }
    Ok(())
}

fn run_bench<'a>(
    bench: &Bench,
    sizes: &[(u32, u32)],
    args: &Args,
    [embree, embree_avx2]: [Option<&'a Embree>; 2],
    found: &mut Found,
) -> anyhow::Result<()> {
    let tris = &bench.triangles;
    let scene = bench.scene.clone();
    let (stage, mut raylab_build) = timed(|| Stage::from(scene));
    // tinybvh and obvhs take a mesh; Embree takes the field's instances too.
    let peers = !tris.is_empty();
    let embree_build = |e: &'a Embree| match &bench.instanced {
        Some(inst) => {
            let meshes: Vec<&[[[f32; 3]; 3]]> =
                inst.meshes.iter().map(|m| &m.triangles[..]).collect();
            e.instanced_scene(&meshes, &inst.placements, &inst.loose)
        }
        None => e.scene(tris),
    };
    let embree_input = peers || bench.instanced.is_some();
    let mut embree_scene = match (embree, embree_input) {
        (Some(e), true) => {
            let (s, t) = timed(|| embree_build(e));
            Some((s.map_err(|e| anyhow!(e))?, t))
        }
        _ => None,
    };
    // (Its build is not timed: the build table compares Embree's best.)
    let embree_avx2_scene = match (embree_avx2, embree_input) {
        (Some(e), true) => Some(embree_build(e).map_err(|e| anyhow!(e))?),
        _ => None,
    };
    // The builds again, interleaved, on as many threads as the largest count (each builder's
    // own parallelism: rayon's pool for raylab, Embree's task threads).
    if peers {
        let threads = args.threads.iter().copied().max().unwrap_or(1);
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()?;
        for round in 1..args.rounds {
            let raylab_round = || {
                let (_, t) = pool.install(|| {
                    timed(|| raylab::accel::Accel::build(&bench.scene.shapes, Default::default()))
                });
                t
            };
            let embree_round = |embree_scene: &mut Option<(embree::EmbreeScene<'_>, Duration)>| {
                if let (Some(e), Some((_, best))) = (embree, embree_scene.as_mut()) {
                    let (s, t) = timed(|| e.scene(tris));
                    drop(s);
                    *best = (*best).min(t);
                }
            };
            if round % 2 == 1 {
                embree_round(&mut embree_scene);
                raylab_build = raylab_build.min(raylab_round());
            } else {
                raylab_build = raylab_build.min(raylab_round());
                embree_round(&mut embree_scene);
            }
        }
        found.builds.push(Builds {
            scene: bench.name.clone(),
            raylab: raylab_build,
            embree: embree_scene.as_ref().map(|(_, t)| *t),
            raylab_bytes: stage.accel().memory_bytes(),
        });
    }
    let vertices: Vec<[f32; 4]> = tris
        .iter()
        .flat_map(|t| t.map(|v| [v[0], v[1], v[2], 0.0]))
        .collect();
    let tiny = match peers {
        true => {
            let (t, d) = timed(|| build_tinybvh(&vertices));
            Some((t?, d))
        }
        false => None,
    };
    let otris: Vec<Triangle> = tris
        .iter()
        .map(|v| Triangle {
            v0: Vec3A::from_array(v[0]),
            v1: Vec3A::from_array(v[1]),
            v2: Vec3A::from_array(v[2]),
        })
        .collect();
    let cwbvh: Option<(CwBvh, Duration)> = peers.then(|| {
        timed(|| {
            build_cwbvh_from_tris(
                &otris,
                BvhBuildParams::medium_build(),
                &mut Duration::default(),
            )
        })
    });
    for &(w, h) in sizes {
        let cam = camera_for(bench, w, h)?;
        let gen = cam.ray_generator(w, h);
        let rays: Vec<Ray> = (0..h)
            .flat_map(|j| (0..w).map(move |i| (i, j)))
            .map(|(i, j)| gen.ray_through(i as f32 + 0.5, j as f32 + 0.5))
            .collect();
        let flat = RenderSettings {
            width: w,
            height: h,
            step: LabStep::Flat,
            ..Default::default()
        };
        let shadows = RenderSettings {
            step: LabStep::Shadows,
            ..flat
        };
        // raylab renders into an image allocated once, as the window does (the other methods
        // write into an answer buffer allocated once): a fresh 3.7 MB buffer per frame at
        // 1280×720 cost its page faults and zeroing in every frame.
        let image = Mutex::new(vec![0u8; flat.buffer_len()]);
        let render = |settings: &RenderSettings| {
            let mut rgba = image.lock().expect("one frame at a time");
            render_into(&stage, &cam, settings, &mut rgba).map_or(0, |stats| stats.hits)
        };
        let mut methods: Vec<Timed> = vec![Timed {
            name: "raylab render (adaptive, exact)".into(),
            role: Role::Render("flat"),
            build: Some(raylab_build),
            frame: Box::new(|_| render(&flat)),
        }];
        // On an AVX-512 CPU, the same frame with the kernels' AVX2 build: both levels in one
        // run.
        let avx2_row = simd::detected() == SimdLevel::Avx512;
        if avx2_row {
            methods.push(Timed {
                name: "raylab render, kernels limited to AVX2".into(),
                role: Role::Render("flat, AVX2"),
                build: Some(raylab_build),
                frame: Box::new(|_| simd::limited(SimdLevel::Avx2, || render(&flat))),
            });
        }
        if bench.name == "cornell" || bench.name == "field" {
            methods.push(Timed {
                name: "raylab render, shadows step".into(),
                role: Role::Render("shadows"),
                build: Some(raylab_build),
                frame: Box::new(|_| render(&shadows)),
            });
            if avx2_row {
                methods.push(Timed {
                    name: "raylab render, shadows step, kernels limited to AVX2".into(),
                    role: Role::Render("shadows, AVX2"),
                    build: Some(raylab_build),
                    frame: Box::new(|_| simd::limited(SimdLevel::Avx2, || render(&shadows))),
                });
            }
        }
        if embree_input {
            methods.push(Timed {
                name: "raylab closest_hit per ray (adaptive, exact)".into(),
                role: Role::Reference,
                build: Some(raylab_build),
                frame: Box::new(|prims| {
                    per_ray(&rays, prims, |r| {
                        (stage.accel())
                            .closest_hit(r, Method::Adaptive, 0.0, f32::INFINITY)
                            .map(|h| h.prim)
                    })
                }),
            });
        }
        let embree_scenes = [
            (
                embree_scene.as_ref().map(|(s, b)| (s, Some(*b))),
                Role::Embree,
                "",
            ),
            (
                embree_avx2_scene.as_ref().map(|s| (s, None)),
                Role::EmbreeAvx2,
                ", kernels limited to AVX2",
            ),
        ];
        for (scene, role, isa) in embree_scenes {
            let Some((scene, build)) = scene else {
                continue;
            };
            methods.push(Timed {
                name: format!("Embree rtcIntersect1 (f32){isa}"),
                role,
                build,
                frame: Box::new(|prims| per_ray(&rays, prims, |r| scene.closest1(r.o, r.d))),
            });
            methods.push(Timed {
                name: format!("Embree rtcIntersect8, 4×2 blocks (f32){isa}"),
                role,
                build,
                frame: Box::new(|prims| {
                    embree_packets::<8>(&rays, (w, h), (4, 2), prims, |p, v| scene.closest8(p, v))
                }),
            });
            methods.push(Timed {
                name: format!("Embree rtcIntersect16, 4×4 blocks (f32){isa}"),
                role,
                build,
                frame: Box::new(|prims| {
                    embree_packets::<16>(&rays, (w, h), (4, 4), prims, |p, v| scene.closest16(p, v))
                }),
            });
        }
        if let Some((tiny, build)) = &tiny {
            methods.push(Timed {
                name: tiny.name.into(),
                role: Role::Peer,
                build: Some(*build),
                frame: Box::new(|prims| per_ray(&rays, prims, |r| (tiny.closest.0)(r.o, r.d))),
            });
        }
        if let Some((cwbvh, build)) = &cwbvh {
            methods.push(Timed {
                name: "obvhs cwbvh (f32)".into(),
                role: Role::Peer,
                build: Some(*build),
                frame: Box::new(|prims| {
                    per_ray(&rays, prims, |r| {
                        let ray = ORay::new_inf(Vec3A::from_array(r.o), Vec3A::from_array(r.d));
                        let mut hit = RayHit::none();
                        cwbvh
                            .ray_traverse(ray, &mut hit, |ray, id| {
                                otris[cwbvh.primitive_indices[id] as usize].intersect(ray)
                            })
                            .then(|| cwbvh.primitive_indices[hit.primitive_id as usize])
                    })
                }),
            });
        }
        // About 2e8 ray-triangle tests per lecture-loop frame, scaled to the whole frame.
        let stride = (rays.len() * tris.len() / 200_000_000).max(1);
        if args.lecture && peers {
            let name = match stride {
                1 => "lecture loop A⁻¹b".to_string(),
                s => format!("lecture loop A⁻¹b (every {s}th ray, scaled)"),
            };
            let rays = &rays;
            methods.push(Timed {
                name,
                role: Role::Lecture,
                build: None,
                frame: Box::new(move |_| {
                    let hits: usize = rays
                        .par_iter()
                        .step_by(stride)
                        .filter(|r| lecture_closest(tris, r).is_some())
                        .count();
                    (hits * stride) as u64
                }),
            });
        }
        // Every method's answers once (not timed), against the exact per-ray query's.
        let answers: Vec<Option<Vec<Option<u32>>>> = methods
            .iter()
            .map(|m| {
                m.role.answers_per_ray().then(|| {
                    let mut prims = vec![None; rays.len()];
                    (m.frame)(&mut prims);
                    prims
                })
            })
            .collect();
        let reference = (methods.iter().zip(&answers))
            .find(|(m, _)| m.role == Role::Reference)
            .and_then(|(_, a)| a.as_deref());
        let accuracy: Vec<String> = (methods.iter().zip(&answers))
            .map(|(m, a)| match (m.role, reference, a) {
                (Role::Reference, ..) => "reference | | | ".into(),
                (_, Some(r), Some(a)) => {
                    let d = disagreements(&bench.scene, &rays, r, a);
                    format!("{} | {} | {} | {}", d.missed, d.extra, d.ties, d.wrong)
                }
                _ => "– | – | – | –".into(),
            })
            .collect();
        for &threads in &args.threads {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()?;
            let mut best = vec![Duration::MAX; methods.len()];
            let mut scratch = vec![None; rays.len()];
            for round in 0..args.rounds {
                let order: Vec<usize> = match round % 2 {
                    0 => (0..methods.len()).collect(),
                    _ => (0..methods.len()).rev().collect(),
                };
                for i in order {
                    let (hits, t) = pool.install(|| timed(|| (methods[i].frame)(&mut scratch)));
                    std::hint::black_box(hits);
                    best[i] = best[i].min(t);
                }
            }
            let base = best[0].as_secs_f64();
            for (i, m) in methods.iter().enumerate() {
                let s = best[i].as_secs_f64();
                println!(
                    "| {} | {w}x{h} | {threads} | {} | {} | {:.2} | {:.1} | {:.2} | {} |",
                    bench.name,
                    m.name,
                    m.build
                        .map_or("–".into(), |b| format!("{:.1}", b.as_secs_f64() * 1e3)),
                    s * 1e3,
                    (w * h) as f64 / s / 1e6,
                    s / base,
                    accuracy[i]
                );
            }
            let fastest = |role: Role| {
                (methods.iter().zip(&best))
                    .filter(|(m, _)| m.role == role)
                    .map(|(_, t)| *t)
                    .min()
            };
            let embree_best = fastest(Role::Embree);
            for (m, t) in methods.iter().zip(&best) {
                let Role::Render(step) = m.role else {
                    continue;
                };
                found
                    .frames
                    .push((bench.name.clone(), format!("{w}x{h}"), threads, step, *t));
            }
            if let Some(embree_best) = embree_best {
                found.versus.push(Versus {
                    scene: bench.name.clone(),
                    size: format!("{w}x{h}"),
                    threads,
                    raylab: best[0],
                    raylab_avx2: avx2_row.then_some(best[1]),
                    embree_best,
                    embree_avx2_best: fastest(Role::EmbreeAvx2),
                });
            }
        }
    }
    Ok(())
}
