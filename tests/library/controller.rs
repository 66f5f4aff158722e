//! The fly-camera controller: moves through the transform stack, frame-rate independent.

use glam::DVec3;
use raylab::controller::{CameraController, ControlInput, MAX_PITCH};

fn input(f: impl FnOnce(&mut ControlInput)) -> ControlInput {
    let mut i = ControlInput::default();
    f(&mut i);
    i
}

#[test]
fn forward_moves_along_the_view_at_half_the_scene_per_second() {
    let mut c = CameraController::cornell();
    let start = c.position;
    assert!(c.update(&input(|i| i.forward = 1.0), 0.2));
    let moved = c.position - start;
    assert!(
        (moved - DVec3::Z * 0.5 * c.scene_size * 0.2).length() < 1e-12,
        "{moved}"
    );
    // Shift is 4x.
    let mut fast = CameraController::cornell();
    fast.update(
        &input(|i| {
            i.forward = 1.0;
            i.fast = true;
        }),
        0.2,
    );
    assert!(((fast.position - start).length() - 4.0 * moved.length()).abs() < 1e-12);
}

#[test]
fn motion_does_not_depend_on_the_frame_rate() {
    let held = input(|i| {
        i.forward = 1.0;
        i.right = -1.0;
        i.up = 1.0;
        i.yaw = 1.0;
        i.pitch = -1.0;
    });
    let mut a = CameraController::cornell();
    let mut b = CameraController::cornell();
    for _ in 0..10 {
        a.update(&held, 0.01);
    }
    b.update(&held, 0.1);
    assert!((a.yaw - b.yaw).abs() < 1e-12 && (a.pitch - b.pitch).abs() < 1e-12);
    // Positions differ only by the path's curvature: at most distance × total turn.
    let distance = (b.position - CameraController::cornell().position).length();
    let bound = distance * (b.yaw.abs() + b.pitch.abs());
    assert!(
        (a.position - b.position).length() <= bound,
        "{} vs {}",
        a.position,
        b.position
    );
}

#[test]
fn strafe_and_up_follow_the_frame() {
    // Scene size 8: a 0.25 s step (the longest frame counted) moves 1 unit.
    let mut c = CameraController::new(DVec3::ZERO, 90f64.to_radians(), 0.0, 1.0, 8.0);
    c.update(&input(|i| i.forward = 1.0), 0.25);
    assert!(
        (c.position - DVec3::X).length() < 1e-12,
        "yawed 90°: forward is +x, {}",
        c.position
    );
    c.update(&input(|i| i.right = 1.0), 0.25);
    assert!(
        (c.position - DVec3::new(1.0, 0.0, -1.0)).length() < 1e-12,
        "right is -z: {}",
        c.position
    );
    c.update(&input(|i| i.up = 1.0), 0.25);
    assert!(
        (c.position - DVec3::new(1.0, -1.0, -1.0)).length() < 1e-12,
        "up is -y: {}",
        c.position
    );
}

#[test]
fn turning_mouse_and_pitch_limit() {
    let mut c = CameraController::cornell();
    c.update(&input(|i| i.yaw = 1.0), 0.25);
    assert!((c.yaw - 0.25 * CameraController::TURN_RATE).abs() < 1e-12);
    c.update(&input(|i| i.mouse = (-100.0, -50.0)), 0.0);
    assert!((c.yaw - (0.25 * CameraController::TURN_RATE - 0.3)).abs() < 1e-12);
    // A stalled frame (a 5 s hitch) counts as 0.25 s, not a leap across the scene.
    let mut d = CameraController::cornell();
    d.update(&input(|i| i.forward = 1.0), 5.0);
    assert!((d.position.z - (-3.001 + 0.5 * d.scene_size * 0.25)).abs() < 1e-12);
    assert!((c.pitch - 0.15).abs() < 1e-12, "mouse up looks up");
    for _ in 0..10 {
        c.update(&input(|i| i.pitch = 1.0), 0.25);
    }
    assert_eq!(c.pitch, MAX_PITCH, "pitch stops short of the pole");
    assert!(c.camera(100).forward().y < 0.0, "looking up is -y");
}

