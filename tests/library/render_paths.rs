//! The paths of a frame render the same image: tile culling on and off, packets and the
//! per-ray search (flat and BVH, camera and shadow rays, blocks the image cuts), a structure
//! reused from other eyes, copies of triangles left out, power-of-two scales, every SIMD
//! build; and a render cancelled, and the cracks view, say what they did.

use crate::common;

use raylab::geometry::{Shape, Sphere, Triangle};
use raylab::render::{render_image, LabStep, RenderSettings, Stage};
use raylab::{Camera, Scene};

/// The Cornell box with a blue icosphere of `levels` subdivisions (20·4^levels triangles),
/// radius `r`, at `centre`, over the structure `choice`.
fn cornell_with_ball(
    levels: u32,
    r: f32,
    centre: [f32; 3],
    choice: raylab::accel::AccelChoice,
) -> Stage {
    common::cornell_with_blue(common::icosphere(levels, r, centre), choice)
}

#[test]
fn tile_culling_gives_the_same_image_for_a_bvh_mesh() {
    // A 1280-triangle closed mesh (culled per tile for camera rays, BVH for shadow rays).
    let scene = cornell_with_ball(3, 0.8, [0.1, -0.2, 0.3], raylab::accel::AccelChoice::Auto);
    assert_eq!(scene.accel().kind(), raylab::accel::AccelChoice::Bvh);
    assert!(scene.accel().flat_triangles().is_some());
    // A ball of 20,480 triangles: its BVH's top boxes are culled, not its triangles.
    let big = cornell_with_ball(5, 0.8, [0.1, -0.2, 0.3], raylab::accel::AccelChoice::Bvh);
    assert!(big.accel().flat_triangles().is_none());
    // The lab's camera, and one facing away from the scene (all of it behind the pinhole).
    let away = Camera::from_yaw_pitch(Camera::cornell(83).position(), 3.0, 0.1, 83.0).unwrap();
    for (scene, cam) in [&scene, &big]
        .into_iter()
        .flat_map(|s| [(s, Camera::cornell(83)), (s, away)])
    {
        for step in [LabStep::Flat, LabStep::Indirect] {
            let on = RenderSettings {
                width: 83,
                height: 57,
                step,
                ..Default::default()
            };
            let off = RenderSettings {
                tile_culling: false,
                ..on
            };
            assert!(
                render_image(scene, &cam, &on).unwrap().0
                    == render_image(scene, &cam, &off).unwrap().0
            );
        }
    }
}

