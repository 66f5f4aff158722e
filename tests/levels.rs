//! The adaptive method's level counters (`geometry::adaptive::levels`, reported by
//! examples/speed_vs_error): they count what the search does, and only while switched on;
//! and with them, that rays from far away and from a triangle's plane stay off the slow
//! levels. (Its own binary, the tests one at a time: the counters are global.)

use raylab::accel::{Accel, AccelChoice};
use raylab::geometry::adaptive::{self, levels, levels::Event};
use raylab::geometry::{Method, Ray, Shape};

/// The tests here take turns: the counters are shared.
static ONE_AT_A_TIME: std::sync::Mutex<()> = std::sync::Mutex::new(());

#[test]
fn levels_count_the_slow_paths_only_while_on() {
    let _turn = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    // Two triangles sharing the edge x = y of the unit square.
    let shapes = vec![
        Shape::from([[0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [1.0, 1.0, 1.0]]),
        Shape::from([[0.0, 0.0, 1.0], [1.0, 1.0, 1.0], [0.0, 1.0, 1.0]]),
    ];
    let accel = Accel::build(&shapes, AccelChoice::Flat);
    let closest = |o: [f32; 3], d: [f32; 3]| {
        let ray = Ray::new(o, d);
        let hit = accel.closest_hit(&ray, Method::Adaptive, 0.0, f32::INFINITY);
        hit.map(|h| {
            (
                h.prim,
                adaptive::rounded_t(&shapes[h.prim as usize], &ray, 0.0, f32::INFINITY),
            )
        })
    };
    let slow = [
        Event::PreciseF32,
        Event::F64Intervals,
        Event::Exact,
        Event::ExactT,
    ];
    let counts = || slow.map(levels::count);

    // Off: nothing is counted, even on a ray exactly through the shared edge.
    levels::reset();
    assert_eq!(
        closest([0.5, 0.5, 0.0], [0.0, 0.0, 1.0]),
        Some((0, Some(1.0)))
    );
    assert_eq!(counts(), [0; 4]);

    levels::count_levels(true);
    // A ray well inside one triangle: the f32 filter decides, t rounds from plain f64.
    assert_eq!(
        closest([0.8, 0.2, 0.0], [0.0, 0.0, 1.0]),
        Some((0, Some(1.0)))
    );
    assert_eq!(counts(), [0; 4]);
    assert_eq!(levels::count(Event::RoundedFromF64), 1);
    // Exactly through the shared edge: only exact arithmetic decides it (a tie, to the lower
    // index).
    assert_eq!(
        closest([0.5, 0.5, 0.0], [0.0, 0.0, 1.0]),
        Some((0, Some(1.0)))
    );
    let [precise, intervals, exact, _] = counts();
    assert!(
        precise >= 1 && intervals >= 1 && exact >= 1,
        "{:?}",
        counts()
    );
    levels::count_levels(false);
    let before = counts();
    closest([0.5, 0.5, 0.0], [0.0, 0.0, 1.0]);
    assert_eq!(counts(), before, "counted while off");
}

#[test]
fn rays_from_far_away_and_from_a_plane_stay_off_the_slow_levels() {
    use raylab::render::{render_image, LabStep, RenderSettings, Stage};
    use raylab::{Camera, Scene};
    let _turn = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());

    // Two placements of a 1,280-triangle ball, seen from 10⁷ away: carried into the mesh's
    // frame from there, a ray needed a pad the size of the ball and every triangle went to
    // the f64 level (1,300 a ray); moved up to the instances first, a few do.
    let dir = tempfile::tempdir().unwrap();
    let ball = format!("{}/assets/meshes/icosphere.obj", env!("CARGO_MANIFEST_DIR"));
    let text = format!("mesh {ball}\npush\ntranslate 1.5 0 0\nmesh {ball}\npop\n");
    let path = dir.path().join("two.scene");
    std::fs::write(&path, text).unwrap();
    let scene = Scene::load(&path, Default::default()).unwrap();
    let placed = Accel::build_with_instances(
        scene.explicit_with_prims(),
        scene.instances(),
        AccelChoice::Auto,
    );
    let flat = Accel::build(&scene.flattened().shapes, AccelChoice::Flat);
    let o = [0.0f32, 0.0, -1e7];
    let rays: Vec<Ray> = (0..400)
        .map(|i| {
            let (x, y) = (-1.5 + 0.2 * (i % 25) as f32, -1.2 + 0.16 * (i / 25) as f32);
            Ray::new(o, [x, y, 1e7])
        })
        .collect();
    levels::reset();
    levels::count_levels(true);
    let far: Vec<_> = (rays.iter())
        .map(|r| {
            placed
                .closest_hit(r, Method::Adaptive, 0.0, f32::INFINITY)
                .map(|h| h.prim)
        })
        .collect();
    levels::count_levels(false);
    let f64_level = levels::count(Event::F64Intervals);
    assert!(f64_level <= 30 * rays.len() as u64, "{f64_level} f64 tests");
    let hits = far.iter().filter(|h| h.is_some()).count();
    assert!(hits > 150, "{hits} hits");
    for (ray, got) in rays.iter().zip(&far) {
        let want = flat.closest_hit(ray, Method::Adaptive, 0.0, f32::INFINITY);
        assert_eq!(*got, want.map(|h| h.prim), "{ray:?}");
    }

    // Rays one by one from the box's corner, in the planes of three walls: every level but
    // the exact one was unsure of those walls' triangles, and rational t's decided each
    // (~40 µs a ray); one orientation now says the line meets their planes at t = 0 only.
    let cornell = Scene::cornell();
    let accel = Accel::build(&cornell.shapes, AccelChoice::Flat);
    levels::reset();
    levels::count_levels(true);
    let mut hits = 0;
    for i in 0..200 {
        let (a, b) = (i as f32 * 0.37, i as f32 * 0.11);
        let d = [-1.0 - 0.3 * a.sin(), -1.0 - 0.3 * b.cos(), -1.0];
        let ray = Ray::new([1.0, 1.0, 1.0], d);
        hits += accel
            .closest_hit(&ray, Method::Adaptive, 0.0, f32::INFINITY)
            .is_some() as u32;
    }
    levels::count_levels(false);
    assert!(hits > 100, "{hits} hits");
    assert_eq!(levels::count(Event::Exact), 0, "exact decisions");

    // The camera on the box's floor, the light on its ceiling: every packet reaching the
    // floor's (the ceiling's) triangles was left to the per-ray path, and there to exact
    // arithmetic (a frame ~1,000 times slower). Each such triangle is now known, exactly and
    // once a frame, to meet no ray from there; the image is the per-ray path's.
    let mut stage = Stage::from(Scene::cornell());
    stage.restyle(|s| s.light.position = [0.0, -1.0, 0.0]);
    let cam = Camera::from_yaw_pitch(glam::DVec3::new(0.0, 1.0, -0.5), 0.0, 0.3, 64.0).unwrap();
    let packets = RenderSettings {
        width: 64,
        height: 48,
        step: LabStep::Shadows,
        ..Default::default()
    };
    levels::reset();
    levels::count_levels(true);
    let (image, stats) = render_image(&stage, &cam, &packets).unwrap();
    levels::count_levels(false);
    let ambiguous = levels::count(Event::CameraLaneAmbiguous);
    let unsure = levels::count(Event::ShadowLaneUnsure);
    assert!(stats.shadow_rays > 300, "{} shadow rays", stats.shadow_rays);
    assert!(
        ambiguous + unsure <= 64,
        "{ambiguous} camera, {unsure} shadow lanes per ray"
    );
    let per_ray = RenderSettings {
        cracks: true,
        ..packets
    };
    assert!(
        image == render_image(&stage, &cam, &per_ray).unwrap().0,
        "images differ"
    );
}

