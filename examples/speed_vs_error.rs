//! The speed-versus-error report: every intersection method on the hard-case suite (errors
//! against the exact reference of tests/common/suite.rs) and on Cornell and bunny primary rays
//! (speed, one thread and all threads), as a Markdown table and an SVG plot.
//!
//! `cargo run --release --example speed_vs_error -- [OUT_DIR]` (default
//! target/speed_vs_error) writes speed_vs_error.md and speed_vs_error.svg there and prints the
//! table. The bunny columns need ../shared/scenes/bunny.obj (left empty without it).

#[path = "../tests/common/mod.rs"]
mod common;

use common::suite::{self, exact_nearest, Counts};
use plotters::prelude::*;
use raylab::accel::{self, Accel, AccelChoice};
use raylab::controller::CameraController;
use raylab::geometry::{adaptive, sphere, Method, Ray, Shape, Sphere};
use raylab::Camera;
use rayon::prelude::*;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// One row of the report.
#[derive(Clone, Copy, PartialEq)]
enum Variant {
    /// A triangle method (spheres by the cancellation-free test, or exactly by `adaptive`).
    F32(Method),
    F64(Method),
    /// The adaptive method with t then correctly rounded (what `raylab trace` prints).
    F32Rounded,
    F64Rounded,
    /// Sphere tests alone, on the sphere families.
    SphereNaive,
    SphereStable,
}

impl Variant {
    fn name(self) -> String {
        match self {
            Variant::F32(Method::Cramer) => "lecture A⁻¹b (cramer) f32".into(),
            Variant::F64(Method::Cramer) => "lecture A⁻¹b (cramer) f64".into(),
            Variant::F32(m) => format!("{m} f32"),
            // The reference loop: f64 intervals then exact, no f32 filter, no acceleration.
            Variant::F64(Method::Adaptive) => {
                "adaptive, no f32 filter (f64 intervals + exact)".into()
            }
            Variant::F64(m) => format!("{m} f64"),
            Variant::F32Rounded => "adaptive f32, t rounded exactly (trace)".into(),
            Variant::F64Rounded => "adaptive f64, t rounded exactly (trace)".into(),
            Variant::SphereNaive => "sphere b²−ac (textbook) f32".into(),
            Variant::SphereStable => "sphere cancellation-free f32".into(),
        }
    }

    fn spheres_only(self) -> bool {
        matches!(self, Variant::SphereNaive | Variant::SphereStable)
    }
}

const VARIANTS: [Variant; 12] = [
    Variant::F32(Method::Adaptive),
    Variant::F32Rounded,
    Variant::F64Rounded,
    Variant::F32(Method::Watertight),
    Variant::F32(Method::Moller),
    Variant::F32(Method::Cramer),
    Variant::F64(Method::Adaptive),
    Variant::F64(Method::Watertight),
    Variant::F64(Method::Moller),
    Variant::F64(Method::Cramer),
    Variant::SphereNaive,
    Variant::SphereStable,
];

/// A prepared scene that answers closest-hit queries with one variant.
struct Tracer {
    variant: Variant,
    accel: Accel,
    shapes: Vec<Shape<f32>>,
    shapes64: Vec<Shape<f64>>,
}

impl Tracer {
    fn new(variant: Variant, shapes: &[Shape<f32>]) -> Self {
        Self {
            variant,
            accel: Accel::build(shapes, AccelChoice::Auto),
            shapes: shapes.to_vec(),
            shapes64: shapes.iter().map(adaptive::widen).collect(),
        }
    }

