//! The window's files under Xvfb: models and scenes opened from the command line, the File
//! menu, a drop or hot reload; images saved; never an input overwritten (views: views.rs).
//!
//! Needs `xvfb-run` and a Vulkan driver (Mesa's lavapipe works without a GPU). Where they are
//! missing the test says so loudly and skips, except under CI=true, where it must run.

use crate::common;

use common::binary::text;
use common::read_png;
use common::window::{against_headless, run_window_with, Around};
use raylab::Scene;
use std::path::Path;
use std::process::Stdio;

/// The window under test.
const RAYLAB: &str = env!("CARGO_BIN_EXE_raylab");

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
    let Some(run) = run_window_with(RAYLAB, &script, dir.path(), &[], Around::Nothing) else {
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
    // The panel's path field names the file dropped (its Load loaded an older one).
    let field = (run.stdout.lines()).find_map(|l| l.strip_prefix("path field: "));
    assert_eq!(field, good.to_str(), "{}", run.stdout);
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

fn cornell_opened_after_a_scene_file_takes_the_labs_camera_and_light() {
    // `cornell` typed in the path field (or dropped) after a scene file with its own camera
    // and light showed the box from that scene's camera, lit by its light, R going back to
    // it, and the status still named the scene file. As an opened file, it takes the lab's.
    let dir = tempfile::tempdir().unwrap();
    let ball = dir.path().join("ball.scene");
    std::fs::write(
        &ball,
        "sphere 0 0 0 1\nlight 3 -5 -5\ncamera 0 0 -10 yaw 5\n",
    )
    .unwrap();
    let script = format!(
        "0 drop {}\n1500 drop cornell\n2500 key R down\n2550 key R up\n2800 key F5 down\n\
         2850 key F5 up\n",
        ball.display()
    );
    let Some(run) = run_window_with(RAYLAB, &script, dir.path(), &[], Around::Nothing) else {
        return;
    };
    assert_eq!(run.fields["scene"], "cornell", "{}", run.stderr);
    assert_eq!(run.nums("camera"), [0.0, 0.0, -3.001], "{}", run.stderr);
    assert_eq!(run.nums("yaw"), [0.0]);
    assert!(
        run.stderr.contains("loaded cornell (30 primitives)"),
        "the status names the box: {}",
        run.stderr
    );
    let view = (std::fs::read_dir(dir.path()).unwrap())
        .map(|e| e.unwrap().path())
        .find(|p| p.extension().is_some_and(|e| e == "view"))
        .unwrap_or_else(|| panic!("no view saved\n{}", run.stderr));
    let text = std::fs::read_to_string(&view).unwrap();
    assert!(text.contains("light 0 -0.5 -0.7"), "{text}");
}

fn a_scene_file_reloads_on_change_keeps_the_camera_and_survives_a_bad_edit() {
    // Opened from a .scene file; the camera moves (W); the file gains a sphere on disk (the
    // window reloads it, keeping the camera, its moves scaled to the scene's new size); then
    // a broken line (the error is shown and the last good scene stays). A push level selected
    // in the transform-stack tree is tinted.
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("s.scene");
    std::fs::write(
        &scene,
        "cornell\npush\ntranslate 0 0.5 0\nsphere 0 0 0 0.3\npop\n",
    )
    .unwrap();
    // (The driver starts with the first image, on or after the script's clock: the first
    // edit comes after the selection. Each edit waits for the window to have read the one
    // before.)
    let script = "300 key W down\n600 key W up\n1000 select 1\n1000 await driver-done\n";
    let driver = "sleep 1; printf 'sphere 20 0 0 1\\n' >> s.scene; \
                  logged 'reloaded '; printf 'sphere 0 0 0\\n' >> s.scene; \
                  logged 'could not reload'";
    let around = Around::RealInputOn(driver, &scene);
    let Some(run) = run_window_with(RAYLAB, script, dir.path(), &[], around) else {
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
    // (The size moves scale with: the box's 2√3 was kept, a tenth of the grown scene's.)
    let grown = dir.path().join("grown.scene");
    let text = "cornell\npush\ntranslate 0 0.5 0\nsphere 0 0 0 0.3\npop\nsphere 20 0 0 1\n";
    std::fs::write(&grown, text).unwrap();
    let size = raylab::scene::file::load_scene_file(&grown).unwrap().size();
    assert!(size > 20.0, "{size}");
    assert_eq!(
        run.nums("scene_size"),
        [size],
        "moves scale with the reloaded scene"
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

fn a_scene_reloads_when_a_mesh_it_places_changes() {
    // A .scene file placing an OBJ twice (instanced): the OBJ gains a triangle on disk and
    // the window reloads the scene, 2 + 2 primitives more (it watched the .scene alone: the
    // old mesh stayed on screen, where the same OBJ opened alone reloaded).
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("tri.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    )
    .unwrap();
    let scene = dir.path().join("s.scene");
    let text = "cornell\nmesh tri.obj lab\npush\ntranslate 0 0.5 0\nmesh tri.obj lab\npop\n";
    std::fs::write(&scene, text).unwrap();
    let script = "0 await driver-done\n";
    let driver = "sleep 1; printf 'v 0 0 1\\nf 1 2 4\\n' >> tri.obj; logged 'reloaded '";
    let around = Around::RealInputOn(driver, &scene);
    let Some(run) = run_window_with(RAYLAB, script, dir.path(), &[], around) else {
        return;
    };
    let log = &run.stderr;
    assert!(
        log.contains("reloaded") && log.contains("(34 primitives)"),
        "{log}"
    );
    assert_eq!(run.fields["primitives"], "34", "{log}");
}

fn real_x_input_the_transform_stack_opened_keeps_the_panels_width() {
    // transform_stack.scene's tree opened by a real click on its header (at (60, 152)): its
    // rows, one under a level counting its nested levels' primitives too, leave the side
    // panel its width (that count beside the row widened it 368 -> 379 points, and the image
    // narrowed for good).
    let dir = tempfile::tempdir().unwrap();
    let scene =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/scenes/transform_stack.scene");
    let script = "0 await driver-done\n";
    let driver = "xdotool windowfocus --sync $win; xdotool mousemove --sync 60 152 click 1; \
                  sleep 1.5";
    let Some(run) = run_window_with(
        RAYLAB,
        script,
        dir.path(),
        &[],
        Around::RealInputOn(driver, &scene),
    ) else {
        return;
    };
    let log = &run.stderr;
    let widths: Vec<f64> = (log.lines())
        .filter_map(|l| l.split_once("side panel ")?.1.split_once(" points wide"))
        .map(|(w, _)| w.parse().unwrap())
        .collect();
    assert!(!widths.is_empty(), "{log}");
    assert_eq!(run.nums("panel_width"), [widths[0]], "{widths:?}\n{log}");
}

fn a_scene_that_failed_to_open_opens_once_fixed() {
    // A dropped .scene file with a broken line fails to open (the Cornell box stays); fixed
    // on disk, it opens (it was not watched: nothing happened until it was loaded again).
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("b.scene"), "sphere 0 0 0\n").unwrap();
    let script = "0 drop b.scene\n0 await driver-done\n";
    let driver = "logged 'could not load'; sleep 0.5; printf 'sphere 0 0 0 1\\n' > b.scene; \
                  logged 'opened again'; logged 'loaded b.scene (1 primitive)'";
    let around = Around::RealInput(driver);
    let Some(run) = run_window_with(RAYLAB, script, dir.path(), &[], around) else {
        return;
    };
    let log = &run.stderr;
    assert!(log.contains("b.scene:1: sphere needs 4 numbers"), "{log}");
    assert_eq!(run.fields["primitives"], "1", "{log}");
}

fn real_x_input_file_menu_saves_an_image_and_opens_a_scene_through_its_dialog() {
    // File > Save image…: the dialog (drawn by egui, so it works under Xvfb) takes a typed
    // name and Return; File > Open scene, OBJ or view…: the only scene file the dialog lists,
    // clicked, opens with Return. (Not a double-click: egui times a click by the UI pass that
    // takes it, so on a loaded machine two quick clicks are two single ones.)
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("s.scene"),
        "cornell\nsphere 0.3 0.4 0.2 0.25\nsphere -0.4 0.5 -0.2 0.2\n",
    )
    .unwrap();
    let script = "0 await driver-done\n";
    let driver = "xdotool windowfocus --sync $win; \
                  xdotool mousemove --sync 22 12; sleep 0.3; xdotool click 1; sleep 0.8; \
                  xdotool mousemove --sync 60 57; sleep 0.3; xdotool click 1; sleep 1.5; \
                  xdotool type --delay 50 chosen; sleep 0.3; xdotool key Return; \
                  logged '] saved '; \
                  xdotool mousemove --sync 22 12; sleep 0.3; xdotool click 1; sleep 0.8; \
                  xdotool mousemove --sync 60 36; sleep 0.3; xdotool click 1; sleep 1.5; \
                  xdotool mousemove --sync 300 112; sleep 0.3; xdotool click 1; sleep 0.8; \
                  xdotool key Return; logged 's.scene (32 primitives)'";
    let Some(run) = run_window_with(RAYLAB, script, dir.path(), &[], Around::RealInput(driver))
    else {
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

fn real_x_input_keys_typed_in_the_file_dialog_are_the_dialogs() {
    // File > Open scene, OBJ or view…, a file of the list clicked, then 3 and w: the first key went
    // both to the dialog's search box and to the window (lab step 3, or the camera moving).
    // While the dialog is open every key is its own. Then the path typed into the dialog's path
    // field (its pencil) and Return at once, as a quick typist does: the dialog read the Return
    // before the characters typed with it, and opened the folder `/`.
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("s.scene"), "cornell\nsphere 0 0 0 0.2\n").unwrap();
    let script = "0 await driver-done\n";
    let driver = "xdotool windowfocus --sync $win; \
                  xdotool mousemove --sync 22 12; sleep 0.3; xdotool click 1; sleep 0.8; \
                  xdotool mousemove --sync 60 36; sleep 0.3; xdotool click 1; sleep 1.5; \
                  xdotool mousemove --sync 300 112; sleep 0.3; xdotool click 1; sleep 0.5; \
                  xdotool key 3; sleep 0.3; xdotool keydown w; sleep 0.4; xdotool keyup w; \
                  sleep 0.5; xdotool mousemove --sync 458 73; sleep 0.3; xdotool click 1; \
                  sleep 0.8; xdotool key ctrl+a BackSpace; sleep 0.3; \
                  xdotool type --delay 0 \"$PWD/s.scene\"; xdotool key Return; \
                  logged 's.scene (31 primitives)'";
    let Some(run) = run_window_with(RAYLAB, script, dir.path(), &[], Around::RealInput(driver))
    else {
        return;
    };
    assert!(
        run.stdout.contains(" step=indirect "),
        "{}\n{}",
        run.stdout,
        run.stderr
    );
    assert!(!run.stderr.contains("lab step 3"), "{}", run.stderr);
    assert_eq!(run.nums("camera"), [0.0, 0.0, -3.001], "{}", run.stderr);
    assert!(run.fields["scene"].ends_with("s.scene"), "{}", run.stderr);
}

fn a_selected_level_tints_what_its_nested_levels_place_too() {
    // The outer push moves the ball its inner push places: selected, it tints the ball (it
    // tinted only what it placed itself, here nothing, and the image did not change).
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("nested.scene");
    let text = "cornell\ncolor 0.75 0.75 0.75\npush\ntranslate 0 0.4 -0.5\npush\n\
                sphere 0 0 0 0.4\npop\npop\n";
    std::fs::write(&scene, text).unwrap();
    let args = [scene.to_str().unwrap()];
    let Some(run) = run_window_with(
        RAYLAB,
        "500 select 1\n",
        dir.path(),
        &[],
        Around::Args(&args),
    ) else {
        return;
    };
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
    assert!(orange > 2000, "{orange} orange pixels\n{}", run.stderr);
}

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
    // (The scene named on the command line is loaded before the window opens.)
    let script = "500 select 2\n";
    let args = [scene.to_str().unwrap()];
    let Some(run) = run_window_with(RAYLAB, script, dir.path(), &[], Around::Args(&args)) else {
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

fn the_window_never_saves_a_screenshot_over_the_model_it_opened() {
    if !common::window::xvfb_for("the window test") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("tri.obj");
    let obj = b"v -1 -1 0\nv 1 -1 0\nv 0 1 0\nf 1 2 3\n";
    std::fs::write(&model, obj).unwrap();
    let link = dir.path().join("shot.png");
    std::os::unix::fs::symlink(&model, &link).unwrap();
    for shot in [&model, &link] {
        let o = common::window::one_window()
            .xvfb_run()
            .args(["-s", "-screen 0 1280x800x24"])
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

fn the_window_opens_cornell_by_name_as_the_command_line_does() {
    if !common::window::xvfb_for("the window test") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let shot = dir.path().join("shot.png");
    let o = common::window::one_window()
        .xvfb_run()
        .args(["-s", "-screen 0 1280x800x24"])
        .arg(env!("CARGO_BIN_EXE_raylab"))
        .args(["cornell", "--frames", "2", "--screenshot"])
        .arg(&shot)
        .env_remove("RUST_LOG")
        .stdin(Stdio::null())
        .output()
        .unwrap();
    let (out, err) = (text(&o.stdout), text(&o.stderr));
    assert!(o.status.success(), "{err}");
    assert!(out.contains("primitives=30"), "the lab's box: {out}");
    // The default log (no RUST_LOG) leaves out egui-wgpu's note on the sRGB surface, which
    // the window chose on purpose.
    assert!(!err.contains("egui_wgpu"), "{err}");
    let (w, h, _) = read_png(&shot);
    assert!(w > 0 && h > 0);
}

fn the_window_builds_the_structure_accel_names() {
    // `raylab --accel bvh`: the lab's box through a BVH (auto picks the flat loop), the same
    // image as the headless render of the final view.
    let dir = tempfile::tempdir().unwrap();
    let Some(run) = run_window_with(
        RAYLAB,
        "",
        dir.path(),
        &[],
        Around::Args(&["--accel", "bvh"]),
    ) else {
        return;
    };
    assert_eq!(run.fields["accel"], "bvh");
    let (mean, off, ..) = against_headless(&run, &Scene::cornell());
    assert!(mean < 2.0 && off < 0.02, "mean {mean}, off {off}");
}

fn an_edit_saved_while_a_reload_loads_is_loaded_too() {
    // The scene file is replaced by a big scene (800,000 triangles: seconds to load), and
    // while the window reloads it, by a small one: the window ends on the small one, the
    // file's last content. (The edit made during the load was dropped: the window ended on
    // the big scene.)
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("s.scene");
    std::fs::write(&scene, "cornell\n").unwrap();
    let mut big = String::new();
    for i in 0..800_000 {
        let (x, y) = (
            (i % 1000) as f64 * 0.002 - 1.0,
            (i / 1000) as f64 * 0.0025 - 1.0,
        );
        big += &format!(
            "tri {x} {y} 0.5 {} {y} 0.5 {x} {} 0.5\n",
            x + 0.001,
            y + 0.001
        );
    }
    std::fs::write(dir.path().join("first.scene"), big).unwrap();
    let last = "cornell\nsphere 0 0.5 0 0.3\nsphere 0.5 0.5 0 0.2\n";
    std::fs::write(dir.path().join("last.scene"), last).unwrap();
    // (Each edit replaces the file whole, as an editor saving it does. The second waits for
    // the window to say it is reloading the first: the big scene then takes seconds to load,
    // the file watcher a quarter of a second to see the second edit. The run lasts until the
    // window has loaded a scene of the last edit's 32 primitives, or a minute.)
    let driver = "mv first.scene s.scene; logged 'reloading'; mv last.scene s.scene; \
                  logged '(32 primitives)'";
    let around = Around::RealInputOn(driver, &scene);
    let Some(run) = run_window_with(RAYLAB, "0 await driver-done\n", dir.path(), &[], around)
    else {
        return;
    };
    let log = &run.stderr;
    assert!(
        log.contains("asked for while a load is under way"),
        "the second edit came during the first reload\n{log}"
    );
    assert!(log.contains("(800000 primitives)"), "{log}");
    assert_eq!(run.fields["primitives"], "32", "{log}");
    let status = run.stdout.lines().find_map(|l| l.strip_prefix("status: "));
    let want = format!("reloaded {} (32 primitives)", scene.display());
    assert_eq!(status, Some(want.as_str()), "{log}");
}

/// Writes the small scene (the box and a ball: 31 primitives) a view names, and that view:
/// its camera at yaw 20, a fixed 320x240.
pub(super) fn small_scene_and_its_view(dir: &std::path::Path) -> std::path::PathBuf {
    std::fs::write(dir.join("small.scene"), "cornell\nsphere 0 0.5 0 0.3\n").unwrap();
    let view = dir.join("v.view");
    std::fs::write(
        &view,
        "scene small.scene\ncamera 0.5 0.2 -2.5 yaw 20 pitch -5 fov 53\nsize 320 240\nspp 1\n",
    )
    .unwrap();
    view
}

/// A pyramid OBJ (6 triangles).
pub(super) const PYRAMID: &str = "v -1 1 -1\nv 1 1 -1\nv 1 1 1\nv -1 1 1\nv 0 -1 0\n\
                       f 1 2 3 4\nf 1 2 5\nf 2 3 5\nf 3 4 5\nf 4 1 5\n";

fn a_file_dropped_while_another_reloads_is_not_lost_to_that_files_save() {
    // The scene shown reloads (its file changed); a second scene is dropped meanwhile; then
    // the first file is saved again: the dropped scene is what the window ends on. (The
    // first file's reload took the queue's place and the drop was lost.)
    let dir = tempfile::tempdir().unwrap();
    let a = dir.path().join("a.scene");
    std::fs::write(&a, "cornell\n").unwrap();
    let b = dir.path().join("b.scene");
    std::fs::write(&b, "cornell\nsphere 0 0.5 0 0.3\nsphere 0.5 0.5 0 0.2\n").unwrap();
    let script = format!(
        "0 changed {a}\n0 drop {b}\n0 changed {a}\n",
        a = a.display(),
        b = b.display()
    );
    let args = [a.to_str().unwrap()];
    let Some(run) = run_window_with(RAYLAB, &script, dir.path(), &[], Around::Args(&args)) else {
        return;
    };
    let log = &run.stderr;
    assert!(log.contains("reloading"), "the first file reloaded\n{log}");
    assert!(log.contains("not reloaded"), "{log}");
    assert!(run.fields["scene"].ends_with("b.scene"), "{log}");
    assert_eq!(run.fields["primitives"], "32", "{log}");
}

fn a_file_saved_while_it_loads_is_loaded_again() {
    // A scene dropped, and its file saved while it loads: it is loaded again once the first
    // load ends (the change was ignored: the file was not yet the one shown).
    let dir = tempfile::tempdir().unwrap();
    let b = dir.path().join("b.scene");
    std::fs::write(&b, "cornell\nsphere 0 0.5 0 0.3\n").unwrap();
    let script = format!("0 drop {b}\n0 changed {b}\n", b = b.display());
    let Some(run) = run_window_with(RAYLAB, &script, dir.path(), &[], Around::Nothing) else {
        return;
    };
    let log = &run.stderr;
    assert!(log.contains("asked for while a load is under way"), "{log}");
    let status = run.stdout.lines().find_map(|l| l.strip_prefix("status: "));
    let want = format!("reloaded {} (31 primitives)", b.display());
    assert_eq!(status, Some(want.as_str()), "{log}");
}

fn real_x_input_enter_in_the_path_field_loads_the_file() {
    // A path typed into the panel's path field and Enter pressed loads it, as the Load button
    // does. (Only the button loaded: Enter left the field and did nothing.) (150, 631): the
    // path field at the default window on the 1280x800 screen.
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("pyramid.obj"),
        "v -1 1 -1\nv 1 1 -1\nv 1 1 1\nv -1 1 1\nv 0 -1 0\nf 1 2 3 4\nf 1 2 5\nf 2 3 5\nf 3 4 5\nf 4 1 5\n",
    )
    .unwrap();
    let script = "0 await driver-done\n";
    // Enter in the field emptied says so, without an error banner ("could not load: : No
    // such file or directory").
    // The second click is where the pointer already is: `mousemove --sync` to it would wait
    // for a move that never comes (some 15 s, till xdotool gives up).
    // (Each click 0.8 s before its keys: a click that gives the field the keyboard and keys
    // taken with it in one late batch would go to the window: P hides the panel.)
    let driver = "xdotool windowfocus --sync $win; xdotool mousemove --sync 150 631 click 1; \
                  sleep 0.8; xdotool key ctrl+a BackSpace Return; logged 'field is empty'; \
                  xdotool click 1; \
                  sleep 0.8; xdotool type pyramid.obj; sleep 0.3; xdotool key Return; \
                  logged 'loaded pyramid.obj'";
    let around = Around::RealInput(driver);
    let Some(run) = run_window_with(RAYLAB, script, dir.path(), &[], around) else {
        return;
    };
    assert!(
        run.fields["scene"].ends_with("pyramid.obj"),
        "{:?}\n{}",
        run.fields,
        run.stderr
    );
    let log = &run.stderr;
    assert!(
        log.contains("the path field is empty: type `cornell` or a"),
        "{log}"
    );
    assert!(!log.contains("could not load"), "{log}");
}

fn real_x_input_a_view_typed_into_the_path_field_says_it_loaded() {
    // A view loaded from the path field sets its step and says so: the status said "lab
    // step 1 flat", the step's change, over "loaded view". (150, 631): the path field.
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("mine.view"), "scene cornell\nstep flat\n").unwrap();
    let script = "0 await driver-done\n";
    let driver = "xdotool windowfocus --sync $win; xdotool mousemove --sync 150 631 click 1; \
                  sleep 0.8; xdotool key ctrl+a BackSpace; xdotool type mine.view; sleep 0.3; \
                  xdotool key Return; logged 'loaded view'";
    let around = Around::RealInput(driver);
    let Some(run) = run_window_with(RAYLAB, script, dir.path(), &[], around) else {
        return;
    };
    let status = run.stdout.lines().find_map(|l| l.strip_prefix("status: "));
    assert!(
        status.is_some_and(|s| s.starts_with("loaded view ") && s.contains("mine.view")),
        "{status:?}\n{}",
        run.stderr
    );
    assert_eq!(run.fields["step"], "flat", "{:?}", run.fields);
}

fn real_x_input_obj_axes_read_the_lab_box_as_it_is() {
    // assets/cornell_lab.obj is written in the lab's frame: opened as an OBJ is usually read
    // (y up: y and z negated), the box shows from behind, a grey square; the panel's OBJ axes
    // "as is" (124, 653, under the path field) reads it again as written: the green floor at
    // the bottom of the image, the box open towards the camera.
    let dir = tempfile::tempdir().unwrap();
    let lab_box = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/cornell_lab.obj");
    std::fs::copy(&lab_box, dir.path().join("box.obj")).unwrap();
    std::fs::copy(
        lab_box.with_extension("mtl"),
        dir.path().join("cornell_lab.mtl"),
    )
    .unwrap();
    let script = "0 await driver-done\n";
    let driver = "xdotool windowfocus --sync $win; xdotool mousemove --sync 150 631 click 1; \
                  sleep 0.3; xdotool type box.obj; sleep 0.3; xdotool key Return; sleep 2; \
                  xdotool mousemove --sync 124 653 click 1; sleep 2";
    let Some(run) = run_window_with(RAYLAB, script, dir.path(), &[], Around::RealInput(driver))
    else {
        return;
    };
    let log = &run.stderr;
    assert_eq!(log.matches("box.obj (30 primitives)").count(), 2, "{log}");
    // The floor's green (none in the grey square seen from behind).
    let green = (run.shot.2.chunks(4))
        .filter(|p| p[1] > p[0].saturating_add(40) && p[1] > p[2].saturating_add(40))
        .count();
    let all = (run.shot.0 * run.shot.1) as usize;
    assert!(green * 40 > all, "{green} green pixels of {all}\n{log}");
}

fn a_field_of_view_past_the_windows_range_is_said_on_load() {
    // A view asking 175° (the window shows 168.6° at most) and a scene asking 0.5° (1.1° at
    // least): each loads at the window's end of the range and the status says so, where it
    // said only "loaded" and F5 then wrote another view than the one loaded.
    let dir = tempfile::tempdir().unwrap();
    let view = small_scene_and_its_view(dir.path());
    let text = std::fs::read_to_string(&view)
        .unwrap()
        .replace("fov 53", "fov 175");
    std::fs::write(&view, text).unwrap();
    let narrow = dir.path().join("narrow.scene");
    std::fs::write(&narrow, "cornell\ncamera 0 0 -3 yaw 0 pitch 0 fov 0.5\n").unwrap();
    let script = format!(
        "0 drop {}\n1500 drop {}\n",
        view.display(),
        narrow.display()
    );
    let Some(run) = run_window_with(RAYLAB, &script, dir.path(), &[], Around::Nothing) else {
        return;
    };
    let log = &run.stderr;
    assert!(
        log.contains(
            "v.view; its field of view 175.0° shown at 168.6°, the window's widest (F5 and copy \
             as command write that)"
        ),
        "{log}"
    );
    assert!(
        log.contains(
            "(30 primitives); its field of view 0.5° shown at 1.1°, the window's narrowest"
        ),
        "{log}"
    );
}

fn a_model_on_the_command_line_is_framed_as_one_opened_in_the_window() {
    // The window frames a model it opens with for its image (it framed it for 640x480 at
    // the start, and another pose when the same file was opened from the panel).
    let dir = tempfile::tempdir().unwrap();
    let pyramid = "v -1 1 -1\nv 1 1 -1\nv 1 1 1\nv -1 1 1\nv 0 -1 0\n\
                   f 1 2 3 4\nf 1 2 5\nf 2 3 5\nf 3 4 5\nf 4 1 5\n";
    std::fs::write(dir.path().join("pyramid.obj"), pyramid).unwrap();
    let args = ["pyramid.obj"];
    let Some(given) = run_window_with(RAYLAB, "", dir.path(), &[], Around::Args(&args)) else {
        return;
    };
    let script = "300 drop pyramid.obj\n";
    let Some(opened) = run_window_with(RAYLAB, script, dir.path(), &[], Around::Nothing) else {
        return;
    };
    assert!(
        opened.fields["scene"].ends_with("pyramid.obj"),
        "{}",
        opened.stderr
    );
    assert_eq!(given.fields["size"], opened.fields["size"]);
    assert_eq!(
        given.fields["camera"], opened.fields["camera"],
        "{}",
        given.stderr
    );
}

fn real_x_input_a_reload_keeps_the_light_moved_in_the_panel() {
    // A light typed into the panel stays through a reload of the scene file, as the camera
    // does (the file's own light came back: a student who placed it lost it on every save).
    // (65, 631): the panel's light x field at the default window on the 1280x800 screen, a
    // scene file's "Transform stack" row above.
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("tri.scene");
    std::fs::write(&scene, "tri -1 -1 0  1 -1 0  0 1 0\n").unwrap();
    let script = "0 await driver-done\n";
    let driver = "xdotool windowfocus --sync $win; xdotool mousemove --sync 65 631; sleep 0.3; \
                  xdotool click 1; sleep 0.8; xdotool key ctrl+a; xdotool type 7; \
                  xdotool key Return; sleep 0.5; printf '# an edit\\n' >> tri.scene; \
                  logged 'reloaded '; xdotool key F5; logged 'saved view'";
    let around = Around::RealInputOn(driver, &scene);
    let Some(run) = run_window_with(RAYLAB, script, dir.path(), &[], around) else {
        return;
    };
    let log = &run.stderr;
    assert!(
        log.contains("the light kept where the panel put it"),
        "{log}"
    );
    let view = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.extension().is_some_and(|e| e == "view"))
        .unwrap_or_else(|| panic!("F5 saved no view\n{log}"));
    let text = std::fs::read_to_string(view).unwrap();
    let light = text.lines().find(|l| l.starts_with("light "));
    assert!(light.is_some_and(|l| l.starts_with("light 7 ")), "{text}");
}

/// This file's tests, by name, for the harness (main.rs).
pub const TESTS: super::Tests = tests![
    a_selected_level_tints_what_its_nested_levels_place_too,
    a_model_on_the_command_line_is_framed_as_one_opened_in_the_window,
    real_x_input_a_reload_keeps_the_light_moved_in_the_panel,
    dropped_obj_files_load_and_bad_ones_leave_the_scene_alone,
    cornell_opened_after_a_scene_file_takes_the_labs_camera_and_light,
    a_scene_file_reloads_on_change_keeps_the_camera_and_survives_a_bad_edit,
    a_scene_reloads_when_a_mesh_it_places_changes,
    a_scene_that_failed_to_open_opens_once_fixed,
    real_x_input_the_transform_stack_opened_keeps_the_panels_width,
    real_x_input_file_menu_saves_an_image_and_opens_a_scene_through_its_dialog,
    real_x_input_keys_typed_in_the_file_dialog_are_the_dialogs,
    an_instanced_scene_opens_and_a_selected_instance_is_tinted,
    the_window_never_saves_a_screenshot_over_the_model_it_opened,
    the_window_opens_cornell_by_name_as_the_command_line_does,
    the_window_builds_the_structure_accel_names,
    an_edit_saved_while_a_reload_loads_is_loaded_too,
    a_file_dropped_while_another_reloads_is_not_lost_to_that_files_save,
    a_file_saved_while_it_loads_is_loaded_again,
    real_x_input_enter_in_the_path_field_loads_the_file,
    real_x_input_a_view_typed_into_the_path_field_says_it_loaded,
    real_x_input_obj_axes_read_the_lab_box_as_it_is,
    a_field_of_view_past_the_windows_range_is_said_on_load,
];
