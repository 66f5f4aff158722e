//! Shadow rays never re-hit the surface they leave (no shadow acne), because their origins are
//! offset by the hit point's error bound rather than a fixed epsilon: on a lone convex object
//! nothing can block the light from a lit point, so the shadowed image must equal the unshadowed
//! one pixel for pixel, at grazing light angles and with everything translated by up to 1e5.
//! And a light far from the scene (a sun 10⁸ away) still casts the shadows a near one does.

use glam::DVec3;
use raylab::geometry::{Shape, Sphere};
use raylab::render::{render_image, LabStep, RenderSettings, Stage};
use raylab::scene::PointLight;
use raylab::{Camera, Scene};

/// `scene` through `camera` at 96×72, lab step 3 (direct) and step 4 (shadows), and the
/// shadow rays step 4 cast.
fn direct_and_shadows(scene: &Scene, camera: &Camera) -> (Vec<u8>, Vec<u8>, u64) {
    let settings = |step| RenderSettings {
        width: 96,
        height: 72,
        step,
        ..Default::default()
    };
    let stage = Stage::from(scene.clone());
    let (direct, _) = render_image(&stage, camera, &settings(LabStep::Direct)).unwrap();
    let (shadows, stats) = render_image(&stage, camera, &settings(LabStep::Shadows)).unwrap();
    (direct, shadows, stats.shadow_rays)
}

fn lit_pixels(scene: &Scene, camera: &Camera) -> (usize, usize) {
    let (direct, shadows, shadow_rays) = direct_and_shadows(scene, camera);
    assert!(shadow_rays > 300, "shadow rays were cast: {shadow_rays}");
    let lit = direct.chunks(4).filter(|p| p[..3] != [0, 0, 0]).count();
    let acne = direct.iter().zip(&shadows).filter(|(d, s)| d != s).count();
    (lit, acne)
}

fn floor_scene(offset: [f32; 3], light_height: f32) -> Scene {
    // A 2-triangle floor in y = 0 (y down: "above" is −y), 20 units wide.
    let p = |x: f32, z: f32| [offset[0] + x, offset[1], offset[2] + z];
    let shapes = vec![
        Shape::from([p(-10.0, -10.0), p(10.0, -10.0), p(10.0, 10.0)]),
        Shape::from([p(-10.0, -10.0), p(10.0, 10.0), p(-10.0, 10.0)]),
    ];
    let light = PointLight {
        position: [offset[0] - 30.0, offset[1] - light_height, offset[2]],
        power: [4000.0 / light_height; 3], // the same irradiance at every elevation
    };
    Scene::new("floor", shapes, vec![[0.8; 3]; 2], light, [0.0; 3])
}

#[test]
fn no_acne_on_a_floor_at_grazing_light() {
    for offset in [[0.0f32; 3], [1e4, -1e4, 1e4], [1e5, 1e5, -1e5]] {
        // Light 30 units away sideways at heights giving 1.9° … 0.0019° of elevation.
        for height in [1.0f32, 0.1, 0.01, 0.001] {
            // At 1e5 the f32 spacing is 0.0078: a lower light would sit in the floor's plane.
            let representable = offset[1] - (offset[1] - height);
            if (representable - height).abs() > 0.5 * height {
                continue;
            }
            let scene = floor_scene(offset, height);
            let o = DVec3::new(
                offset[0] as f64,
                offset[1] as f64 - 6.0,
                offset[2] as f64 - 12.0,
            );
            let camera =
                Camera::look_to(o, DVec3::new(0.0, 6.0, 12.0), DVec3::NEG_Y, 96.0).unwrap();
            let (lit, acne) = lit_pixels(&scene, &camera);
            assert!(
                lit > 2000,
                "offset {offset:?} height {height}: only {lit} lit pixels"
            );
            assert_eq!(acne, 0, "offset {offset:?} height {height}: {acne} channel values darkened by self-shadowing");
        }
    }
}

#[test]
fn no_acne_on_a_sphere() {
    for offset in [0.0f32, 1e3, 1e5] {
        for radius in [1.0f32, 100.0] {
            let c = [offset, -offset, offset];
            let scene = Scene::new(
                "sphere",
                vec![Shape::Sphere(Sphere { centre: c, radius })],
                vec![[0.8; 3]],
                // Light off to the side: half the visible sphere is lit, with a grazing terminator.
                PointLight {
                    position: [c[0] + 3.0 * radius, c[1], c[2]],
                    power: [400.0 * radius * radius; 3],
                },
                [0.0; 3],
            );
            let eye = DVec3::new(c[0] as f64, c[1] as f64, (c[2] - 4.0 * radius) as f64);
            let camera = Camera::look_to(eye, DVec3::Z, DVec3::NEG_Y, 96.0).unwrap();
            let (lit, acne) = lit_pixels(&scene, &camera);
            assert!(
                lit > 300,
                "offset {offset} radius {radius}: {lit} lit pixels"
            );
            assert_eq!(acne, 0, "offset {offset} radius {radius}: self-shadowing");
        }
    }
}

