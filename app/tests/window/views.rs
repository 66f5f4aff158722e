//! The window's views under Xvfb: a view saved (F5, the File menu) renders headless as the
//! window showed it; a view opened (a drop, the command line) sets its camera, light and
//! settings over its own scene.
//!
//! Needs `xvfb-run` and a Vulkan driver (Mesa's lavapipe works without a GPU). Where they are
//! missing the test says so loudly and skips, except under CI=true, where it must run.

use crate::common;

use super::files::{small_scene_and_its_view, PYRAMID};
use common::binary::text;
use common::window::{run_window_with, Around};
use common::{pixels_off, read_png};
use raylab::render::{LabStep, RenderSettings};
use raylab::Scene;
use std::path::Path;
use std::process::Command;

/// The window under test.
const RAYLAB: &str = env!("CARGO_BIN_EXE_raylab");

fn a_saved_view_renders_headless_as_the_window_saved_it() {
    // Move, turn, zoom and light the scene as a user would, press F5 (save the view) and F12
    // (a full-quality screenshot of the same view); `raylab render --view` must give that
    // picture. (At half the window's resolution: with the cracks view on, every sample is
    // checked exactly, in the window, its screenshot and the headless render.)
    let dir = tempfile::tempdir().unwrap();
    let script = "0 scale 0.5\n0 key W down\n250 key W up\n300 key Left down\n500 key Left up\n\
                  550 wheel 2\n600 step shadows\n610 set method moller\n620 set cracks on\n\
                  1500 key F5 down\n1520 key F5 up\n\
                  1600 key F12 down\n1620 key F12 up\n";
    let Some(run) = run_window_with(RAYLAB, script, dir.path(), &[], Around::Nothing) else {
        return;
    };
    let view = saved_as(dir.path(), "raylab-view-", &run.stderr);
    let shot = saved_as(dir.path(), "raylab-1", &run.stderr);
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
    // The focal length itself, which `inspect` takes as written (a field of view gave it
    // back within an ulp: 499.9999999999999 for 500).
    let focal = (text.lines().find_map(|l| l.strip_prefix("focal ")))
        .unwrap_or_else(|| panic!("no focal line: {text}"));
    assert!(!text.contains(" fov "), "{text}");
    let o = Command::new(RAYLAB)
        .args(["inspect", "--pixel", "0,0", "--view"])
        .arg(&view)
        .output()
        .unwrap();
    let out = String::from_utf8_lossy(&o.stdout);
    let uvf = out
        .lines()
        .find(|l| l.starts_with("uvf: "))
        .unwrap_or_default();
    assert!(
        uvf.ends_with(&format!(" {focal}")),
        "{uvf} for focal {focal}\n{out}"
    );
    assert_view_renders_as(&view, &shot);
}

/// The file the run saved in `dir` whose name starts with `prefix` (F12's `raylab-1…png`,
/// F5's `raylab-view-…`).
pub(super) fn saved_as(dir: &Path, prefix: &str, log: &str) -> std::path::PathBuf {
    (std::fs::read_dir(dir).unwrap())
        .map(|e| e.unwrap().path())
        .find(|p| p.file_name().unwrap().to_string_lossy().starts_with(prefix))
        .unwrap_or_else(|| panic!("no {prefix}* in the run's directory\n{log}"))
}

/// `raylab render --view VIEW` is the image `shot` but for at most 0.1% of its pixels (yaw
/// and the field of view pass through degrees: an ulp of camera may move a pixel).
pub(super) fn assert_view_renders_as(view: &Path, shot: &Path) {
    let out = shot.with_file_name("headless.png");
    let o = Command::new(RAYLAB)
        .args(["render", "--view"])
        .arg(view)
        .arg("-o")
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (off, n) = pixels_off(&read_png(shot), &read_png(&out));
    assert!(off * 1000 <= n, "{off} of {n} pixels differ");
}

/// A view of the box from a moved and turned camera, at a fixed size, in the shadows step.
const SHADOWS_VIEW: &str = "scene cornell\ncamera 0.2 -0.1 -2.2 yaw 15 pitch -4\n\
                            light 0.4 -0.6 -0.6\nsize 320 240\nstep shadows\nspp 1\n\
                            method adaptive\ncracks off\n";

