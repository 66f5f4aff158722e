//! The real window under Xvfb: a scripted run moves and turns the camera and zooms, and what
//! the window showed must match the headless render of the same final camera.
//!
//! Needs `xvfb-run` and a Vulkan driver (Mesa's lavapipe works without a GPU). Where they are
//! missing the test says so loudly and skips, except under CI=true, where it must run.
#[path = "../../tests/common/mod.rs"]
mod common;

use common::window::{against_headless, compare, Around, Run};
use common::{pixels_off, read_png, run_in_shell};
use glam::DVec3;
use raylab::geometry::Method;
use raylab::render::{render_image, LabStep, RenderSettings};
use raylab::{Camera, Scene};
use std::collections::HashMap;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Runs raylab's window under Xvfb with `script`; None (after saying so) where Xvfb is missing.
fn run_window(script: &str, dir: &std::path::Path) -> Option<Run> {
    run_window_env(script, dir, &[])
}

/// [`run_window`] with extra environment variables.
fn run_window_env(script: &str, dir: &std::path::Path, env: &[(&str, &str)]) -> Option<Run> {
    run_window_with(script, dir, env, Around::Nothing)
}

/// [`run_window_env`] with something running beside the app ([`Around`]).
fn run_window_with(
    script: &str,
    dir: &std::path::Path,
    env: &[(&str, &str)],
    around: Around,
) -> Option<Run> {
    let exe = env!("CARGO_BIN_EXE_raylab");
    common::window::run_window_with(exe, script, dir, env, around)
}

#[test]
fn scripted_window_run_matches_the_headless_render() {
    let dir = tempfile::tempdir().unwrap();
    let script = "# forward, turn right, look up with the mouse, zoom in, switch to shadows, F12\n\
         0 key W down\n300 key W up\n350 key Right down\n600 key Right up\n\
         650 mouse 0 -40\n700 wheel 3\n750 step shadows\n800 key F12 down\n820 key F12 up\n";
    let Some(run) = run_window(script, dir.path()) else {
        return;
    };
    let (camera, w, h, rect) = run.camera();
    let pos = camera.position();
    let (yaw, pitch, focal) = (
        run.nums("yaw")[0],
        run.nums("pitch")[0],
        run.nums("focal")[0],
    );
    assert_eq!(run.fields["step"], "shadows");
    // While W and Right were held, preview frames kept arriving (not cancelled by the motion).
    let moving_frames: u32 = run.fields["moving_frames"].parse().unwrap();
    assert!(
        moving_frames >= 2,
        "only {moving_frames} frames shown while moving"
    );
    assert_eq!(run.fields["scene"], "cornell");
    assert_eq!(
        run.fields["accel"], "flat",
        "auto: the flat loop for the lab's box"
    );

    // The camera really moved, turned, looked up and zoomed.
    assert!(pos.z > -3.0 + 0.1, "moved forward: {pos}");
    assert!(
        pos.x.abs() < 1e-9 && pos.y.abs() < 1e-9,
        "straight ahead: {pos}"
    );
    assert!(yaw > 5.0 && yaw < 60.0, "turned right: {yaw}");
    assert!(
        (pitch - (40.0f64 * 0.003).to_degrees()).abs() < 1e-6,
        "looked up: {pitch}"
    );
    assert!(
        (focal / w as f64 - 1.1f64.powi(3)).abs() < 1e-9,
        "zoomed in: {focal} at {w}"
    );

    // What the window showed is the headless render of that camera.
    let shot = &run.shot;
    assert!(
        rect[0] > 100.0,
        "the image sits beside the panel, not under it: {rect:?}"
    );
    assert!(rect[0] + rect[2] <= shot.0 as f64 + 0.5 && rect[1] + rect[3] <= shot.1 as f64 + 0.5);
    let scene = raylab::render::Stage::from(Scene::cornell());
    let settings = RenderSettings {
        width: w,
        height: h,
        step: LabStep::Shadows,
        spp: 2,
        ..Default::default()
    };
    let (expected, _) = render_image(&scene, &camera, &settings).unwrap();
    let (mean, off) = compare(shot, rect, &expected, w, h);
    println!(
        "window vs headless: mean difference {mean:.2}/255, {:.2}% of pixels off by > 8",
        off * 100.0
    );
    assert!(mean < 2.0 && off < 0.02, "mean {mean}, off {off}");

    // And differs clearly from where the camera started.
    let start_cam =
        Camera::from_yaw_pitch(DVec3::new(0.0, 0.0, -3.001), 0.0, 0.0, w as f64).unwrap();
    let (start_img, _) = render_image(&scene, &start_cam, &settings).unwrap();
    let (mean0, _) = compare(shot, rect, &start_img, w, h);
    assert!(
        mean0 > 10.0 * mean.max(1.0),
        "the start view differs by only {mean0}"
    );

    // F12 saved the same view at full quality, named by time, in the working directory.
    let saved: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            p.file_name()
                .unwrap()
                .to_string_lossy()
                .starts_with("raylab-")
        })
        .collect();
    assert_eq!(saved.len(), 1, "{saved:?}");
    assert!(
        run.stderr.contains("saved ") && run.stderr.contains("raylab-"),
        "{}",
        run.stderr
    );
    let (sw, sh, spx) = read_png(&saved[0]);
    assert_eq!((sw, sh), (w, h));
    assert!(
        spx == expected,
        "the F12 file is the full-quality render of the final view"
    );

    // The panel is drawn left of the image (not black, not the scene).
    let panel_px = &shot.2[4 * (50 * shot.0 + 20) as usize..][..3];
    assert!(
        panel_px.iter().all(|&c| c > 10 && c < 80),
        "panel background {panel_px:?}"
    );
}