#[test]
fn tiles_off_a_bvh_meshs_box_are_background_and_the_image_is_unchanged() {
    // A 2560-triangle open cube alone (a BVH, no per-triangle culling): a tile its box cannot
    // show in is filled as background without tracing. Its sides' near edges frame its box's
    // screen rectangle, so hits reach the rectangle's edges; 64 cameras sweep those edges across
    // tile boundaries a quarter pixel at a time. Every tile said to show nothing must have no
    // hit per ray at any sample position; and culling on and off (no projection: every tile
    // traced) must give the same bits and counts, also close up (the box past the image's
    // edges), turned (the box at the edge), behind the camera, and far (a few pixels).
    // Open at the front (z = 0), so the far side shows through: the walk's far start nodes
    // matter too.
    let mesh: Vec<_> = common::cube(16, 1.0, [-0.5, -0.5, 0.0])
        .into_iter()
        .filter(|s| !s.triangle().is_some_and(|v| v.iter().all(|p| p[2] == 0.0)))
        .collect();
    let n = mesh.len();
    let light = raylab::scene::PointLight {
        position: [0.3, -1.5, -1.0],
        power: [5.0; 3],
    };
    let scene = Stage::from(Scene::new(
        "cube",
        mesh,
        vec![[0.2, 0.5, 0.9]; n],
        light,
        [0.1; 3],
    ));
    assert_eq!(scene.accel().kind(), raylab::accel::AccelChoice::Bvh);
    assert!(scene.accel().flat_triangles().is_none());
    let at = |p: [f64; 3], yaw: f64, pitch: f64| {
        Camera::from_yaw_pitch(glam::DVec3::from(p), yaw, pitch, 90.0).unwrap()
    };
    let sweep = (0..64).map(|k| {
        let s = k as f64 / 128.0;
        at([s, (s - 0.25) * 1.4, -2.0], 0.0, 0.0)
    });
    let others = [
        at([0.1, -0.2, -0.6], 0.0, 0.0),
        at([0.1, -0.2, -2.5], 0.45, 0.2),
        at([0.1, -0.2, -2.5], 3.1, 0.0),
        at([0.1, -0.2, -40.0], 0.0, 0.0),
    ];
    let (w, h) = (101, 67);
    let adaptive = raylab::geometry::Method::Adaptive;
    let mut fewest_empty = usize::MAX;
    for (k, cam) in sweep.chain(others).enumerate() {
        let accel = scene.accel();
        let gen = cam.ray_generator(w, h);
        let queries = accel.for_frame(&raylab::accel::FrameSetup {
            eye: gen.origin(),
            light: scene.scene().light.position,
            projection: Some(cam.projection(w, h)),
            method: adaptive,
            camera_rays: (w * h) as usize,
            shadows: false,
            per_ray: false,
        });
        let mut scratch = raylab::accel::TileScratch::default();
        let mut empty = 0;
        let (tw, th) = (raylab::render::TILE, raylab::render::BAND);
        for y0 in (0..h).step_by(th as usize) {
            for x0 in (0..w).step_by(tw as usize) {
                let tile = [x0, y0, (x0 + tw).min(w), (y0 + th).min(h)];
                if !queries.tile(tile, &mut scratch).shows_nothing() {
                    continue;
                }
                empty += 1;
                for j in tile[1]..tile[3] {
                    for i in tile[0]..tile[2] {
                        for (sx, sy) in [
                            (0.5, 0.5),
                            (0.25, 0.25),
                            (0.75, 0.25),
                            (0.25, 0.75),
                            (0.75, 0.75),
                        ] {
                            let ray = gen.ray_through(i as f32 + sx, j as f32 + sy);
                            let hit = accel.closest_hit(&ray, adaptive, 0.0, f32::INFINITY);
                            assert!(
                                hit.is_none(),
                                "camera {k}: ({i}, {j}) hits in an empty tile"
                            );
                        }
                    }
                }
            }
        }
        if k < 64 {
            // The cube covers about 45×45 of 101×67 pixels: most tiles around it are empty.
            fewest_empty = fewest_empty.min(empty);
        }
        if k < 64 && k % 8 != 0 {
            continue;
        }
        for (step, spp, hits) in culling_changes_nothing(&scene, &cam, w, h, k) {
            if k < 64 {
                assert!(hits > 1500 * spp * spp, "camera {k} {step}: {hits} hits");
            }
        }
    }
    let (tw, th) = (raylab::render::TILE, raylab::render::BAND);
    let tiles = w.div_ceil(tw) * h.div_ceil(th);
    assert!(
        fewest_empty * 5 >= tiles as usize * 2,
        "{fewest_empty} empty tiles of {tiles}"
    );
}

#[test]
fn bvh_shadow_packets_render_as_the_per_ray_path() {
    // A 1280-triangle sphere in the Cornell box, traced through the BVH (no tile culling):
    // camera and shadow rays go 8 at a time from the camera and from the light. The cracks
    // view traces every ray per ray (with the adaptive method it marks nothing), so both
    // images must be the same, sphere shadow included.
    let scene = cornell_with_ball(3, 0.4, [0.2, 0.5, 0.1], raylab::accel::AccelChoice::Bvh);
    let cam = Camera::cornell(120);
    for step in [LabStep::Shadows, LabStep::Indirect] {
        let packets = RenderSettings {
            width: 120,
            height: 90,
            step,
            tile_culling: false,
            ..Default::default()
        };
        let (a, _) = common::renders_as_per_ray(&scene, &cam, &packets, &step.to_string());
        // The sphere shadows part of the floor and walls: darker than with direct light only.
        let direct = RenderSettings {
            step: LabStep::Direct,
            ..packets
        };
        let lit = render_image(&scene, &cam, &direct).unwrap().0;
        if step == LabStep::Shadows {
            let shadowed = a
                .chunks_exact(4)
                .zip(lit.chunks_exact(4))
                .filter(|(s, d)| s[..3] != d[..3])
                .count();
            assert!(shadowed > 300, "{shadowed} pixels in shadow");
        }
    }
}

