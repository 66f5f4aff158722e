//! Intersection code that is not raylab's, linked in: the seam a student's Rust code plugs into
//! (the lab crate; `raylab check --program` is the route for a program in any language).
//!
//! [`LabCode`] is what such code answers: the camera ray of an image position and the nearest
//! hit with its (t, u, v). [`answers`] puts it through rays as `raylab trace` would, for
//! [`super::grade`]; [`render_into_cancellable`] draws a frame from it, shaded as every raylab
//! path shades (the colour depends only on the ray and the primitive hit), with the cracks view
//! marking each sample where it differs from the exact answer as `raylab check --image` does
//! ([`Verdict::mark`]). [`Exact`] is raylab's own answer behind the same seam: rendered through
//! it, a frame is `render::render_into`'s to the byte.

use super::grade::{self, Answer, Tally, Verdict};
use super::Family;
use crate::camera::Camera;
use crate::geometry::{adaptive, Hit, Ray, Shape};
use crate::render::driver::{self, Counts, Sample, Samples, Tile, TileTracer};
use crate::render::shade;
use crate::render::{RenderSettings, RenderStats, SettingsError, Stage};
use crate::tracefile::TraceRay;
use rayon::prelude::*;
use std::borrow::Cow;
use std::time::Instant;

/// The lab's pieces as code that is not raylab's writes them.
pub trait LabCode: Send + Sync {
    /// The name the method selector and the reports show.
    fn name(&self) -> &str;

    /// The ray from `camera` through image position (x, y) of a `width`×`height` image, in
    /// pixels from the top-left corner ((i + ½, j + ½) is the centre of pixel (i, j)).
    fn camera_ray(&self, camera: &Camera, width: u32, height: u32, x: f32, y: f32) -> Ray;

    /// The nearest of `shapes` that `ray` meets with tmin < t < tmax: its t, its index
    /// (`prim`) and, on a triangle, the barycentric weights (u, v) of vertices 1 and 2 (`b1`,
    /// `b2`; 0 on a sphere).
    fn closest_hit(&self, shapes: &[Shape], ray: &Ray, tmin: f32, tmax: f32) -> Option<Hit>;
}

/// raylab's own answers behind the seam: the camera's ray generator and the exact search
/// (`geometry::adaptive`), t and (u, v) rounded to f32.
#[derive(Clone, Copy, Debug, Default)]
pub struct Exact;

impl LabCode for Exact {
    fn name(&self) -> &str {
        "exact"
    }

    fn camera_ray(&self, camera: &Camera, width: u32, height: u32, x: f32, y: f32) -> Ray {
        camera.ray_generator(width, height).ray_through(x, y)
    }

    fn closest_hit(&self, shapes: &[Shape], ray: &Ray, tmin: f32, tmax: f32) -> Option<Hit> {
        let h = adaptive::closest_hit_reference(shapes, ray, tmin, tmax)?;
        let shape = &shapes[h.prim as usize];
        Some(Hit {
            t: adaptive::rounded_t(shape, ray, tmin, tmax).unwrap_or(h.t as f32),
            prim: h.prim,
            b1: h.b1 as f32,
            b2: h.b2 as f32,
        })
    }
}

/// The code's answers to `rays` over `shapes`, one per ray, as an answer file holds them.
pub fn answers(code: &dyn LabCode, shapes: &[Shape], rays: &[TraceRay<f32>]) -> Vec<Answer<f32>> {
    (rays.par_iter())
        .map(|r| match code.closest_hit(shapes, &r.ray, r.tmin, r.tmax) {
            Some(h) => Answer::Hit {
                t: h.t,
                prim: h.prim,
            },
            None => Answer::Miss,
        })
        .collect()
}

