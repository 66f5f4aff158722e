//! The lecture's pinhole camera.
//!
//! Camera space is x right, y down, z forward (right-handed). Pixel (i, j) of a W×H image is
//! sampled through its centre, u = i − W/2 + 0.5, v = j − H/2 + 0.5, along the camera-space
//! direction normalize(u, v, f) with the focal length f in pixels, which is then taken to the
//! world by `world_from_camera`. The horizontal field of view 2·atan(W / 2f) is derived from f
//! and the width, never stored.

use crate::geometry::Ray;
use crate::math::lanes::{LaneOps, Lanes};
use crate::math::simd::each3;
use crate::math::{TransformStack, MAX_VIEW_COORDINATE};
use glam::{DMat3, DMat4, DVec3, Vec3};

/// Lowest and highest accepted focal lengths in pixels (about 180° and 0.00001° of view at
/// 1000 px): outside this range the image is meaningless or the rays overflow.
pub const FOCAL_RANGE: (f64, f64) = (1e-3, 1e9);

/// A pinhole camera: pose (`world_from_camera`, a rotation and a translation) and focal length.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    world_from_camera: DMat4,
    /// Focal length in pixels.
    pub focal: f64,
}

/// Why a camera cannot be built.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum CameraError {
    /// Focal length not finite or outside [`FOCAL_RANGE`].
    #[error("focal length {0:?} px is out of range (expected a finite value in [{min}, {max}])", min = FOCAL_RANGE.0, max = FOCAL_RANGE.1)]
    Focal(f64),
    /// A non-finite position or angle.
    #[error("camera {0} must be finite, got {1}")]
    NotFinite(&'static str, String),
    /// A position beyond [`crate::math::MAX_VIEW_COORDINATE`].
    #[error("{0}")]
    OutOfRange(String),
    /// View and up directions that do not span a frame.
    #[error("view direction {0:?} and up direction {1:?} must be non-zero and not parallel")]
    Frame(DVec3, DVec3),
}

fn check_focal(focal: f64) -> Result<f64, CameraError> {
    if focal.is_finite() && (FOCAL_RANGE.0..=FOCAL_RANGE.1).contains(&focal) {
        Ok(focal)
    } else {
        Err(CameraError::Focal(focal))
    }
}

fn check_finite(what: &'static str, v: DVec3) -> Result<DVec3, CameraError> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(CameraError::NotFinite(what, format!("{v}")))
    }
}

fn check_position(p: DVec3) -> Result<DVec3, CameraError> {
    check_finite("position", p)?;
    crate::math::check_range("camera position", p.to_array(), MAX_VIEW_COORDINATE)
        .map_err(CameraError::OutOfRange)?;
    Ok(p)
}

impl Camera {
    /// The lab camera for a `width`-pixel-wide image: at (0, 0, −3.001), looking along +z,
    /// focal length = width.
    pub fn cornell(width: u32) -> Self {
        Self::from_yaw_pitch(DVec3::new(0.0, 0.0, -3.001), 0.0, 0.0, width as f64)
            .expect("the lab camera is valid")
    }

    /// A camera at `position` turned by `yaw` about y, then `pitch` about its own x (radians):
    /// world_from_camera = T(position) · Ry(yaw) · Rx(pitch), built on the transform stack.
    pub fn from_yaw_pitch(
        position: DVec3,
        yaw: f64,
        pitch: f64,
        focal: f64,
    ) -> Result<Self, CameraError> {
        check_position(position)?;
        let angles = [("yaw", yaw), ("pitch", pitch)];
        if let Some((name, value)) = angles.iter().find(|(_, a)| !a.is_finite()) {
            return Err(CameraError::NotFinite(
                "yaw/pitch",
                format!("{name} {value}"),
            ));
        }
        let mut stack = TransformStack::new();
        stack.translate(position).rotate_y(yaw).rotate_x(pitch);
        Ok(Self {
            world_from_camera: stack.matrix(),
            focal: check_focal(focal)?,
        })
    }