    fn trace(&self, ray: &Ray<f32>) -> Option<(f64, u32)> {
        let inf = f32::INFINITY;
        match self.variant {
            Variant::F32(m) => self
                .accel
                .closest_hit(ray, m, 0.0, inf)
                .map(|h| (h.t as f64, h.prim)),
            Variant::F64(m) => {
                let r = Ray::new(ray.o.map(f64::from), ray.d.map(f64::from));
                accel::closest_hit(&self.shapes64, &r, m, 0.0, f64::INFINITY).map(|h| (h.t, h.prim))
            }
            Variant::F32Rounded => {
                let h = self.accel.closest_hit(ray, Method::Adaptive, 0.0, inf)?;
                let shape = &self.shapes[h.prim as usize];
                let t = adaptive::rounded_t(shape, ray, 0.0, inf).unwrap_or(f32::NAN);
                Some((t as f64, h.prim))
            }
            Variant::F64Rounded => {
                let r = Ray::new(ray.o.map(f64::from), ray.d.map(f64::from));
                let h =
                    accel::closest_hit(&self.shapes64, &r, Method::Adaptive, 0.0, f64::INFINITY)?;
                let shape = &self.shapes64[h.prim as usize];
                let t = adaptive::rounded_t(shape, &r, 0.0, f64::INFINITY).unwrap_or(f64::NAN);
                Some((t, h.prim))
            }
            Variant::SphereNaive | Variant::SphereStable => {
                let mut best: Option<(f64, u32)> = None;
                for (i, s) in self.shapes.iter().enumerate() {
                    let Shape::Sphere(Sphere { centre, radius }) = s else {
                        continue;
                    };
                    let far = best.map_or(inf, |b| b.0 as f32);
                    let t = if self.variant == Variant::SphereNaive {
                        sphere::intersect_naive(ray.o, ray.d, *centre, *radius, 0.0, far)
                    } else {
                        sphere::intersect(ray.o, ray.d, *centre, *radius, 0.0, far)
                    };
                    if let Some(t) = t {
                        best = Some((t as f64, i as u32));
                    }
                }
                best
            }
        }
    }
}

/// How far the adaptive method (f32, per ray, the structure `auto` picks) goes on each ray of
/// the suite: the deepest level any candidate reached, and how its t gets rounded.
#[derive(Default)]
struct SuiteLevels {
    rays: u64,
    /// Rays whose deepest level was the f32 filter, f32 with pbrt's bound, f64 intervals,
    /// exact (a candidate decided exactly, or two t's compared exactly).
    deepest: [u64; 4],
    rounded_from_f64: u64,
    rounded_exactly: u64,
}

impl SuiteLevels {
    fn add(&mut self, family: &suite::Family) {
        use adaptive::levels::{self, count, Event};
        let tracer = Tracer::new(Variant::F32(Method::Adaptive), &family.shapes);
        levels::count_levels(true);
        for ray in &family.rays {
            let seen = |e| count(e);
            let before = [
                Event::PreciseF32,
                Event::F64Intervals,
                Event::Exact,
                Event::ExactT,
            ]
            .map(seen);
            let hit = tracer.trace(ray);
            let after = [
                Event::PreciseF32,
                Event::F64Intervals,
                Event::Exact,
                Event::ExactT,
            ]
            .map(seen);
            let reached = |i: usize| after[i] > before[i];
            let deepest = match () {
                _ if reached(2) || reached(3) => 3,
                _ if reached(1) => 2,
                _ if reached(0) => 1,
                _ => 0,
            };
            self.deepest[deepest] += 1;
            self.rays += 1;
            if let Some((_, prim)) = hit {
                let shape = &family.shapes[prim as usize];
                let (f, e) = (count(Event::RoundedFromF64), count(Event::RoundedExactly));
                adaptive::rounded_t(shape, ray, 0.0, f32::INFINITY);
                self.rounded_from_f64 += count(Event::RoundedFromF64) - f;
                self.rounded_exactly += count(Event::RoundedExactly) - e;
            }
        }
        levels::count_levels(false);
    }

    fn write(&self, md: &mut String) -> std::fmt::Result {
        let pc = |n: u64, of: u64| format!("{n} ({:.2}%)", 100.0 * n as f64 / of.max(1) as f64);
        let hits = self.rounded_from_f64 + self.rounded_exactly;
        writeln!(md)?;
        writeln!(md, "How far the adaptive method goes on the suite's {} rays (f32, per ray; the deepest level any candidate of the ray reached), and how the t `raylab trace` prints is rounded for its {hits} hits:", self.rays)?;
        writeln!(md)?;
        writeln!(md, "| f32 filter only | f32 with pbrt's bound | f64 intervals | exact | t rounded from f64 | t rounded exactly |")?;
        writeln!(md, "|---|---|---|---|---|---|")?;
        writeln!(
            md,
            "| {} | {} | {} | {} | {} | {} |",
            pc(self.deepest[0], self.rays),
            pc(self.deepest[1], self.rays),
            pc(self.deepest[2], self.rays),
            pc(self.deepest[3], self.rays),
            pc(self.rounded_from_f64, hits),
            pc(self.rounded_exactly, hits)
        )
    }
}

