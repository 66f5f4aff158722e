//! The camera controller, fly or orbit: plain-data input in, camera out. The window shell translates
//! keyboard and mouse events into a [`ControlInput`]; nothing here knows about winit.
//!
//! Every move is an op on a [`TransformStack`]: a step forward is `translate` in the camera
//! frame of world_from_camera = T(position) · Ry(yaw) · Rx(pitch), a turn is a change of the
//! yaw/pitch rotations, never an ad-hoc edit of a vector. Speeds are in scene sizes per second
//! and radians per second, scaled by the frame time, so motion is the same at any frame rate.

use crate::camera::Camera;
use crate::math::TransformStack;
use crate::scene::Bounds;
use glam::DVec3;

/// What the user asks for this frame; axes are in −1..=1 (a fraction where a key was held for
/// part of the frame).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ControlInput {
    /// +1 forward (W), −1 back (S).
    pub forward: f64,
    /// +1 right (D), −1 left (A).
    pub right: f64,
    /// +1 up (E), −1 down (Q); "up" is the world's −y.
    pub up: f64,
    /// +1 turn right, −1 left (arrow keys).
    pub yaw: f64,
    /// +1 look up, −1 down (arrow keys).
    pub pitch: f64,
    /// Move and turn faster (Shift).
    pub fast: bool,
    /// Mouse motion in device units accumulated since the last frame (mouse-look).
    pub mouse: (f64, f64),
    /// Wheel lines since the last frame; positive (wheel up) zooms in (fly: the focal length;
    /// orbit: the distance to the target).
    pub wheel: f64,
    /// Move and turn slower (Ctrl).
    pub slow: bool,
    /// Orbit drag (left button) in pixels since the last frame: around the target.
    pub orbit: (f64, f64),
    /// Pan drag in pixels since the last frame: the target and the camera move with it.
    pub pan: (f64, f64),
}

/// How the mouse and wheel move the camera.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Mode {
    /// Fly: keys move, the right-drag looks around, the wheel zooms (focal length).
    #[default]
    Fly,
    /// Orbit (three.js OrbitControls, Blender): the left-drag turns the camera around the
    /// target, the right- or middle-drag pans, the wheel dollies towards the target; keys
    /// move camera and target together.
    Orbit,
}

impl ControlInput {
    /// Whether any held key moves or turns the camera (so the app keeps animating).
    pub fn is_moving(&self) -> bool {
        self.forward != 0.0
            || self.right != 0.0
            || self.up != 0.0
            || self.yaw != 0.0
            || self.pitch != 0.0
    }
}

/// Pitch stays inside ±89° so the view never flips over the pole.
pub const MAX_PITCH: f64 = 89.0 * std::f64::consts::PI / 180.0;
/// Focal length as a fraction of the image width: 0.05 (about 169° of view) to 50 (1.1°).
pub const FOCAL_RATIO_RANGE: (f64, f64) = (0.05, 50.0);

/// A camera pose with the speeds that suit the scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraController {
    /// Position in the world.
    pub position: DVec3,
    /// Yaw in radians (positive turns right).
    pub yaw: f64,
    /// Pitch in radians (positive looks up).
    pub pitch: f64,
    /// Focal length divided by the image width (1 = the lab's f = W, 53° of view).
    pub focal_ratio: f64,
    /// Scene size (bounding-box diagonal): moving at 1× covers 0.5 of it per second.
    pub scene_size: f64,
    /// Fly or orbit.
    pub mode: Mode,
    /// The point orbits turn around (the scene's centre at the start).
    pub target: DVec3,
    /// Moving speed factor (`+`/`-`), 1 at the start.
    pub speed: f64,
    home: (DVec3, f64, f64, f64),
    /// The target at the start: [`reset`](Self::reset) puts the target back at its distance.
    home_target: DVec3,
}