#[test]
fn dropped_obj_files_load_and_bad_ones_leave_the_scene_alone() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.obj");
    std::fs::write(&bad, "v 0 0 0\nv 1 0 0\nv 0 nan 0\nf 1 2 3\n").unwrap();
    let good = dir.path().join("pyramid.obj");
    std::fs::write(
        &good,
        "v -1 1 -1\nv 1 1 -1\nv 1 1 1\nv -1 1 1\nv 0 -1 0\nf 1 2 3 4\nf 1 2 5\nf 2 3 5\nf 3 4 5\nf 4 1 5\n",
    )
    .unwrap();
    let script = format!("0 drop {}\n600 drop {}\n", bad.display(), good.display());
    let Some(run) = run_window(&script, dir.path()) else {
        return;
    };
    assert!(
        run.stderr.contains("could not load") && run.stderr.contains("bad.obj:3"),
        "the failed load is reported with file and line: {}",
        run.stderr
    );
    assert!(
        run.fields["scene"].ends_with("pyramid.obj"),
        "{:?}",
        run.fields
    );
    let scene = raylab::scene::load_obj_file(&good, raylab::scene::ObjFrame::YUp).unwrap();
    let (mean, off, expected, w, h) = against_headless(&run, &scene);
    assert!(mean < 2.0 && off < 0.02, "mean {mean}, off {off}");
    // Framed: the model covers the image centre.
    let c = 4 * ((h / 2) * w + w / 2) as usize;
    assert!(
        expected[c..c + 3].iter().any(|&v| v > 30),
        "{:?}",
        &expected[c..c + 3]
    );
}

#[test]
fn resizes_minimise_hidpi_and_rapid_slider_changes() {
    let dir = tempfile::tempdir().unwrap();
    // At 1.5 device pixels per point; small, very large, minimised and restored; the focal
    // slider dragged back and forth every 10 ms while frames render; the scale changed; a
    // draw failing as on a lost surface (the app must report it and draw again).
    let mut script = String::from(
        "0 resize 520 320\n400 resize 2400 1500\n400 scale 0.2\n900 resize 0 0\n1400 restore\n",
    );
    for k in 0..40 {
        let focal = if k % 2 == 0 { 300 } else { 900 };
        script.push_str(&format!("{} focal {focal}\n", 1450 + 10 * k));
    }
    script.push_str("1900 scale 0.6\n1900 resize 900 600\n2300 lose-surface\n");
    let Some(run) = run_window_env(&script, dir.path(), &[("WINIT_X11_SCALE_FACTOR", "1.5")])
    else {
        return;
    };
    for line in [
        "minimised: rendering paused",
        "restored: rendering resumed",
        "the window surface was lost (injected); drawing again",
    ] {
        assert!(run.stderr.contains(line), "{line}: {}", run.stderr);
    }
    let shot = &run.shot;
    assert_eq!(
        (shot.0, shot.1),
        (900, 600),
        "the window took its last size"
    );
    let (_, w, h, rect) = run.camera();
    // The render is 0.6 of the image area, which fills the window right of the panel.
    assert!(
        (rect[2] * 0.6 - w as f64).abs() <= 1.5 && (rect[3] * 0.6 - h as f64).abs() <= 1.5,
        "{w}x{h} in {rect:?}"
    );
    assert!(rect[0] > 150.0, "a 1.5x panel is wider: {rect:?}");
    let (mean, off, ..) = against_headless(&run, &Scene::cornell());
    println!(
        "after the faults: mean difference {mean:.2}/255, {:.2}% off",
        off * 100.0
    );
    assert!(mean < 2.0 && off < 0.02, "mean {mean}, off {off}");
}

#[test]
fn a_desktop_hidpi_change_while_running() {
    // The desktop's DPI goes from 96 to 192 (scale 1 to 2) 2 s into the run, through an
    // XSETTINGS manager as a desktop does it; the panel doubles in device pixels, the image
    // area shrinks, and what is shown is still the headless render of the final view.
    let dir = tempfile::tempdir().unwrap();
    let script = "0 resize 1000 600\n500 key D down\n900 key D up\n3500 focal 600\n";
    let Some(run) = run_window_with(
        script,
        dir.path(),
        &[],
        Around::DpiChange {
            at_ms: 2000,
            dpi: 192,
        },
    ) else {
        return;
    };
    assert!(
        run.stderr.contains("scale factor changed to 2"),
        "no scale factor change reported: {}",
        run.stderr
    );
    // The window keeps its logical size, so it doubles in pixels; so does the panel
    // (about 184 pixels wide at scale 1: the image starts right of it).
    assert_eq!(
        (run.shot.0, run.shot.1),
        (2000, 1200),
        "window after the change"
    );
    let (_, w, h, rect) = run.camera();
    assert!(
        rect[0] > 300.0 && rect[0] < 500.0,
        "panel at scale 2: {rect:?}"
    );
    let (mean, off, ..) = against_headless(&run, &Scene::cornell());
    println!(
        "after the DPI change: {w}x{h} in {rect:?}, mean difference {mean:.2}/255, {:.2}% off",
        off * 100.0
    );
    assert!(mean < 2.0 && off < 0.02, "mean {mean}, off {off}");
}