#[test]
fn a_far_lights_frames_render_as_the_per_ray_path() {
    // A light 10⁸ away (a sun) is beyond the reach from which shadow rays start at it
    // (`Scene::shadows_from_light`): they start at the points, one by one. The camera rays
    // still go 8 at a time; every pixel and count must be the per-ray path's (the cracks
    // view's, which marks nothing with the adaptive method), on the box with a sphere (per-tile
    // lists, a shape beside the triangles) and with a 1280-triangle ball (BVH).
    let sphere = Shape::Sphere(Sphere {
        centre: [0.3, -0.6, 0.2],
        radius: 0.3,
    });
    let scenes = [
        common::cornell_with_blue(vec![sphere], raylab::accel::AccelChoice::Auto),
        cornell_with_ball(3, 0.4, [0.2, 0.5, 0.1], raylab::accel::AccelChoice::Bvh),
    ];
    for (k, mut scene) in scenes.into_iter().enumerate() {
        // In front of the box's open side, bright enough to light it from there.
        scene.restyle(|s| {
            s.light.position = [2e7, 3e7, -1e8];
            s.light.power = [1.5e17; 3];
        });
        assert!(!scene.scene().shadows_from_light(), "a far light");
        let cam = Camera::cornell(64);
        for (step, spp) in [(LabStep::Shadows, 1), (LabStep::Indirect, 2)] {
            let packets = RenderSettings {
                width: 64,
                height: 48,
                step,
                spp,
                ..Default::default()
            };
            let at = format!("scene {k} {step} spp {spp}");
            let (a, _) = common::renders_as_per_ray(&scene, &cam, &packets, &at);
            // The ball shadows the walls behind it: some lit points' rays are blocked.
            let direct = RenderSettings {
                step: LabStep::Direct,
                ..packets
            };
            let lit = render_image(&scene, &cam, &direct).unwrap().0;
            let shadowed = (a.chunks_exact(4).zip(lit.chunks_exact(4)))
                .filter(|(s, d)| s[..3] != d[..3])
                .count();
            assert!(
                shadowed > 20,
                "{at}: {shadowed} pixels differ from direct light"
            );
        }
    }
}

#[test]
fn packets_render_as_the_per_ray_path_where_the_image_cuts_their_blocks() {
    // Camera packets trace blocks of 4×2 pixels (4×4 in the AVX-512 build's flat one-sample
    // frame). At 37×23 the right tiles are 5 pixels wide (a block of 4 and one of 1) and the
    // last band is 7 rows high (its last blocks are one row, or three): their other lanes
    // are dead. At 3×1 the one block is 3×1. Every step at 1 and 2²
    // samples must give the per-ray path's bits and counts, on the plain box (per-tile lists;
    // one colour table for the flat frame) and with a 5120-triangle ball (BVH; more
    // triangles than the flat frame's table is made for, so its pixels are encoded one by one).
    let scenes = [
        Stage::from(Scene::cornell()),
        cornell_with_ball(4, 0.5, [0.1, 0.4, 0.0], raylab::accel::AccelChoice::Bvh),
    ];
    for (k, scene) in scenes.iter().enumerate() {
        for (w, h) in [(37, 23), (3, 1)] {
            let cam = Camera::cornell(w);
            for step in LabStep::ALL {
                for spp in [1, 2] {
                    let packets = RenderSettings {
                        width: w,
                        height: h,
                        step,
                        spp,
                        ..Default::default()
                    };
                    let at = format!("scene {k} {w}x{h} {step} spp {spp}");
                    let (_, stats) = common::renders_as_per_ray(scene, &cam, &packets, &at);
                    assert!(stats.hits > 0, "{at}: the box fills the view");
                }
            }
        }
    }
}