/// One timing of tracing `rays`, in ns per ray, on one thread or on all.
fn time_ns_per_ray(tracer: &Tracer, rays: &[Ray<f32>], parallel: bool) -> f64 {
    let start = Instant::now();
    let hits: usize = if parallel {
        rays.par_iter()
            .filter(|r| tracer.trace(r).is_some())
            .count()
    } else {
        rays.iter().filter(|r| tracer.trace(r).is_some()).count()
    };
    std::hint::black_box(hits);
    start.elapsed().as_secs_f64() * 1e9 / rays.len() as f64
}

/// Primary rays of a w×h image from the viewer's framing of `shapes` (the Cornell camera for
/// the Cornell box).
fn camera_rays(shapes: &[Shape<f32>], cornell: bool, w: u32, h: u32) -> Vec<Ray<f32>> {
    let cam = if cornell {
        raylab::Camera::cornell(w)
    } else {
        let scene = raylab::Scene::new(
            "mesh",
            shapes.to_vec(),
            vec![[0.5; 3]; shapes.len()],
            raylab::scene::PointLight {
                position: [0.0; 3],
                power: [1.0; 3],
            },
            [0.0; 3],
        );
        CameraController::framing(scene.bounds().expect("non-empty"), w, h).camera(w)
    };
    (0..h)
        .flat_map(|j| (0..w).map(move |i| (i, j)))
        .map(|(i, j)| cam.ray_for_pixel(i, j, w, h))
        .collect()
}

/// Random spheres and rays at them, for timing the sphere tests.
fn sphere_scene() -> (Vec<Shape<f32>>, Vec<Ray<f32>>) {
    let mut rng = common::Rng(7);
    let shapes: Vec<Shape<f32>> = (0..64)
        .map(|_| {
            Shape::Sphere(Sphere {
                centre: [0, 1, 2]
                    .map(|k| rng.range(-4.0, 4.0) as f32 + if k == 2 { 10.0 } else { 0.0 }),
                radius: rng.range(0.1, 1.0) as f32,
            })
        })
        .collect();
    let rays = (0..40_000)
        .map(|_| {
            let d = [rng.range(-0.4, 0.4), rng.range(-0.4, 0.4), 1.0];
            Ray::new([0.0; 3], d.map(|x| x as f32))
        })
        .collect();
    (shapes, rays)
}

struct Row {
    name: String,
    counts: Counts,
    cornell: Option<[f64; 2]>,
    bunny: Option<[f64; 2]>,
}