    /// A camera at `position` looking along `view`, with `up` (−y in the lab frame) pointing
    /// up on screen as far as it can while staying perpendicular to `view`.
    pub fn look_to(
        position: DVec3,
        view: DVec3,
        up: DVec3,
        focal: f64,
    ) -> Result<Self, CameraError> {
        check_position(position)?;
        let forward = view.normalize_or_zero();
        let right = forward.cross(up).normalize_or_zero();
        if forward == DVec3::ZERO || right == DVec3::ZERO || !right.is_finite() {
            return Err(CameraError::Frame(view, up));
        }
        let down = forward.cross(right);
        let rotation = DMat4::from_mat3(DMat3::from_cols(right, down, forward));
        Ok(Self {
            world_from_camera: DMat4::from_translation(position) * rotation,
            focal: check_focal(focal)?,
        })
    }

    /// The camera-to-world matrix (rigid: rotation then translation).
    pub fn world_from_camera(&self) -> DMat4 {
        self.world_from_camera
    }

    /// The world-to-camera matrix: the exact inverse of a rigid transform, Rᵀ · T(−position).
    pub fn camera_from_world(&self) -> DMat4 {
        self.camera_from_world_at(self.position())
    }

    /// [`Camera::camera_from_world`] with the camera's axes placed at `eye`: Rᵀ · T(−eye).
    fn camera_from_world_at(&self, eye: DVec3) -> DMat4 {
        let r = DMat3::from_mat4(self.world_from_camera).transpose();
        DMat4::from_mat3(r) * DMat4::from_translation(-eye)
    }

    /// The camera position in the world.
    pub fn position(&self) -> DVec3 {
        self.world_from_camera.w_axis.truncate()
    }

    /// The unit view direction (camera +z) in the world.
    pub fn forward(&self) -> DVec3 {
        self.world_from_camera.z_axis.truncate()
    }

    /// The unit screen-right direction (camera +x) in the world.
    pub fn right(&self) -> DVec3 {
        self.world_from_camera.x_axis.truncate()
    }

    /// The unit screen-down direction (camera +y) in the world.
    pub fn down(&self) -> DVec3 {
        self.world_from_camera.y_axis.truncate()
    }

    /// Horizontal field of view in radians for an image `width` pixels wide.
    pub fn fov_x(&self, width: u32) -> f64 {
        fov_of_focal(self.focal, width as f64)
    }

    /// The focal length giving a horizontal field of view `fov` (radians) at `width` pixels.
    pub fn focal_for_fov(fov: f64, width: u32) -> f64 {
        focal_of_fov(fov, width as f64)
    }

    /// The ray through the continuous image position (x, y) in pixels from the top-left corner
    /// of a `width`×`height` image; (i + 0.5, j + 0.5) is the centre of pixel (i, j).
    pub fn ray_through(&self, x: f64, y: f64, width: u32, height: u32) -> Ray<f32> {
        self.ray_generator(width, height)
            .ray_through(x as f32, y as f32)
    }

    /// The ray through the centre of pixel (i, j).
    pub fn ray_for_pixel(&self, i: u32, j: u32, width: u32, height: u32) -> Ray<f32> {
        self.ray_through(i as f64 + 0.5, j as f64 + 0.5, width, height)
    }

    /// The pinhole projection onto a `width`×`height` image (the inverse of
    /// [`Camera::ray_through`]'s direction, in f64), for screen-space culling.
    pub fn projection(&self, width: u32, height: u32) -> Projection {
        let position = self.position();
        Projection {
            camera_from_world: self.camera_from_world(),
            centre: [width as f64 / 2.0, height as f64 / 2.0],
            focal: self.focal,
            eye_rounding: (position - position.as_vec3().as_dvec3()).length(),
        }
    }