impl CameraController {
    /// Turn rate for the arrow keys, radians per second.
    pub const TURN_RATE: f64 = 1.2;
    /// Mouse-look sensitivity, radians per device unit.
    pub const MOUSE_SENSITIVITY: f64 = 0.003;
    /// Speed factor with Shift held.
    pub const FAST: f64 = 4.0;
    /// Speed factor with Ctrl held.
    pub const SLOW: f64 = 0.25;
    /// Orbit turn per pixel of drag, radians.
    pub const ORBIT_SENSITIVITY: f64 = 0.005;
    /// Pan per pixel of drag, as a fraction of the distance to the target.
    pub const PAN_SENSITIVITY: f64 = 0.002;
    /// The range of the speed factor.
    pub const SPEED_RANGE: (f64, f64) = (1.0 / 64.0, 64.0);
    /// The most seconds of held keys one update moves by: after a stall (a slow load, a
    /// hidden window) the camera does not leap.
    pub const LONGEST_STEP: f64 = 0.25;

    /// A controller at the given pose, which [`reset`](Self::reset) returns to.
    pub fn new(position: DVec3, yaw: f64, pitch: f64, focal_ratio: f64, scene_size: f64) -> Self {
        let focal_ratio = focal_ratio.clamp(FOCAL_RATIO_RANGE.0, FOCAL_RATIO_RANGE.1);
        let mut controller = Self {
            position,
            yaw,
            pitch: pitch.clamp(-MAX_PITCH, MAX_PITCH),
            focal_ratio,
            scene_size: 1.0,
            home: (position, yaw, pitch, focal_ratio),
            home_target: DVec3::ZERO,
            mode: Mode::Fly,
            target: DVec3::ZERO,
            speed: 1.0,
        };
        controller.set_scene_size(scene_size);
        controller
    }

    /// The size moves scale with: a scene's, as it is now (a reload that grows the scene
    /// keeps the pose, not the old size). 1 where `size` is not a positive number.
    pub fn set_scene_size(&mut self, size: f64) {
        self.scene_size = if size.is_finite() && size > 0.0 {
            size
        } else {
            1.0
        };
    }

    /// This controller orbiting `target` (also where [`Mode::Orbit`] turns around).
    pub fn with_target(mut self, target: DVec3) -> Self {
        (self.target, self.home_target) = (target, target);
        self
    }

    /// Switches between fly and orbit. Entering orbit keeps the pose; the target is moved
    /// onto the view axis at its current distance, so the first drag turns around what the
    /// camera looks at.
    pub fn toggle_mode(&mut self) {
        self.mode = match self.mode {
            Mode::Fly => {
                let dist = (self.target - self.position).length();
                let dist = if dist.is_finite() && dist > 0.0 {
                    dist
                } else {
                    self.scene_size
                };
                self.target = self.position + self.forward() * dist;
                Mode::Orbit
            }
            Mode::Orbit => Mode::Fly,
        };
    }

    /// Multiplies the moving speed by `factor` (within [`Self::SPEED_RANGE`]).
    pub fn scale_speed(&mut self, factor: f64) {
        if factor.is_finite() && factor > 0.0 {
            self.speed = (self.speed * factor).clamp(Self::SPEED_RANGE.0, Self::SPEED_RANGE.1);
        }
    }

    /// The unit view direction (camera +z in the world).
    pub fn forward(&self) -> DVec3 {
        self.stack().transform_direction(DVec3::Z)
    }

    /// The lab's start: (0, 0, −3.001) looking along +z, f = W, for the Cornell box's size.
    pub fn cornell() -> Self {
        Self::new(DVec3::new(0.0, 0.0, -3.001), 0.0, 0.0, 1.0, 12f64.sqrt())
    }