#[test]
fn real_x_input_moves_turns_and_zooms_the_camera() {
    // Real X events (XTEST, as a user's keyboard and mouse give them), not script events:
    // W held, the wheel over the image, a right-drag over the image. The script only keeps
    // the run alive while the driver works.
    let dir = tempfile::tempdir().unwrap();
    // (The driver waits for the first frames: the wheel and drag must meet a drawn image.)
    let script = "11000 step indirect\n";
    let driver = "xdotool windowfocus --sync $win; \
                  xdotool keydown w; sleep 0.4; xdotool keyup w; sleep 0.3; \
                  xdotool mousemove --sync 730 310; sleep 0.3; \
                  for i in 1 2 3 4 5; do xdotool click 4; sleep 0.05; done; sleep 0.3; \
                  xdotool mousedown 3; sleep 0.2; \
                  for i in $(seq 20); do xdotool mousemove_relative 10 0; sleep 0.02; done; \
                  xdotool mouseup 3";
    let Some(run) = run_window_with(script, dir.path(), &[], Around::RealInput(driver)) else {
        return;
    };
    let pos = run.nums("camera");
    let (yaw, focal) = (run.nums("yaw")[0], run.nums("focal")[0]);
    let width = run.nums("size")[0];
    // The lab camera starts at z = -3.001 looking along +z, focal = the image width.
    assert!(pos[2] > -2.9, "W moved the camera forward: z = {}", pos[2]);
    assert!(
        focal > width * 1.3,
        "5 wheel clicks up over the image zoomed in: focal {focal} for width {width}\n{}",
        run.stderr
    );
    assert!(
        yaw > 5.0,
        "a right-drag to the right over the image turned the view right: yaw {yaw}\n{}",
        run.stderr
    );
}

#[test]
fn a_scene_file_reloads_on_change_keeps_the_camera_and_survives_a_bad_edit() {
    // Opened from a .scene file; the camera moves (W); the file gains a sphere on disk (the
    // window reloads it, keeping the camera); then a broken line (the error is shown and the
    // last good scene stays). A push level selected in the transform-stack tree is tinted.
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("s.scene");
    std::fs::write(
        &scene,
        "cornell\npush\ntranslate 0 0.5 0\nsphere 0 0 0 0.3\npop\n",
    )
    .unwrap();
    let script = "300 key W down\n600 key W up\n1000 select 1\n8000 step indirect\n";
    let driver = "sleep 2.5; printf 'sphere 0.5 0.5 0 0.2\\n' >> s.scene; \
                  sleep 2.5; printf 'sphere 0 0 0\\n' >> s.scene";
    let around = Around::RealInputOn(driver, &scene);
    let Some(run) = run_window_with(script, dir.path(), &[], around) else {
        return;
    };
    let log = &run.stderr;
    assert!(
        log.contains("reloaded") && log.contains("(32 primitives)"),
        "{log}"
    );
    assert!(
        log.contains("could not reload") && log.contains("s.scene:7: sphere needs 4 numbers"),
        "the bad edit is reported with file and line: {log}"
    );
    assert_eq!(run.fields["primitives"], "32", "the last good scene stays");
    let z = run.nums("camera")[2];
    assert!(
        z > -2.9,
        "the camera moved by W stayed through the reloads: z = {z}"
    );
    // The selected level's sphere is tinted orange: r well above g, g well above b.
    let (_, _, _, rect) = run.camera();
    let (sw, _, px) = &run.shot;
    let mut orange = 0;
    for y in rect[1] as u32..(rect[1] + rect[3]) as u32 {
        for x in rect[0] as u32..(rect[0] + rect[2]) as u32 {
            let p = &px[4 * (y * sw + x) as usize..][..3];
            let (r, g, b) = (p[0] as i32, p[1] as i32, p[2] as i32);
            orange += (r > g + 40 && g > b + 40) as u32;
        }
    }
    assert!(orange > 200, "{orange} orange pixels");
}

#[test]
fn a_saved_view_renders_headless_as_the_window_saved_it() {
    // Move, turn, zoom and light the scene as a user would, press F5 (save the view) and F12
    // (a full-quality screenshot of the same view); `raylab render --view` must give that
    // picture.
    let dir = tempfile::tempdir().unwrap();
    let script = "0 key W down\n250 key W up\n300 key Left down\n500 key Left up\n\
                  550 wheel 2\n600 step shadows\n610 set method moller\n620 set cracks on\n\
                  1500 key F5 down\n1520 key F5 up\n\
                  1600 key F12 down\n1620 key F12 up\n";
    let Some(run) = run_window(script, dir.path()) else {
        return;
    };
    let find = |prefix: &str, ext: &str| {
        std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().path())
            .find(|p| {
                let name = p.file_name().unwrap().to_string_lossy().into_owned();
                name.starts_with(prefix) && name.ends_with(ext)
            })
            .unwrap_or_else(|| panic!("no {prefix}*{ext} in the run's directory\n{}", run.stderr))
    };
    let view = find("raylab-view-", ".view");
    let shot = find("raylab-1", ".png");
    assert!(run.stderr.contains("saved view"), "{}", run.stderr);
    let text = std::fs::read_to_string(&view).unwrap();
    assert!(
        text.contains("step shadows") && text.contains("camera "),
        "{text}"
    );
    // The panel's controls, set by the script as its widgets set them, saved with the view.
    assert!(
        text.contains("method moller\n") && text.contains("cracks on\n"),
        "{text}"
    );
    assert_eq!(run.fields["method"], "moller", "{}", run.stderr);
    assert_eq!(run.fields["cracks"], "on", "{}", run.stderr);
    let out = dir.path().join("headless.png");
    let o = Command::new(env!("CARGO_BIN_EXE_raylab"))
        .args(["render", "--view"])
        .arg(&view)
        .arg("-o")
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (off, n) = pixels_off(&read_png(&shot), &read_png(&out));
    // (Yaw and the field of view pass through degrees: an ulp of camera may move a pixel.)
    assert!(off * 1000 <= n, "{off} of {n} pixels differ");
}