#[test]
fn a_bvh_frame_after_frames_from_other_eyes_renders_as_on_a_fresh_structure() {
    // The triangles prepared for the eye and the light are kept from frame to frame (the
    // structure's caches): a frame from another eye and light must be the image and counts a
    // freshly built structure gives, for the mesh traced in packets through the BVH (5120
    // triangles: above the per-tile lists; 8 camera rays a triangle: prepared once a frame).
    let mut scene = cornell_with_ball(4, 0.4, [0.2, 0.5, 0.1], raylab::accel::AccelChoice::Bvh);
    assert!(scene.accel().flat_triangles().is_none());
    let (w, h) = (256, 192);
    let cams = [
        Camera::cornell(w),
        Camera::from_yaw_pitch(glam::DVec3::new(0.3, 0.2, -0.5), 0.8, 0.3, 80.0).unwrap(),
        Camera::from_yaw_pitch(glam::DVec3::new(-0.4, -0.1, 0.6), -2.2, -0.2, 120.0).unwrap(),
    ];
    let setup = raylab::accel::FrameSetup {
        eye: cams[0].ray_generator(w, h).origin(),
        light: scene.scene().light.position,
        projection: None,
        method: raylab::geometry::Method::Adaptive,
        camera_rays: (w * h) as usize,
        shadows: true,
        per_ray: false,
    };
    assert!(scene.accel().for_frame(&setup).prepares_once());
    let settings = RenderSettings {
        width: w,
        height: h,
        step: LabStep::Shadows,
        tile_culling: false,
        ..Default::default()
    };
    let lights = [
        scene.scene().light.position,
        [0.1, 0.9, 0.2],
        [-0.5, 0.3, -0.4],
    ];
    let mut images = Vec::new();
    for (k, cam) in cams.iter().enumerate() {
        scene.restyle(|s| s.light.position = lights[k]);
        let (kept, sk) = render_image(&scene, cam, &settings).unwrap();
        let fresh = Stage::new(scene.scene().clone(), raylab::accel::AccelChoice::Bvh);
        let (new, sn) = render_image(&fresh, cam, &settings).unwrap();
        assert!(kept == new, "camera {k}: images differ");
        assert_eq!((sk.hits, sk.shadow_rays), (sn.hits, sn.shadow_rays));
        assert!(
            sk.hits > 3000 && sk.shadow_rays > 1000,
            "camera {k}: {sk:?}"
        );
        images.push(kept);
    }
    assert!(images[0] != images[1] && images[1] != images[2]);
}

#[test]
fn tile_culling_gives_the_same_image() {
    use std::f64::consts::{FRAC_PI_2, PI};
    // Cameras inside, outside, turned, very wide and with triangles behind the camera.
    let scene = Stage::from(Scene::cornell());
    let cams = [
        Camera::cornell(97),
        Camera::from_yaw_pitch(glam::DVec3::new(0.3, 0.2, -0.5), 0.8, 0.3, 20.0).unwrap(),
        Camera::from_yaw_pitch(glam::DVec3::new(-0.9, 0.9, 0.9), -2.5, -0.7, 60.0).unwrap(),
        Camera::from_yaw_pitch(glam::DVec3::new(0.0, 0.0, -6.0), 0.0, 0.0, 400.0).unwrap(),
        // Facing away (every triangle behind the pinhole), and from a wall's plane along it.
        Camera::from_yaw_pitch(glam::DVec3::new(0.0, 0.0, -3.0), PI, 0.0, 97.0).unwrap(),
        Camera::from_yaw_pitch(glam::DVec3::new(-1.0, 0.0, 0.0), FRAC_PI_2, 0.0, 5.0).unwrap(),
        Camera::from_yaw_pitch(glam::DVec3::new(0.0, 0.0, -1e11), PI, 0.0, 97.0).unwrap(),
    ];
    for (k, cam) in cams.iter().enumerate() {
        culling_changes_nothing(&scene, cam, 97, 61, k);
    }
}