fn main() -> anyhow::Result<()> {
    let out = PathBuf::from(
        std::env::args()
            .nth(1)
            .unwrap_or_else(|| "target/speed_vs_error".into()),
    );
    std::fs::create_dir_all(&out)?;
    let threads = rayon::current_num_threads();
    let cpu = raylab::machine::cpu_model();
    let machine = format!("{cpu}, {threads} threads (rayon), release build");
    println!("machine: {machine}");

    // Errors on the suite.
    let families = suite::all();
    let total_rays: usize = families.iter().map(|f| f.rays.len()).sum();
    println!("suite: {} families, {total_rays} rays", families.len());
    let mut rows: Vec<Row> = VARIANTS
        .iter()
        .map(|v| Row {
            name: v.name(),
            counts: Counts::default(),
            cornell: None,
            bunny: None,
        })
        .collect();
    let mut suite_levels = SuiteLevels::default();
    for family in &families {
        suite_levels.add(family);
        let exact: Vec<_> = family
            .rays
            .iter()
            .map(|r| exact_nearest(&family.shapes, r))
            .collect();
        let has_spheres = family.shapes.iter().any(|s| matches!(s, Shape::Sphere(_)));
        let only_spheres = family.shapes.iter().all(|s| matches!(s, Shape::Sphere(_)));
        for (row, &v) in rows.iter_mut().zip(&VARIANTS) {
            if v.spheres_only() && !(has_spheres && only_spheres) {
                continue;
            }
            let tracer = Tracer::new(v, &family.shapes);
            for (ray, ex) in family.rays.iter().zip(&exact) {
                row.counts.add(&family.shapes, ray, ex, tracer.trace(ray));
            }
        }
    }

    // Speed: Cornell box and bunny primary rays; sphere tests on a sphere scene.
    let cornell = raylab::Scene::cornell().shapes;
    let cornell_rays = camera_rays(&cornell, true, 640, 360);
    let bunny_path = Path::new("../shared/scenes/bunny.obj");
    let bunny = bunny_path
        .exists()
        .then(|| raylab::scene::obj::load_obj_file(bunny_path, Default::default()))
        .transpose()?
        .map(|s| s.shapes);
    let bunny_rays = bunny.as_ref().map(|b| camera_rays(b, false, 320, 180));
    let (spheres, sphere_rays) = sphere_scene();
    // Round robin over the variants, best of ROUNDS: a shared machine's slow spells then hit
    // every variant alike instead of one.
    const ROUNDS: usize = 7;
    let tracers: Vec<(Tracer, Option<Tracer>)> = VARIANTS
        .iter()
        .map(|&v| {
            let scene = if v.spheres_only() { &spheres } else { &cornell };
            let on_bunny = match (&bunny, v) {
                (Some(b), Variant::F32(_) | Variant::F32Rounded) => Some(Tracer::new(v, b)),
                _ => None,
            };
            (Tracer::new(v, scene), on_bunny)
        })
        .collect();
    for round in 0..ROUNDS {
        for (row, (small, big)) in rows.iter_mut().zip(&tracers) {
            let rays = if small.variant.spheres_only() {
                &sphere_rays
            } else {
                &cornell_rays
            };
            let t = [false, true].map(|p| time_ns_per_ray(small, rays, p));
            let best = row.cornell.get_or_insert([f64::INFINITY; 2]);
            *best = [best[0].min(t[0]), best[1].min(t[1])];
            if let (Some(big), Some(rays)) = (big, &bunny_rays) {
                let t = [false, true].map(|p| time_ns_per_ray(big, rays, p));
                let best = row.bunny.get_or_insert([f64::INFINITY; 2]);
                *best = [best[0].min(t[0]), best[1].min(t[1])];
            }
        }
        println!("timing round {}/{ROUNDS}", round + 1);
    }

    // The table.
    let mut md = String::new();
    writeln!(
        md,
        "Machine: {machine}. Generated by `cargo run --release --example speed_vs_error`."
    )?;
    writeln!(md)?;
    writeln!(
        md,
        "Errors: the {total_rays} rays of the hard-case suite ({} families) against exact rational references (sphere-only rows: the sphere families). \
         Speed: closest-hit queries for the Cornell box's 640x360 primary rays (sphere-only rows: 64 spheres, 40k rays) and the bunny's 320x180 (69k triangles, BVH; f64 methods have no BVH path); best of 7 rounds (round robin), in ns per ray on 1 thread and Mrays/s on 1 and {threads} threads. \
         t errors are relative, over the rays that found the right primitive; the adaptive rows give t with their level's bound (what shading uses), the \"t rounded exactly\" rows the exact t correctly rounded (what `raylab trace` prints, at the cost shown).",
        families.len()
    )?;
    writeln!(md)?;
    writeln!(md, "| method | suite rays | wrong | bad-ray rate | leaks | false hits | wrong nearest | pass-through | median rel. t error | max rel. t error | Cornell ns/ray (1 thread) | Cornell Mrays/s (1 / {threads} threads) | bunny Mrays/s (1 / {threads} threads) |")?;
    writeln!(md, "|---|---|---|---|---|---|---|---|---|---|---|---|---|")?;
    let mrays = |ns: f64| 1e3 / ns;
    for r in &rows {
        let c = &r.counts;
        let cornell = r.cornell.expect("timed");
        let bunny = r.bunny.map_or("n/a".to_string(), |b| {
            format!("{:.1} / {:.1}", mrays(b[0]), mrays(b[1]))
        });
        writeln!(
            md,
            "| {} | {} | {} | {:.2e} | {} | {} | {} | {} | {:.1e} | {:.1e} | {:.0} | {:.1} / {:.1} | {} |",
            r.name,
            c.rays,
            c.wrong(),
            c.wrong() as f64 / c.rays.max(1) as f64,
            c.leaks,
            c.false_hits,
            c.wrong_nearest,
            c.pass_through,
            c.rel(0.5),
            c.rel(1.0),
            cornell[0],
            mrays(cornell[0]),
            mrays(cornell[1]),
            bunny
        )?;
    }
    suite_levels.write(&mut md)?;
    render_table(&mut md, bunny_path, threads)?;
    print!("{md}");
    std::fs::write(out.join("speed_vs_error.md"), &md)?;
    plot(&rows, &out.join("speed_vs_error.svg"), &machine)?;
    println!("wrote {}", out.display());
    Ok(())
}