#[test]
fn a_dropped_view_file_sets_the_camera_light_and_settings() {
    let dir = tempfile::tempdir().unwrap();
    let view = dir.path().join("v.view");
    std::fs::write(
        &view,
        "scene cornell\ncamera 0.2 -0.1 -2.2 yaw 15 pitch -4\nlight 0.4 -0.6 -0.6\n\
         size 320 240\nstep shadows\nspp 1\nmethod adaptive\ncracks off\n",
    )
    .unwrap();
    // (Then the script's `inspect`, a click without a pointer, on the view's fixed size.)
    let script = format!("200 drop {}\n1500 inspect 100 80\n", view.display());
    let Some(run) = run_window(&script, dir.path()) else {
        return;
    };
    assert!(run.stderr.contains("loaded view"), "{}", run.stderr);
    // The inspection printed is the library's of that pixel from the view's camera (through
    // degrees: t to 1e-6).
    let (camera, w, h, _) = run.camera();
    let settings = RenderSettings {
        width: w,
        height: h,
        step: LabStep::Shadows,
        ..Default::default()
    };
    let expected =
        raylab::render::inspect::inspect(&Scene::cornell().into(), &camera, &settings, 100, 80)
            .unwrap();
    let hit = expected
        .hit
        .as_ref()
        .expect("pixel (100, 80) shows the box");
    let ins = &run.inspector;
    assert_eq!(ins["pixel"], "100 80", "{}", run.stderr);
    assert_eq!(ins["uvf"], format!("-59.5 -39.5 {}", camera.focal));
    assert_eq!(ins["hit"], hit.prim.to_string(), "{ins:?}\n{expected}");
    let t: f32 = ins["t"].parse().unwrap();
    assert!((t - hit.t).abs() <= 1e-6 * hit.t, "t {t} vs {}", hit.t);
    let pos = run.nums("camera");
    let close = |a: f64, b: f64| (a - b).abs() < 1e-9;
    assert!(
        close(pos[0], 0.2) && close(pos[1], -0.1) && close(pos[2], -2.2),
        "{pos:?}"
    );
    assert!(close(run.nums("yaw")[0], 15.0) && close(run.nums("pitch")[0], -4.0));
    assert_eq!(run.fields["step"], "shadows");
    assert_eq!(run.fields["size"], "320x240");
}

#[test]
fn real_x_input_orbits_with_tab_and_a_left_drag() {
    // Tab switches to orbit around the box centre; a left-drag across the image turns the
    // camera around it at the same distance (3.001).
    let dir = tempfile::tempdir().unwrap();
    // (The driver waits for the first frames: the drag must start over a drawn image, and a
    // fresh CI machine under lavapipe can take seconds to draw one.)
    let script = "12000 step indirect\n";
    let driver = "xdotool windowfocus --sync $win; sleep 0.3; xdotool key Tab; sleep 0.3; \
                  xdotool mousemove --sync 600 310; sleep 0.2; xdotool mousedown 1; sleep 0.2; \
                  for i in $(seq 20); do xdotool mousemove_relative 10 0; sleep 0.02; done; \
                  xdotool mouseup 1";
    let Some(run) = run_window_with(script, dir.path(), &[], Around::RealInput(driver)) else {
        return;
    };
    let pos = run.nums("camera");
    let dist = (pos[0] * pos[0] + pos[1] * pos[1] + pos[2] * pos[2]).sqrt();
    let yaw = run.nums("yaw")[0];
    assert!(
        (dist - 3.001).abs() < 1e-6,
        "distance to the centre {dist}\n{}",
        run.stderr
    );
    assert!(
        yaw > 20.0,
        "the drag turned the camera around the centre: yaw {yaw}"
    );
    assert!(pos[0] < -1.0, "to the left of the box's axis: {pos:?}");
}

#[test]
fn real_x_input_click_inspects_the_pixel_under_the_pointer() {
    // A left click (a real X press and release) over the image with the inspector on: the
    // panel's fields are those of the library's inspection of that pixel from the run's
    // camera, and a scripted `inspect` gives the same as the click on the same pixel.
    let dir = tempfile::tempdir().unwrap();
    let script = "9000 step indirect\n";
    // (W moves the camera first and R takes it back to the start, where the click is made.)
    let driver = "xdotool windowfocus --sync $win; xdotool keydown w; sleep 0.3; \
                  xdotool keyup w; sleep 0.3; xdotool key r; sleep 0.3; \
                  xdotool mousemove --sync 700 300; sleep 0.3; xdotool click 1";
    let Some(run) = run_window_with(script, dir.path(), &[], Around::RealInput(driver)) else {
        return;
    };
    let ins = &run.inspector;
    assert!(
        !ins.is_empty(),
        "the click inspected nothing\n{}",
        run.stderr
    );
    let pixel: Vec<u32> = ins["pixel"]
        .split(' ')
        .map(|x| x.parse().unwrap())
        .collect();
    // The image size and focal length at the click (the inspector's panel then takes room
    // from the image): u = i + 1/2 - W/2, v = j + 1/2 - H/2.
    let uvf: Vec<f64> = ins["uvf"].split(' ').map(|x| x.parse().unwrap()).collect();
    let w = (2.0 * (pixel[0] as f64 + 0.5 - uvf[0])) as u32;
    let h = (2.0 * (pixel[1] as f64 + 0.5 - uvf[1])) as u32;
    let (pose, ..) = run.camera();
    let lab = DVec3::new(0.0, 0.0, -3.001);
    assert_eq!(pose.position(), lab, "R reset the camera W had moved");
    let camera = Camera::from_yaw_pitch(lab, 0.0, 0.0, uvf[2]).unwrap();
    assert_eq!(pose.forward(), camera.forward(), "the camera did not turn");
    let settings = RenderSettings {
        width: w,
        height: h,
        step: LabStep::Indirect,
        ..Default::default()
    };
    let expected = raylab::render::inspect::inspect(
        &Scene::cornell().into(),
        &camera,
        &settings,
        pixel[0],
        pixel[1],
    )
    .unwrap();
    let expected: HashMap<String, String> = expected
        .to_string()
        .lines()
        .filter_map(|l| l.split_once(": "))
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect();
    for key in [
        "pixel",
        "uvf",
        "hit",
        "t",
        "decided_by",
        "x_tuv",
        "blocked_by",
        "colour",
    ] {
        assert_eq!(ins.get(key), expected.get(key), "{key}");
    }
    // (700, 300) in the window is right of the panel, a little above the middle: on the box.
    assert!(ins["hit"].parse::<u32>().is_ok(), "{:?}", ins.get("hit"));
}