/// Renders `scene` through `cam` (camera number `k`, for the messages) with tile culling on
/// and off, flat and with shadows, at 1 and 2² samples per pixel; asserts the same bits and
/// the same hit and shadow-ray counts. Returns (step, samples per side, camera hits) of each.
fn culling_changes_nothing(
    scene: &Stage,
    cam: &Camera,
    width: u32,
    height: u32,
    k: usize,
) -> Vec<(LabStep, u64, u64)> {
    let mut hits = Vec::new();
    for step in [LabStep::Flat, LabStep::Shadows] {
        for spp in [1, 2] {
            let on = RenderSettings {
                width,
                height,
                step,
                spp,
                ..Default::default()
            };
            let off = RenderSettings {
                tile_culling: false,
                ..on
            };
            let (a, sa) = render_image(scene, cam, &on).unwrap();
            let (b, sb) = render_image(scene, cam, &off).unwrap();
            assert!(a == b, "camera {k} {step} spp {spp}: images differ");
            assert_eq!((sa.hits, sa.shadow_rays), (sb.hits, sb.shadow_rays));
            hits.push((step, spp as u64, sa.hits));
        }
    }
    hits
}

#[test]
fn a_cancelled_render_stops_and_says_so() {
    use std::sync::atomic::{AtomicUsize, Ordering};
    let scene = Stage::from(Scene::cornell());
    let cam = Camera::cornell(64);
    let settings = RenderSettings {
        width: 64,
        height: 64,
        ..Default::default()
    };
    let mut buf = vec![0u8; settings.buffer_len()];
    let polls = AtomicUsize::new(0);
    // Cancelled after the first few bands: no stats, and not every band was drawn.
    let stop_later = || polls.fetch_add(1, Ordering::Relaxed) >= 3;
    let r = raylab::render::render_into_cancellable(&scene, &cam, &settings, &mut buf, &stop_later)
        .unwrap();
    assert!(r.is_none());
    assert!(buf.chunks(4).any(|p| p[3] == 0), "some bands were skipped");
    let r = raylab::render::render_into_cancellable(&scene, &cam, &settings, &mut buf, &|| false)
        .unwrap();
    assert_eq!(r.unwrap().primary_rays, 64 * 64);
}

#[test]
fn a_render_asks_to_stop_before_each_tile_and_stops_within_a_band() {
    use std::sync::atomic::{AtomicU64, Ordering};
    let scene = Stage::from(Scene::cornell());
    // One band of 64 tiles.
    let settings = RenderSettings {
        width: 16 * 64,
        height: 16,
        ..Default::default()
    };
    let cam = Camera::cornell(settings.width);
    let mut buf = vec![0u8; settings.buffer_len()];
    let asks = AtomicU64::new(0);
    let counted = || asks.fetch_add(1, Ordering::Relaxed) == u64::MAX;
    let r = raylab::render::render_into_cancellable(&scene, &cam, &settings, &mut buf, &counted);
    assert!(r.unwrap().is_some());
    let tiles = raylab::render::tiles(settings.width, settings.height);
    assert_eq!(
        (tiles, asks.into_inner()),
        (64, 64 + 1),
        "each tile, then the end"
    );
    // Stopped at the third ask: the band's other 62 tiles are not drawn.
    let mut buf = vec![0u8; settings.buffer_len()];
    let asks = AtomicU64::new(0);
    let third = || asks.fetch_add(1, Ordering::Relaxed) >= 2;
    let r = raylab::render::render_into_cancellable(&scene, &cam, &settings, &mut buf, &third);
    assert!(r.unwrap().is_none());
    let drawn = buf.chunks(4).filter(|p| p[3] == 255).count();
    assert_eq!(drawn, 2 * 16 * 16, "two tiles drawn of the band's 64");
}

