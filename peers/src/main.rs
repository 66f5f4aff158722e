//! Peers in the same run: raylab beside Embree 3, tinybvh and obvhs (and,
//! with `--lecture`, the lecture's naive loop), on the same scenes, camera rays, frame sizes
//! and thread counts, interleaved: each round times one frame of every method, in an order
//! that alternates from round to round; the best round is reported.
//!
//! `cargo run --release -p peers -- [--rounds N] [--sizes 1280x720,640x360]
//! [--threads 1,2] [--scenes cornell,bunny,igea,igea_1m,field] [--lecture]`; the floor with N
//! balls only when named: `--scenes spheres100,spheres1000,spheres10000` (see `spheres.rs`).
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
//! (the camera framing the mesh, or the lab's, or the scene file's).
//!
//! A `spheresN` scene (a floor and N balls, generated) is timed by raylab and Embree alone:
//! raylab's frame on the exact spheres, the same frame on the same balls as instanced
//! icospheres (1,280 triangles each, one stored mesh), the per-ray reference, and Embree with
//! the balls as its sphere points (`RTC_GEOMETRY_TYPE_SPHERE_POINT`) beside the floor's two
//! triangles, checked against the reference (floor and balls numbered in file order).
//!
//! Accuracy columns: against raylab's exact per-ray answer (the nearest primitive along the
//! f32 ray), the rays a method missed where the exact answer hits (a leak), hit where it
//! misses, or named another triangle: a tie where that one is hit at exactly the same t (on a
//! shared edge both are nearest), else wrong.

mod embree;
mod report;
mod scenes;
mod spheres;
mod tiny;

use anyhow::anyhow;
use clap::Parser;
use embree::{Embree, RayHitN, ValidN};
use glam_obvhs::Vec3A;
use obvhs::cwbvh::builder::build_cwbvh_from_tris;
use obvhs::cwbvh::CwBvh;
use obvhs::ray::{Ray as ORay, RayHit};
use obvhs::triangle::Triangle;
use obvhs::BvhBuildParams;
use raylab::geometry::adaptive::closest_hit_reference;
use raylab::geometry::{Method, Ray, Shape, Sphere};
use raylab::math::simd::{self, SimdLevel};
use raylab::render::{render_into, LabStep, RenderSettings, Stage};
use raylab::Scene;
use rayon::prelude::*;
use report::{Builds, Found, Versus};
use scenes::{camera_for, load_benches, Bench};
use std::sync::Mutex;
use std::time::{Duration, Instant};
use tiny::build_tinybvh;

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
    /// Only these scenes (cornell, bunny, igea, igea_1m, field, and spheresN: a floor with N
    /// balls, e.g. spheres100,spheres1000,spheres10000); by default all of the first five that
    /// exist, no spheresN.
    #[arg(long, value_delimiter = ',')]
    scenes: Vec<String>,
    /// Also write each spheresN scene's two `.scene` files (exact spheres, icospheres) here.
    #[arg(long, value_name = "DIR")]
    write_scenes: Option<std::path::PathBuf>,
    /// Also time the lecture's loop (every ray against every triangle; strided on meshes).
    #[arg(long)]
    lecture: bool,
}

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

fn parse_size(s: &str) -> anyhow::Result<(u32, u32)> {
    let (w, h) = s
        .split_once('x')
        .ok_or_else(|| anyhow!("size '{s}' is not WIDTHxHEIGHT"))?;
    let size = (w.parse()?, h.parse()?);
    anyhow::ensure!(size.0 > 0 && size.1 > 0, "size '{s}' is empty");
    Ok(size)
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
        if let Some((t, _, _)) = Shape::from(*v).intersect(ray, Method::Cramer, 0.0, best.0) {
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
    let benches = load_benches(&args.scenes, args.write_scenes.as_deref())?;
    println!();
    println!("| scene | size | threads | method | build ms | best frame ms | Mrays/s | time / raylab render | missed | extra hits | other triangle, a tie | other triangle, wrong |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    let mut found = Found::default();
    for bench in &benches {
        let embrees = [embree.as_ref().ok(), embree_avx2.as_ref()];
        run_bench(bench, &sizes, &args, embrees, &mut found)?;
    }
    report::print_summaries(&found);
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
    found.notes.extend(bench.description.clone());
    let scene = bench.scene.clone();
    let (stage, mut raylab_build) = timed(|| Stage::from(scene));
    // The same balls as icospheres: raylab's second frame.
    let icospheres = (bench.icospheres.clone()).map(|s| timed(|| Stage::from(s)));
    // tinybvh and obvhs take a mesh; Embree takes the field's instances and the balls too.
    let peers = !tris.is_empty();
    let (mut loose_tris, mut balls) = (Vec::new(), Vec::new());
    if bench.icospheres.is_some() {
        for (shape, prim) in bench.scene.explicit_with_prims() {
            match shape {
                Shape::Triangle(raylab::geometry::Triangle(v)) => loose_tris.push((v, prim)),
                Shape::Sphere(Sphere { centre, radius }) => {
                    balls.push(([centre[0], centre[1], centre[2], radius], prim))
                }
            }
        }
    }
    let embree_build = |e: &'a Embree| match &bench.instanced {
        Some(inst) => {
            let meshes: Vec<&[[[f32; 3]; 3]]> =
                inst.meshes.iter().map(|m| &m.triangles[..]).collect();
            e.instanced_scene(&meshes, &inst.placements, &inst.loose)
        }
        None if !balls.is_empty() => e.spheres_scene(&loose_tris, &balls),
        None => e.scene(tris),
    };
    let embree_input = peers || bench.instanced.is_some() || !balls.is_empty();
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
        let render_stage = |stage: &Stage, settings: &RenderSettings| {
            let mut rgba = image.lock().expect("one frame at a time");
            render_into(stage, &cam, settings, &mut rgba).map_or(0, |stats| stats.hits)
        };
        let render = |settings: &RenderSettings| render_stage(&stage, settings);
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
        if let Some((stage, build)) = &icospheres {
            methods.push(Timed {
                name: "raylab render, the balls as instanced icospheres (1,280 triangles)".into(),
                role: Role::Render("flat, icospheres"),
                build: Some(*build),
                frame: Box::new(|_| render_stage(stage, &flat)),
            });
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
        if let (Some(r), Some(_)) = (reference, &bench.icospheres) {
            found.notes.push(spheres::seen(&bench.scene, (w, h), r));
        }
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
