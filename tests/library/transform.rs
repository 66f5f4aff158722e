//! The transform stack: order, inverses, points vs directions vs normals.

use glam::{DMat3, DMat4, DVec3, DVec4};
use proptest::prelude::*;
use raylab::math::{rotation_x, rotation_xyz, rotation_y, rotation_z, TransformStack};

/// inverse·M = I holds to this max-abs-entry tolerance for the translations (|t| ≤ 1e3),
/// angles and scales (0.1..10) used here: a few ulps of the largest entry.
const INV_TOL: f64 = 1e-11;

fn max_abs_diff(a: DMat4, b: DMat4) -> f64 {
    (a - b)
        .to_cols_array()
        .iter()
        .fold(0.0f64, |m, x| m.max(x.abs()))
}

#[test]
fn push_pop_restores_exactly() {
    let mut s = TransformStack::new();
    s.translate(DVec3::new(1.5, -2.0, 3.25)).rotate_y(0.3);
    let before = (s.matrix(), s.inverse());
    s.push();
    s.rotate_x(1.1)
        .scale(DVec3::new(2.0, 3.0, 0.5))
        .translate(DVec3::splat(7.0));
    assert_ne!(s.matrix(), before.0);
    assert_eq!(s.depth(), 1);
    assert!(s.pop());
    assert_eq!(
        (s.matrix(), s.inverse()),
        before,
        "pop must restore bit for bit"
    );
    assert!(!s.pop(), "popping the base is refused");
    assert_eq!(s.matrix(), before.0);
}

#[test]
fn lecture_rotation_matrices() {
    let a = 0.7f64;
    let (s, c) = a.sin_cos();
    // Rows as the lecture writes them.
    let rx = DMat3::from_cols_array(&[1.0, 0.0, 0.0, 0.0, c, s, 0.0, -s, c]);
    let ry = DMat3::from_cols_array(&[c, 0.0, -s, 0.0, 1.0, 0.0, s, 0.0, c]);
    let rz = DMat3::from_cols_array(&[c, s, 0.0, -s, c, 0.0, 0.0, 0.0, 1.0]);
    assert_eq!(DMat3::from_mat4(rotation_x(a)), rx);
    assert_eq!(DMat3::from_mat4(rotation_y(a)), ry);
    assert_eq!(DMat3::from_mat4(rotation_z(a)), rz);
    // Positive yaw turns +z towards +x (right); positive pitch turns +z towards -y (up).
    let yawed = rotation_y(0.1).transform_vector3(DVec3::Z);
    assert!(yawed.x > 0.0);
    let pitched = rotation_x(0.1).transform_vector3(DVec3::Z);
    assert!(pitched.y < 0.0);
}

#[test]
fn composite_rotation_is_rz_ry_rx() {
    let angles = DVec3::new(0.3, -1.2, 2.5);
    let expected = rotation_z(angles.z) * rotation_y(angles.y) * rotation_x(angles.x);
    assert_eq!(rotation_xyz(angles), expected);
    // And it is not the other order (so the documented order is really what is tested).
    let other = rotation_x(angles.x) * rotation_y(angles.y) * rotation_z(angles.z);
    assert!(max_abs_diff(rotation_xyz(angles), other) > 0.1);
    // x is applied first: a point on the x axis rotated by Rx alone stays put.
    let p = rotation_xyz(DVec3::new(1.0, 0.0, 0.0)).transform_point3(DVec3::X);
    assert_eq!(p, DVec3::X);
    let mut s = TransformStack::new();
    s.rotate_xyz(angles);
    assert_eq!(s.matrix(), expected);
}

#[test]
fn trs_applies_scale_then_rotate_then_translate() {
    let t = DVec3::new(10.0, 20.0, 30.0);
    let r = DVec3::new(0.0, std::f64::consts::FRAC_PI_2, 0.0);
    let sc = DVec3::new(2.0, 3.0, 4.0);
    let mut s = TransformStack::new();
    s.trs(t, r, sc);
    let m = DMat4::from_translation(t) * rotation_xyz(r) * DMat4::from_scale(sc);
    assert_eq!(s.matrix(), m);
    // (1,0,0): scaled to (2,0,0), rotated 90° about y to (0,0,-2), translated.
    let p = s.transform_point(DVec3::X);
    assert!((p - DVec3::new(10.0, 20.0, 28.0)).length() < 1e-12, "{p}");
}