#[test]
fn real_x_input_sets_every_image_control_in_the_panel() {
    // The panel draws one widget per row of the controls table: real clicks on the "direct"
    // radio button, a press on the supersampling slider's rail (egui moves a slider while the
    // button is down, so a press and a release), the "show cracks" check box and the method
    // drop-down's "moller" set them, and the window shows the headless render of those
    // settings. (Positions: the panel at the window's default size on a 1280x800 screen.)
    let dir = tempfile::tempdir().unwrap();
    let script = "12000 key H down\n12010 key H up\n12020 key H down\n12030 key H up\n";
    let driver = "xdotool windowfocus --sync $win; \
                  xdotool mousemove --sync 15 122; sleep 0.3; xdotool click 1; sleep 0.3; \
                  xdotool mousemove --sync 40 529; sleep 0.3; xdotool mousedown 1; sleep 0.3; \
                  xdotool mouseup 1; sleep 0.3; \
                  xdotool mousemove --sync 15 571; sleep 0.3; xdotool click 1; sleep 0.3; \
                  xdotool mousemove --sync 55 550; sleep 0.3; xdotool click 1; sleep 0.6; \
                  xdotool mousemove --sync 40 617; sleep 0.3; xdotool click 1; sleep 0.3";
    let Some(run) = run_window_with(script, dir.path(), &[], Around::RealInput(driver)) else {
        return;
    };
    let f = &run.fields;
    assert_eq!(
        (
            f["step"].as_str(),
            f["method"].as_str(),
            f["cracks"].as_str()
        ),
        ("direct", "moller", "on"),
        "{}",
        run.stderr
    );
    let spp: u32 = f["spp"].parse().unwrap();
    assert!(spp > 2 && spp <= 8, "the press on the slider set spp {spp}");
    let (camera, w, h, rect) = run.camera();
    let settings = RenderSettings {
        width: w,
        height: h,
        step: LabStep::Direct,
        spp,
        method: Method::Moller,
        cracks: true,
        ..Default::default()
    };
    let (expected, _) = render_image(&Scene::cornell().into(), &camera, &settings).unwrap();
    let (mean, off) = compare(&run.shot, rect, &expected, w, h);
    assert!(mean < 2.0 && off < 0.02, "mean {mean}, off {off}");
}

#[test]
fn real_x_input_copy_as_command_renders_what_the_window_shows() {
    // Move (A held), press C (copy as command) and F12 (a full-quality screenshot of the same
    // view); the clipboard, read back with xclip, holds a `raylab render` line that a shell
    // runs to the same picture.
    if !common::tool_for("xclip", "xclip", "the copy-as-command test") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let script = "9000 step indirect\n";
    let driver = "xdotool windowfocus --sync $win; xdotool keydown a; sleep 0.4; \
                  xdotool keyup a; sleep 0.5; xdotool key c; sleep 0.5; xdotool key F12; \
                  sleep 1; xclip -selection clipboard -o > cmd.txt";
    let Some(run) = run_window_with(script, dir.path(), &[], Around::RealInput(driver)) else {
        return;
    };
    let command = std::fs::read_to_string(dir.path().join("cmd.txt")).unwrap();
    assert!(
        command.starts_with("raylab render --scene=cornell --camera=-"),
        "{command}\n{}",
        run.stderr
    );
    let o = run_in_shell(&command, dir.path(), env!("CARGO_BIN_EXE_raylab"));
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let shot = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| {
            p.file_name()
                .unwrap()
                .to_string_lossy()
                .starts_with("raylab-1")
        })
        .unwrap_or_else(|| panic!("no F12 screenshot\n{}", run.stderr));
    let (off, n) = pixels_off(&read_png(&shot), &read_png(&dir.path().join("raylab.png")));
    assert!(off * 1000 <= n, "{off} of {n} pixels differ");
}

