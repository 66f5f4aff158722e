//! The window's ray inspector under Xvfb, driven by real X input: the inspector following
//! its pixel as the view changes, and its overlay hidden with it (the cracks view and its
//! steps: cracks.rs).
//!
//! Needs `xvfb-run` and a Vulkan driver (Mesa's lavapipe works without a GPU). Where they are
//! missing the test says so loudly and skips, except under CI=true, where it must run.

use crate::common;

use common::window::{pixels_off_where, run_window_with, segment_distance, Around};
use glam::DVec3;
use raylab::render::{render_image, LabStep, RenderSettings};
use raylab::Camera;
use raylab::Scene;
use std::collections::HashMap;

/// The window under test.
const RAYLAB: &str = env!("CARGO_BIN_EXE_raylab");

fn a_scripts_pixel_off_the_image_is_named_as_given() {
    // A script's `inspect` may name a pixel past the image: the status names that pixel (it
    // named the first pixel past the edge, (W, 10) for (W + 6, 10)).
    let dir = tempfile::tempdir().unwrap();
    let script = "300 inspect 5000 10\n";
    let Some(run) = run_window_with(RAYLAB, script, dir.path(), &[], Around::Nothing) else {
        return;
    };
    let (w, h) = run.view_size();
    let status = (run.stdout.lines())
        .find_map(|l| l.strip_prefix("status: "))
        .unwrap_or_default();
    let expected = format!("cannot inspect: pixel (5000, 10) is outside the {w}x{h} image");
    assert_eq!(status, expected, "{}", run.stderr);
}

fn a_zoom_that_loses_the_inspected_ray_says_so() {
    // Zoomed in until the chosen pixel's ray is off the image: the inspector shows the edge
    // pixel, and the status line says so (it had swapped in another ray without a word).
    // Zoomed in further, the edge pixel shown moves along the edge: the status line follows
    // it (it kept naming the first edge pixel).
    let dir = tempfile::tempdir().unwrap();
    let script = "0 inspect 700 380\n300 wheel 12\n1000 wheel 12\n";
    let Some(run) = run_window_with(RAYLAB, script, dir.path(), &[], Around::Nothing) else {
        return;
    };
    let status = (run.stdout.lines()).find_map(|l| l.strip_prefix("status: "));
    let pixel = run.inspector["pixel"].replace(' ', ", ");
    let said = format!(
        "the ray inspected at pixel (700, 380) lies off the image at this focal length: the \
         inspector shows the edge pixel ({pixel}) until it is back"
    );
    assert_eq!(status, Some(said.as_str()), "{}", run.stderr);
    // (Said once in the log, at the first zoom, of another edge pixel.)
    let first = (run.stderr.lines())
        .find_map(|l| l.split("the inspector shows the edge pixel ").nth(1))
        .unwrap_or_else(|| panic!("no notice logged\n{}", run.stderr));
    assert!(
        !first.starts_with(&format!("({pixel})")),
        "{first}: the second zoom moves the edge pixel"
    );
}

fn a_zoom_that_loses_the_inspected_ray_keeps_an_error_on_the_status_line() {
    // A failed load, then a zoom that loses the inspected ray: the status line keeps the
    // error (the notice, which follows on its own, is logged). (The notice replaced it: a
    // panel opening after a failed load read as "the ray inspected ... lies off the image".)
    let dir = tempfile::tempdir().unwrap();
    let script = "0 inspect 497 420\n100 drop n.obj\n700 wheel 30\n";
    let Some(run) = run_window_with(RAYLAB, script, dir.path(), &[], Around::Nothing) else {
        return;
    };
    let log = &run.stderr;
    let (failed, lost) = (
        log.find("could not load: n.obj"),
        log.find("lies off the image"),
    );
    assert!(
        failed.zip(lost).is_some_and(|(f, l)| f < l),
        "the load failed, then the zoom lost the ray\n{log}"
    );
    let status = (run.stdout.lines()).find_map(|l| l.strip_prefix("status: "));
    assert!(
        status.is_some_and(|s| s.starts_with("could not load: n.obj")),
        "{status:?}\n{log}"
    );
}

