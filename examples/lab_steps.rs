//! The lab's steps with the library API: build the camera on the transform stack, render the
//! Cornell box once per shading step, and save each as a PNG.
//!
//! `cargo run --release --example lab_steps -- [OUT_DIR]` writes lab_flat.png, lab_direct.png,
//! lab_shadows.png and lab_indirect.png (default: the current directory).

use glam::DVec3;
use raylab::render::{render_image, write_png, LabStep, RenderSettings};
use raylab::{Camera, Scene, TransformStack};
use std::path::PathBuf;

fn main() -> anyhow::Result<()> {
    let out = PathBuf::from(std::env::args().nth(1).unwrap_or_else(|| ".".into()));
    std::fs::create_dir_all(&out)?;
    let scene = raylab::render::Stage::from(Scene::cornell());

    // Step 2, the camera: move back a little and turn 10° to the right, as stack operations.
    let mut stack = TransformStack::new();
    stack
        .translate(DVec3::new(0.0, 0.0, -3.001))
        .rotate_y(10f64.to_radians());
    let position = stack.transform_point(DVec3::ZERO);
    let view = stack.transform_direction(DVec3::Z);
    let (width, height) = (500, 500);
    let camera = Camera::look_to(position, view, DVec3::NEG_Y, width as f64)?;
    println!(
        "camera at {position}, looking along {view}, field of view {:.1}°",
        camera.fov_x(width).to_degrees()
    );

    for step in LabStep::ALL {
        let settings = RenderSettings {
            width,
            height,
            step,
            ..Default::default()
        };
        let (rgba, stats) = render_image(&scene, &camera, &settings)?;
        let path = out.join(format!("lab_{}.png", step.name()));
        write_png(&path, width, height, &rgba)?;
        println!(
            "{:<8} {:<55} {:>7.1} ms -> {}",
            step.name(),
            step.explanation(),
            stats.elapsed.as_secs_f64() * 1e3,
            path.display()
        );
    }
    Ok(())
}