#[test]
fn wheel_zooms_and_reset_returns_home() {
    let mut c = CameraController::cornell();
    assert_eq!(c.focal(640), 640.0);
    c.update(&input(|i| i.wheel = 2.0), 0.016);
    assert!(
        (c.focal(640) - 640.0 * 1.21).abs() < 1e-9,
        "wheel up zooms in"
    );
    assert!(c.camera(640).fov_x(640) < 2.0 * 0.5f64.atan());
    c.update(&input(|i| i.wheel = -1e6), 0.016);
    assert_eq!(
        c.focal_ratio,
        raylab::controller::FOCAL_RATIO_RANGE.0,
        "clamped"
    );
    c.update(&input(|i| i.forward = 1.0), 0.3);
    c.reset();
    assert_eq!(c, CameraController::cornell());
    // Nothing held: nothing changes.
    assert!(!c.update(&ControlInput::default(), 0.1));
    // A NaN frame time does not poison the pose.
    c.update(&input(|i| i.forward = 1.0), f64::NAN);
    assert_eq!(c.position, CameraController::cornell().position);
}

#[test]
fn the_camera_is_built_on_the_transform_stack() {
    let c = CameraController::new(DVec3::new(0.5, -0.25, -2.0), 0.3, -0.2, 1.5, 3.0);
    let cam = c.camera(400);
    assert_eq!(cam.world_from_camera(), c.stack().matrix());
    assert_eq!(cam.focal, 600.0);
}

#[test]
fn framing_puts_the_model_in_view() {
    let bounds = ([-2.0, 10.0, 4.0], [6.0, 12.0, 8.0]);
    let c = CameraController::framing(bounds, 640, 480);
    let cam = c.camera(640);
    // The bounding box's corners all project inside the image.
    for corner in 0..8 {
        let p = DVec3::new(
            if corner & 1 == 0 { -2.0 } else { 6.0 },
            if corner & 2 == 0 { 10.0 } else { 12.0 },
            if corner & 4 == 0 { 4.0 } else { 8.0 },
        );
        let q = cam.camera_from_world().transform_point3(p);
        assert!(q.z > 0.0);
        let (x, y) = (cam.focal * q.x / q.z, cam.focal * q.y / q.z);
        assert!(
            x.abs() <= 320.0 && y.abs() <= 240.0,
            "corner {p} at ({x}, {y})"
        );
    }
}

#[test]
fn orbit_turns_around_the_target_pans_with_it_and_dollies() {
    use raylab::controller::Mode;
    let mut c = CameraController::cornell();
    let dt = 1.0 / 60.0;
    // Entering orbit: the target on the view axis at its distance (the box centre here).
    c.toggle_mode();
    assert_eq!(c.mode, Mode::Orbit);
    assert!(c.target.length() < 1e-12, "target {:?}", c.target);
    let dist = |c: &CameraController| (c.position - c.target).length();
    let d0 = dist(&c);
    // A drag turns around the target: same distance, still looking at it.
    let drag = ControlInput {
        orbit: (120.0, -40.0),
        ..Default::default()
    };
    assert!(c.update(&drag, dt));
    assert!((dist(&c) - d0).abs() < 1e-12 * d0);
    let towards = (c.target - c.position).normalize();
    assert!((c.forward() - towards).length() < 1e-12);
    assert!((c.yaw - 120.0 * CameraController::ORBIT_SENSITIVITY).abs() < 1e-12);
    // A pan moves target and camera together.
    let (p, t) = (c.position, c.target);
    let pan = ControlInput {
        pan: (30.0, 10.0),
        ..Default::default()
    };
    assert!(c.update(&pan, dt));
    assert!(((c.position - p) - (c.target - t)).length() < 1e-12);
    assert!((c.target - t).length() > 0.01);
    // The wheel dollies: 10% nearer per line, never through the target.
    let d1 = dist(&c);
    let wheel = ControlInput {
        wheel: 1.0,
        ..Default::default()
    };
    assert!(c.update(&wheel, dt));
    assert!((dist(&c) - 0.9 * d1).abs() < 1e-12);
    let far_in = ControlInput {
        wheel: 1000.0,
        ..Default::default()
    };
    c.update(&far_in, dt);
    assert!(dist(&c) > 0.0 && c.position.is_finite());
    // R after the pan and dolly: the start, which the next frame keeps (the panned target
    // had pulled the camera aside again), and the box centre the target.
    c.reset();
    c.update(&ControlInput::default(), dt);
    let start = CameraController::cornell();
    assert_eq!((c.position, c.yaw, c.pitch), (start.position, 0.0, 0.0));
    assert!(c.target.length() < 1e-12, "target {:?}", c.target);
    // Back to fly: the wheel is the focal length again.
    c.toggle_mode();
    let f = c.focal_ratio;
    c.update(&wheel, dt);
    assert!(c.focal_ratio > f);
}