fn a_pixel_under_the_inspectors_panel_is_inspected_as_chosen() {
    // A first click near the image's left edge: the inspector's panel opens and crops the
    // image's sides, leaving the pixel under it. The inspector answers that pixel (it showed
    // the crop's edge pixel, another ray, and blamed the focal length), and says where it is.
    let dir = tempfile::tempdir().unwrap();
    let script = "0 inspect 22 400\n";
    let Some(run) = run_window_with(RAYLAB, script, dir.path(), &[], Around::Nothing) else {
        return;
    };
    assert_eq!(run.inspector["pixel"], "22 400", "{}", run.stderr);
    let status = (run.stdout.lines()).find_map(|l| l.strip_prefix("status: "));
    let said = "the pixel inspected, (22, 400), lies off the image's left side, which the ray \
                inspector's panel crops";
    assert!(
        status.is_some_and(|s| s.starts_with(said)),
        "{status:?}\n{}",
        run.stderr
    );
}

fn a_pixel_off_the_image_is_said_once_not_over_what_came_after() {
    // A pixel under the inspector's panel is said so once; lab step 3 chosen after it (a new
    // frame, which the inspector answers again) keeps its own word on the status line (the
    // notice came back at every frame and wiped it).
    let dir = tempfile::tempdir().unwrap();
    let script = "0 inspect 22 400\n800 key 3 down\n850 key 3 up\n";
    let Some(run) = run_window_with(RAYLAB, script, dir.path(), &[], Around::Nothing) else {
        return;
    };
    let log = &run.stderr;
    assert!(log.contains("lies off the image's left side"), "{log}");
    let status = (run.stdout.lines()).find_map(|l| l.strip_prefix("status: "));
    assert_eq!(status, Some("lab step 3 direct"), "{log}");
}

fn the_inspector_comes_back_to_its_pixel_after_a_zoom_that_lost_it() {
    // A pixel inspected, then the view zoomed in 17x (the pixel's ray leaves the image: the
    // inspector shows the edge's pixel meanwhile) and out again: the inspector is back on
    // the pixel chosen, as in a run without the zoom. (It followed from the edge, and came
    // back elsewhere.)
    let pixel_after = |zoom: &str| {
        let dir = tempfile::tempdir().unwrap();
        let script = format!("0 inspect 497 420\n{zoom}");
        let run = run_window_with(RAYLAB, &script, dir.path(), &[], Around::Nothing)?;
        Some((run.inspector["pixel"].clone(), run.stderr))
    };
    let Some((still, _)) = pixel_after("") else {
        return;
    };
    let Some((zoomed, log)) = pixel_after("300 wheel 30\n700 wheel -30\n") else {
        return;
    };
    assert_eq!(zoomed, still, "{log}");
}

/// The library's inspection of the inspected pixel (its `pixel` field) of `scene` from the
/// run's final camera at its final image size, at lab step 5, as `name: value` lines.
fn inspected_by_the_library(run: &common::window::Run, scene: Scene) -> String {
    let (camera, ..) = run.camera();
    let (width, height) = run.view_size();
    let pixel: Vec<u32> = (run.inspector["pixel"].split(' '))
        .map(|x| x.parse().unwrap())
        .collect();
    let settings = RenderSettings {
        width,
        height,
        step: LabStep::Indirect,
        ..Default::default()
    };
    raylab::render::inspect::inspect(&scene.into(), &camera, &settings, pixel[0], pixel[1])
        .unwrap()
        .to_string()
}

/// Every field of `expected` (`name: value` lines) as the window's inspector showed it.
/// `raylab inspect` of one ray (`--pixel X,Y` or `--at X,Y`) of the view file `view`.
pub(super) fn inspect_headless(ray: &[&str], view: &std::path::Path) -> String {
    let out = std::process::Command::new(RAYLAB)
        .arg("inspect")
        .args(ray)
        .arg("--view")
        .arg(view)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    String::from_utf8_lossy(&out.stdout).into_owned()
}