    /// A controller framing `bounds` from −z, as `raylab render` frames an OBJ model, for an
    /// image of aspect `width`/`height`; it orbits the bounds' centre.
    pub fn framing(bounds: Bounds, width: u32, height: u32) -> Self {
        let (lo, hi) = bounds;
        let lo = DVec3::from_array(lo.map(f64::from));
        let hi = DVec3::from_array(hi.map(f64::from));
        let centre = (lo + hi) / 2.0;
        let diagonal = (hi - lo).length();
        let radius = (diagonal / 2.0).max(1e-30);
        let focal = width as f64;
        let half_fov = crate::camera::fov_of_focal(focal, width.min(height) as f64) / 2.0;
        // (Within the camera's range: a scene near the edge of its range seen from a very
        // flat image would need more; it is then seen from the edge, not all in view.)
        let distance = (radius / half_fov.sin()).min(centre.z + crate::math::MAX_VIEW_COORDINATE);
        Self::new(centre - DVec3::Z * distance, 0.0, 0.0, 1.0, diagonal).with_target(centre)
    }

    /// Where `scene` is first seen from in an image of aspect `width`/`height`: its `.scene`
    /// file's camera, the lab's for the built-in box (`cornell`), else one framing its bounds
    /// (an empty scene without a camera: the lab's).
    pub fn starting(scene: &crate::scene::Scene, cornell: bool, width: u32, height: u32) -> Self {
        match (scene.camera, cornell, scene.bounds()) {
            (Some(c), _, _) => Self::from_scene_camera(&c, scene.size()),
            (None, false, Some(b)) => Self::framing(b, width, height),
            _ => Self::cornell(),
        }
    }

    /// The starting pose a `.scene` file names, for a scene `scene_size` across.
    pub fn from_scene_camera(c: &crate::scene::SceneCamera, scene_size: f64) -> Self {
        let position = DVec3::from_array(c.position);
        let radians = crate::math::radians_of_degrees;
        let (yaw, pitch) = (radians(c.yaw), radians(c.pitch));
        Self::new(position, yaw, pitch, c.focal_ratio(), scene_size)
    }

    /// Back to the starting pose.
    pub fn reset(&mut self) {
        (self.position, self.yaw, self.pitch, self.focal_ratio) = self.home;
        // (The target too, on the starting view axis at its starting distance: orbit mode
        // keeps the camera looking at it, and after a pan R left the view shifted.)
        let dist = (self.home_target - self.position).length();
        let dist = match dist.is_finite() && dist > 0.0 {
            true => dist,
            false => self.scene_size,
        };
        self.target = self.position + self.forward() * dist;
    }

    /// The transform stack holding world_from_camera = T(position) · Ry(yaw) · Rx(pitch).
    pub fn stack(&self) -> TransformStack {
        let mut s = TransformStack::new();
        s.translate(self.position)
            .rotate_y(self.yaw)
            .rotate_x(self.pitch);
        s
    }

    /// The camera for an image `width` pixels wide.
    pub fn camera(&self, width: u32) -> Camera {
        // (A position typed into the panel may be anywhere: the camera takes the nearest one
        // within its range.)
        let max = crate::math::MAX_VIEW_COORDINATE;
        let position = self.position.clamp(DVec3::splat(-max), DVec3::splat(max));
        Camera::from_yaw_pitch(position, self.yaw, self.pitch, self.focal(width))
            .expect("the controller keeps its pose finite and its focal length in range")
    }

    /// Focal length in pixels for an image `width` pixels wide.
    pub fn focal(&self, width: u32) -> f64 {
        self.focal_ratio * width.max(1) as f64
    }

    /// Sets the focal length in pixels at `width`, clamped to [`FOCAL_RATIO_RANGE`].
    pub fn set_focal(&mut self, focal: f64, width: u32) {
        if focal.is_finite() {
            let r = focal / width.max(1) as f64;
            self.focal_ratio = r.clamp(FOCAL_RATIO_RANGE.0, FOCAL_RATIO_RANGE.1);
        }
    }