#[test]
fn real_x_input_file_menu_saves_an_image_and_opens_a_scene_through_its_dialog() {
    // File > Save image…: the dialog (drawn by egui, so it works under Xvfb) takes a typed
    // name and Return; File > Open scene or OBJ…: a double-click on the only scene file the
    // dialog lists opens it.
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("s.scene"),
        "cornell\nsphere 0.3 0.4 0.2 0.25\nsphere -0.4 0.5 -0.2 0.2\n",
    )
    .unwrap();
    let script = "16000 step indirect\n";
    let driver = "xdotool windowfocus --sync $win; \
                  xdotool mousemove --sync 22 12; sleep 0.3; xdotool click 1; sleep 0.8; \
                  xdotool mousemove --sync 60 57; sleep 0.3; xdotool click 1; sleep 1.5; \
                  xdotool type --delay 50 chosen; sleep 0.3; xdotool key Return; sleep 3; \
                  xdotool mousemove --sync 22 12; sleep 0.3; xdotool click 1; sleep 0.8; \
                  xdotool mousemove --sync 60 36; sleep 0.3; xdotool click 1; sleep 1.5; \
                  xdotool mousemove --sync 300 112; sleep 0.3; \
                  xdotool click --repeat 2 --delay 80 1";
    let Some(run) = run_window_with(script, dir.path(), &[], Around::RealInput(driver)) else {
        return;
    };
    let saved = dir.path().join("chosen.png");
    assert!(saved.exists(), "no chosen.png\n{}", run.stderr);
    let (w, h, _) = read_png(&saved);
    assert!(w > 300 && h > 300, "{w}x{h}");
    assert!(
        run.fields["scene"].ends_with("s.scene") && run.fields["primitives"] == "32",
        "the dialog opened the scene: {:?}\n{}",
        run.fields,
        run.stderr
    );
}

#[test]
fn real_x_input_drives_every_other_key() {
    // The keys the other real-input runs do not press, each checked from the outside: D moves
    // right, then Shift+D 4x as far; Ctrl+E moves up at a quarter of the speed, Q down; S
    // moves back; the four arrows turn; + + - scale the speed; I turns the inspector off, H, F1
    // and H leave the shortcuts shown, F5 saves the view; R is pressed first (from the start pose it changes
    // nothing); Esc once asks before quitting.
    let dir = tempfile::tempdir().unwrap();
    let script = "14000 step indirect\n";
    let driver = "xdotool windowfocus --sync $win; sleep 0.3; xdotool key r; sleep 0.2; \
                  xdotool keydown d; sleep 0.3; xdotool keyup d; sleep 0.2; \
                  xdotool keydown shift keydown d; sleep 0.3; xdotool keyup d keyup shift; \
                  sleep 0.2; xdotool keydown ctrl keydown e; sleep 0.3; \
                  xdotool keyup e keyup ctrl; sleep 0.2; \
                  xdotool keydown q; sleep 0.3; xdotool keyup q; sleep 0.2; \
                  xdotool keydown s; sleep 0.3; xdotool keyup s; sleep 0.2; \
                  xdotool keydown Up; sleep 0.4; xdotool keyup Up; sleep 0.2; \
                  xdotool keydown Down; sleep 0.2; xdotool keyup Down; sleep 0.2; \
                  xdotool keydown Right; sleep 0.4; xdotool keyup Right; sleep 0.2; \
                  xdotool keydown Left; sleep 0.2; xdotool keyup Left; sleep 0.2; \
                  xdotool key plus; xdotool key plus; xdotool key minus; \
                  xdotool key i; xdotool key h; xdotool key F1; xdotool key h; xdotool key F5; \
                  sleep 0.5; \
                  xdotool key Escape";
    let Some(run) = run_window_with(script, dir.path(), &[], Around::RealInput(driver)) else {
        return;
    };
    let pos = run.nums("camera");
    let f = |k: &str| run.fields[k].clone();
    // Half the scene size (12^0.5) per second: D for 0.3 s is about 0.52, with Shift 2.1.
    // The middle-drag then pans left (the scene follows the cursor to the right).
    // Ctrl+E up at a quarter speed (-0.13), then Q down at full speed (+0.52): without Ctrl
    // the sum would be near 0, without Q negative.
    assert!(
        pos[1] > 0.15 && pos[1] < 0.6,
        "Ctrl+E up slowly, Q down: y {}",
        pos[1]
    );
    assert!(pos[2] < -3.3, "S moved back: z {}", pos[2]);
    // Up for 0.4 s then Down for 0.2 s, Right then Left alike: half of the first turn is
    // left (one alone turns about 30°).
    let (pitch, yaw) = (run.nums("pitch")[0], run.nums("yaw")[0]);
    assert!(pitch > 4.0 && pitch < 25.0, "Up then Down: pitch {pitch}");
    assert!(yaw > 4.0 && yaw < 25.0, "Right then Left: yaw {yaw}");
    assert!(
        (run.nums("speed")[0] - 1.25).abs() < 1e-9,
        "+ + -: {}",
        f("speed")
    );
    assert_eq!((f("inspector"), f("help")), ("off".into(), "on".into()));
    let saved = std::fs::read_dir(dir.path())
        .unwrap()
        .any(|e| e.unwrap().file_name().to_string_lossy().ends_with(".view"));
    assert!(saved, "F5 saved a view\n{}", run.stderr);
    assert!(
        run.stderr.contains("press Esc again to quit"),
        "Esc asked first\n{}",
        run.stderr
    );
    // D and Shift+D together moved right well beyond what D alone would (0.5 + 2.1);
    // without Shift it would be about 1.0.
    assert!(pos[0] > 1.6, "Shift made D faster: x {}", pos[0]);
}