pub(super) fn assert_inspector_shows(ins: &HashMap<String, String>, expected: &str) {
    for line in expected.lines() {
        let (key, value) = line.split_once(": ").unwrap();
        assert_eq!(ins.get(key).map(String::as_str), Some(value), "{key}");
    }
}

/// The status line tells of the pixel the inspector shows, not only of the one clicked: it
/// follows the pixel as the inspector does.
fn assert_status_names_the_inspected_pixel(run: &common::window::Run) {
    let pixel = run.inspector["pixel"].replace(' ', ", ");
    let status = (run.stdout.lines())
        .find_map(|l| l.strip_prefix("status: "))
        .unwrap_or_default();
    assert!(
        status.starts_with(&format!("inspected pixel ({pixel}): ")),
        "the status line says {status:?}, the inspector pixel {pixel}"
    );
}

fn real_x_input_the_inspector_follows_its_pixel_as_the_view_changes() {
    // A click inspects a pixel (the inspector's panel then opens and narrows the image), and W
    // moves the camera: the inspector answers its pixel again for the frame shown, so its
    // fields are the library's for that pixel from the final camera at the final image size,
    // not those of the click.
    let dir = tempfile::tempdir().unwrap();
    let script = "0 await driver-done\n";
    let driver = "xdotool windowfocus --sync $win; xdotool mousemove --sync 700 300; \
                  sleep 0.3; xdotool click 1; sleep 1.5; xdotool keydown w; logged 'W down'; \
                  sleep 0.6; xdotool keyup w";
    let Some(run) = run_window_with(RAYLAB, script, dir.path(), &[], Around::RealInput(driver))
    else {
        return;
    };
    let ins = &run.inspector;
    assert!(
        !ins.is_empty(),
        "the click inspected nothing\n{}",
        run.stderr
    );
    let (camera, w, _, _) = run.camera();
    assert!(camera.position().z > -3.0, "W moved the camera");
    assert_inspector_shows(ins, &inspected_by_the_library(&run, Scene::cornell()));
    // The focal length is the final view's, which the inspector's panel left as it was: the
    // panel crops the image's sides (the click was made on the wider image).
    let f: f64 = ins["uvf"].split(' ').nth(2).unwrap().parse().unwrap();
    let focal = run.nums("focal")[0];
    assert!(
        (f - focal).abs() <= 1e-3 * focal,
        "f {f}, the view's {focal}"
    );
    assert!(focal > w as f64 * 1.2, "f {focal} went with the width {w}");
    assert_status_names_the_inspected_pixel(&run);
}

fn real_x_input_the_inspector_follows_the_light_typed_into_the_panel() {
    // A click inspects a pixel of the blue block; then the light's y is typed into the
    // panel's field (a real click, Ctrl+A, the value, Return) and F5 saves the view: the
    // inspector's fields are the library's for that pixel under the light the view saved.
    // (113, 601) is the Light row's y field on the 1280×800 screen with the inspector open,
    // as docs/screenshot.png shows it.
    let dir = tempfile::tempdir().unwrap();
    let script = "0 await driver-done\n";
    let driver = "xdotool windowfocus --sync $win; xdotool mousemove --sync 680 420; \
                  sleep 0.3; xdotool click 1; sleep 1.5; xdotool mousemove --sync 113 601; \
                  sleep 0.3; xdotool click 1; sleep 0.3; xdotool key ctrl+a; \
                  xdotool type --delay 50 -- -0.95; xdotool key Return; sleep 1.5; \
                  xdotool key F5; logged 'saved view'";
    let Some(run) = run_window_with(RAYLAB, script, dir.path(), &[], Around::RealInput(driver))
    else {
        return;
    };
    let ins = &run.inspector;
    assert!(
        !ins.is_empty(),
        "the click inspected nothing\n{}",
        run.stderr
    );
    let view = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.extension().is_some_and(|e| e == "view"))
        .unwrap_or_else(|| panic!("F5 saved no view\n{}", run.stderr));
    let text = std::fs::read_to_string(&view).unwrap();
    let light: Vec<f32> = (text.lines())
        .find_map(|l| l.strip_prefix("light "))
        .unwrap_or_else(|| panic!("no light in the view: {text}"))
        .split_whitespace()
        .map(|x| x.parse().unwrap())
        .collect();
    assert_eq!(
        light[1], -0.95,
        "the typed light reached the window: {text}"
    );
    let mut lit = Scene::cornell();
    lit.light.position = [light[0], light[1], light[2]];
    let expected = inspected_by_the_library(&run, lit);
    assert_inspector_shows(ins, &expected);
    // And not the answer under the lab's light: the typed light changed what it shows.
    let before = inspected_by_the_library(&run, Scene::cornell());
    assert_ne!(before, expected, "the light moved nothing at this pixel");
}

