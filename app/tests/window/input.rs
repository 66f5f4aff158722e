//! The real window under Xvfb, driven by scripts and by real X input: the camera moves,
//! turns, orbits and zooms, the panel's controls set the image, and what the window showed
//! must match the headless render of the same final camera.
//!
//! Needs `xvfb-run` and a Vulkan driver (Mesa's lavapipe works without a GPU). Where they are
//! missing the test says so loudly and skips, except under CI=true, where it must run.

use crate::common;

use common::window::{compare, run_window_with, Around, NOT_LOGGED};
use common::{pixels_off, read_png, run_in_shell};
use glam::DVec3;
use raylab::geometry::Method;
use raylab::render::{render_image, LabStep, RenderSettings};
use raylab::{Camera, Scene};

/// The window under test.
const RAYLAB: &str = env!("CARGO_BIN_EXE_raylab");

fn scripted_window_run_matches_the_headless_render() {
    let dir = tempfile::tempdir().unwrap();
    // The wheel and F12 come due together: F12 saves the view the wheel made, as a person
    // who scrolls and presses F12 within one frame expects.
    let script = "# forward, turn right, look up with the mouse, switch to shadows, zoom in, F12\n\
         0 key W down\n300 key W up\n350 key Right down\n600 key Right up\n\
         650 mouse 0 -40\n750 step shadows\n800 wheel 3\n800 key F12 down\n820 key F12 up\n";
    let Some(run) = run_window_with(RAYLAB, script, dir.path(), &[], Around::Nothing) else {
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
    // (A slow frame that took W's last milliseconds and Right's first both turns and moves:
    // its step goes a little to the side, at most 0.05 for a frame of the longest step.
    // A sideways key moves 0.4 in the same time.)
    assert!(
        pos.x.abs() < 0.05 && pos.y.abs() < 1e-9,
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
    // (The status line's message came between egui's passes: the widgets after it changed
    // their ids, and egui warned of each.)
    assert!(!run.stderr.contains("changed id"), "{}", run.stderr);
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

fn real_x_input_moves_turns_and_zooms_the_camera() {
    // Real X events (XTEST, as a user's keyboard and mouse give them), not script events:
    // W held, the wheel over the image, a right-drag over the image. The script only keeps
    // the run alive while the driver works.
    let dir = tempfile::tempdir().unwrap();
    // (The driver waits for the first frames: the wheel and drag must meet a drawn image.)
    let script = "0 await driver-done\n";
    let driver = "xdotool windowfocus --sync $win; \
                  xdotool keydown w; logged 'W down'; sleep 0.4; xdotool keyup w; sleep 0.3; \
                  xdotool mousemove --sync 730 310; sleep 0.3; \
                  for i in 1 2 3 4 5; do xdotool click 4; sleep 0.05; done; sleep 0.3; \
                  xdotool mousedown 3; sleep 0.2; \
                  for i in $(seq 20); do xdotool mousemove_relative 10 0; sleep 0.02; done; \
                  xdotool mouseup 3";
    let Some(run) = run_window_with(RAYLAB, script, dir.path(), &[], Around::RealInput(driver))
    else {
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

fn real_x_input_a_wheel_as_the_pointer_enters_over_the_panel_is_not_the_cameras() {
    // The pointer comes in from outside the window (x 1200 on the 1280x800 screen; the window
    // is 1152 wide) straight onto the side panel and the wheel turns there at once: the panel
    // scrolls, the camera keeps its focal length (egui's last frame, drawn with the pointer
    // away, did not claim it: the camera zoomed out three times). Then the same onto the
    // image: the camera zooms in.
    let dir = tempfile::tempdir().unwrap();
    let script = "0 await driver-done\n";
    let driver = "xdotool windowfocus --sync $win; \
                  for i in 1 2 3; do xdotool mousemove --sync 1200 760; sleep 0.3; \
                  xdotool mousemove 150 300 click 5; sleep 0.3; done; \
                  xdotool mousemove --sync 1200 760; sleep 0.3; \
                  xdotool mousemove 730 310 click 4; sleep 0.5";
    let Some(run) = run_window_with(RAYLAB, script, dir.path(), &[], Around::RealInput(driver))
    else {
        return;
    };
    let (focal, width) = (run.nums("focal")[0], run.nums("size")[0]);
    // The lab camera starts with the focal length the image's width; a notch is 1.1x.
    assert!(
        focal > width * 1.05 && focal < width * 1.25,
        "three wheel notches down over the panel left the focal length, one up over the \
         image zoomed in once: focal {focal} for width {width}\n{}",
        run.stderr
    );
}

fn a_right_drag_with_an_absolute_pointer_turns_the_view() {
    // A pointer that reports positions only (VNC, a tablet, a VM's mouse integration, and
    // xdotool's `mousemove X Y`) gives no raw motion: the cursor's moves turn the view.
    let dir = tempfile::tempdir().unwrap();
    let script = "0 await driver-done\n";
    let driver = "xdotool windowfocus --sync $win; sleep 0.3; \
                  xdotool mousemove --sync 600 310; sleep 0.3; xdotool mousedown 3; sleep 0.2; \
                  for i in $(seq 20); do xdotool mousemove $((600 + 10 * i)) 310; sleep 0.02; done; \
                  xdotool mouseup 3";
    let Some(run) = run_window_with(RAYLAB, script, dir.path(), &[], Around::RealInput(driver))
    else {
        return;
    };
    let yaw = run.nums("yaw")[0];
    assert!(
        yaw > 5.0,
        "a right-drag to the right turned the view right: yaw {yaw}\n{}",
        run.stderr
    );
}

fn real_x_input_orbits_with_tab_and_a_left_drag() {
    // Tab switches to orbit around the box centre; a left-drag across the image turns the
    // camera around it at the same distance (3.001).
    let dir = tempfile::tempdir().unwrap();
    // (The driver waits for the first frames: the drag must start over a drawn image, and a
    // fresh CI machine under lavapipe can take seconds to draw one.)
    let script = "0 await driver-done\n";
    let driver = "xdotool windowfocus --sync $win; sleep 0.3; xdotool key Tab; sleep 0.3; \
                  xdotool mousemove --sync 600 310; sleep 0.2; xdotool mousedown 1; sleep 0.2; \
                  for i in $(seq 20); do xdotool mousemove_relative 10 0; sleep 0.02; done; \
                  xdotool mouseup 1";
    let Some(run) = run_window_with(RAYLAB, script, dir.path(), &[], Around::RealInput(driver))
    else {
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

fn real_x_input_sets_every_image_control_in_the_panel() {
    // The panel draws one widget per row of the controls table: real clicks on the "direct"
    // radio button, a press on the supersampling slider's rail near its left end (egui moves
    // a slider while the button is down, so a press and a release; 3x3 samples, each of which
    // the cracks view checks against the exact method), the "show cracks" check box and the
    // method drop-down's "moller" set them, and the window shows the headless render of those
    // settings. (Positions: the panel at the window's default size on a 1280x800 screen. The
    // image at half the window's resolution: its samples, each checked exactly, were most of
    // the test's time.)
    let dir = tempfile::tempdir().unwrap();
    let script =
        "0 scale 0.5\n0 await driver-done\n0 key H down\n10 key H up\n20 key H down\n30 key H up\n";
    let driver = "xdotool windowfocus --sync $win; \
                  xdotool mousemove --sync 15 122; sleep 0.3; xdotool click 1; sleep 0.3; \
                  xdotool mousemove --sync 27 529; sleep 0.3; xdotool mousedown 1; sleep 0.3; \
                  xdotool mouseup 1; sleep 0.3; \
                  xdotool mousemove --sync 15 571; sleep 0.3; xdotool click 1; sleep 0.3; \
                  xdotool mousemove --sync 55 550; sleep 0.3; xdotool click 1; sleep 0.6; \
                  xdotool mousemove --sync 40 617; sleep 0.3; xdotool click 1; sleep 0.3";
    let Some(run) = run_window_with(RAYLAB, script, dir.path(), &[], Around::RealInput(driver))
    else {
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
    // (The radio button says so in the status line, as the digit key does; the check box and
    // the drop-down too: the status kept "supersampling set to 3" over a method chosen.)
    for said in [
        "lab step 3 direct",
        "show cracks on",
        "ray/triangle method: moller",
    ] {
        assert!(run.stderr.contains(said), "{said}: {}", run.stderr);
    }
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

fn f5_c_and_r_take_the_motion_of_a_key_just_released() {
    // W let go and F5 pressed at one moment: the view saved is where W took the camera, as C
    // copies it later with nothing moving between; D let go and R pressed at one moment: the
    // camera is back at the start. (F5 saved the pose before W's last part, which the next
    // frame then moved; after R the next frame moved by D's.)
    let dir = tempfile::tempdir().unwrap();
    let script = "0 key W down\n300 key W up\n300 key F5 down\n320 key F5 up\n\
                  1000 key C down\n1020 key C up\n1200 key D down\n1500 key D up\n\
                  1500 key R down\n1520 key R up\n";
    let Some(run) = run_window_with(RAYLAB, script, dir.path(), &[], Around::Nothing) else {
        return;
    };
    let log = &run.stderr;
    let view = super::views::saved_as(dir.path(), "raylab-view-", log);
    let view = std::fs::read_to_string(view).unwrap();
    let saved: Vec<f64> = (view.lines().find_map(|l| l.strip_prefix("camera ")))
        .expect("a camera line")
        .split_whitespace()
        .take(3)
        .map(|x| x.parse().unwrap())
        .collect();
    let copied: Vec<f64> = (log.split("--camera=").nth(1))
        .and_then(|rest| rest.split_whitespace().next())
        .unwrap_or_else(|| panic!("C copied no command\n{log}"))
        .split(',')
        .map(|x| x.parse().unwrap())
        .collect();
    assert!(saved[2] > -2.9, "W moved the camera: {saved:?}");
    assert_eq!(
        saved, copied,
        "F5's view is where W left the camera\n{view}\n{log}"
    );
    assert_eq!(
        run.nums("camera"),
        [0.0, 0.0, -3.001],
        "R: the start\n{log}"
    );
}

fn real_x_input_copy_as_command_renders_what_the_window_shows() {
    // Move (A held), press C (copy as command), click the status line that says what it
    // copied, and press F12 (a full-quality screenshot of the same view); the clipboard, read
    // back with xclip, holds a `raylab render` line that a shell runs to the same picture (the
    // click copied the whole message, "copied to the clipboard: raylab render ...").
    if !common::tool_for("xclip", "xclip", "the copy-as-command test") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let script = "0 await driver-done\n";
    let driver = "xdotool windowfocus --sync $win; xdotool keydown a; logged 'A down'; \
                  sleep 0.4; xdotool keyup a; sleep 0.5; xdotool key c; sleep 0.5; \
                  xdotool mousemove --sync 500 710 click 1; sleep 0.5; xdotool key F12; \
                  logged '] saving raylab-'; xclip -selection clipboard -o > cmd.txt";
    let Some(run) = run_window_with(RAYLAB, script, dir.path(), &[], Around::RealInput(driver))
    else {
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
    let shot = super::views::saved_as(dir.path(), "raylab-1", &run.stderr);
    let (off, n) = pixels_off(&read_png(&shot), &read_png(&dir.path().join("raylab.png")));
    assert!(off * 1000 <= n, "{off} of {n} pixels differ");
}

fn real_x_input_digits_choose_the_lab_step() {
    // 1, 3, 4 and 5 choose the lab step as the panel's radio buttons do (the digit keys did
    // nothing); 2, the camera's step, changes no shading and says why.
    let dir = tempfile::tempdir().unwrap();
    let script = "0 await driver-done\n";
    let driver = "xdotool windowfocus --sync $win; xdotool mousemove --sync 700 400; \
                  xdotool key 1; logged 'lab step 1 flat'; xdotool key 5; \
                  logged 'lab step 5 indirect'; xdotool key KP_3; logged 'lab step 3 direct'; \
                  xdotool key 4; logged 'lab step 4 shadows'; xdotool key 2; \
                  logged 'lab step 2 is the camera'";
    let Some(run) = run_window_with(RAYLAB, script, dir.path(), &[], Around::RealInput(driver))
    else {
        return;
    };
    let stdout = &run.stdout;
    assert!(
        stdout.contains(" step=shadows "),
        "{stdout}\n{}",
        run.stderr
    );
    let status = stdout.lines().find_map(|l| l.strip_prefix("status: "));
    assert!(
        status.is_some_and(|s| s.starts_with("lab step 2 is the camera")),
        "{status:?}"
    );
}

fn real_x_input_drives_every_other_key() {
    // The keys the other real-input runs do not press, each checked from the outside: D moves
    // right, then Shift+D 4x as far; Ctrl+E moves up at a quarter of the speed, Q down; S
    // moves back; the four arrows turn; + + - scale the speed; I turns the inspector off, H, F1
    // and H leave the shortcuts shown, F5 saves the view; R is pressed first (from the start
    // pose it changes nothing); Esc closes the shortcuts, and Esc then asks before quitting.
    let dir = tempfile::tempdir().unwrap();
    let script = "0 await driver-done\n";
    // (Each hold in one xdotool run: a second process started between press and release
    // held the key longer on a busy machine, and Right then Left once left 40.2°.)
    let driver = "xdotool windowfocus --sync $win; sleep 0.3; xdotool key r; sleep 0.2; \
                  xdotool keydown d sleep 0.3 keyup d; sleep 0.2; \
                  xdotool keydown shift keydown d sleep 0.3 keyup d keyup shift; \
                  sleep 0.2; xdotool keydown ctrl keydown e sleep 0.3 keyup e keyup ctrl; \
                  sleep 0.2; xdotool keydown q sleep 0.3 keyup q; sleep 0.2; \
                  xdotool keydown s sleep 0.3 keyup s; sleep 0.2; \
                  xdotool keydown Up sleep 0.8 keyup Up; sleep 0.2; \
                  xdotool keydown Down sleep 0.4 keyup Down; sleep 0.2; \
                  xdotool keydown Right sleep 0.8 keyup Right; sleep 0.2; \
                  xdotool keydown Left sleep 0.4 keyup Left; sleep 0.2; \
                  xdotool key plus; xdotool key plus; xdotool key minus; \
                  xdotool key i; xdotool key h; xdotool key F1; xdotool key h; xdotool key F5; \
                  logged 'saved view'; xdotool key Escape; logged 'Esc closed'; \
                  xdotool key Escape; logged 'press Esc again'";
    let around = Around::RealInputAlone(driver);
    let Some(run) = run_window_with(RAYLAB, script, dir.path(), &[], around) else {
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
    // Up for 0.8 s then Down for 0.4 s, Right then Left alike: at 1.2 rad/s, 27.5° of the
    // first turn's 55° is left. A press and its release taken in one late batch of events
    // count less (a frame counts at most 0.25 s of a held key, too), so the run is alone and
    // the bounds leave 0.2 s of either key's hold for that: a second key that did nothing
    // leaves more than 40°.
    let (pitch, yaw) = (run.nums("pitch")[0], run.nums("yaw")[0]);
    println!("Up then Down: pitch {pitch}°; Right then Left: yaw {yaw}°");
    assert!(pitch > 4.0 && pitch < 40.0, "Up then Down: pitch {pitch}");
    assert!(yaw > 4.0 && yaw < 40.0, "Right then Left: yaw {yaw}");
    assert!(
        (run.nums("speed")[0] - 1.25).abs() < 1e-9,
        "+ + -: {}",
        f("speed")
    );
    // (The shortcuts shown after H, F1, H are what the first Esc closed.)
    assert_eq!((f("inspector"), f("help")), ("off".into(), "off".into()));
    let saved = std::fs::read_dir(dir.path())
        .unwrap()
        .any(|e| e.unwrap().file_name().to_string_lossy().ends_with(".view"));
    assert!(saved, "F5 saved a view\n{}", run.stderr);
    let log = &run.stderr;
    let (closed, asked) = (
        log.find("Esc closed the shortcuts"),
        log.find("press Esc again"),
    );
    assert!(
        closed.zip(asked).is_some_and(|(c, a)| c < a),
        "Esc closed the shortcuts, then Esc asked before quitting\n{log}"
    );
    // D and Shift+D together moved right well beyond what D alone would (0.5 + 2.1);
    // without Shift it would be about 1.0.
    assert!(pos[0] > 1.6, "Shift made D faster: x {}", pos[0]);
}

fn real_x_input_escape_twice_quits() {
    // With the mouse captured for looking (right button held over the image), Esc releases
    // it; Esc then asks, and Esc again quits at once: the run ends before its script, which
    // awaits the driver (had the first Esc not released the mouse, the third would only ask).
    let dir = tempfile::tempdir().unwrap();
    let script = "0 await driver-done\n";
    let driver = "xdotool windowfocus --sync $win; xdotool mousemove --sync 800 400; \
                  sleep 0.2; xdotool mousedown 3; sleep 0.3; xdotool key Escape; sleep 0.3; \
                  xdotool key Escape; sleep 0.5; xdotool key Escape; sleep 0.2; \
                  xdotool mouseup 3";
    let Some(run) = run_window_with(RAYLAB, script, dir.path(), &[], Around::RealInput(driver))
    else {
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
}

fn real_x_input_escape_quits_only_right_after_asking() {
    // Esc asks; a click on the panel comes between, so Esc asks again rather than quitting;
    // then a failed load raises the banner (the status now says the error), Esc dismisses
    // it, and the next Esc asks again. The run is never quit: it ends with its final line.
    // (The prompt stayed armed through the click and the error: the window quit at the
    // second Esc while the status showed something else.) The click withdraws the prompt.
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("bad.obj"), "v 0 0 0\nv 1 0 nan\nf 1 2 1\n").unwrap();
    // (The load fails once the driver has pressed Esc the second time and the window asked.)
    let script = "0 await asked-twice\n0 drop bad.obj\n0 await driver-done\n";
    // (150, 680): the panel's empty space below the path field at the default window on
    // the harness's 1280x800 screen: a click on no widget.
    // (Each step waits for the app to log the last: a click and an Esc taken in one late
    // batch would be one moment to the app.)
    let driver = "xdotool windowfocus --sync $win; xdotool key Escape; \
                  logged 'press Esc again to quit'; xdotool mousemove --sync 150 680; \
                  sleep 0.2; xdotool click 1; logged 'quit prompt withdrawn'; \
                  xdotool key Escape; logged 'press Esc again to quit' 2; : > asked-twice; \
                  logged 'could not load'; sleep 0.3; \
                  xdotool key Escape; logged 'error banner dismissed'; xdotool key Escape; \
                  logged 'press Esc again to quit' 3";
    let Some(run) = run_window_with(RAYLAB, script, dir.path(), &[], Around::RealInput(driver))
    else {
        return;
    };
    let log = &run.stderr;
    assert!(!run.fields.is_empty(), "the window quit\n{log}");
    assert_eq!(run.fields["banner"], "off", "{log}");
    let asked: Vec<usize> = log
        .match_indices("press Esc again to quit")
        .map(|m| m.0)
        .collect();
    let failed = log.find("could not load").expect("the load failed");
    let dismissed = log
        .find("error banner dismissed")
        .expect("Esc dismissed it");
    assert_eq!(asked.len(), 3, "{log}");
    assert!(
        asked[1] < failed && failed < dismissed && dismissed < asked[2],
        "{log}"
    );
    // The click withdrew the first prompt from the status line (it stayed, no longer true).
    let withdrawn = log.find("quit prompt withdrawn").expect("withdrawn");
    assert!(asked[0] < withdrawn && withdrawn < asked[1], "{log}");
}

fn real_x_input_middle_drag_pans_in_orbit_mode() {
    // Tab, then a middle-drag 100 pixels to the right over the image: the scene follows the
    // cursor, so the camera (and its target) move left, keeping height and depth.
    let dir = tempfile::tempdir().unwrap();
    let script = "0 await driver-done\n";
    let driver = "xdotool windowfocus --sync $win; sleep 0.3; xdotool key Tab; sleep 0.3; \
                  xdotool mousemove --sync 800 400; sleep 0.2; xdotool mousedown 2; sleep 0.2; \
                  for i in $(seq 10); do xdotool mousemove_relative 10 0; sleep 0.02; done; \
                  xdotool mouseup 2";
    let Some(run) = run_window_with(RAYLAB, script, dir.path(), &[], Around::RealInput(driver))
    else {
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

fn real_x_input_keys_still_move_the_camera_after_tab() {
    // Tab twice (orbit, then fly again), then W: egui once took Tab to move its keyboard focus
    // to a panel widget, and the app ignored every key while any widget had focus, so the
    // second Tab and W did nothing.
    let dir = tempfile::tempdir().unwrap();
    let script = "0 await driver-done\n";
    let driver = "xdotool windowfocus --sync $win; sleep 0.3; xdotool key Tab; sleep 0.5; \
                  xdotool key Tab; sleep 0.5; xdotool keydown w; logged 'W down'; sleep 0.4; \
                  xdotool keyup w";
    let Some(run) = run_window_with(RAYLAB, script, dir.path(), &[], Around::RealInput(driver))
    else {
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

fn real_x_input_escape_leaves_a_text_field_menu_or_dialog_before_it_asks() {
    // Esc while typing in the path field leaves the field, Esc in the open File menu closes
    // it, Esc with File ▸ Open's dialog shown closes the dialog: each is egui's alone. So
    // Esc, Esc in the field asks once (the second Esc) and the window stays; the menu's Esc
    // asks nothing; Esc, Esc in the dialog asks once more. (Each click in between is
    // something else done: the next Esc asks again rather than quitting.) Positions: the
    // panel's path field and the File menu at the default window on the 1280x800 screen.
    let dir = tempfile::tempdir().unwrap();
    let script = "0 await driver-done\n";
    // (A click 0.8 s before its keys: see the typed positions' test.)
    let driver = "xdotool windowfocus --sync $win; \
                  xdotool mousemove --sync 150 631; sleep 0.3; xdotool click 1; sleep 0.8; \
                  xdotool type --delay 50 abc; sleep 0.3; xdotool key Escape; sleep 0.5; \
                  xdotool key Escape; sleep 0.5; \
                  xdotool mousemove --sync 19 11; sleep 0.3; xdotool click 1; sleep 0.8; \
                  xdotool key Escape; sleep 0.5; \
                  xdotool click 1; sleep 0.8; xdotool mousemove --sync 78 36; sleep 0.3; \
                  xdotool click 1; sleep 1.5; xdotool mousemove --sync 900 650; sleep 0.3; \
                  xdotool key Escape; sleep 0.8; xdotool key Escape";
    let around = Around::RealInput(driver);
    let Some(run) = run_window_with(RAYLAB, script, dir.path(), &[], around) else {
        return;
    };
    let log = &run.stderr;
    assert!(!run.fields.is_empty(), "the window quit\n{log}");
    let asked = log.matches("press Esc again to quit").count();
    assert_eq!(
        asked, 2,
        "the second Esc of each pair asked, nothing else\n{log}"
    );
    assert_eq!(
        run.stdout.lines().find_map(|l| l.strip_prefix("status: ")),
        Some("press Esc again to quit")
    );
    // The field's Esc gave it back what it held (nothing: the built-in box) before `abc`.
    let field = run
        .stdout
        .lines()
        .find_map(|l| l.strip_prefix("path field: "));
    assert_eq!(field, Some(""), "{log}");
}

fn real_x_input_escape_closes_the_shortcuts_before_it_asks() {
    // A failed load's banner, then H: Esc closes the shortcuts on top (Esc, Esc had quit the
    // window from them), Esc then dismisses the banner under them, and the next Esc asks.
    let dir = tempfile::tempdir().unwrap();
    let script = "0 drop n.obj\n0 await driver-done\n";
    let driver = "xdotool windowfocus --sync $win; logged 'could not load'; xdotool key h; \
                  sleep 0.5; xdotool key Escape; logged 'Esc closed'; xdotool key Escape; \
                  logged 'banner dismissed'; xdotool key Escape; logged 'press Esc again to quit'";
    let around = Around::RealInput(driver);
    let Some(run) = run_window_with(RAYLAB, script, dir.path(), &[], around) else {
        return;
    };
    let log = &run.stderr;
    assert!(!run.fields.is_empty(), "the window quit\n{log}");
    assert_eq!(run.fields["help"], "off", "{log}");
    let at = |line: &str| {
        log.find(line)
            .unwrap_or_else(|| panic!("no '{line}'\n{log}"))
    };
    let (closed, dismissed) = (at("Esc closed"), at("error banner dismissed"));
    assert!(
        closed < dismissed && dismissed < at("press Esc again to quit"),
        "{log}"
    );
    assert_eq!(log.matches("press Esc again to quit").count(), 1, "{log}");
}

fn real_x_input_f5_while_a_text_field_types_says_it_did_nothing() {
    // F5 pressed while the path field has the keyboard saves no view (the field's edit is not
    // the view's yet) and says why on the status line; after Esc leaves the field, F5 saves.
    // (It had done nothing, in silence.) Position: the panel's path field at the default window
    // on the 1280x800 screen.
    let dir = tempfile::tempdir().unwrap();
    let script = "0 await driver-done\n";
    let driver = "xdotool windowfocus --sync $win; \
                  xdotool mousemove --sync 150 631; sleep 0.3; xdotool click 1; sleep 0.8; \
                  xdotool type --delay 50 abc; sleep 0.3; xdotool key F5; \
                  logged 'F5 did nothing'; grep -c 'saved view' app.log > saved-while-typing.txt; \
                  xdotool key Escape; sleep 0.5; xdotool key F5; logged 'saved view'";
    let Some(run) = run_window_with(RAYLAB, script, dir.path(), &[], Around::RealInput(driver))
    else {
        return;
    };
    let log = &run.stderr;
    assert!(
        log.contains("F5 did nothing: a text field has the keyboard (Enter or Esc ends the edit"),
        "{log}"
    );
    let saved = std::fs::read_to_string(dir.path().join("saved-while-typing.txt")).unwrap();
    assert_eq!(saved.trim(), "0", "no view saved while typing\n{log}");
    assert_eq!(log.matches("saved view").count(), 1, "{log}");
}

fn real_x_input_quick_clicks_each_count() {
    // Plain clicks (press and release together, as a mouse's quick click gives them) on the
    // focal slider, at its right end, its left end, its right end and its left end: the
    // focal length ends where the last click put it, the least (0.05 of the image width).
    // Then three quick clicks on the ray inspector's check box: it toggles three times, off.
    // (Input that came between two frames went to egui as one moment: a slider took a press
    // with its release as no drag and ignored the click, and two clicks were one.)
    // Positions: the panel at the default window on the 1280x800 screen (the focal slider's
    // rail from x 8 to 108 at y 225; the check box at (15, 378)).
    let dir = tempfile::tempdir().unwrap();
    let script = "0 await driver-done\n";
    // (The driver waits for the third toggle: on a loaded machine the app takes the quick
    // clicks' passes one frame each, after the driver is done.)
    let driver = "xdotool windowfocus --sync $win; \
                  for x in 106 10 106 10; do xdotool mousemove --sync $x 225 click 1; done; \
                  sleep 0.5; xdotool mousemove --sync 15 378; sleep 0.3; \
                  xdotool click --repeat 3 --delay 0 1; logged 'ray inspector o' 3";
    let Some(run) = run_window_with(RAYLAB, script, dir.path(), &[], Around::RealInput(driver))
    else {
        return;
    };
    let log = &run.stderr;
    let (focal, width) = (run.nums("focal")[0], run.nums("size")[0]);
    assert!(
        (focal / width - 0.05).abs() < 1e-9,
        "the last click, at the slider's left end: focal {focal} at width {width}\n{log}"
    );
    let toggles = log.matches("ray inspector o").count();
    assert_eq!(toggles, 3, "three clicks on the check box\n{log}");
    assert_eq!(run.fields["inspector"], "off", "{log}");
}

fn a_drivers_step_never_logged_fails_the_run() {
    // Esc twice quits; the driver then waits for a line the app never logs: `logged` gives up
    // at once (the app has ended) and the run fails, saying which line. (Such a run passed,
    // the driver going on; where the app still ran, after a silent minute's wait.)
    let dir = tempfile::tempdir().unwrap();
    let script = "0 await driver-done\n";
    let driver = "xdotool windowfocus --sync $win; xdotool key Escape; logged 'press Esc again'; \
                  xdotool key Escape; sleep 0.5; logged 'a line never logged'";
    // (This harness does not capture output: the run's panic and log are printed.)
    eprintln!("input::a_drivers_step_never_logged_fails_the_run: the panic below is expected");
    let failed = std::panic::catch_unwind(|| {
        run_window_with(RAYLAB, script, dir.path(), &[], Around::RealInput(driver))
    });
    let Err(panic) = failed else {
        // (None: Xvfb or xdotool missing, said so already.)
        assert!(failed.unwrap().is_none(), "the run passed");
        return;
    };
    let said = (panic.downcast_ref::<String>()).expect("a formatted panic message");
    assert!(
        said.contains(&format!("{NOT_LOGGED}a line never logged")),
        "{said}"
    );
}

/// This file's tests, by name, for the harness (main.rs).
pub const TESTS: super::Tests = tests![
    a_drivers_step_never_logged_fails_the_run,
    scripted_window_run_matches_the_headless_render,
    real_x_input_moves_turns_and_zooms_the_camera,
    real_x_input_a_wheel_as_the_pointer_enters_over_the_panel_is_not_the_cameras,
    a_right_drag_with_an_absolute_pointer_turns_the_view,
    real_x_input_orbits_with_tab_and_a_left_drag,
    real_x_input_sets_every_image_control_in_the_panel,
    f5_c_and_r_take_the_motion_of_a_key_just_released,
    real_x_input_copy_as_command_renders_what_the_window_shows,
    real_x_input_digits_choose_the_lab_step,
    real_x_input_drives_every_other_key,
    real_x_input_escape_twice_quits,
    real_x_input_escape_quits_only_right_after_asking,
    real_x_input_middle_drag_pans_in_orbit_mode,
    real_x_input_keys_still_move_the_camera_after_tab,
    real_x_input_escape_leaves_a_text_field_menu_or_dialog_before_it_asks,
    real_x_input_escape_closes_the_shortcuts_before_it_asks,
    real_x_input_quick_clicks_each_count,
    real_x_input_f5_while_a_text_field_types_says_it_did_nothing,
];