/// Two log-log panels: bad-ray rate and median relative t error against ns per ray.
/// What the exactness costs where users see it: whole 1280x720 frames through the renderer
/// (camera rays in packets or from a prepared origin for the adaptive method, the per-ray
/// watertight loop otherwise), adaptive against watertight, round robin, best of 7.
fn render_table(md: &mut String, bunny: &Path, threads: usize) -> anyhow::Result<()> {
    use raylab::render::{render_image, LabStep, RenderSettings, Stage};
    let cornell = Stage::from(raylab::Scene::cornell());
    let mut scenes = vec![("cornell", cornell, Camera::cornell(1280))];
    if bunny.exists() {
        let scene = raylab::scene::obj::load_obj_file(bunny, Default::default())?;
        let framing = CameraController::framing(scene.bounds().expect("non-empty"), 1280, 720);
        scenes.push((
            "bunny",
            Stage::new(scene, AccelChoice::Auto),
            framing.camera(1280),
        ));
    }
    let pools: Vec<(usize, rayon::ThreadPool)> = [1, threads]
        .into_iter()
        .map(|n| Ok((n, rayon::ThreadPoolBuilder::new().num_threads(n).build()?)))
        .collect::<anyhow::Result<_>>()?;
    let methods = [Method::Adaptive, Method::Watertight];
    // (scene, step, threads) -> best ms per method.
    let mut best: Vec<((usize, LabStep, usize), [f64; 2])> = Vec::new();
    for round in 0..7 {
        for (si, (_, scene, cam)) in scenes.iter().enumerate() {
            for step in [LabStep::Flat, LabStep::Shadows] {
                for (n, pool) in &pools {
                    let key = (si, step, *n);
                    let mut times = [0.0; 2];
                    for (mi, method) in methods.iter().enumerate() {
                        let settings = RenderSettings {
                            width: 1280,
                            height: 720,
                            step,
                            method: *method,
                            ..Default::default()
                        };
                        let (_, stats) = pool.install(|| render_image(scene, cam, &settings))?;
                        times[mi] = stats.elapsed.as_secs_f64() * 1e3;
                    }
                    match best.iter_mut().find(|(k, _)| *k == key) {
                        Some((_, b)) => *b = [b[0].min(times[0]), b[1].min(times[1])],
                        None => best.push((key, times)),
                    }
                }
            }
        }
        println!("render round {}/7", round + 1);
    }
    writeln!(md)?;
    writeln!(md, "Whole frames, 1280x720, through the renderer (what the window and `raylab render` do), best of 7 rounds:")?;
    writeln!(md)?;
    writeln!(
        md,
        "| scene | step | threads | adaptive ms | watertight ms | adaptive / watertight |"
    )?;
    writeln!(md, "|---|---|---|---|---|---|")?;
    for ((si, step, n), [a, w]) in &best {
        writeln!(
            md,
            "| {} | {step} | {n} | {a:.1} | {w:.1} | {:.2} |",
            scenes[*si].0,
            a / w
        )?;
    }
    // How far the adaptive method goes in those frames (one more frame each, counted).
    use adaptive::levels::{self, count, Event};
    writeln!(md)?;
    writeln!(md, "How far the adaptive method goes in those frames (events counted over one frame; a lane or candidate may reach several levels):")?;
    writeln!(md)?;
    writeln!(md, "| scene | step | camera rays | shadow rays | camera lanes ambiguous in packets | shadow lanes unsure in packets | f32 with pbrt's bound | f64 intervals | exact | exact t comparisons |")?;
    writeln!(md, "|---|---|---|---|---|---|---|---|---|---|")?;
    for (name, scene, cam) in &scenes {
        for step in [LabStep::Flat, LabStep::Shadows] {
            let settings = RenderSettings {
                width: 1280,
                height: 720,
                step,
                ..Default::default()
            };
            levels::reset();
            levels::count_levels(true);
            let (_, stats) = render_image(scene, cam, &settings)?;
            levels::count_levels(false);
            let per = |e, of: u64| {
                let n = count(e);
                format!("{n} ({:.3}%)", 100.0 * n as f64 / of.max(1) as f64)
            };
            let (cam_rays, shadow_rays) = (stats.primary_rays, stats.shadow_rays);
            writeln!(
                md,
                "| {name} | {step} | {cam_rays} | {shadow_rays} | {} | {} | {} | {} | {} | {} |",
                per(Event::CameraLaneAmbiguous, cam_rays),
                per(Event::ShadowLaneUnsure, shadow_rays),
                count(Event::PreciseF32),
                count(Event::F64Intervals),
                count(Event::Exact),
                count(Event::ExactT),
            )?;
        }
    }
    Ok(())
}