#[test]
fn rays_passing_far_from_a_tiny_triangle_stay_off_the_exact_level() {
    // A grid of 200 triangles 2·10⁻²⁰ across, 5 away, and rays passing it a unit off: its
    // vertices less a ray's origin agree in every bit f64 holds, so every edge sign was
    // within its rounding and each test went to exact rationals (~100 µs; `raylab trace`'s
    // reference took 49 s for 3,000 rays). The ray plainly misses the triangle's box.
    let _turn = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let s = 1e-21f32;
    let mut shapes = Vec::new();
    for i in -5..5 {
        for j in -5..5 {
            let (x, y) = (2.0 * s * i as f32, 2.0 * s * j as f32);
            let (x1, y1) = (x + 2.0 * s, y + 2.0 * s);
            shapes.push(Shape::from([[x, y, 5.0], [x1, y, 5.0], [x1, y1, 5.0]]));
            shapes.push(Shape::from([[x, y, 5.0], [x1, y1, 5.0], [x, y1, 5.0]]));
        }
    }
    levels::reset();
    levels::count_levels(true);
    for k in 0..50 {
        let a = k as f32 * 0.7;
        let ray = Ray::new([a.cos(), a.sin(), 2.5], [0.1 * a.sin(), 0.2, 1.0]);
        let hit = adaptive::closest_hit_reference(&shapes, &ray, 0.0, f32::INFINITY);
        assert_eq!(hit, None, "{ray:?}");
    }
    levels::count_levels(false);
    assert_eq!(levels::count(Event::Exact), 0, "exact decisions");
    // A ray through the grid's middle vertex still hits it, at t = 5 (a tie of the six
    // triangles there, to the lowest index).
    let ray = Ray::new([0.0, 0.0, 0.0], [0.0, 0.0, 1.0]);
    let hit = adaptive::closest_hit_reference(&shapes, &ray, 0.0, f32::INFINITY).unwrap();
    assert_eq!(
        adaptive::rounded_t(&shapes[hit.prim as usize], &ray, 0.0, f32::INFINITY),
        Some(5.0)
    );
    let tiebreak = (0..shapes.len() as u32).find(|&i| {
        let one = [shapes[i as usize]];
        adaptive::closest_hit_reference(&one, &ray, 0.0, f32::INFINITY).is_some()
    });
    assert_eq!(Some(hit.prim), tiebreak);
}