#[test]
fn no_acne_in_the_cornell_box_with_a_grazing_light() {
    // The lab light moved down to 1e-3 above the floor (y = 1): every floor point sees it at a
    // grazing angle. Shadows may only darken pixels whose shadow ray really meets a block or
    // wall, which the Cornell geometry puts nowhere near the floor's own plane; compare against
    // the same render with the floor triangles removed from the shadow test's reach by
    // checking that each darkened floor pixel's shadow ray is blocked by a non-floor primitive.
    let mut scene = Scene::cornell();
    scene.light.position = [0.0, 1.0 - 1e-3, -0.2];
    let camera = Camera::cornell(96);
    let (direct, shadows, _) = direct_and_shadows(&scene, &camera);
    // Floor-only scene: the same view with nothing but the floor (triangles 0 and 1).
    let floor = Scene::new(
        "floor",
        scene.shapes[..2].to_vec(),
        scene.colors()[..2].to_vec(),
        scene.light,
        [0.0; 3],
    );
    let (floor_direct, floor_shadows, _) = direct_and_shadows(&floor, &camera);
    assert_eq!(
        floor_direct, floor_shadows,
        "the floor alone never shadows itself"
    );
    let lit_floor = floor_direct.chunks(4).filter(|p| p[1] > 0).count();
    assert!(lit_floor > 500, "{lit_floor}");
    assert!(
        direct.iter().zip(&shadows).any(|(d, s)| s < d),
        "the blocks do cast shadows"
    );
}

/// A floor in y = 0 with a ball of radius 1 resting on it at the origin, lit from straight
/// above at `height` (y down: above is −y), with the same irradiance at every height.
fn ball_on_a_floor(height: f32) -> Scene {
    let mut scene = floor_scene([0.0; 3], 1.0);
    scene.shapes.push(Shape::Sphere(Sphere {
        centre: [0.0, -1.0, 0.0],
        radius: 1.0,
    }));
    scene.colors_mut().push([0.8; 3]);
    scene.light = PointLight {
        position: [0.0, -height, 0.0],
        power: [40.0 * height * height; 3],
    };
    scene
}

/// The floor pixels the ball shadows (darker with shadows than without), and the shadow rays.
fn shadowed_pixels(scene: &Scene) -> (usize, u64) {
    let camera = Camera::look_to(
        DVec3::new(0.0, -6.0, -8.0),
        DVec3::new(0.0, 6.0, 8.0),
        DVec3::NEG_Y,
        96.0,
    )
    .unwrap();
    let (direct, shadows, shadow_rays) = direct_and_shadows(scene, &camera);
    let dark = (direct.chunks(4).zip(shadows.chunks(4)))
        .filter(|(d, s)| s[..3] != d[..3])
        .count();
    (dark, shadow_rays)
}

#[test]
fn a_far_light_still_casts_the_shadow_under_a_ball() {
    // From 10 units up the shadow is a disc a little wider than the ball; from a sun-like
    // 10⁸ it is the ball's own disc. A shadow ray from the light would end 2⁻²²·10⁸ ≈ 24
    // units short of the floor and miss the ball: the far light's rays start at the floor.
    let near = ball_on_a_floor(10.0);
    assert!(near.shadows_from_light());
    let (near_dark, _) = shadowed_pixels(&near);
    assert!(
        near_dark > 100,
        "{near_dark} shadowed pixels with the light 10 up"
    );
    for height in [1e4f32, 1e6, 1e8, 1e11] {
        let scene = ball_on_a_floor(height);
        let (dark, rays) = shadowed_pixels(&scene);
        assert!(rays > 3000, "light {height:e} up: {rays} shadow rays");
        assert!(
            dark as f64 > 0.7 * near_dark as f64 && dark <= near_dark,
            "light {height:e} up: {dark} shadowed pixels, {near_dark} with the light 10 up"
        );
    }
}

#[test]
fn shadow_rays_start_at_the_light_within_1024_scene_sizes() {
    // The box of the ball on the floor: x and z in ±10, y in [−2, 0]; its longest side 20.
    let mut scene = ball_on_a_floor(10.0);
    assert!(scene.shadows_from_light());
    for (x, from_light) in [
        (10.0 + 1024.0 * 20.0, true),
        (10.0 + 1025.0 * 20.0, false),
        (-10.0 - 1024.0 * 20.0, true),
        (-10.0 - 1025.0 * 20.0, false),
    ] {
        scene.light.position = [x, -1.0, 0.0];
        assert_eq!(scene.shadows_from_light(), from_light, "light at x = {x}");
    }
}