fn plot(rows: &[Row], path: &Path, machine: &str) -> anyhow::Result<()> {
    let root = SVGBackend::new(path, (1200, 520)).into_drawing_area();
    root.fill(&WHITE)?;
    let (title, body) = root.split_vertically(40);
    title.draw_text(
        &format!("Speed versus error on the hard-case suite ({machine})"),
        &("sans-serif", 18).into_font().color(&BLACK),
        (10, 10),
    )?;
    let panels = body.split_evenly((1, 2));
    // Zero cannot sit on a log axis: it is drawn at the floor and labelled "0".
    let floors = [1e-5, 1e-10];
    let xs: Vec<f64> = rows.iter().map(|r| r.cornell.expect("timed")[0]).collect();
    // Whole decades, so the log axis gets its tick labels.
    let decade = |x: f64, up: bool| {
        let e = x.log10();
        10f64.powf(if up { e.ceil() } else { e.floor() })
    };
    let (xmin, xmax) = (
        decade(xs.iter().cloned().fold(f64::INFINITY, f64::min), false),
        decade(xs.iter().cloned().fold(0.0, f64::max), true),
    );
    for (k, panel) in panels.iter().enumerate() {
        let ys: Vec<f64> = rows
            .iter()
            .map(|r| {
                let c = &r.counts;
                let y = if k == 0 {
                    c.wrong() as f64 / c.rays.max(1) as f64
                } else {
                    c.rel(0.5)
                };
                y.max(floors[k])
            })
            .collect();
        let ymax = ys.iter().cloned().fold(floors[k] * 10.0, f64::max) * 3.0;
        let caption = if k == 0 {
            "bad-ray rate (wrong answers / rays; floor = 0)"
        } else {
            "median relative t error (floor = 0)"
        };
        let mut chart = ChartBuilder::on(panel)
            .caption(caption, ("sans-serif", 16))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(70)
            .build_cartesian_2d(
                (xmin..xmax).log_scale(),
                (floors[k] / 2.0..ymax).log_scale(),
            )?;
        chart
            .configure_mesh()
            .x_desc("ns per ray, Cornell box, 1 thread")
            .x_labels(12)
            .y_label_formatter(&|y| {
                if *y <= floors[k] * 1.01 {
                    "0".to_string()
                } else {
                    format!("{y:.0e}")
                }
            })
            .x_label_formatter(&|x| format!("{x:.0}"))
            .draw()?;
        let font = ("sans-serif", 11).into_font();
        let mut points = Vec::new();
        let mut sizes = Vec::new();
        for (i, (r, (&x, &y))) in rows.iter().zip(xs.iter().zip(&ys)).enumerate() {
            let colour = Palette99::pick(i).to_rgba();
            chart.draw_series(std::iter::once(Circle::new((x, y), 5, colour.filled())))?;
            points.push(chart.backend_coord(&(x, y)));
            let (w, h) = root.estimate_text_size(&r.name, &TextStyle::from(font.clone()))?;
            sizes.push((w as i32, h as i32));
        }
        // Every label where it overlaps no other label or point and stays inside the plot,
        // with a line back to its point where it had to move away.
        let (xr, yr) = chart.plotting_area().get_pixel_range();
        let area = (xr.start, yr.start, xr.end, yr.end);
        let placed = place_labels(&points, &sizes, area);
        for (i, ((r, &p), &(lx, ly))) in rows.iter().zip(&points).zip(&placed).enumerate() {
            let (w, h) = sizes[i];
            let near = (lx.max(p.0.min(lx + w)), ly.max(p.1.min(ly + h)));
            if (near.0 - p.0).abs() + (near.1 - p.1).abs() > 12 {
                let colour = Palette99::pick(i).to_rgba();
                root.draw(&PathElement::new(vec![p, near], colour.stroke_width(1)))?;
            }
            root.draw(&Text::new(r.name.clone(), (lx, ly), font.clone()))?;
        }
    }
    root.present()?;
    Ok(())
}