fn real_x_input_i_hides_the_inspected_ray_with_the_inspector() {
    // A click on the lit floor draws the inspected ray, its ring and its shadow ray over the
    // image; I turns the inspector off, and with it what it drew: the window then shows the
    // headless render of its view and nothing over it.
    let dir = tempfile::tempdir().unwrap();
    let script = "0 await driver-done\n";
    let driver = "xdotool windowfocus --sync $win; xdotool mousemove --sync 680 690; \
                  sleep 0.3; xdotool click 1; sleep 1.5; xdotool key i";
    let Some(run) = run_window_with(RAYLAB, script, dir.path(), &[], Around::RealInput(driver))
    else {
        return;
    };
    assert_eq!(run.fields["inspector"], "off", "{}", run.stderr);
    let ins = &run.inspector;
    assert!(
        ins.get("shadow_ray").is_some_and(|s| s.starts_with("from")),
        "the click met a lit surface: {ins:?}\n{}",
        run.stderr
    );
    // Where the overlay was drawn: the shadow ray from the light to the hit point (2 pixels
    // wide) and the ring around the point. There the window shows the headless render too.
    let ends: Vec<f32> = (ins["shadow_ray"].split(' '))
        .filter_map(|x| x.parse().ok())
        .collect();
    let (camera, w, h, rect) = run.camera();
    let projection = camera.projection(w, h);
    let light = projection.project([ends[0], ends[1], ends[2]]).unwrap();
    let point = projection.project([ends[3], ends[4], ends[5]]).unwrap();
    let settings = RenderSettings {
        width: w,
        height: h,
        step: LabStep::Indirect,
        spp: 2,
        ..Default::default()
    };
    let (expected, _) = render_image(&Scene::cornell().into(), &camera, &settings).unwrap();
    let under = |p: [f64; 2]| {
        let ring = segment_distance(p, point, point) <= 8.0;
        ring || segment_distance(p, light, point) <= 2.0
    };
    let (near, off) = pixels_off_where(&run.shot, rect, &expected, (w, h), under);
    assert!(
        near > 200,
        "the shadow ray runs across the image: {near} pixels"
    );
    assert!(
        off * 20 <= near,
        "{off} of the {near} pixels under the inspector's drawing differ from the headless render"
    );
}