#[test]
fn the_cracks_view_marks_exactly_the_leaks() {
    use raylab::geometry::{Method, Shape};
    use raylab::render::{is_crack, linear_to_srgb8, CRACK};
    use raylab::scene::PointLight;
    // A 64x64 camera whose pixel-centre rays meet the plane z = 64 at odd integers (up to the
    // rounding of the normalised direction): the grid's shared vertices and edges sit there.
    let mut shapes = Vec::new();
    for gy in (-65..65).step_by(2) {
        for gx in (-65..65).step_by(2) {
            let p = |x: i32, y: i32| [x as f32, y as f32, 64.0];
            let (a, b, c, d) = (p(gx, gy), p(gx + 2, gy), p(gx, gy + 2), p(gx + 2, gy + 2));
            shapes.push(Shape::from([a, b, d]));
            shapes.push(Shape::from([a, d, c]));
        }
    }
    let n = shapes.len();
    let light = PointLight {
        position: [0.0, 0.0, 0.0],
        power: [1.0; 3],
    };
    let scene = Stage::from(Scene::new(
        "grid",
        shapes,
        vec![[0.5; 3]; n],
        light,
        [0.0; 3],
    ));
    let cam = Camera::from_yaw_pitch(glam::DVec3::ZERO, 0.0, 0.0, 32.0).unwrap();
    let magenta = CRACK.map(linear_to_srgb8);
    let mut total = [0usize; 4];
    for (k, method) in Method::ALL.into_iter().enumerate() {
        let s = RenderSettings {
            width: 64,
            height: 64,
            method,
            cracks: true,
            ..Default::default()
        };
        let (img, _) = render_image(&scene, &cam, &s).unwrap();
        for j in 0..64u32 {
            for i in 0..64u32 {
                let px = &img[4 * (j * 64 + i) as usize..][..3];
                let ray = cam.ray_for_pixel(i, j, 64, 64);
                let crack = is_crack(scene.accel(), &ray, method);
                assert_eq!(px == magenta, crack, "{method} pixel ({i},{j})");
                total[k] += crack as usize;
            }
        }
    }
    println!(
        "cracks on the grid: adaptive {} watertight {} moller {} cramer {}",
        total[0], total[1], total[2], total[3]
    );
    assert_eq!(total[0], 0, "the reference never disagrees with itself");
    assert_eq!(total[1], 0, "watertight never lets a ray through");
    assert!(
        total[2] + total[3] > 0,
        "rays at shared vertices slip through the other methods"
    );
    // At 2×2 samples a pixel, a pixel one of whose samples slips through is marked whole,
    // not a quarter magenta.
    let gen = cam.ray_generator(64, 64);
    let mut partly = 0;
    for method in [Method::Moller, Method::Cramer] {
        let s = RenderSettings {
            width: 64,
            height: 64,
            method,
            cracks: true,
            spp: 2,
            ..Default::default()
        };
        let (img, _) = render_image(&scene, &cam, &s).unwrap();
        for j in 0..64u32 {
            for i in 0..64u32 {
                let px = &img[4 * (j * 64 + i) as usize..][..3];
                let samples = [(0.25, 0.25), (0.75, 0.25), (0.25, 0.75), (0.75, 0.75)];
                let cracked = (samples.iter())
                    .filter(|(x, y)| {
                        let ray = gen.ray_through(i as f32 + x, j as f32 + y);
                        is_crack(scene.accel(), &ray, method)
                    })
                    .count();
                assert_eq!(px == magenta, cracked > 0, "{method} 2x2, pixel ({i},{j})");
                partly += usize::from((1..4).contains(&cracked));
            }
        }
    }
    assert!(partly > 0, "some pixels have cracked and whole samples");
}

#[test]
fn copied_triangles_change_no_pixel() {
    // Every Cornell triangle followed by exact copies, one with -0 for 0 (left out by the
    // structures: the first answers every ray a copy would), and by its vertices turned and
    // reversed (kept: an inexact method may answer differently for them; the exact default
    // method gives the first the tie). Every path draws the plain box's pixels, shadows too.
    let plain = Scene::cornell();
    let mut copied = Scene::cornell();
    copied.shapes.clear();
    copied.colors_mut().clear();
    for (shape, colour) in plain.shapes.iter().zip(plain.colors()) {
        let raylab::geometry::Shape::Triangle(Triangle([a, b, c])) = *shape else {
            unreachable!("the box is triangles")
        };
        let negated_zero = |p: [f32; 3]| p.map(|x| if x == 0.0 { -0.0 } else { x });
        let exact = [a, b, c];
        let signed = exact.map(negated_zero);
        for copy in [exact, exact, signed, [b, c, a], [negated_zero(a), c, b]] {
            copied.shapes.push(raylab::geometry::Shape::from(copy));
            copied.colors_mut().push(*colour);
        }
    }
    let cam = Camera::cornell(96);
    for choice in [
        raylab::accel::AccelChoice::Flat,
        raylab::accel::AccelChoice::Bvh,
    ] {
        let copied = Stage::new(copied.clone(), choice);
        assert_eq!(copied.accel().copies_left_out(), 60);
        assert_eq!(copied.accel().triangle_count(), 90);
        assert!(copied
            .scene()
            .warnings
            .iter()
            .any(|w| w.contains("60 triangles repeat")));
        let plain = Stage::new(plain.clone(), choice);
        assert!(plain.scene().warnings.is_empty());
        for step in LabStep::ALL {
            for tile_culling in [true, false] {
                let settings = RenderSettings {
                    width: 96,
                    height: 72,
                    step,
                    tile_culling,
                    ..Default::default()
                };
                assert!(
                    render_image(&plain, &cam, &settings).unwrap().0
                        == render_image(&copied, &cam, &settings).unwrap().0,
                    "{choice:?} {step:?} culling {tile_culling}"
                );
            }
        }
    }
}

