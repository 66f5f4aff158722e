//! The seam for linked code that is not raylab's (`check::code`): raylab's own answers behind
//! it give raylab's frames and answers to the bit; a plain formula behind it shows its cracks
//! where raylab's cracks view shows them.

use raylab::check::code::{self, Exact, LabCode};
use raylab::check::grade::{self, Verdict, FALSE_HIT, WRONG};
use raylab::check::suite;
use raylab::geometry::{Hit, Method, Ray, Shape};
use raylab::render::{linear_to_srgb8, render_into, LabStep, RenderSettings, Stage, CRACK};
use raylab::scene::ObjFrame;
use raylab::{Camera, Scene};

/// Möller–Trumbore and the plain quadratic behind the seam, with raylab's camera rays: the
/// nearest hit over every shape, a tie to the lower index.
struct Plain(Method);

impl LabCode for Plain {
    fn name(&self) -> &str {
        self.0.name()
    }

    fn camera_ray(&self, camera: &Camera, width: u32, height: u32, x: f32, y: f32) -> Ray {
        camera.ray_generator(width, height).ray_through(x, y)
    }

    fn closest_hit(&self, shapes: &[Shape], ray: &Ray, tmin: f32, tmax: f32) -> Option<Hit> {
        let mut nearest: Option<Hit> = None;
        for (prim, shape) in shapes.iter().enumerate() {
            let tmax = nearest.map_or(tmax, |h| h.t);
            if let Some((t, b1, b2)) = shape.intersect(ray, self.0, tmin, tmax) {
                let prim = prim as u32;
                nearest = Some(Hit { t, prim, b1, b2 });
            }
        }
        nearest
    }
}

fn render_code(code: &dyn LabCode, stage: &Stage, settings: &RenderSettings) -> Vec<u8> {
    let camera = Camera::cornell(settings.width);
    let mut rgba = vec![0; settings.buffer_len()];
    code::render_into_cancellable(code, stage, &camera, settings, &mut rgba, &|| false)
        .unwrap()
        .expect("not cancelled");
    rgba
}

fn render_raylab(stage: &Stage, settings: &RenderSettings) -> Vec<u8> {
    let camera = Camera::cornell(settings.width);
    let mut rgba = vec![0; settings.buffer_len()];
    render_into(stage, &camera, settings, &mut rgba).unwrap();
    rgba
}

#[test]
fn raylab_s_exact_answers_behind_the_seam_render_raylab_s_frames_to_the_byte() {
    let spheres = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/scenes/cornell_spheres.scene"
    );
    for scene in [
        Scene::cornell(),
        Scene::open(spheres, ObjFrame::Lab).unwrap(),
    ] {
        let stage = Stage::from(scene);
        for step in [LabStep::Flat, LabStep::Direct, LabStep::Shadows] {
            for (spp, cracks) in [(1, false), (2, false), (1, true)] {
                let settings = RenderSettings {
                    width: 96,
                    height: 72,
                    step,
                    spp,
                    cracks,
                    ..Default::default()
                };
                let ours = render_raylab(&stage, &settings);
                let theirs = render_code(&Exact, &stage, &settings);
                let lit = ours.chunks(4).filter(|p| p[..3] != [0, 0, 0]).count();
                assert!(
                    lit > 96 * 72 / 2,
                    "{} {step:?}: {lit} lit",
                    stage.scene().name
                );
                assert!(ours == theirs, "{} {step:?} spp {spp}", stage.scene().name);
            }
        }
    }
}

#[test]
fn moller_behind_the_seam_is_marked_where_the_cracks_view_marks_it() {
    // raylab's cracks view marks a pixel where Möller–Trumbore's hit or miss differs from the
    // exact answer; behind the seam those are the leaks (magenta) and false hits (yellow).
    let icosphere = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/meshes/icosphere.obj");
    let mut total = 0;
    for scene in [
        Scene::cornell(),
        Scene::open(icosphere, ObjFrame::Lab).unwrap(),
    ] {
        let stage = Stage::from(scene);
        let settings = RenderSettings {
            width: 320,
            height: 240,
            step: LabStep::Flat,
            cracks: true,
            ..Default::default()
        };
        let moller = RenderSettings {
            method: Method::Moller,
            ..settings
        };
        let cracks_view = render_raylab(&stage, &moller);
        let code = render_code(&Plain(Method::Moller), &stage, &settings);
        let is = |p: &[u8], c: [f32; 3]| p[..3] == c.map(linear_to_srgb8);
        let marked_here: Vec<bool> = (code.chunks(4))
            .map(|p| is(p, CRACK) || is(p, FALSE_HIT))
            .collect();
        let marked_there: Vec<bool> = cracks_view.chunks(4).map(|p| is(p, CRACK)).collect();
        let count = marked_here.iter().filter(|m| **m).count();
        let name = &stage.scene().name;
        total += count;
        assert!(marked_here == marked_there, "{name}: {count} marked");
        // Everything else is the exact flat frame, a wrong primitive marked cyan, or another
        // primitive met at exactly the same t (a tie: right, and maybe of another colour).
        // (Past the flat step the code's shadow rays leak too.)
        let exact = render_raylab(&stage, &settings);
        let camera = Camera::cornell(settings.width);
        let shapes = &stage.scene().shapes;
        for (k, (p, e)) in code.chunks(4).zip(exact.chunks(4)).enumerate() {
            if marked_here[k] || is(p, WRONG) || p == e {
                continue;
            }
            let (i, j) = ((k % 320) as u32, (k / 320) as u32);
            let ray = camera.ray_for_pixel(i, j, 320, 240);
            let hit = |code: &dyn LabCode| code.closest_hit(shapes, &ray, 0.0, f32::INFINITY);
            let verdict = code::verdict(shapes, &ray, hit(&Exact), hit(&Plain(Method::Moller)));
            assert_eq!(verdict, Verdict::Tie, "{name}: pixel {i},{j}");
        }
    }
    assert!(total >= 1, "Möller–Trumbore leaks on the box's diagonals");
}

