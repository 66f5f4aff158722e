//! The lab crate: your code ([`yours`]) behind raylab's seam for code that is not its own
//! ([`raylab::check::LabCode`]), so that raylab's window draws with it and its tests grade it.
//! This file only translates between raylab's types and yours; the lab is in src/yours.rs.

pub mod yours;

use raylab::camera::Camera;
use raylab::check::LabCode;
use raylab::geometry::{Hit, Ray, Shape};

/// Your code, as raylab calls it.
#[derive(Clone, Copy, Debug, Default)]
pub struct YourCode;

impl LabCode for YourCode {
    fn name(&self) -> &str {
        "your code"
    }

    fn camera_ray(&self, camera: &Camera, width: u32, height: u32, x: f32, y: f32) -> Ray {
        let world_from_camera = camera.world_from_camera().as_mat4();
        let ray = yours::camera_ray(
            world_from_camera,
            camera.focal as f32,
            (width, height),
            x,
            y,
        );
        Ray::new(ray.origin.to_array(), ray.dir.to_array())
    }

    fn closest_hit(&self, shapes: &[Shape], ray: &Ray, tmin: f32, tmax: f32) -> Option<Hit> {
        let ray = yours::Ray {
            origin: ray.o.into(),
            dir: ray.d.into(),
        };
        let hit = yours::closest_hit(shapes, &ray, tmin, tmax)?;
        Some(Hit {
            t: hit.t,
            prim: hit.index as u32,
            b1: hit.u,
            b2: hit.v,
        })
    }
}