/// The code graded on every family (each ray over its interval, f32, as exported): the table
/// `raylab check --suite` prints — a row per family with the code's time beside the exact
/// answers', and the total — and each family's tally, the total last.
pub fn check_suite(code: &dyn LabCode, families: &[Family]) -> (String, Vec<(String, Tally)>) {
    let mut table = grade::table_header() + "\n";
    let (mut tallies, mut total) = (Vec::new(), Tally::default());
    let (mut code_ms, mut exact_ms) = (0.0, 0.0);
    for family in families {
        let rays = family.trace_rays();
        let start = Instant::now();
        let given = answers(code, &family.shapes, &rays);
        let ms = start.elapsed().as_secs_f64() * 1e3;
        let start = Instant::now();
        let exact = grade::exact_answers(&family.shapes, &rays);
        let ms = (ms, start.elapsed().as_secs_f64() * 1e3);
        let mut tally = Tally::default();
        let shape_of = |p: u32| family.shapes[p as usize];
        for ((ray, exact), given) in rays.iter().zip(exact).zip(given) {
            // An index past the family's primitives is wrong, never looked up.
            if let Answer::Hit { prim, .. } = given {
                if prim as usize >= family.shapes.len() {
                    let verdict = match exact {
                        Answer::Hit { .. } => Verdict::Wrong,
                        Answer::Miss => Verdict::FalseHit,
                    };
                    tally.add(&grade::Graded {
                        verdict,
                        t_error: None,
                        relative: 0.0,
                    });
                    continue;
                }
            }
            tally.add(&grade::grade(
                shape_of,
                ray,
                exact,
                given,
                grade::DEFAULT_T_TOLERANCE,
            ));
        }
        table += &(tally.row(&family.name, ms) + "\n");
        total.merge(&tally);
        (code_ms, exact_ms) = (code_ms + ms.0, exact_ms + ms.1);
        tallies.push((family.name.clone(), tally));
    }
    table += &(total.row("total", (code_ms, exact_ms)) + "\n");
    table += &total.line();
    tallies.push(("total".to_string(), total));
    (table, tallies)
}

/// The verdict on the code's answer `hit` to camera ray `ray`, against the exact one
/// (`exact`, found by the stage's structure); ties decided exactly as [`grade::grade`] does;
/// an index past the scene's primitives is a wrong primitive (a false hit where nothing is
/// met, as any hit there).
pub fn verdict(scene_shapes: &[Shape], ray: &Ray, exact: Option<Hit>, hit: Option<Hit>) -> Verdict {
    // An index past the end is graded before anything is looked up, whatever the exact
    // answer (grading may look the answer's primitive up: a zero-area tie, an exact tie).
    if let Some(h) = hit {
        if h.prim as usize >= scene_shapes.len() {
            return match exact {
                Some(_) => Verdict::Wrong,
                None => Verdict::FalseHit,
            };
        }
    }
    let answer = |h: Option<Hit>| match h {
        Some(h) => Answer::Hit {
            t: h.t,
            prim: h.prim,
        },
        None => Answer::Miss,
    };
    let shape_of = |p: u32| scene_shapes[p as usize];
    grade::grade(
        shape_of,
        &TraceRay::whole(*ray),
        answer(exact),
        answer(hit),
        grade::DEFAULT_T_TOLERANCE,
    )
    .verdict
}

/// Renders `stage`'s scene through `camera` with `code` answering every ray — camera rays from
/// [`LabCode::camera_ray`], nearest hits and shadow rays from [`LabCode::closest_hit`] — into
/// `rgba` (RGBA8, rows top to bottom), through the render driver every raylab frame takes
/// (`render::driver`: the same sample positions, averaging and encoding). With
/// `settings.cracks` a sample whose answer is not right (nor an exact tie) shows its mark
/// ([`Verdict::mark`]) instead of its colour. Gives up, `Ok(None)`, when `cancelled()` turns
/// true (asked before each tile and once at the end). `settings.method` is not used: the
/// code is the method.
pub fn render_into_cancellable(
    code: &dyn LabCode,
    stage: &Stage,
    camera: &Camera,
    settings: &RenderSettings,
    rgba: &mut [u8],
    cancelled: &(dyn Fn() -> bool + Sync),
) -> Result<Option<RenderStats>, SettingsError> {
    let started = driver::start(settings, rgba)?;
    let scene = stage.scene();
    let frame = CodeFrame {
        code,
        stage,
        camera,
        settings,
        // The code is given every primitive one by one (instanced meshes placed).
        shapes: match scene.instances().is_empty() {
            true => Cow::Borrowed(&scene.shapes),
            false => Cow::Owned(scene.all_shapes().collect()),
        },
        samples: Samples::new(settings),
    };
    Ok(driver::drive(settings, rgba, cancelled, started, &frame))
}

/// What every tile of a frame drawn by linked code shares.
struct CodeFrame<'a> {
    code: &'a dyn LabCode,
    stage: &'a Stage,
    camera: &'a Camera,
    settings: &'a RenderSettings,
    shapes: Cow<'a, [Shape]>,
    samples: Samples,
}

