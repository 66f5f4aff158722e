//! The pinhole camera: pixel centres, focal length, field of view, pose.

use glam::{DVec3, Vec3};
use raylab::camera::CameraError;
use raylab::Camera;

fn dir(c: &Camera, i: u32, j: u32, w: u32, h: u32) -> DVec3 {
    DVec3::from_array(c.ray_for_pixel(i, j, w, h).d.map(f64::from))
}

#[test]
fn lab_camera_pose() {
    let c = Camera::cornell(640);
    assert_eq!(c.position(), DVec3::new(0.0, 0.0, -3.001));
    assert_eq!(c.forward(), DVec3::Z);
    assert_eq!(c.right(), DVec3::X);
    assert_eq!(c.down(), DVec3::Y);
    assert_eq!(c.focal, 640.0);
    let r = c.ray_for_pixel(0, 0, 640, 480);
    assert_eq!(r.o, [0.0, 0.0, -3.001f32]);
}

#[test]
fn rays_pass_through_pixel_centres() {
    let (w, h) = (640u32, 480u32);
    let c = Camera::cornell(w);
    for (i, j) in [(0, 0), (639, 479), (320, 240), (17, 401)] {
        let expected = Vec3::new(i as f32 - 320.0 + 0.5, j as f32 - 240.0 + 0.5, 640.0).normalize();
        let d = Vec3::from_array(c.ray_for_pixel(i, j, w, h).d);
        assert!(
            (d - expected).length() < 1e-6,
            "pixel ({i},{j}): {d} vs {expected}"
        );
        assert!((d.length() - 1.0).abs() < 1e-6);
    }
    // The two centre pixels of an even image are mirror images: the optical axis lies between.
    let a = dir(&c, 319, 239, w, h);
    let b = dir(&c, 320, 240, w, h);
    assert!((a.x + b.x).abs() < 1e-7 && (a.y + b.y).abs() < 1e-7 && (a.z - b.z).abs() < 1e-7);
}

#[test]
fn fov_is_derived_from_focal_and_width() {
    let c = Camera::cornell(500);
    let fov = c.fov_x(500);
    assert!((fov - 2.0 * 0.5f64.atan()).abs() < 1e-15);
    assert!((fov.to_degrees() - 53.130_102_354).abs() < 1e-8);
    // Same focal, twice the width: wider view. Focal for a given fov round-trips.
    assert!(c.fov_x(1000) > fov);
    let f = Camera::focal_for_fov(fov, 500);
    assert!((f - 500.0).abs() < 1e-9);
    // The edge pixel's ray makes (almost) half the fov with the axis.
    let edge = c.ray_through(0.0, 250.0, 500, 500);
    let angle = (edge.d[2] as f64).acos();
    assert!((angle - fov / 2.0).abs() < 1e-6);
}

#[test]
fn a_camera_ray_projects_onto_its_own_pixel_from_where_the_rays_leave() {
    // 10¹² + 12345 rounds to f32 4096 units from the pinhole: from the pinhole a ray's points
    // near the eye project far from its pixel (the window drew a line to the image's centre);
    // from where the rays leave, every point of the ray lands on its pixel.
    let (w, h) = (320u32, 240u32);
    for (position, yaw) in [
        (DVec3::new(1e12 + 12345.0, 0.3, -2.0), -1.3),
        (DVec3::new(0.0, 0.0, -1e9), 0.0),
    ] {
        let c = Camera::from_yaw_pitch(position, yaw, 0.2, 300.0).unwrap();
        let (from_rays, from_pinhole) = (c.ray_projection(w, h), c.projection(w, h));
        let (x, y) = (250.5, 40.5);
        let ray = c.ray_through(x, y, w, h);
        let mut pinhole_off = 0.0f64;
        for t in [20.0, 1e3, 1e6, 1e9] {
            let p = [0, 1, 2].map(|k| f64::from(ray.o[k]) + t * f64::from(ray.d[k]));
            let q = from_rays.project_f64(p).unwrap();
            assert!(
                (q[0] - x).abs() < 1e-3 && (q[1] - y).abs() < 1e-3,
                "{t}: {q:?}"
            );
            if let Some(q) = from_pinhole.project_f64(p) {
                pinhole_off = pinhole_off.max((q[0] - x).abs() + (q[1] - y).abs());
            }
        }
        if position.x != 0.0 {
            assert!(pinhole_off > 10.0, "from the pinhole: {pinhole_off} px");
        }
    }
}