#[test]
fn speed_and_the_slow_key_scale_moves() {
    let dt = 0.1;
    let forward = ControlInput {
        forward: 1.0,
        ..Default::default()
    };
    let moved = |speed: f64, slow: bool| {
        let mut c = CameraController::cornell();
        c.scale_speed(speed);
        let start = c.position;
        c.update(&ControlInput { slow, ..forward }, dt);
        (c.position - start).length()
    };
    let one = moved(1.0, false);
    assert!((moved(2.0, false) - 2.0 * one).abs() < 1e-12);
    assert!((moved(1.0, true) - 0.25 * one).abs() < 1e-12);
    let mut c = CameraController::cornell();
    c.scale_speed(1e9);
    assert_eq!(c.speed, CameraController::SPEED_RANGE.1);
}

#[test]
fn flying_and_framing_stay_within_the_cameras_range() {
    // Flying on at full speed from near the edge of the camera's range stops at it (the
    // camera is always one the renderer can take), and framing a scene at the edge of the
    // scene range places the camera within range.
    let max = raylab::math::MAX_VIEW_COORDINATE;
    let size = raylab::math::MAX_SCENE_COORDINATE;
    let mut c = CameraController::new(DVec3::new(0.0, 0.0, 0.9 * max), 0.0, 0.0, 1.0, size);
    c.scale_speed(64.0);
    for _ in 0..100 {
        c.update(
            &input(|i| {
                i.forward = 1.0;
                i.fast = true;
            }),
            0.25,
        );
    }
    assert!(
        c.position.z <= max && c.position.z >= 0.9 * max,
        "{}",
        c.position
    );
    let _ = c.camera(640); // (built without panicking: in range)
    let lo = [-size as f32; 3];
    let hi = [size as f32; 3];
    for (w, h) in [(640, 480), (1000, 10)] {
        let c = CameraController::framing((lo, hi), w, h);
        assert!(c.position.abs().max_element() <= max, "{}", c.position);
        let _ = c.camera(w);
    }
}

#[test]
fn input_no_pose_can_hold_is_ignored_and_the_camera_still_builds() {
    let huge = [f64::INFINITY, f64::NEG_INFINITY, f64::NAN, f64::MAX, 1e308];
    for mode_orbit in [false, true] {
        for &x in &huge {
            let mut c = CameraController::cornell();
            if mode_orbit {
                c.toggle_mode();
            }
            let start = (c.position, c.yaw, c.pitch, c.focal_ratio);
            for _ in 0..2 {
                c.update(&input(|i| i.mouse = (x, x)), 0.1);
                c.update(&input(|i| i.orbit = (x, -x)), 0.1);
                c.update(&input(|i| i.pan = (x, x)), 0.1);
                c.update(&input(|i| i.wheel = x), 0.1);
                c.update(&input(|i| i.yaw = x), 0.1);
            }
            assert!(
                c.yaw.is_finite() && c.pitch.is_finite(),
                "{x}: {} {}",
                c.yaw,
                c.pitch
            );
            assert!(c.position.is_finite() && c.focal_ratio.is_finite(), "{x}");
            // A finite turn that is merely large is taken (the yaw wraps); nothing else moved.
            if !x.is_finite() {
                assert!(
                    (c.position - start.0).length() < 1e-9,
                    "{x}: {}",
                    c.position
                );
                assert_eq!(
                    (c.yaw, c.pitch, c.focal_ratio),
                    (start.1, start.2, start.3),
                    "{x}"
                );
            }
            let _ = c.camera(640);
        }
    }
}