/// The window ended on [`SHADOWS_VIEW`]'s camera, step and size.
fn assert_shows_the_shadows_view(run: &common::window::Run) {
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

fn a_dropped_view_file_sets_the_camera_light_and_settings() {
    let dir = tempfile::tempdir().unwrap();
    let view = dir.path().join("v.view");
    std::fs::write(&view, SHADOWS_VIEW).unwrap();
    // (Then the script's `inspect`, a click without a pointer, on the view's fixed size.)
    let script = format!("200 drop {}\n1500 inspect 100 80\n", view.display());
    let Some(run) = run_window_with(RAYLAB, &script, dir.path(), &[], Around::Nothing) else {
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
    // The view has show cracks off: the crack row says so beside its verdict (it said "not
    // marked", as if the view had marked other pixels).
    assert_eq!(ins["crack"], "the centre ray: right (show cracks is off)");
    assert_shows_the_shadows_view(&run);
}

/// `raylab FILE.view` opens a saved view as the File menu and a drop do: its camera, light
/// and settings, then its scene (it said "no triangles", reading the view as a scene).
fn a_views_missing_scene_is_named_with_the_view() {
    // A view whose scene is not there: the error names the view as well as the scene
    // ("could not load: gone.scene: No such file" did not say which file asked for it).
    let dir = tempfile::tempdir().unwrap();
    let view = dir.path().join("mine.view");
    std::fs::write(&view, "scene gone.scene\nsize 320 240\n").unwrap();
    let script = format!("200 drop {}\n", view.display());
    let Some(run) = run_window_with(RAYLAB, &script, dir.path(), &[], Around::Nothing) else {
        return;
    };
    let status = (run.stdout.lines()).find_map(|l| l.strip_prefix("status: "));
    let said = format!(
        "could not load: scene 'gone.scene' of view '{}': gone.scene",
        view.display()
    );
    assert!(
        status.is_some_and(|s| s.starts_with(&said)),
        "{status:?}\n{}",
        run.stderr
    );
}

fn a_view_named_on_the_command_line_opens_as_the_file_menu_opens_it() {
    let dir = tempfile::tempdir().unwrap();
    let view = dir.path().join("v.view");
    std::fs::write(&view, SHADOWS_VIEW).unwrap();
    let view_arg = view.to_str().unwrap().to_string();
    let args = [view_arg.as_str()];
    let Some(run) = run_window_with(
        RAYLAB,
        "1500 inspect 100 80\n",
        dir.path(),
        &[],
        Around::Args(&args),
    ) else {
        return;
    };
    assert_shows_the_shadows_view(&run);
}

fn a_view_without_a_camera_shows_its_scene_from_where_it_starts() {
    // The model shown, the camera moved and turned, a view of it with a light of its own
    // dropped; then a view of it naming no camera and no light: the window frames the model
    // again at the view's size and lights it with its own light, as `raylab render --view`
    // does (it took the lab's camera, from inside the model, and kept the light shown), and
    // its F12 is that render.
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("pyramid.obj");
    std::fs::write(&model, PYRAMID).unwrap();
    let lit = dir.path().join("lit.view");
    std::fs::write(&lit, "scene pyramid.obj\nlight 3 -2 -1\n").unwrap();
    let view = dir.path().join("v.view");
    std::fs::write(
        &view,
        "scene pyramid.obj\nsize 320 240\nstep direct\nspp 1\n",
    )
    .unwrap();
    let script = format!(
        "0 key W down\n300 key W up\n300 key Left down\n500 key Left up\n800 drop {}\n\
         1600 drop {}\n2300 key F12 down\n2320 key F12 up\n",
        lit.display(),
        view.display()
    );
    let args = [model.to_str().unwrap()];
    let Some(run) = run_window_with(RAYLAB, &script, dir.path(), &[], Around::Args(&args)) else {
        return;
    };
    let bounds = Scene::load(&model, raylab::scene::ObjFrame::YUp)
        .unwrap()
        .bounds()
        .unwrap();
    let start = raylab::controller::CameraController::framing(bounds, 320, 240).position;
    let pos = run.nums("camera");
    assert!(
        (0..3).all(|k| (pos[k] - start[k]).abs() < 1e-9),
        "{pos:?}, framing at {start}\n{}",
        run.stderr
    );
    assert_eq!((run.nums("yaw")[0], run.nums("pitch")[0]), (0.0, 0.0));
    let shot = saved_as(dir.path(), "raylab-1", &run.stderr);
    assert_view_renders_as(&view, &shot);
}

fn a_view_dropped_while_a_model_loads_opens_its_own_scene_with_its_camera() {
    // A model dropped, and in the same moment (its load under way) a view of another scene:
    // the view's scene loads after the model, then the view's camera applies to it. (The
    // view's scene was skipped as "not the file shown" and the model's framing camera
    // replaced the view's: the window ended on the model at yaw 0.)
    let dir = tempfile::tempdir().unwrap();
    let view = small_scene_and_its_view(dir.path());
    let model = dir.path().join("pyramid.obj");
    std::fs::write(&model, PYRAMID).unwrap();
    let script = format!("0 drop {}\n0 drop {}\n", model.display(), view.display());
    let Some(run) = run_window_with(RAYLAB, &script, dir.path(), &[], Around::Nothing) else {
        return;
    };
    let log = &run.stderr;
    assert!(log.contains("asked for while a load is under way"), "{log}");
    assert!(log.contains("pyramid.obj (6 primitives)"), "{log}");
    assert!(run.fields["scene"].ends_with("small.scene"), "{log}");
    assert_eq!(run.fields["primitives"], "31", "{log}");
    assert!((run.nums("yaw")[0] - 20.0).abs() < 1e-9, "{log}");
    assert!((run.nums("pitch")[0] + 5.0).abs() < 1e-9, "{log}");
    assert_eq!(run.fields["size"], "320x240");
    assert!(log.contains("loaded view"), "{log}");
    // The fixed 320x240, magnified to fill the image area, shows each pixel as one square of
    // its colour (blended with its neighbours, 1,448 of them varied inside).
    let (_, w, h, rect) = run.camera();
    assert!(rect[2] >= 1.5 * w as f64, "magnified: {rect:?} for {w}x{h}");
    let (flat, varied) = magnified_pixels(&run.shot, rect, (w, h));
    assert!(
        flat > w * h / 2 && varied == 0,
        "{varied} of {} varied",
        flat + varied
    );
}

/// Of the image's pixels the window shows magnified, how many show as one colour and how many
/// vary inside (the screen's pixels whose centres lie well inside an image pixel, between a
/// tenth and nine tenths of it across and down, are compared).
fn magnified_pixels(shot: &(u32, u32, Vec<u8>), rect: [f64; 4], (w, h): (u32, u32)) -> (u32, u32) {
    let (sw, sh, px) = shot;
    let mut colours: std::collections::HashMap<(u32, u32), Vec<[u8; 3]>> = Default::default();
    let inside = |screen: u32, start: f64, size: f64, n: u32| {
        let at = (screen as f64 + 0.5 - start) * n as f64 / size;
        let frac = at - at.floor();
        (at >= 0.0 && at < n as f64 && (0.1..0.9).contains(&frac)).then_some(at as u32)
    };
    for y in 0..*sh {
        let Some(j) = inside(y, rect[1], rect[3], h) else {
            continue;
        };
        for x in 0..*sw {
            let Some(i) = inside(x, rect[0], rect[2], w) else {
                continue;
            };
            let p = &px[4 * (y * sw + x) as usize..][..3];
            colours.entry((i, j)).or_default().push([p[0], p[1], p[2]]);
        }
    }
    let varies = |c: &Vec<[u8; 3]>| c.iter().any(|p| (0..3).any(|k| p[k].abs_diff(c[0][k]) > 1));
    let varied = colours.values().filter(|c| varies(c)).count() as u32;
    (colours.len() as u32 - varied, varied)
}

fn the_command_a_saved_view_names_runs_in_a_shell_from_a_folder_with_a_space() {
    // F5's message names a command that renders the view: its path is quoted for a shell (a
    // folder with a space in its name made it two words, and the command a usage error).
    let top = tempfile::tempdir().unwrap();
    let dir = top.path().join("my views");
    std::fs::create_dir(&dir).unwrap();
    let script = "300 key F5 down\n350 key F5 up\n";
    let Some(run) = run_window_with(RAYLAB, script, &dir, &[], Around::Nothing) else {
        return;
    };
    let log = &run.stderr;
    let said = log
        .lines()
        .find_map(|l| l.split_once("saved view ").map(|s| s.1));
    let said = said.unwrap_or_else(|| panic!("no view saved\n{log}"));
    let command = said.split_once(" (").and_then(|s| s.1.strip_suffix(')'));
    let command = command.unwrap_or_else(|| panic!("no command in {said}"));
    assert!(command.contains("'"), "quoted: {command}");
    let out = top.path().join("out.png");
    let command = command.replacen("raylab ", &format!("{RAYLAB} "), 1);
    let command = command.replace(" -o out.png", &format!(" -o {}", out.display()));
    let o = Command::new("sh").args(["-c", &command]).output().unwrap();
    assert!(o.status.success(), "{command}\n{}", text(&o.stderr));
    assert!(read_png(&out).0 > 0, "rendered");
}

fn real_x_input_a_click_on_f5s_message_copies_its_command() {
    // F5's message names the command that renders the view; a click on the status line
    // copies that command, as after C (it copied the whole sentence), and says so (it said
    // nothing: had it copied?).
    if !common::tool_for("xclip", "xclip", "the saved view's command test") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let script = "0 await driver-done\n";
    // (500, 710): the status line under the image at the default window on 1280x800.
    let driver = "xdotool windowfocus --sync $win; xdotool key F5; logged 'saved view'; \
                  xdotool mousemove --sync 500 710 click 1; logged 'was copied'; \
                  xclip -selection clipboard -o > cmd.txt";
    let Some(run) = run_window_with(RAYLAB, script, dir.path(), &[], Around::RealInput(driver))
    else {
        return;
    };
    let command = std::fs::read_to_string(dir.path().join("cmd.txt")).unwrap();
    assert!(
        command.starts_with("raylab render --view "),
        "{command}\n{}",
        run.stderr
    );
    let status = (run.stdout.lines()).find_map(|l| l.strip_prefix("status: "));
    assert_eq!(
        status,
        Some(format!("copied to the clipboard: {command}").as_str()),
        "{}",
        run.stderr
    );
    let command = command.replacen("raylab ", &format!("{RAYLAB} "), 1);
    let o = Command::new("sh")
        .args(["-c", &command])
        .current_dir(dir.path())
        .output()
        .unwrap();
    assert!(o.status.success(), "{command}\n{}", text(&o.stderr));
    assert!(read_png(&dir.path().join("out.png")).0 > 0, "rendered");
}

fn real_x_input_a_views_size_stays_in_the_resolution_list() {
    // A view at 800x600, a size of no preset: the resolution list offers it beside the presets
    // (it was not listed, and once 640x480 was chosen, the view's size was gone).
    let dir = tempfile::tempdir().unwrap();
    let view = dir.path().join("big.view");
    std::fs::write(&view, "scene cornell\nsize 800 600\n").unwrap();
    let script = "0 await driver-done\n";
    // (57, 439): the list's button at the default window; its items 21 pixels apart below it,
    // the scale of the window first.
    let driver = "xdotool windowfocus --sync $win; \
                  xdotool mousemove --sync 57 439; sleep 0.3; xdotool click 1; sleep 0.8; \
                  xdotool mousemove --sync 44 506; sleep 0.3; xdotool click 1; \
                  logged 'resolution 640x480'; \
                  xdotool mousemove --sync 57 439; sleep 0.3; xdotool click 1; sleep 0.8; \
                  xdotool mousemove --sync 44 527; sleep 0.3; xdotool click 1; \
                  logged 'resolution 800x600'";
    let around = Around::RealInputOn(driver, &view);
    let Some(run) = run_window_with(RAYLAB, script, dir.path(), &[], around) else {
        return;
    };
    assert_eq!(run.fields["size"], "800x600", "{}", run.stderr);
}

/// This file's tests, by name, for the harness (main.rs).
pub const TESTS: super::Tests = tests![
    a_saved_view_renders_headless_as_the_window_saved_it,
    a_dropped_view_file_sets_the_camera_light_and_settings,
    a_views_missing_scene_is_named_with_the_view,
    a_view_named_on_the_command_line_opens_as_the_file_menu_opens_it,
    a_view_without_a_camera_shows_its_scene_from_where_it_starts,
    a_view_dropped_while_a_model_loads_opens_its_own_scene_with_its_camera,
    the_command_a_saved_view_names_runs_in_a_shell_from_a_folder_with_a_space,
    real_x_input_a_click_on_f5s_message_copies_its_command,
    real_x_input_a_views_size_stays_in_the_resolution_list,
];