#[test]
fn behind_the_pinhole_is_where_no_camera_ray_reaches() {
    // Facing +z from the origin: behind means z < 0 by more than 2⁻¹⁶ of the distance.
    let c = Camera::from_yaw_pitch(DVec3::ZERO, 0.0, 0.0, 100.0).unwrap();
    let p = c.projection(200, 100);
    assert!(p.behind([0.0, 0.0, -1.0]));
    assert!(!p.behind([0.0, 0.0, 1.0]));
    assert!(!p.behind([5.0, 0.0, -1e-6]), "within the margin");
    assert!(p.behind([5.0, 0.0, -1e-3]));
    // The rays leave from the position rounded to f32: 2³⁹ + 20000 rounds to 2³⁹, 20000
    // behind the pinhole, where a ray may meet a point 20000 behind the pinhole; one an f32
    // step further (32768 there) is out of reach.
    let z = 2f64.powi(39) + 20000.0;
    let far = Camera::from_yaw_pitch(DVec3::new(0.0, 0.0, z), 0.0, 0.0, 100.0).unwrap();
    let eye = far.ray_through(100.0, 50.0, 200, 100).o[2];
    assert_eq!(eye, 2f32.powi(39));
    let p = far.projection(200, 100);
    assert!(!p.behind([0.0, 0.0, eye]));
    assert!(p.behind([0.0, 0.0, eye - 32768.0]));
    // A field of view within 10⁻⁴° of 180°: the rays' forward part is lost in rounding.
    let wide = Camera::from_yaw_pitch(DVec3::ZERO, 0.0, 0.0, 1e-3).unwrap();
    assert!(!wide.projection(1280, 720).behind([0.0, 0.0, -1.0]));
}

#[test]
fn projecting_a_world_point_lands_on_the_pixel_whose_ray_passes_through_it() {
    let c = Camera::from_yaw_pitch(DVec3::new(0.3, -0.2, -2.5), 0.2, -0.1, 400.0).unwrap();
    let (w, h) = (320u32, 240u32);
    for p in [
        DVec3::new(0.1, 0.2, 0.5),
        DVec3::new(-0.6, 0.4, 0.9),
        DVec3::new(0.5, -0.7, -0.3),
    ] {
        let q = c.camera_from_world().transform_point3(p);
        assert!(q.z > 0.0);
        let x = c.focal * q.x / q.z + w as f64 / 2.0;
        let y = c.focal * q.y / q.z + h as f64 / 2.0;
        let ray = c.ray_through(x, y, w, h);
        let o = DVec3::from_array(ray.o.map(f64::from));
        let d = DVec3::from_array(ray.d.map(f64::from));
        // The angle between the ray and the point, to f32 precision of the direction.
        let sin = (p - o).normalize().cross(d.normalize()).length();
        assert!(sin < 1e-6, "{p}: angle {sin}");
    }
}

#[test]
fn yaw_turns_right_pitch_turns_up() {
    let right = Camera::from_yaw_pitch(DVec3::ZERO, 90f64.to_radians(), 0.0, 100.0).unwrap();
    assert!((right.forward() - DVec3::X).length() < 1e-15);
    let up = Camera::from_yaw_pitch(DVec3::ZERO, 0.0, 90f64.to_radians(), 100.0).unwrap();
    assert!((up.forward() - DVec3::NEG_Y).length() < 1e-15, "up is -y");
}