    /// Applies one frame of input over `dt` seconds (at most [`Self::LONGEST_STEP`]); returns
    /// whether the pose changed.
    pub fn update(&mut self, input: &ControlInput, dt: f64) -> bool {
        let before = (
            self.position,
            self.yaw,
            self.pitch,
            self.focal_ratio,
            self.target,
        );
        let dt = if dt.is_finite() {
            dt.clamp(0.0, Self::LONGEST_STEP)
        } else {
            0.0
        };
        let boost = match (input.fast, input.slow) {
            (true, false) => Self::FAST,
            (false, true) => Self::SLOW,
            _ => 1.0,
        };

        // Turn: arrow keys at a rate, the mouse by its motion.
        self.yaw +=
            (input.yaw * Self::TURN_RATE * boost * dt) + input.mouse.0 * Self::MOUSE_SENSITIVITY;
        self.pitch = (self.pitch + input.pitch * Self::TURN_RATE * boost * dt
            - input.mouse.1 * Self::MOUSE_SENSITIVITY)
            .clamp(-MAX_PITCH, MAX_PITCH);
        self.yaw = self.yaw.rem_euclid(std::f64::consts::TAU);
        if self.yaw > std::f64::consts::PI {
            self.yaw -= std::f64::consts::TAU;
        }

        // Move: forward/right in the camera frame, up along the world's −y (in orbit mode
        // the target comes along).
        let step = 0.5 * self.scene_size * self.speed * boost * dt;
        let start = self.position;
        if input.forward != 0.0 || input.right != 0.0 || input.up != 0.0 {
            let mut stack = self.stack();
            stack.translate(DVec3::new(input.right * step, 0.0, input.forward * step));
            let moved = stack.transform_point(DVec3::ZERO);
            let mut world = TransformStack::new();
            world
                .translate(moved)
                .translate(DVec3::new(0.0, -input.up * step, 0.0));
            self.position = world.transform_point(DVec3::ZERO);
        }
        if self.mode == Mode::Orbit {
            self.target += self.position - start;
            self.orbit(input);
        } else if input.wheel != 0.0 && input.wheel.is_finite() {
            self.focal_ratio = (self.focal_ratio * 1.1f64.powf(input.wheel))
                .clamp(FOCAL_RATIO_RANGE.0, FOCAL_RATIO_RANGE.1);
        }
        let after = (
            self.position,
            self.yaw,
            self.pitch,
            self.focal_ratio,
            self.target,
        );
        let max = crate::math::MAX_VIEW_COORDINATE;
        let within = |p: DVec3| p.abs().max_element() <= max; // (false for NaN)
        let finite = within(self.position)
            && self.target.is_finite()
            && self.yaw.is_finite()
            && self.pitch.is_finite()
            && self.focal_ratio.is_finite();
        if !finite {
            // (Never leave a pose the camera cannot take: finite, within the view range.)
            (
                self.position,
                self.yaw,
                self.pitch,
                self.focal_ratio,
                self.target,
            ) = before;
        }
        finite && before != after
    }

    /// Orbit mode's drags and wheel: turn around the target at the same distance, pan the
    /// target and the camera together, dolly towards the target (never through it).
    fn orbit(&mut self, input: &ControlInput) {
        let mut dist = (self.position - self.target).length();
        if !(dist.is_finite() && dist > 0.0) {
            dist = self.scene_size;
        }
        let (ox, oy) = input.orbit;
        if ox.is_finite() && oy.is_finite() {
            self.yaw += ox * Self::ORBIT_SENSITIVITY;
            self.pitch = (self.pitch - oy * Self::ORBIT_SENSITIVITY).clamp(-MAX_PITCH, MAX_PITCH);
        }
        let (px, py) = input.pan;
        if px.is_finite() && py.is_finite() && (px, py) != (0.0, 0.0) {
            // The scene follows the cursor: the camera moves against the drag.
            let stack = self.stack();
            let right = stack.transform_direction(DVec3::X);
            let down = stack.transform_direction(DVec3::Y);
            self.target -= (right * px + down * py) * dist * Self::PAN_SENSITIVITY;
        }
        if input.wheel != 0.0 && input.wheel.is_finite() {
            let min = 1e-6 * self.scene_size;
            dist = (dist * 0.9f64.powf(input.wheel)).clamp(min, 1e3 * self.scene_size);
        }
        self.position = self.target - self.forward() * dist;
    }
}
