//! raylab: a teaching-grade CPU raycaster built from the raytracing lecture's lab.
//!
//! This crate is the renderer core. It never imports winit, egui or wgpu (it does not depend
//! on them): the command line and the window (the `raylab-app` package in app/) are a thin
//! layer over it, and everything the window shows can be rendered headless to PNG.
//!
//! # Conventions (stated once, tested in `tests/`)
//! - **Units and world frame**: the lab scene's frame. The Cornell box fills [-1, 1]³; its lab
//!   vertices (room size L = 555) are mapped by `v*2/L - 1`, then x and y negated.
//! - **Handedness**: right-handed everywhere. Camera space is x right, y **down**, z forward (the
//!   lab's screen convention), so in the Cornell box "up" is −y. The default camera sits at
//!   (0, 0, −3.001) looking along +z.
//! - **Pixel centres**: pixel (i, j) (column i from the left, row j from the top) is sampled at
//!   u = i − W/2 + 0.5, v = j − H/2 + 0.5; the camera-space ray direction is normalize(u, v, f)
//!   with the focal length f in pixels. The default focal length is the image width.
//! - **Transforms**: 4×4 homogeneous matrices, points w = 1, directions w = 0, normals by the
//!   inverse transpose. An object's transform is always composed in the fixed order
//!   M = T · R · S (scale first, then rotate, then translate), with R = Rz · Ry · Rx (x first).
//!   Matrices are named by their frames, `world_from_camera`, and compose right to left.
//! - **Angles**: radians inside, degrees only at the CLI and UI. Positive yaw (about +y) turns
//!   the view to the right (+x), positive pitch (about +x) turns it up (−y).
//! - **Rays**: o + t·d with d not necessarily normalised; a hit counts for tmin < t < tmax, the
//!   nearest wins, and on an exact tie the lower primitive index wins. Triangles are closed
//!   (edges and vertices belong) and two-sided; one seen edge-on is missed; a ray tangent to a
//!   sphere hits it. The default method (`geometry::adaptive`) decides all of this exactly for
//!   the given float inputs.
//! - **Colour**: linear RGB in f32 inside; sRGB-encoded once, when writing RGBA8.
//!
//! # Layers
//! Each imports only those below it (docs/architecture.md has the map and where to add a
//! shape, a layout, a lab step or a control):
//! - [`math`]: the transform stack, `Real`, intervals, SIMD lanes and their dispatch;
//! - [`geometry`]: rays, shapes, the intersection methods and the exact search;
//! - [`scene`]: primitives, colours, instances, the light; the OBJ and `.scene` loaders;
//! - [`accel`]: the structures over a scene and their queries;
//! - [`render`]: the tile loop, the lab steps' shading, the inspector, images;
//! - [`check`]: the hard-case suite and the grading of answers from code that is not raylab's;
//! - app/ (another package): the command line and the window, over all of these.
//!
//! # Example
//! The lab's Cornell box, step 4 (shadows), rendered and written as a PNG:
//! ```
//! use raylab::{render_into, Camera, LabStep, RenderSettings};
//! // The scene and the structure that answers its rays, built once.
//! let stage = raylab::Stage::from(raylab::Scene::cornell());
//! let settings = RenderSettings { width: 64, height: 48, step: LabStep::Shadows, ..Default::default() };
//! let camera = Camera::cornell(settings.width);
//! let mut rgba = vec![0u8; settings.buffer_len()];
//! let stats = render_into(&stage, &camera, &settings, &mut rgba)?;
//! assert_eq!(stats.primary_rays, 64 * 48);
//! let path = std::env::temp_dir().join("raylab-example.png");
//! raylab::render::write_png(&path, settings.width, settings.height, &rgba)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! Unsafe code only where the hardware or shared buffers need it, each with its reason: the
//! calls into the packet kernels' AVX2 and AVX-512 builds, made only after checking the CPU at
//! run time (`math::simd::level`), and their intrinsics; a prefetch in the packet walk; and
//! the frame's leaf cache, whose blocks one thread fills and every thread then reads.
#![deny(unsafe_code)]

pub mod accel;
pub mod camera;
pub mod check;
pub mod controller;
pub mod geometry;
pub mod input;
pub mod limits;
pub mod machine;
pub mod math;
pub mod render;
pub mod scene;
pub mod tracefile;
#[cfg(feature = "unit-tests")]
#[doc(hidden)]
pub mod unit_tests;
pub mod view;
pub mod words;

pub use camera::Camera;
pub use geometry::{Hit, Method, Ray, Shape};
pub use math::TransformStack;
pub use render::{render_into, LabStep, RenderSettings, RenderStats, Stage};
pub use scene::Scene;