impl CodeFrame<'_> {
    /// What the sample at image position (x, y) shows: the code's hit shaded, or its mark.
    fn sample(&self, x: f32, y: f32, shadow_rays: &mut u64) -> Option<Sample> {
        let (code, shapes, settings) = (self.code, &self.shapes[..], self.settings);
        let (w, h) = (settings.width, settings.height);
        let ray = code.camera_ray(self.camera, w, h, x, y);
        let hit = code.closest_hit(shapes, &ray, 0.0, f32::INFINITY);
        // An index past the scene's primitives is a wrong primitive: marked as one, never
        // shaded.
        let beyond = hit.is_some_and(|h| h.prim as usize >= shapes.len());
        if settings.cracks || beyond {
            let exact = self.stage.accel().closest_hit(
                &ray,
                crate::geometry::Method::Adaptive,
                0.0,
                f32::INFINITY,
            );
            if let Some(mark) = verdict(shapes, &ray, exact, hit).mark() {
                return Some(Sample::Mark(mark));
            }
        }
        // Blocked: the code meets something between the light (t = 0) and the point (t = 1)
        // other than the point's own primitive.
        let blocked = |shadow: &Ray, skip: u32| {
            let h = code.closest_hit(shapes, shadow, 0.0, 1.0);
            h.is_some_and(|h| h.prim != skip)
        };
        let scene = self.stage.scene();
        let colour = shade::shade(scene, &ray, &hit?, settings.step, blocked, shadow_rays);
        Some(Sample::Colour(colour))
    }
}

impl TileTracer for CodeFrame<'_> {
    type Scratch = ();

    fn trace(&self, tile: &Tile, _: &mut (), rows: &mut [u8], counts: &mut Counts) {
        (self.samples).each_pixel(tile, rows, counts, |x, y, counts| {
            self.sample(x, y, &mut counts.1)
        });
    }
}

/// The code's answer for one pixel of the window's image, beside the exact one on the same
/// ray: what the ray inspector shows for code that is not raylab's.
#[derive(Clone, Debug, PartialEq)]
pub struct CodeInspection {
    /// The code's name.
    pub name: String,
    /// The code's camera ray through the pixel's centre (or the position inspected:
    /// [`inspect_at`]).
    pub ray: Ray,
    /// raylab's camera ray through the same position.
    pub raylab_ray: Ray,
    /// The code's nearest hit on its ray: t, primitive, (u, v).
    pub hit: Option<Hit>,
    /// The exact nearest hit on the code's ray, (u, v) and t rounded to f32.
    pub exact: Option<Hit>,
    /// The code's answer graded against the exact one.
    pub verdict: Verdict,
}

/// Inspects pixel (i, j) of a `width`×`height` image through `code`: its camera ray and its
/// nearest hit beside the exact one.
pub fn inspect(
    code: &dyn LabCode,
    scene: &crate::scene::Scene,
    camera: &Camera,
    (width, height): (u32, u32),
    (i, j): (u32, u32),
) -> CodeInspection {
    inspect_at(
        code,
        scene,
        camera,
        (width, height),
        (i as f32 + 0.5, j as f32 + 0.5),
    )
}

/// Inspects the ray through image position (x, y) of a `width`×`height` image through `code`
/// (a sample of a supersampled pixel): as [`inspect`] does the pixel's centre.
pub fn inspect_at(
    code: &dyn LabCode,
    scene: &crate::scene::Scene,
    camera: &Camera,
    (width, height): (u32, u32),
    (x, y): (f32, f32),
) -> CodeInspection {
    let shapes: Vec<Shape> = scene.all_shapes().collect();
    let ray = code.camera_ray(camera, width, height, x, y);
    let hit = code.closest_hit(&shapes, &ray, 0.0, f32::INFINITY);
    let exact = Exact.closest_hit(&shapes, &ray, 0.0, f32::INFINITY);
    CodeInspection {
        name: code.name().to_string(),
        ray,
        raylab_ray: Exact.camera_ray(camera, width, height, x, y),
        hit,
        exact,
        verdict: verdict(&shapes, &ray, exact, hit),
    }
}

impl std::fmt::Display for CodeInspection {
    /// The lines the inspector shows (and a scripted window run prints).
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        let hit = |h: &Option<Hit>| match h {
            Some(h) => format!("t {} primitive {} (u, v) ({}, {})", h.t, h.prim, h.b1, h.b2),
            None => "miss".to_string(),
        };
        let d = |r: &Ray| format!("{} {} {}", r.d[0], r.d[1], r.d[2]);
        writeln!(f, "{} d world: {}", self.name, d(&self.ray))?;
        writeln!(f, "raylab d world: {}", d(&self.raylab_ray))?;
        writeln!(f, "{} hit: {}", self.name, hit(&self.hit))?;
        writeln!(f, "exact hit: {}", hit(&self.exact))?;
        write!(f, "verdict: {}", self.verdict.name())
    }
}