#[test]
fn a_huge_dropped_view_is_shown_smaller_and_escape_still_quits() {
    // A view of 16384x8192 at 16x16 samples (34 G rays): the window shows it at the largest
    // size it renders (4072x2036: 8.3 million pixels, the same field of view), keeps its own size for F5, and
    // real Esc presses while it refines quit at once (the refinement stops at its next band).
    let dir = tempfile::tempdir().unwrap();
    let view = dir.path().join("huge.view");
    let text = "scene cornell\ncamera 0 0 -3.001 yaw 0 pitch 0 fov 53\nsize 16384 8192\nspp 16\n";
    std::fs::write(&view, text).unwrap();
    let script = format!("300 drop {}\n60000 step indirect\n", view.display());
    let driver = "xdotool windowfocus --sync $win; sleep 5; xdotool key F5; sleep 1; \
                  xdotool key Escape; sleep 0.3; xdotool key Escape";
    let start = Instant::now();
    let Some(run) = run_window_with(&script, dir.path(), &[], Around::RealInput(driver)) else {
        return;
    };
    let log = &run.stderr;
    assert!(
        run.fields.is_empty(),
        "Esc ended the run before its script\n{log}"
    );
    assert!(
        log.contains("its 16384x8192 shown at 4072x2036 (F5 and copy as command keep 16384x8192)"),
        "{log}"
    );
    assert!(log.contains("press Esc again to quit"), "{log}");
    assert!(
        start.elapsed() < Duration::from_secs(40),
        "{:?}",
        start.elapsed()
    );
    // F5 saved the view at its own size.
    let saved: Vec<String> = (std::fs::read_dir(dir.path()).unwrap())
        .map(|e| e.unwrap().path())
        .filter(|p| {
            p.file_name()
                .unwrap()
                .to_string_lossy()
                .starts_with("raylab-view-")
        })
        .map(|p| std::fs::read_to_string(p).unwrap())
        .collect();
    assert_eq!(saved.len(), 1, "{log}");
    assert!(saved[0].contains("size 16384 8192\n"), "{}", saved[0]);
}

#[test]
fn real_x_input_escape_twice_quits() {
    // With the mouse captured for looking (right button held over the image), Esc releases
    // it; Esc then asks, and Esc again quits at once: the run ends long before its script
    // would (had the first Esc not released the mouse, the third would only ask).
    let dir = tempfile::tempdir().unwrap();
    let script = "20000 step indirect\n";
    let driver = "xdotool windowfocus --sync $win; xdotool mousemove --sync 800 400; \
                  sleep 0.2; xdotool mousedown 3; sleep 0.3; xdotool key Escape; sleep 0.3; \
                  xdotool key Escape; sleep 0.5; xdotool key Escape; sleep 0.2; \
                  xdotool mouseup 3";
    let start = Instant::now();
    let Some(run) = run_window_with(script, dir.path(), &[], Around::RealInput(driver)) else {
        return;
    };
    assert!(
        run.fields.is_empty(),
        "the run ended without finishing its script"
    );
    let log = &run.stderr;
    let on = log.find("mouse look on");
    let off = on.and_then(|i| log[i..].find("mouse look off").map(|j| i + j));
    let ask = log.find("press Esc again to quit");
    assert!(
        on.is_some() && on < off && off < ask,
        "the right button captured the mouse, Esc released it, then Esc asked\n{log}"
    );
    assert!(
        start.elapsed() < Duration::from_secs(18),
        "{:?}",
        start.elapsed()
    );
}

#[test]
fn real_x_input_middle_drag_pans_in_orbit_mode() {
    // Tab, then a middle-drag 100 pixels to the right over the image: the scene follows the
    // cursor, so the camera (and its target) move left, keeping height and depth.
    let dir = tempfile::tempdir().unwrap();
    let script = "9000 step indirect\n";
    let driver = "xdotool windowfocus --sync $win; sleep 0.3; xdotool key Tab; sleep 0.3; \
                  xdotool mousemove --sync 800 400; sleep 0.2; xdotool mousedown 2; sleep 0.2; \
                  for i in $(seq 10); do xdotool mousemove_relative 10 0; sleep 0.02; done; \
                  xdotool mouseup 2";
    let Some(run) = run_window_with(script, dir.path(), &[], Around::RealInput(driver)) else {
        return;
    };
    let pos = run.nums("camera");
    assert_eq!(run.fields["mode"], "orbit");
    assert!(
        pos[0] < -0.05,
        "the camera panned left: x {}\n{}",
        pos[0],
        run.stderr
    );
    assert!(
        pos[1].abs() < 1e-9 && (pos[2] + 3.001).abs() < 1e-9,
        "{pos:?}"
    );
    assert!(run.nums("yaw")[0].abs() < 1e-9, "a pan does not turn");
}

#[test]
fn real_x_input_keys_still_move_the_camera_after_tab() {
    // Tab twice (orbit, then fly again), then W: egui once took Tab to move its keyboard focus
    // to a panel widget, and the app ignored every key while any widget had focus, so the
    // second Tab and W did nothing.
    let dir = tempfile::tempdir().unwrap();
    let script = "8000 step indirect\n";
    let driver = "xdotool windowfocus --sync $win; sleep 0.3; xdotool key Tab; sleep 0.5; \
                  xdotool key Tab; sleep 0.5; xdotool keydown w; sleep 0.4; xdotool keyup w";
    let Some(run) = run_window_with(script, dir.path(), &[], Around::RealInput(driver)) else {
        return;
    };
    assert_eq!(
        run.fields["mode"], "fly",
        "the second Tab switched back\n{}",
        run.stderr
    );
    assert!(
        run.nums("camera")[2] > -2.9,
        "W moved the camera: {:?}",
        run.fields
    );
}