/// Top-left corners for labels of `sizes` (pixels) beside `points`, inside `area` (x0, y0,
/// x1, y1): for each point in turn, the nearest of a ring of spots around it (right, left,
/// above, below, then further out) where the label overlaps neither an earlier label nor any
/// point's marker (a 12-pixel square). Where no spot is free, the one with the least overlap.
fn place_labels(
    points: &[(i32, i32)],
    sizes: &[(i32, i32)],
    area: (i32, i32, i32, i32),
) -> Vec<(i32, i32)> {
    type Rect = (i32, i32, i32, i32);
    let overlap = |a: Rect, b: Rect| {
        let w = (a.2.min(b.2) - a.0.max(b.0)).max(0);
        let h = (a.3.min(b.3) - a.1.max(b.1)).max(0);
        w * h
    };
    let markers: Vec<Rect> = points
        .iter()
        .map(|&(x, y)| (x - 6, y - 6, x + 6, y + 6))
        .collect();
    let mut placed: Vec<Rect> = Vec::new();
    let mut corners = Vec::new();
    for (&(px, py), &(w, h)) in points.iter().zip(sizes) {
        let mut best: Option<(i32, (i32, i32))> = None;
        'search: for ring in 0..14 {
            let r = 8 + 12 * ring;
            for k in 0..16 {
                // Right and left first, then above and below, alternating.
                let angle = [0, 8, 1, 9, 15, 7, 2, 10, 14, 6, 3, 11, 13, 5, 4, 12][k] as f64
                    * std::f64::consts::PI
                    / 8.0;
                let (c, s) = (angle.cos(), angle.sin());
                let ax = px + (r as f64 * c).round() as i32;
                let ay = py - (r as f64 * s).round() as i32;
                let x = if c >= -0.01 { ax } else { ax - w };
                let y = ay - h / 2 - (s * h as f64 / 2.0).round() as i32;
                let rect = (x, y, x + w, y + h);
                if rect.0 < area.0 || rect.1 < area.1 || rect.2 > area.2 || rect.3 > area.3 {
                    continue;
                }
                let cost: i32 = placed.iter().map(|p| overlap(*p, rect)).sum::<i32>()
                    + markers.iter().map(|m| overlap(*m, rect)).sum::<i32>();
                if best.is_none_or(|b| cost < b.0) {
                    best = Some((cost, (x, y)));
                }
                if cost == 0 {
                    break 'search;
                }
            }
        }
        let (_, (x, y)) = best.unwrap_or((0, (area.0, area.1)));
        placed.push((x, y, x + w, y + h));
        corners.push((x, y));
    }
    corners
}

#[cfg(test)]
mod tests {
    use super::place_labels;

    #[test]
    fn labels_of_clustered_points_neither_overlap_nor_leave_the_plot() {
        // The plot's hard case: a cluster of points a few pixels apart with long names, two
        // on the same spot, one at the right edge (its label used to run off the plot).
        let points = [
            (100, 100),
            (108, 102),
            (112, 99),
            (112, 99),
            (300, 200),
            (306, 204),
            (590, 300),
            (20, 20),
        ];
        let sizes = [
            (90, 11),
            (160, 11),
            (60, 11),
            (70, 11),
            (120, 11),
            (200, 11),
            (240, 11),
            (80, 11),
        ];
        let area = (0, 0, 600, 320);
        let corners = place_labels(&points, &sizes, area);
        let rects: Vec<_> = corners
            .iter()
            .zip(&sizes)
            .map(|(&(x, y), &(w, h))| (x, y, x + w, y + h))
            .collect();
        for (i, a) in rects.iter().enumerate() {
            assert!(
                a.0 >= 0 && a.1 >= 0 && a.2 <= 600 && a.3 <= 320,
                "label {i} {a:?}"
            );
            for (j, b) in rects.iter().enumerate().skip(i + 1) {
                let apart = a.2 <= b.0 || b.2 <= a.0 || a.3 <= b.1 || b.3 <= a.1;
                assert!(apart, "labels {i} {a:?} and {j} {b:?} overlap");
            }
            for (j, p) in points.iter().enumerate() {
                let clear = p.0 + 6 <= a.0 || a.2 <= p.0 - 6 || p.1 + 6 <= a.1 || a.3 <= p.1 - 6;
                assert!(clear, "label {i} {a:?} covers point {j}");
            }
        }
    }
}