    /// [`Camera::projection`] from where the camera rays leave, the position rounded to f32
    /// (up to 2¹⁵ units from the pinhole at 10¹²): each camera ray projects onto its own pixel
    /// at every distance, as an overlay drawing a ray over the image needs.
    pub fn ray_projection(&self, width: u32, height: u32) -> Projection {
        let rays_from = self.position().as_vec3().as_dvec3();
        Projection {
            camera_from_world: self.camera_from_world_at(rays_from),
            eye_rounding: 0.0,
            ..self.projection(width, height)
        }
    }

    /// Precomputed f32 basis for generating many rays of one image.
    pub fn ray_generator(&self, width: u32, height: u32) -> RayGenerator {
        let f = |v: DVec3| v.as_vec3();
        let (right, down, forward) = (f(self.right()), f(self.down()), f(self.forward()));
        RayGenerator {
            origin: f(self.position()),
            right,
            down,
            forward,
            half_w: width as f32 / 2.0,
            half_h: height as f32 / 2.0,
            focal: self.focal as f32,
            component_bound: component_bound(right, down, forward),
        }
    }
}

/// A bound on |dₖ| for every direction d = right·cx + down·cy + forward·cz made from a unit
/// camera-space c (rounded): by Cauchy–Schwarz |dₖ| ≤ ‖(rightₖ, downₖ, forwardₖ)‖·‖c‖, and
/// ‖c‖ and the rounding of the sums stay within 1 + 2⁻¹⁹ (focal lengths in [`FOCAL_RANGE`]
/// keep c's squares clear of underflow and overflow); the margin 1 + 10⁻⁵ covers both.
/// NaN where an axis is not finite (the packet kernels then leave every lane ambiguous).
fn component_bound(right: Vec3, down: Vec3, forward: Vec3) -> f32 {
    let row = |k: usize| {
        let v = [right[k], down[k], forward[k]].map(f64::from);
        (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
    };
    let bound = row(0).max(row(1)).max(row(2)) * (1.0 + 1e-5);
    match bound.is_finite() {
        true => bound as f32,
        false => f32::NAN,
    }
}

/// Where world points land on the image: (x, y) = f·(cx, cy)/cz + (W/2, H/2) for the point
/// at c in camera space, the pixel-centre convention of [`RayGenerator::ray_through`].
#[derive(Clone, Copy, Debug)]
pub struct Projection {
    camera_from_world: DMat4,
    /// W/2, H/2.
    centre: [f64; 2],
    focal: f64,
    /// How far the camera rays' origin (the position rounded to f32) lies from the pinhole.
    eye_rounding: f64,
}

impl Projection {
    /// Whether `p` lies where no camera ray reaches (t ≥ 0, from the eye rounded to f32):
    /// behind the pinhole's plane by more than the eye's rounding and 2⁻¹⁶ of its distance
    /// (a margin far beyond every method's rounding). Every camera ray moves forward: its
    /// direction's forward part, the focal length, outweighs the rounding of its sideways
    /// parts where the image's half-sides stay under 2¹⁶ focal lengths (else nothing is).
    pub fn behind(&self, p: [f32; 3]) -> bool {
        let forward = self.focal * 65536.0 >= self.centre[0] + self.centre[1];
        let c = self
            .camera_from_world
            .transform_point3(DVec3::from_array(p.map(f64::from)));
        forward && c.z < -(self.eye_rounding + c.length() / 65536.0)
    }

    /// The image position of world point `p`; `None` where it is not in front of the pinhole
    /// (camera-space z ≤ 10⁻⁹·|c|).
    pub fn project(&self, p: [f32; 3]) -> Option<[f64; 2]> {
        self.project_f64(p.map(f64::from))
    }

    /// [`Projection::project`] of a point in f64 (one along a ray, say, not rounded to f32).
    pub fn project_f64(&self, p: [f64; 3]) -> Option<[f64; 2]> {
        let c = self
            .camera_from_world
            .transform_point3(DVec3::from_array(p));
        if c.z <= 1e-9 * c.length() {
            return None;
        }
        let f = self.focal;
        Some([
            f * c.x / c.z + self.centre[0],
            f * c.y / c.z + self.centre[1],
        ])
    }
}

/// The camera's affine part in f32, for the hot path.
#[derive(Clone, Copy, Debug)]
pub struct RayGenerator {
    origin: Vec3,
    right: Vec3,
    down: Vec3,
    forward: Vec3,
    half_w: f32,
    half_h: f32,
    focal: f32,
    /// A bound on every |dₖ| of the directions made ([`RayGenerator::component_bound`]).
    component_bound: f32,
}

impl RayGenerator {
    /// The ray through image position (x, y) in pixels from the top-left corner, with a unit
    /// direction: world_from_camera applied to normalize(x − W/2, y − H/2, f).
    #[inline]
    pub fn ray_through(&self, x: f32, y: f32) -> Ray<f32> {
        let cam = Vec3::new(x - self.half_w, y - self.half_h, self.focal).normalize();
        let d = self.right * cam.x + self.down * cam.y + self.forward * cam.z;
        Ray::new(self.origin.to_array(), d.to_array())
    }

    /// The directions of [`RayGenerator::ray_through`] at image positions (`xs[l]`, y), 8 at a
    /// time: the same f32 operations in the same order, so each lane is bit-identical to the
    /// scalar ray. Computed at full width where the CPU has AVX2 (`wide`'s f32x8 is two SSE
    /// halves in the default build: 18 instructions a pixel of the Cornell flat frame).
    #[inline]
    pub fn directions_x8(&self, xs: wide::f32x8, ys: wide::f32x8) -> [wide::f32x8; 3] {
        use crate::math::simd::avx512_avx2_or_baseline;
        let generator = self;
        avx512_avx2_or_baseline!(lanes RayGenerator::directions_x8_in => (generator: &RayGenerator, xs: wide::f32x8, ys: wide::f32x8)
            -> [wide::f32x8; 3])
    }

    /// A bound on every component's magnitude of the directions this makes: the packet
    /// kernels' d_max without a reduction per packet (NaN where the camera's axes are not
    /// finite).
    pub fn component_bound(&self) -> f32 {
        self.component_bound
    }

    /// The shared origin of the rays.
    pub fn origin(&self) -> [f32; 3] {
        self.origin.to_array()
    }
}

impl RayGenerator {
    /// [`RayGenerator::directions_x8`] inside a kernel already built for lanes `V` (the
    /// frame's tile loop), in the kernels' public form.
    #[inline(always)]
    pub(crate) fn directions_x8_in<V: Lanes>(
        &self,
        xs: wide::f32x8,
        ys: wide::f32x8,
    ) -> [wide::f32x8; 3] {
        let d = self.directions_in::<V>(V::from_wide(xs), V::from_wide(ys));
        each3(|k| d[k].to_wide())
    }

    /// [`RayGenerator::directions_x8`] inside a kernel already built for lanes `V`.
    #[inline(always)]
    pub(crate) fn directions_in<V: LaneOps>(&self, xs: V, ys: V) -> [V; 3] {
        let cx = xs - V::splat(self.half_w);
        let cy = ys - V::splat(self.half_h);
        let cz = V::splat(self.focal);
        let recip = V::one() / (cx * cx + cy * cy + cz * cz).sqrt();
        let (cx, cy, cz) = (cx * recip, cy * recip, cz * recip);
        let axis = |k: usize| {
            let (r, d, f) = (self.right[k], self.down[k], self.forward[k]);
            V::splat(r) * cx + V::splat(d) * cy + V::splat(f) * cz
        };
        each3(axis)
    }
}

/// The field of view (radians) across `side` pixels seen at focal length `focal` pixels,
/// 2·atan(side / 2f): the one formula the panel, the `.view` and `.scene` files and the
/// framing of a model read.
pub fn fov_of_focal(focal: f64, side: f64) -> f64 {
    2.0 * (side / (2.0 * focal)).atan()
}

/// The focal length (pixels) that sees a field of view `fov` (radians) across `side` pixels
/// ([`fov_of_focal`]'s inverse).
pub fn focal_of_fov(fov: f64, side: f64) -> f64 {
    side / (2.0 * (fov / 2.0).tan())
}