#[test]
fn look_to_matches_yaw_pitch() {
    let a = Camera::from_yaw_pitch(DVec3::new(1.0, 2.0, 3.0), 0.4, 0.25, 300.0).unwrap();
    let b = Camera::look_to(DVec3::new(1.0, 2.0, 3.0), a.forward(), DVec3::NEG_Y, 300.0).unwrap();
    let diff = (a.world_from_camera() - b.world_from_camera())
        .to_cols_array()
        .iter()
        .fold(0.0f64, |m, x| m.max(x.abs()));
    assert!(diff < 1e-14, "{diff}");
}

#[test]
fn bad_cameras_are_errors() {
    for f in [0.0, -1.0, f64::NAN, f64::INFINITY, 1e300] {
        assert!(matches!(
            Camera::from_yaw_pitch(DVec3::ZERO, 0.0, 0.0, f),
            Err(CameraError::Focal(_))
        ));
    }
    assert!(Camera::from_yaw_pitch(DVec3::new(f64::NAN, 0.0, 0.0), 0.0, 0.0, 1.0).is_err());
    assert!(
        Camera::look_to(DVec3::ZERO, DVec3::Y, DVec3::NEG_Y, 1.0).is_err(),
        "parallel"
    );
    assert!(
        Camera::look_to(DVec3::ZERO, DVec3::ZERO, DVec3::NEG_Y, 1.0).is_err(),
        "zero view"
    );
}

#[test]
fn every_direction_stays_within_the_generators_component_bound() {
    // The packet kernels take the generator's bound as max|dₖ| instead of reducing each
    // packet: it must hold for every pixel of every pose and focal length, and stay close to 1
    // (a loose bound widens the kernels' unsure band).
    let mut worst: f32 = 0.0;
    for k in 0..40 {
        let yaw = k as f64 * 0.7 - 10.0;
        let pitch = (k as f64 * 0.37).sin() * 1.5;
        for focal in [1e-3, 0.7, 64.0, 1e9] {
            let c = Camera::from_yaw_pitch(DVec3::new(0.1, -0.2, 0.3), yaw, pitch, focal).unwrap();
            let (w, h) = (33, 21);
            let gen = c.ray_generator(w, h);
            let bound = gen.component_bound();
            assert!(bound > 0.999 && bound < 1.00002, "bound {bound}");
            for j in 0..h {
                for i in 0..w {
                    for (sx, sy) in [(0.5, 0.5), (0.0, 0.0), (1.0, 1.0)] {
                        let d = gen.ray_through(i as f32 + sx, j as f32 + sy).d;
                        let m = d.iter().fold(0f32, |m, c| m.max(c.abs()));
                        assert!(m <= bound, "camera {k} focal {focal}: {d:?} beyond {bound}");
                        worst = worst.max(m / bound);
                    }
                }
            }
        }
    }
    // Some direction comes near the bound (it is not loose by more than the margin).
    assert!(worst > 0.9999, "{worst}");
}

#[test]
fn an_angle_that_is_not_finite_is_named() {
    // It said `got [0, inf, 0]`: three numbers for two angles.
    let at = glam::DVec3::new(0.0, 0.0, -3.0);
    for (yaw, pitch, said) in [
        (0.0, f64::INFINITY, "pitch inf"),
        (f64::NAN, 0.0, "yaw NaN"),
    ] {
        let e = raylab::Camera::from_yaw_pitch(at, yaw, pitch, 640.0).unwrap_err();
        assert_eq!(
            e.to_string(),
            format!("camera yaw/pitch must be finite, got {said}")
        );
    }
    // In degrees, as `--yaw inf` gives it, still the angle given (`inf % 360` is NaN).
    let radians = raylab::math::radians_of_degrees;
    let e =
        raylab::Camera::from_yaw_pitch(at, radians(f64::INFINITY), radians(-f64::INFINITY), 640.0);
    let said = e.unwrap_err().to_string();
    assert_eq!(said, "camera yaw/pitch must be finite, got yaw inf");
    assert_eq!(radians(720.5), 0.5f64.to_radians());
}
