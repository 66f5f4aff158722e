//! `cargo run -p lab`: raylab's window with your code chosen in the method selector, run under
//! Xvfb (needs `xvfb-run`, `xdotool` and a Vulkan driver; skipped with a loud line where they
//! are missing, except under CI=true).
//!
//! The scene is one triangle 2⁻¹³⁰ across, seen from as close: the lecture's Cramer rule
//! computes det = −d·(e1 × e2), whose cross product of such short edges underflows to 0 in
//! f32, so the plain code misses the whole triangle, which the cracks view paints magenta.

#[path = "../../tests/common/mod.rs"]
mod common;

use common::window::{compare, run_window_with, Around, Run};
use raylab::check::code;
use raylab::render::{LabStep, RenderSettings, Stage, CRACK};
use raylab::scene::ObjFrame;
use raylab::Scene;

/// (Its light 10⁻¹⁸ away: nearer, the lit steps' squared distance underflows f32, which the
/// scene's load warns of, a line more in the panel.)
const TINY: &str =
    "camera 0 0 -3e-39\nlight 0 0 -1e-18\ntri -1e-39 -1e-39 0 1e-39 -1e-39 0 0 1e-39 0\n";

/// Runs the lab's window on the tiny triangle with `script`, and `driver` (real X input)
/// beside it if given; the run and the scene.
fn run_on_tiny(script: &str, driver: Option<&str>) -> Option<(Run, Scene)> {
    let dir = tempfile::tempdir().unwrap();
    let scene_path = dir.path().join("tiny.scene");
    std::fs::write(&scene_path, TINY).unwrap();
    let scene = Scene::open(scene_path.to_str().unwrap(), ObjFrame::Lab).unwrap();
    let arg = [scene_path.to_str().unwrap()];
    let around = match driver {
        Some(driver) => Around::RealInputOn(driver, &scene_path),
        None => Around::Args(&arg),
    };
    let exe = env!("CARGO_BIN_EXE_lab");
    let run = run_window_with(exe, script, dir.path(), &[], around)?;
    Some((run, scene))
}

/// The window's final image quality (indirect light, 2×2 samples) with the cracks view on.
fn final_settings(run: &Run) -> RenderSettings {
    let (_, w, h, _) = run.camera();
    RenderSettings {
        width: w,
        height: h,
        step: LabStep::Indirect,
        spp: 2,
        cracks: true,
        ..Default::default()
    }
}

/// The fraction of the image's pixels that are the cracks view's magenta.
fn magenta(rgba: &[u8]) -> f64 {
    let crack = CRACK.map(raylab::render::linear_to_srgb8);
    let n = rgba.chunks(4).filter(|p| p[..3] == crack).count();
    n as f64 / (rgba.len() / 4) as f64
}

#[test]
fn the_window_draws_your_code_and_the_inspector_shows_its_answer() {
    let script = "100 set cracks on\n200 inspect 400 300\n";
    let Some((run, scene)) = run_on_tiny(script, None) else {
        return;
    };
    assert_eq!(run.fields["code"], "on", "{}", run.stderr);
    // What the window showed is your code's frame: the whole triangle leaks.
    let (camera, w, h, rect) = run.camera();
    let settings = final_settings(&run);
    let mut yours = vec![0; settings.buffer_len()];
    let stage = Stage::from(scene);
    code::render_into_cancellable(
        &lab::YourCode,
        &stage,
        &camera,
        &settings,
        &mut yours,
        &|| false,
    )
    .unwrap();
    assert!(magenta(&yours) > 0.05, "{} magenta", magenta(&yours));
    let (mean, off) = compare(&run.shot, rect, &yours, w, h);
    assert!(mean < 2.0 && off < 0.02, "mean {mean}, off {off}");
    let (raylab, _) = raylab::render::render_image(&stage, &camera, &settings).unwrap();
    assert_eq!(magenta(&raylab), 0.0);
    let (_, off) = compare(&run.shot, rect, &raylab, w, h);
    assert!(
        off > 0.05,
        "raylab's own frame is not what was shown: {off} of the pixels off"
    );
    // The inspector: your ray is raylab's, your code misses, the exact answer hits.
    let ins = &run.inspector;
    assert_eq!(ins["your code d world"], ins["raylab d world"], "{ins:?}");
    assert_eq!(ins["your code hit"], "miss", "{ins:?}");
    assert!(ins["exact hit"].contains("primitive 0"), "{ins:?}");
    assert_eq!(ins["verdict"], "leak");
}

#[test]
fn real_x_input_switches_from_your_code_to_raylab_s_method() {
    // The method drop-down (its place in the panel for a `.scene` file at the window's
    // default size on a 1280x800 screen) lists "your code" after raylab's methods; a real
    // click on its first entry, "adaptive", hands the rays back to raylab: the triangle shows.
    let driver = "xdotool windowfocus --sync $win; \
                  xdotool mousemove --sync 55 580; sleep 0.3; xdotool click 1; sleep 0.6; \
                  xdotool mousemove --sync 40 607; sleep 0.3; xdotool click 1; sleep 0.3";
    let script =
        "100 set cracks on\n12000 key H down\n12010 key H up\n12020 key H down\n12030 key H up\n";
    let Some((run, scene)) = run_on_tiny(script, Some(driver)) else {
        return;
    };
    let f = &run.fields;
    let chosen = (f["code"].as_str(), f["method"].as_str());
    assert_eq!(chosen, ("off", "adaptive"), "{}", run.stderr);
    let (camera, w, h, rect) = run.camera();
    let stage = Stage::from(scene);
    let settings = final_settings(&run);
    let (expected, _) = raylab::render::render_image(&stage, &camera, &settings).unwrap();
    let lit = expected.chunks(4).filter(|p| p[..3] != [0, 0, 0]).count();
    assert!(
        lit > (w * h / 5) as usize,
        "the triangle fills the view: {lit} pixels"
    );
    let (mean, off) = compare(&run.shot, rect, &expected, w, h);
    assert!(mean < 2.0 && off < 0.02, "mean {mean}, off {off}");
}
