//! The lecture's transform stack: 4×4 homogeneous matrices in f64.
//!
//! Every op post-multiplies the current matrix, so ops called in the order translate, rotate,
//! scale give M = T · R · S, which applies to a point scale first, then rotation, then
//! translation. [`TransformStack::trs`] composes exactly that fixed order in one call. The
//! composite rotation is R = Rz · Ry · Rx: a point is rotated about x first, then y, then z.
//!
//! The stack keeps each matrix together with its inverse, built from the inverses of the ops
//! (T(−t), Rᵀ, S(1/s)) rather than by a general 4×4 inversion, so `inverse · matrix` is the
//! identity to within a few ulps. f64 here costs nothing (the stack is touched once per frame),
//! while the hot path uses the f32 affine part the camera extracts from it.

use glam::{DMat3, DMat4, DVec3, DVec4};

/// sin and cos of an angle in degrees: exactly 0 and ±1 at multiples of 90°, so a quarter
/// turn maps axis-aligned geometry to axis-aligned geometry to the last bit.
pub fn sin_cos_degrees(deg: f64) -> (f64, f64) {
    // `%` is exact in floating point.
    let r = deg % 360.0;
    if r % 90.0 == 0.0 {
        return match ((r / 90.0) as i64).rem_euclid(4) {
            0 => (0.0, 1.0),
            1 => (1.0, 0.0),
            2 => (0.0, -1.0),
            _ => (-1.0, 0.0),
        };
    }
    r.to_radians().sin_cos()
}

/// An angle in degrees (a camera's yaw or pitch) in radians, reduced mod 360 first, exactly:
/// 1e300° turns as 1e300 mod 360 = 0° does, as a scene file's `rotate` takes it (1e300 × π/180
/// is a rounding of a turn, an angle nobody asked for). Below 360° the same as `to_radians`.
pub fn radians_of_degrees(deg: f64) -> f64 {
    // (`%` is exact in floating point; an infinite angle stays one, for the error that names
    // it: `inf % 360` is NaN.)
    match deg.is_finite() {
        true => (deg % 360.0).to_radians(),
        false => deg,
    }
}

/// `deg` as the same turn within (-180°, 180°], exactly (as the window shows a yaw).
pub fn degrees_within_half_turn(deg: f64) -> f64 {
    // (Both subtractions are exact: Sterbenz.)
    match deg % 360.0 {
        r if r > 180.0 => r - 360.0,
        r if r <= -180.0 => r + 360.0,
        r => r,
    }
}

/// The rotations about +x, +y and +z by the angle whose sine and cosine are `(s, c)`.
fn rotation_about(axis: usize, (s, c): (f64, f64)) -> DMat4 {
    match axis {
        0 => DMat4::from_cols(
            DVec4::new(1.0, 0.0, 0.0, 0.0),
            DVec4::new(0.0, c, s, 0.0),
            DVec4::new(0.0, -s, c, 0.0),
            DVec4::W,
        ),
        1 => DMat4::from_cols(
            DVec4::new(c, 0.0, -s, 0.0),
            DVec4::Y,
            DVec4::new(s, 0.0, c, 0.0),
            DVec4::W,
        ),
        _ => DMat4::from_cols(
            DVec4::new(c, s, 0.0, 0.0),
            DVec4::new(-s, c, 0.0, 0.0),
            DVec4::Z,
            DVec4::W,
        ),
    }
}

/// Rotation about +x by `a` radians (the lecture's Rx): y turns towards z.
pub fn rotation_x(a: f64) -> DMat4 {
    let (s, c) = a.sin_cos();
    DMat4::from_cols(
        DVec4::new(1.0, 0.0, 0.0, 0.0),
        DVec4::new(0.0, c, s, 0.0),
        DVec4::new(0.0, -s, c, 0.0),
        DVec4::W,
    )
}

/// Rotation about +y by `a` radians (the lecture's Ry): z turns towards x.
pub fn rotation_y(a: f64) -> DMat4 {
    let (s, c) = a.sin_cos();
    DMat4::from_cols(
        DVec4::new(c, 0.0, -s, 0.0),
        DVec4::Y,
        DVec4::new(s, 0.0, c, 0.0),
        DVec4::W,
    )
}

/// Rotation about +z by `a` radians (the lecture's Rz): x turns towards y.
pub fn rotation_z(a: f64) -> DMat4 {
    let (s, c) = a.sin_cos();
    DMat4::from_cols(
        DVec4::new(c, s, 0.0, 0.0),
        DVec4::new(-s, c, 0.0, 0.0),
        DVec4::Z,
        DVec4::W,
    )
}

/// The composite rotation R = Rz(z) · Ry(y) · Rx(x): about x first, then y, then z.
pub fn rotation_xyz(angles: DVec3) -> DMat4 {
    rotation_z(angles.z) * rotation_y(angles.y) * rotation_x(angles.x)
}