#[test]
fn answers_through_the_seam_are_graded_as_a_program_s() {
    let mut leaks = 0;
    for family in suite::all() {
        let rays = family.trace_rays();
        let exact = grade::exact_answers(&family.shapes, &rays);
        assert_eq!(
            code::answers(&Exact, &family.shapes, &rays),
            exact,
            "{}",
            family.name
        );
        let moller = code::answers(&Plain(Method::Moller), &family.shapes, &rays);
        leaks += (exact.iter().zip(&moller))
            .filter(|(e, m)| {
                matches!(e, grade::Answer::Hit { .. }) && matches!(m, grade::Answer::Miss)
            })
            .count();
    }
    // The figure `raylab check --suite` gives Möller–Trumbore in f32.
    assert_eq!(leaks, 534);
}

/// Linked code whose index is past the last primitive (an off-by-one at the end of the
/// list): graded a wrong primitive and marked as one, whether the cracks view is on or not;
/// the window never shades a primitive that does not exist (it panicked).
struct PastTheEnd;

impl LabCode for PastTheEnd {
    fn name(&self) -> &str {
        "past the end"
    }

    fn camera_ray(&self, camera: &Camera, width: u32, height: u32, x: f32, y: f32) -> Ray {
        camera.ray_generator(width, height).ray_through(x, y)
    }

    fn closest_hit(&self, shapes: &[Shape], ray: &Ray, tmin: f32, tmax: f32) -> Option<Hit> {
        let mut h = Exact.closest_hit(shapes, ray, tmin, tmax)?;
        h.prim = shapes.len() as u32;
        Some(h)
    }
}

#[test]
fn an_index_past_the_scene_is_a_wrong_primitive_not_a_panic() {
    let scene = Scene::cornell();
    let last = scene.shapes.len() as u32 - 1;
    let stage = Stage::from(Scene::cornell());
    let wrong_px = WRONG.map(linear_to_srgb8);
    for cracks in [false, true] {
        let settings = RenderSettings {
            width: 64,
            height: 48,
            cracks,
            ..Default::default()
        };
        let rgba = render_code(&PastTheEnd, &stage, &settings);
        let marked = rgba.chunks(4).filter(|p| p[..3] == wrong_px).count();
        assert_eq!(
            marked,
            64 * 48,
            "cracks {cracks}: every pixel meets the box"
        );
    }
    let ray = Camera::cornell(64)
        .ray_generator(64, 48)
        .ray_through(32.0, 24.0);
    let exact = Exact.closest_hit(&scene.shapes, &ray, 0.0, f32::INFINITY);
    let past = Hit {
        t: 1.0,
        prim: last + 1,
        b1: 0.0,
        b2: 0.0,
    };
    assert_eq!(
        code::verdict(&scene.shapes, &ray, exact, Some(past)),
        Verdict::Wrong
    );
}

#[test]
fn an_index_past_the_scene_on_a_ray_that_meets_nothing_is_a_false_hit_not_a_panic() {
    // Grading looks a hit's primitive up to decide a tie on a triangle of zero area: an index
    // past the end must be graded before that, also where the exact answer is a miss.
    let scene = Scene::cornell();
    let ray = Ray::new([0.0, 0.0, -1e6], [0.0, 0.0, -1.0]);
    let exact = Exact.closest_hit(&scene.shapes, &ray, 0.0, f32::INFINITY);
    assert_eq!(exact, None, "the ray leaves the box behind");
    for past in [scene.shapes.len() as u32, u32::MAX] {
        let hit = Hit {
            t: 1.0,
            prim: past,
            b1: 0.0,
            b2: 0.0,
        };
        let verdict = code::verdict(&scene.shapes, &ray, exact, Some(hit));
        assert_eq!(verdict, Verdict::FalseHit, "primitive {past}");
        assert_eq!(verdict.mark(), Some(FALSE_HIT));
    }
}

/// Each family of the suite says the arithmetic its correct programs need, by its directory's
/// name: the twelve that some correct double programs fail by rounding and the eight every
/// correct float program passes are all found (a misspelt name would be a family lost).
#[test]
fn each_family_names_the_arithmetic_correct_code_needs() {
    use raylab::check::rounding::Needs;
    let needs: Vec<Needs> = (raylab::check::suite::slugs().iter())
        .map(|slug| Needs::of(slug))
        .collect();
    let count = |n: Needs| needs.iter().filter(|&&m| m == n).count();
    assert_eq!((count(Needs::Exact), count(Needs::F32)), (12, 8));
    // The twelve are the ones docs/grading.md tells a course grading the lecture's level to
    // weigh less, by number.
    let numbers: Vec<String> = (needs.iter().enumerate())
        .filter(|(_, &n)| n == Needs::Exact)
        .map(|(k, _)| format!("{:02}", k + 1))
        .collect();
    let listed = [
        "03", "04", "16", "17", "18", "21", "25", "26", "28", "30", "32", "33",
    ];
    assert_eq!(numbers, listed);
    let grading = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/grading.md"),
    )
    .unwrap();
    let stated = "weigh 03, 04, 16–18, 21, 25, 26, 28, 30, 32 and 33 less";
    assert!(grading
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ")
        .contains(stated));
    assert_eq!(Needs::of("cube-from-inside"), Needs::F64);
    assert!(Needs::Exact.rounding_fails(true) && !Needs::F64.rounding_fails(true));
    assert!(Needs::F64.rounding_fails(false) && !Needs::F32.rounding_fails(false));
}