#[test]
fn an_instanced_scene_opens_and_a_selected_instance_is_tinted() {
    // A .scene placing one mesh (the repo's icosphere, 1,280 triangles) three times in the
    // Cornell box: the window loads it as instances (one stored mesh), draws it as the
    // headless renderer does, and selecting the push level of one placement tints that ball.
    let dir = tempfile::tempdir().unwrap();
    let mesh = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../assets/meshes/icosphere.obj"
    );
    std::fs::copy(mesh, dir.path().join("ball.obj")).unwrap();
    let scene = dir.path().join("balls.scene");
    std::fs::write(
        &scene,
        "cornell\ncolor 0.2 0.5 0.9\n\
         push\ntranslate -0.55 0.7 -0.55\nscale 0.3\nmesh ball.obj\npop\n\
         push\ntranslate 0.05 0.7 -0.75\nscale 0.3\nmesh ball.obj\npop\n\
         push\ntranslate 0.6 0.7 -0.6\nscale 0.3\nmesh ball.obj\npop\n",
    )
    .unwrap();
    let loaded = raylab::scene::load_scene_file(&scene).unwrap();
    assert_eq!(loaded.instances().len(), 3);
    let script = "1500 select 2\n4000 step indirect\n";
    let Some(run) = run_window_with(script, dir.path(), &[], Around::RealInputOn("true", &scene))
    else {
        return;
    };
    assert_eq!(run.fields["primitives"], (30 + 3 * 1280).to_string());
    // The middle ball (level 2) is tinted orange; the others stay blue.
    let (_, _, _, rect) = run.camera();
    let (sw, _, px) = &run.shot;
    let (mut orange, mut blue) = (0, 0);
    for y in rect[1] as u32..(rect[1] + rect[3]) as u32 {
        for x in rect[0] as u32..(rect[0] + rect[2]) as u32 {
            let p = &px[4 * (y * sw + x) as usize..][..3];
            let (r, g, b) = (p[0] as i32, p[1] as i32, p[2] as i32);
            orange += (r > g + 40 && g > b + 40) as u32;
            blue += (b > r + 60 && b > g + 20) as u32;
        }
    }
    assert!(orange > 500, "{orange} orange pixels");
    assert!(blue > 1000, "{blue} blue pixels");
}

#[test]
fn the_window_never_saves_a_screenshot_over_the_model_it_opened() {
    if !common::tool_for(
        "xvfb-run",
        "xvfb xauth mesa-vulkan-drivers",
        "the window test",
    ) {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("tri.obj");
    let obj = b"v -1 -1 0\nv 1 -1 0\nv 0 1 0\nf 1 2 3\n";
    std::fs::write(&model, obj).unwrap();
    let link = dir.path().join("shot.png");
    std::os::unix::fs::symlink(&model, &link).unwrap();
    for shot in [&model, &link] {
        let o = Command::new("xvfb-run")
            .args(["-a", "-s", "-screen 0 1280x800x24"])
            .arg(env!("CARGO_BIN_EXE_raylab"))
            .arg(&model)
            .args(["--frames", "3", "--screenshot"])
            .arg(shot)
            .env("RUST_LOG", "warn")
            .stdin(Stdio::null())
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{err}");
        assert!(err.contains("refusing to overwrite an input"), "{err}");
        assert_eq!(
            std::fs::read(&model).unwrap(),
            obj,
            "the model is as it was"
        );
    }
    let mut names: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    names.sort();
    assert_eq!(names, ["shot.png", "tri.obj"], "no temporary file left");
}

#[test]
fn the_window_opens_cornell_by_name_as_the_command_line_does() {
    if !common::tool_for(
        "xvfb-run",
        "xvfb xauth mesa-vulkan-drivers",
        "the window test",
    ) {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let shot = dir.path().join("shot.png");
    let o = Command::new("xvfb-run")
        .args(["-a", "-s", "-screen 0 1280x800x24"])
        .arg(env!("CARGO_BIN_EXE_raylab"))
        .args(["cornell", "--frames", "2", "--screenshot"])
        .arg(&shot)
        .env("RUST_LOG", "warn")
        .stdin(Stdio::null())
        .output()
        .unwrap();
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(out.contains("primitives=30"), "the lab's box: {out}");
    let (w, h, _) = read_png(&shot);
    assert!(w > 0 && h > 0);
}

#[test]
fn the_window_builds_the_structure_accel_names() {
    // `raylab --accel bvh`: the lab's box through a BVH (auto picks the flat loop), the same
    // image as the headless render of the final view.
    let dir = tempfile::tempdir().unwrap();
    let Some(run) = run_window_with("", dir.path(), &[], Around::Args(&["--accel", "bvh"])) else {
        return;
    };
    assert_eq!(run.fields["accel"], "bvh");
    let (mean, off, ..) = against_headless(&run, &Scene::cornell());
    assert!(mean < 2.0 && off < 0.02, "mean {mean}, off {off}");
}

/// `raylab FILE.view` opens a saved view as the File menu and a drop do: its camera, light
/// and settings, then its scene (it said "no triangles", reading the view as a scene).
#[test]
fn a_view_named_on_the_command_line_opens_as_the_file_menu_opens_it() {
    let dir = tempfile::tempdir().unwrap();
    let view = dir.path().join("v.view");
    std::fs::write(
        &view,
        "scene cornell\ncamera 0.2 -0.1 -2.2 yaw 15 pitch -4\nlight 0.4 -0.6 -0.6\n\
         size 320 240\nstep shadows\nspp 1\nmethod adaptive\ncracks off\n",
    )
    .unwrap();
    let view_arg = view.to_str().unwrap().to_string();
    let args = [view_arg.as_str()];
    let Some(run) = run_window_with(
        "1500 inspect 100 80\n",
        dir.path(),
        &[],
        Around::Args(&args),
    ) else {
        return;
    };
    let pos = run.nums("camera");
    let close = |a: f64, b: f64| (a - b).abs() < 1e-9;
    assert!(
        close(pos[0], 0.2) && close(pos[1], -0.1) && close(pos[2], -2.2),
        "{pos:?} {}",
        run.stderr
    );
    assert!(close(run.nums("yaw")[0], 15.0) && close(run.nums("pitch")[0], -4.0));
    assert_eq!(run.fields["step"], "shadows");
    assert_eq!(run.fields["size"], "320x240");
}