/// A matrix with its exact-by-construction inverse.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Entry {
    matrix: DMat4,
    inverse: DMat4,
}

/// A stack of homogeneous transforms, as in the lecture (and OpenGL's matrix stack).
#[derive(Clone, Debug)]
pub struct TransformStack {
    current: Entry,
    saved: Vec<Entry>,
}

impl Default for TransformStack {
    fn default() -> Self {
        Self::new()
    }
}

impl TransformStack {
    /// A stack whose current matrix is the identity.
    pub fn new() -> Self {
        Self {
            current: Entry {
                matrix: DMat4::IDENTITY,
                inverse: DMat4::IDENTITY,
            },
            saved: Vec::new(),
        }
    }

    /// Saves the current matrix; [`pop`](Self::pop) restores it bit for bit.
    pub fn push(&mut self) -> &mut Self {
        self.saved.push(self.current);
        self
    }

    /// Restores the matrix saved by the matching [`push`](Self::push); `false` if none was saved.
    pub fn pop(&mut self) -> bool {
        match self.saved.pop() {
            Some(entry) => {
                self.current = entry;
                true
            }
            None => false,
        }
    }

    /// How many matrices are saved below the current one.
    pub fn depth(&self) -> usize {
        self.saved.len()
    }

    fn apply(&mut self, op: DMat4, op_inverse: DMat4) -> &mut Self {
        self.current.matrix *= op;
        self.current.inverse = op_inverse * self.current.inverse;
        self
    }

    /// Post-multiplies a translation by `t`.
    pub fn translate(&mut self, t: DVec3) -> &mut Self {
        self.apply(DMat4::from_translation(t), DMat4::from_translation(-t))
    }

    /// Post-multiplies a rotation about x by `a` radians.
    pub fn rotate_x(&mut self, a: f64) -> &mut Self {
        let r = rotation_x(a);
        self.apply(r, r.transpose())
    }

    /// Post-multiplies a rotation about y by `a` radians.
    pub fn rotate_y(&mut self, a: f64) -> &mut Self {
        let r = rotation_y(a);
        self.apply(r, r.transpose())
    }

    /// Post-multiplies a rotation about z by `a` radians.
    pub fn rotate_z(&mut self, a: f64) -> &mut Self {
        let r = rotation_z(a);
        self.apply(r, r.transpose())
    }

    /// Post-multiplies a rotation about axis `axis` (0 = x, 1 = y, 2 = z) by `deg` degrees,
    /// exact at multiples of 90° ([`sin_cos_degrees`]).
    pub fn rotate_degrees(&mut self, axis: usize, deg: f64) -> &mut Self {
        let r = rotation_about(axis, sin_cos_degrees(deg));
        self.apply(r, r.transpose())
    }

    /// Post-multiplies the composite rotation Rz · Ry · Rx (see [`rotation_xyz`]).
    pub fn rotate_xyz(&mut self, angles: DVec3) -> &mut Self {
        let r = rotation_xyz(angles);
        self.apply(r, r.transpose())
    }

    /// Post-multiplies a scale by `s`; every component must be non-zero (else the inverse is
    /// not finite, which [`is_finite`](Self::is_finite) reports).
    pub fn scale(&mut self, s: DVec3) -> &mut Self {
        self.apply(DMat4::from_scale(s), DMat4::from_scale(s.recip()))
    }

    /// Post-multiplies T(t) · Rz·Ry·Rx(angles) · S(s): the lecture's one fixed order.
    pub fn trs(&mut self, t: DVec3, angles: DVec3, s: DVec3) -> &mut Self {
        self.translate(t).rotate_xyz(angles).scale(s)
    }

    /// The current matrix, e.g. `world_from_object`.
    pub fn matrix(&self) -> DMat4 {
        self.current.matrix
    }

    /// The inverse of the current matrix, e.g. `object_from_world`.
    pub fn inverse(&self) -> DMat4 {
        self.current.inverse
    }

    /// Whether the matrix and its inverse are finite (a zero scale makes the inverse infinite).
    pub fn is_finite(&self) -> bool {
        self.current.matrix.is_finite() && self.current.inverse.is_finite()
    }

    /// Transforms a point (w = 1): translation applies.
    pub fn transform_point(&self, p: DVec3) -> DVec3 {
        self.current.matrix.transform_point3(p)
    }

    /// Transforms a direction (w = 0, a point at infinity): translation does not apply.
    pub fn transform_direction(&self, d: DVec3) -> DVec3 {
        self.current.matrix.transform_vector3(d)
    }

    /// Transforms a surface normal by the inverse transpose, so it stays perpendicular to the
    /// transformed surface under non-uniform scale. The result is not normalised.
    pub fn transform_normal(&self, n: DVec3) -> DVec3 {
        DMat3::from_mat4(self.current.inverse).transpose() * n
    }
}