/// A cube of side 2·`scale` (12 triangles) framed as `raylab render` frames a model, with the
/// light placed for its size.
fn framed_cube(scale: f32, w: u32, h: u32) -> (Scene, Camera) {
    let corner =
        |i: usize| [i & 1, (i >> 1) & 1, (i >> 2) & 1].map(|b| (2.0 * b as f32 - 1.0) * scale);
    let quads = [
        [0, 1, 3, 2],
        [4, 6, 7, 5],
        [0, 4, 5, 1],
        [2, 3, 7, 6],
        [0, 2, 6, 4],
        [1, 5, 7, 3],
    ];
    let mut shapes = Vec::new();
    for q in quads {
        let [a, b, c, d] = q.map(corner);
        shapes.push(raylab::geometry::Shape::from([a, b, c]));
        shapes.push(raylab::geometry::Shape::from([a, c, d]));
    }
    let n = shapes.len();
    let dark = raylab::scene::PointLight {
        position: [0.0; 3],
        power: [0.0; 3],
    };
    let mut scene = Scene::new("cube", shapes, vec![[0.75; 3]; n], dark, [0.5; 3]);
    let bounds = scene.bounds().unwrap();
    scene.light = Scene::light_for_bounds(bounds);
    // Turned so three faces show, each lit differently.
    let mut controller = raylab::controller::CameraController::framing(bounds, w, h);
    controller.yaw = 0.5;
    controller.pitch = -0.4;
    let distance = (controller.position - controller.target).length();
    controller.position = controller.target - controller.forward() * distance;
    (scene, controller.camera(w))
}

#[test]
fn a_scene_scaled_by_a_power_of_two_renders_the_same_up_to_the_range_limit() {
    // Scaling the scene, its light and its camera by 2^k is exact in floating point, so every
    // step must draw the same picture at any scale the core accepts. Before faces' normals
    // were rescaled, a cube of side 2e10 rendered black with light (|n|² overflowed f32).
    // (Below 2⁻⁶³ the light's power, scaled by 2^2k, leaves f32's normal range.)
    let (w, h) = (64, 48);
    let (unit, unit_cam) = framed_cube(1.0, w, h);
    let unit = Stage::from(unit);
    for k in [-60, -20, 20, 33, 37] {
        let s = 2f32.powi(k);
        let (scaled, cam) = framed_cube(s, w, h);
        assert!(scaled.check_ranges().is_ok(), "2^{k}");
        let scaled = Stage::from(scaled);
        for step in [LabStep::Flat, LabStep::Shadows, LabStep::Indirect] {
            let settings = RenderSettings {
                width: w,
                height: h,
                step,
                ..Default::default()
            };
            let a = render_image(&unit, &unit_cam, &settings).unwrap().0;
            let b = render_image(&scaled, &cam, &settings).unwrap().0;
            let lit = b.chunks(4).filter(|p| p[0] > 40).count();
            assert!(lit > 500, "2^{k} {step:?}: only {lit} lit pixels");
            let differ = a.chunks(4).zip(b.chunks(4)).filter(|(p, q)| p != q).count();
            assert_eq!(differ, 0, "2^{k} {step:?}: pixels differ");
        }
    }
    // Beyond the range: refused, naming the value.
    let (big, _) = framed_cube(2f32.powi(39), w, h);
    let e = big.check_ranges().unwrap_err();
    assert!(
        e.contains("549755800000") && e.contains("beyond ±2.74877906944e11"),
        "{e}"
    );
}