fn real_x_input_click_inspects_the_pixel_under_the_pointer() {
    // A left click (a real X press and release) over the image with the inspector on: the
    // panel's fields are those of the library's inspection of that pixel from the run's
    // camera, and a scripted `inspect` gives the same as the click on the same pixel.
    let dir = tempfile::tempdir().unwrap();
    let script = "0 await driver-done\n";
    // (W moves the camera first and R takes it back to the start, where the click is made.)
    let driver = "xdotool windowfocus --sync $win; xdotool keydown w; logged 'W down'; \
                  sleep 0.3; xdotool keyup w; sleep 0.3; xdotool key r; sleep 0.3; \
                  xdotool mousemove --sync 700 300; sleep 0.3; xdotool click 1";
    let Some(run) = run_window_with(RAYLAB, script, dir.path(), &[], Around::RealInput(driver))
    else {
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
    assert_eq!(
        (w, h),
        run.view_size(),
        "the view F5 writes, not the crop shown"
    );
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
    assert_status_names_the_inspected_pixel(&run);
}

fn real_x_input_clicks_on_windows_over_the_image_do_not_inspect() {
    // With the inspector on, clicks on egui windows drawn over the image are theirs: the
    // shortcuts overlay (H) and its close button, File ▸ Open's dialog and its Cancel button.
    // None inspects a pixel; the click on the image after them does, once. The first click
    // comes with the pointer entering the window onto the overlay, before egui has drawn a
    // frame with the pointer there (it inspected: egui's last frame had the pointer outside).
    // (Positions: the default window on the 1280x800 screen, where the image spans
    // x 358..1151, y 0..697; (1250, 780) is outside the window.)
    let dir = tempfile::tempdir().unwrap();
    let script = "0 await driver-done\n";
    let driver = "xdotool windowfocus --sync $win; xdotool key h; sleep 0.8; \
                  xdotool mousemove --sync 1250 780; sleep 0.3; \
                  xdotool mousemove 700 300 click 1; sleep 0.5; \
                  xdotool mousemove --sync 700 250; sleep 0.3; xdotool click 1; sleep 0.5; \
                  xdotool mousemove --sync 1122 29; sleep 0.3; xdotool click 1; sleep 0.5; \
                  xdotool mousemove --sync 19 11; sleep 0.3; xdotool click 1; sleep 0.8; \
                  xdotool mousemove --sync 78 36; sleep 0.3; xdotool click 1; sleep 1.5; \
                  xdotool mousemove --sync 459 200; sleep 0.3; xdotool click 1; sleep 0.5; \
                  xdotool mousemove --sync 537 367; sleep 0.3; xdotool click 1; sleep 0.8; \
                  xdotool mousemove --sync 1000 600; sleep 0.3; xdotool click 1; \
                  logged '] inspected pixel'";
    let Some(run) = run_window_with(RAYLAB, script, dir.path(), &[], Around::RealInput(driver))
    else {
        return;
    };
    let log = &run.stderr;
    assert_eq!(
        run.fields["help"], "off",
        "the close button closed the overlay\n{log}"
    );
    let inspected: Vec<&str> = (log.lines())
        .filter_map(|l| l.split_once("] inspected pixel ").map(|p| p.1))
        .collect();
    assert_eq!(inspected.len(), 1, "only the last click inspected\n{log}");
    // The last click's pixel: right of and below the middle of the 794x698 image.
    let pixel: Vec<u32> = (inspected[0].split(':').next().unwrap())
        .trim_matches(['(', ')'])
        .split(", ")
        .map(|x| x.parse().unwrap())
        .collect();
    assert!(pixel[0] > 600 && pixel[1] > 550, "{pixel:?}");
}

fn real_x_input_the_status_follows_the_inspector_check_box() {
    // I, I (off, on again), then a real click unticks the panel's check box: the status says
    // the inspector is off, as the check box does. ((15, 378): the check box at the default
    // window on the 1280x800 screen.)
    let dir = tempfile::tempdir().unwrap();
    let script = "0 await driver-done\n";
    let driver = "xdotool windowfocus --sync $win; xdotool key i; sleep 0.3; xdotool key i; \
                  sleep 0.3; xdotool mousemove --sync 15 378; sleep 0.3; xdotool click 1; \
                  sleep 0.5";
    let Some(run) = run_window_with(RAYLAB, script, dir.path(), &[], Around::RealInput(driver))
    else {
        return;
    };
    let log = &run.stderr;
    assert_eq!(
        run.fields["inspector"], "off",
        "the click unticked it\n{log}"
    );
    let status = (run.stdout.lines()).find_map(|l| l.strip_prefix("status: "));
    assert_eq!(status, Some("ray inspector off"), "{log}");
}

fn an_obj_opened_beside_the_inspectors_panel_is_framed_as_without_it() {
    // The camera that frames a model does not depend on the inspector's panel: opened while
    // the panel cropped the image's sides, an OBJ was framed for the crop's width taken as
    // the focal length (the model overflowed the image, and R kept that pose).
    let dir = tempfile::tempdir().unwrap();
    let pyramid = "v -1 1 -1\nv 1 1 -1\nv 1 1 1\nv -1 1 1\nv 0 -1 0\n\
                   f 1 2 3 4\nf 1 2 5\nf 2 3 5\nf 3 4 5\nf 4 1 5\n";
    std::fs::write(dir.path().join("pyramid.obj"), pyramid).unwrap();
    let mut cameras = Vec::new();
    for script in [
        "0 inspect 497 420\n600 drop pyramid.obj\n",
        "600 drop pyramid.obj\n",
    ] {
        let Some(run) = run_window_with(RAYLAB, script, dir.path(), &[], Around::Nothing) else {
            return;
        };
        assert!(
            run.fields["scene"].ends_with("pyramid.obj"),
            "{}",
            run.stderr
        );
        let beside = !run.inspector.is_empty();
        cameras.push((
            beside,
            run.fields["camera"].clone(),
            run.fields["focal"].clone(),
        ));
    }
    assert!(
        cameras[0].0 && !cameras[1].0,
        "the panel beside the first only"
    );
    assert_eq!(cameras[0].1, cameras[1].1, "the framing camera's position");
    assert_eq!(cameras[0].2, cameras[1].2, "the focal length");
}

fn a_selected_push_level_tints_the_image_not_the_inspectors_answer() {
    // Selecting a push level tints what it places on screen; the inspector answers for the
    // scene as `raylab inspect` does (it reported the tint's ρ and colour: a red triangle's
    // ρ 0.9 0.1 0.1 read 0.965 0.327 0.035, as if its colour had been ignored).
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("red.scene");
    let text =
        "cornell\npush\ncolor 0.9 0.1 0.1\ntri -0.3 -0.3 -0.5  0.3 -0.3 -0.5  0 0.3 -0.5\npop\n";
    std::fs::write(&scene, text).unwrap();
    let args = [scene.to_str().unwrap()];
    let mut answers = Vec::new();
    for select in ["", "200 select 1\n"] {
        let script = format!("{select}600 inspect 392 349\n");
        let around = Around::Args(&args);
        let Some(run) = run_window_with(RAYLAB, &script, dir.path(), &[], around) else {
            return;
        };
        assert_eq!(run.inspector["rho"], "0.9 0.1 0.1", "{:?}", run.inspector);
        answers.push(run.inspector);
    }
    assert_eq!(answers[0], answers[1], "the same answer, selected or not");
}

/// This file's tests, by name, for the harness (main.rs).
pub const TESTS: super::Tests = tests![
    a_scripts_pixel_off_the_image_is_named_as_given,
    a_zoom_that_loses_the_inspected_ray_says_so,
    a_zoom_that_loses_the_inspected_ray_keeps_an_error_on_the_status_line,
    a_pixel_under_the_inspectors_panel_is_inspected_as_chosen,
    the_inspector_comes_back_to_its_pixel_after_a_zoom_that_lost_it,
    real_x_input_the_inspector_follows_its_pixel_as_the_view_changes,
    real_x_input_the_inspector_follows_the_light_typed_into_the_panel,
    real_x_input_i_hides_the_inspected_ray_with_the_inspector,
    real_x_input_click_inspects_the_pixel_under_the_pointer,
    a_pixel_off_the_image_is_said_once_not_over_what_came_after,
    real_x_input_clicks_on_windows_over_the_image_do_not_inspect,
    real_x_input_the_status_follows_the_inspector_check_box,
    an_obj_opened_beside_the_inspectors_panel_is_framed_as_without_it,
    a_selected_push_level_tints_the_image_not_the_inspectors_answer,
];