#[test]
fn rotations_are_orthonormal() {
    for k in 0..50 {
        let a = DVec3::new(k as f64 * 0.37, k as f64 * -0.91, k as f64 * 1.3);
        let r = DMat3::from_mat4(rotation_xyz(a));
        let err = max_abs_diff(DMat4::from_mat3(r.transpose() * r), DMat4::IDENTITY);
        assert!(err < 4.0 * f64::EPSILON, "RᵀR − I = {err}");
        assert!((r.determinant() - 1.0).abs() < 4.0 * f64::EPSILON);
    }
}

proptest! {
    #[test]
    fn inverse_times_matrix_is_identity(
        t in prop::array::uniform3(-1e3f64..1e3),
        r in prop::array::uniform3(-7.0f64..7.0),
        sc in prop::array::uniform3(0.1f64..10.0),
        t2 in prop::array::uniform3(-1e3f64..1e3),
    ) {
        let mut s = TransformStack::new();
        s.trs(DVec3::from_array(t), DVec3::from_array(r), DVec3::from_array(sc));
        s.translate(DVec3::from_array(t2)).rotate_z(r[0]);
        let m = s.matrix();
        // Relative to the entries' size.
        let scale = m.to_cols_array().iter().fold(1.0f64, |a, x| a.max(x.abs()));
        prop_assert!(max_abs_diff(s.inverse() * m, DMat4::IDENTITY) < INV_TOL * scale);
        prop_assert!(max_abs_diff(m * s.inverse(), DMat4::IDENTITY) < INV_TOL * scale);
        // Round trip of a point.
        let p = DVec3::new(0.3, -4.0, 2.0);
        let back = s.inverse().transform_point3(m.transform_point3(p));
        prop_assert!((back - p).length() < 1e-9);
    }
}

#[test]
fn directions_ignore_translation_points_do_not() {
    let mut s = TransformStack::new();
    s.translate(DVec3::new(5.0, 6.0, 7.0));
    assert_eq!(
        s.transform_direction(DVec3::new(1.0, 2.0, 3.0)),
        DVec3::new(1.0, 2.0, 3.0)
    );
    assert_eq!(
        s.transform_point(DVec3::new(1.0, 2.0, 3.0)),
        DVec3::new(6.0, 8.0, 10.0)
    );
    // As homogeneous 4-vectors: w = 0 is a point at infinity, unmoved by translation.
    assert_eq!(
        s.matrix() * DVec4::new(1.0, 2.0, 3.0, 0.0),
        DVec4::new(1.0, 2.0, 3.0, 0.0)
    );
}

#[test]
fn normals_use_inverse_transpose() {
    // The plane x + y = 0 has normal (1,1,0). Scale x by 4: the plane becomes x/4 + y = 0,
    // with normal (1/4, 1, 0)·k, which the plain matrix gets wrong.
    let mut s = TransformStack::new();
    s.rotate_z(0.0).scale(DVec3::new(4.0, 1.0, 1.0));
    let n = s.transform_normal(DVec3::new(1.0, 1.0, 0.0));
    let tangent = s.transform_direction(DVec3::new(1.0, -1.0, 0.0));
    assert!(n.dot(tangent).abs() < 1e-15, "normal stays perpendicular");
    let wrong = s.transform_direction(DVec3::new(1.0, 1.0, 0.0));
    assert!(wrong.dot(tangent).abs() > 1.0, "the plain matrix does not");
}

#[test]
fn lecture_world_to_camera_recipe_is_the_inverse() {
    // camera_from_world in the lecture: translate by −origin, then rotate by −θ.
    let origin = DVec3::new(0.4, -0.2, -3.001);
    let (yaw, pitch) = (0.35, -0.2);
    let mut world_from_camera = TransformStack::new();
    world_from_camera
        .translate(origin)
        .rotate_y(yaw)
        .rotate_x(pitch);
    let mut camera_from_world = TransformStack::new();
    camera_from_world
        .rotate_x(-pitch)
        .rotate_y(-yaw)
        .translate(-origin);
    assert!(max_abs_diff(camera_from_world.matrix(), world_from_camera.inverse()) < 1e-15);
    assert!(
        max_abs_diff(
            camera_from_world.matrix() * world_from_camera.matrix(),
            DMat4::IDENTITY
        ) < 1e-15
    );
    // And the camera built from yaw/pitch agrees.
    let cam = raylab::Camera::from_yaw_pitch(origin, yaw, pitch, 500.0).unwrap();
    assert!(max_abs_diff(cam.world_from_camera(), world_from_camera.matrix()) < 1e-15);
    assert!(max_abs_diff(cam.camera_from_world(), camera_from_world.matrix()) < 1e-15);
}