#[test]
fn every_simd_build_renders_the_same_bytes() {
    // The kernels and the tile loop are compiled for the baseline, AVX2 and AVX-512 and
    // chosen at run time; every build the CPU runs must render the same image, at every lab
    // step, with and without supersampling (the spheres scene: triangles and spheres; the
    // ball: a 5120-triangle BVH, which the AVX-512 build's flat frame walks with 16-ray
    // packets; 97×61 cuts the 4×4 blocks at the right and bottom edges).
    use raylab::math::simd::{self, SimdLevel};
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/scenes/cornell_spheres.scene"
    );
    let spheres = Scene::load(std::path::Path::new(path), Default::default()).unwrap();
    let ball = cornell_with_ball(4, 0.5, [0.1, 0.4, 0.0], raylab::accel::AccelChoice::Bvh);
    let mut compared = 0;
    for (scene, spp) in [
        (Stage::from(Scene::cornell()), 1),
        (Stage::from(Scene::cornell()), 2),
        (Stage::from(spheres), 1),
        (ball, 1),
    ] {
        for step in [
            LabStep::Flat,
            LabStep::Direct,
            LabStep::Shadows,
            LabStep::Indirect,
        ] {
            let settings = RenderSettings {
                width: 97,
                height: 61,
                step,
                spp,
                ..Default::default()
            };
            let render = || {
                render_image(&scene, &Camera::cornell(97), &settings)
                    .unwrap()
                    .0
            };
            let best = render();
            for lower in SimdLevel::ALL.into_iter().filter(|l| *l < simd::detected()) {
                let other = simd::limited(lower, render);
                assert!(best == other, "{lower} build, {step:?}, spp {spp}");
                compared += 1;
            }
        }
    }
    if simd::detected() > SimdLevel::Baseline {
        assert_eq!(compared, 16 * simd::detected() as usize);
    }
}

#[test]
fn coincident_spheres_are_kept_once_and_render_as_one() {
    use raylab::geometry::Shape;
    let sphere = |r: f32| {
        Shape::Sphere(Sphere {
            centre: [0.0, 0.0, 0.0],
            radius: r,
        })
    };
    let light = raylab::scene::PointLight {
        position: [0.0, -3.0, -3.0],
        power: [14.0; 3],
    };
    let one = Stage::from(Scene::new(
        "one",
        vec![sphere(1.0)],
        vec![[0.8, 0.2, 0.2]],
        light,
        [0.1; 3],
    ));
    // The same sphere twice more (another colour: the lower index shows), -0 for 0 in one,
    // and a sphere an ulp larger, which is another sphere and stays.
    let mut shapes = vec![sphere(1.0), sphere(1.0)];
    shapes.push(Shape::Sphere(Sphere {
        centre: [-0.0, 0.0, 0.0],
        radius: 1.0,
    }));
    let colors = vec![[0.8, 0.2, 0.2], [0.1, 0.9, 0.1], [0.1, 0.1, 0.9]];
    let copies = Scene::new("copies", shapes, colors, light, [0.1; 3]);
    let mut other = copies.clone();
    let copies = Stage::from(copies);
    assert_eq!(copies.accel().other_copies_left_out(), 2);
    let warning = copies.accel().copies_warning(copies.scene()).unwrap();
    assert_eq!(copies.scene().warnings, std::slice::from_ref(&warning));
    assert!(
        warning.contains("2 spheres repeat an earlier sphere exactly"),
        "{warning}"
    );
    other.shapes.push(sphere(1.0 + f32::EPSILON));
    other.colors_mut().push([0.5; 3]);
    let other = Stage::from(other);
    assert_eq!(other.accel().other_copies_left_out(), 2);
    let cam = Camera::from_yaw_pitch(glam::DVec3::new(0.0, 0.0, -4.0), 0.0, 0.0, 64.0).unwrap();
    for step in LabStep::ALL {
        let settings = RenderSettings {
            width: 64,
            height: 48,
            step,
            ..Default::default()
        };
        assert!(
            render_image(&one, &cam, &settings).unwrap().0
                == render_image(&copies, &cam, &settings).unwrap().0,
            "{step:?}"
        );
    }
}
