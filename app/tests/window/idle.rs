//! The real window run as a user runs it, without a script (it draws nothing while nothing
//! changes), driven by real X input under Xvfb: what it does when idle, and the view F5 saves.
//!
//! Needs `xvfb-run`, `xdotool` and a Vulkan driver (Mesa's lavapipe works without a GPU).
//! Where they are missing the test says so loudly and skips, except under CI=true, where it
//! must run.

use crate::common;

use common::window::{one_window, window_alone, WindowSlot};
use common::window::{FIND_WINDOW, LOGGED, NOT_LOGGED};

/// The window under test.
const RAYLAB: &str = env!("CARGO_BIN_EXE_raylab");

/// Shell functions for a driver: `idle` waits (two minutes at most: a view refined to 11x11
/// samples with every one checked takes a loaded machine one) until the app has used no
/// CPU for 2 s (the last 9 of its CPU times, read every quarter second, the same): its view
/// refined and nothing left to draw.
const IDLE: &str = "cpu() { awk '{print $14 + $15}' /proc/$app/stat; }; \
     idle() { set --; n=0; while [ $n -lt 480 ]; do set -- \"$@\" $(cpu); \
     [ $# -gt 9 ] && shift; [ $# = 9 ] && [ $1 = $9 ] && return 0; \
     sleep 0.25; n=$((n+1)); done; return 1; }";

/// Runs the window as a user does (no script: it draws nothing while nothing changes) under
/// Xvfb on the 1280x800 screen, drives it with `driver` (xdotool, the window in `$win`, the
/// app in `$app`, its log in `$log`, [`LOGGED`]) once its first image is on screen, then
/// saves the view (F5) and quits (Esc, Esc). The saved view's text and the log; None (after
/// saying so) where Xvfb or xdotool is missing. The screen as drawn is the file `$screen`
/// (Xvfb's framebuffer, an XWD image), which the driver can copy ([`read_xwd`]). The run
/// holds `slot` (`window_alone()` where the driver's checks rest on timing).
fn run_idle_window(
    dir: &std::path::Path,
    driver: &str,
    slot: WindowSlot,
) -> Option<(String, String)> {
    if !common::tool_for("xdotool", "xdotool", "the idle window test")
        || !common::window::xvfb_for("the idle window test")
    {
        return None;
    }
    let wrapper = format!(
        "log=app.log; {LOGGED}; \"$1\" 2>app.log & app=$!; \
         logged 'first image on screen'; {FIND_WINDOW}; sleep 0.5; {driver}; sleep 0.3; \
         xdotool key F5; \
         logged 'saved view'; xdotool key Escape; sleep 0.3; xdotool key Escape; \
         n=0; while kill -0 $app 2>/dev/null && [ $n -lt 100 ]; do sleep 0.1; n=$((n+1)); done; \
         kill $app 2>/dev/null; wait $app"
    );
    let out = std::process::Command::new("timeout")
        .args(["300", "xvfb-run"])
        .args(slot.server_args())
        .arg("-s")
        .arg(format!("-screen 0 1280x800x24 -fbdir {}", dir.display()))
        .args(["sh", "-c", &wrapper, "sh", RAYLAB])
        .env("RUST_LOG", "raylab=info")
        .env("screen", dir.join("Xvfb_screen0"))
        .env_remove("XDG_RUNTIME_DIR")
        .env_remove("WAYLAND_DISPLAY")
        .env_remove("WAYLAND_SOCKET")
        .current_dir(dir)
        .output()
        .expect("start xvfb-run");
    let log = std::fs::read_to_string(dir.join("app.log")).unwrap_or_default();
    assert!(out.status.success(), "{:?}\n{log}", out.status);
    assert!(!log.contains("panicked"), "{log}");
    let driver_said = String::from_utf8_lossy(&out.stderr);
    assert!(!driver_said.contains(NOT_LOGGED), "{driver_said}\n{log}");
    let view = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.extension().is_some_and(|e| e == "view"))
        .unwrap_or_else(|| panic!("F5 saved no view\n{log}"));
    Some((std::fs::read_to_string(view).unwrap(), log))
}

fn real_x_input_a_key_tap_after_idle_moves_only_as_long_as_it_was_held() {
    // The window idle (nothing drawn for 2 s), Shift held, a tap of W (held 50 ms), Shift let
    // go; idle again, a 50 ms tap of Left. A motion's first frame counts from the press, not
    // from the last frame drawn: at 4 x 1.73 units/s and 1.2 rad/s, W moves about 0.35 and
    // Left turns about 3.4°, give or take a frame. (A first frame that counted the idle time,
    // cut to a frame's most, 0.25 s, moved 1.73 and turned 17.2°, and more with the frames
    // after it.)
    let dir = tempfile::tempdir().unwrap();
    // (Each tap in one xdotool run: a second process started between press and release
    // held the key longer on a busy machine.)
    let driver = "xdotool windowfocus --sync $win; sleep 2; xdotool keydown shift; sleep 0.3; \
                  xdotool keydown w sleep 0.05 keyup w; sleep 0.1; \
                  xdotool keyup shift; sleep 2; \
                  xdotool keydown Left sleep 0.05 keyup Left";
    let alone = window_alone();
    let Some((view, log)) = run_idle_window(dir.path(), driver, alone) else {
        return;
    };
    // camera x y z yaw Y pitch P
    let camera: Vec<&str> = (view.lines())
        .find_map(|l| l.strip_prefix("camera "))
        .unwrap_or_else(|| panic!("{view}"))
        .split_whitespace()
        .collect();
    let (z, yaw): (f64, f64) = (camera[2].parse().unwrap(), camera[4].parse().unwrap());
    let moved = z + 3.001;
    println!("Shift+W moved {moved}, Left turned {yaw}°");
    // Bounds with room for a slow frame (up to 0.15 s past the release: a busy machine's
    // window test moved 1.27), below what counting the idle time moves.
    assert!(
        (0.0..1.5).contains(&moved),
        "Shift+W tapped moved {moved}\n{view}\n{log}"
    );
    assert!(
        (-14.0..=0.0).contains(&yaw),
        "Left tapped turned {yaw}°\n{view}"
    );
}

/// An XWD image of a 24-bit screen (as Xvfb's `-fbdir` keeps it): width, height and RGB
/// pixels in rows.
fn read_xwd(path: &std::path::Path) -> (usize, usize, Vec<[u8; 3]>) {
    let data = std::fs::read(path).unwrap();
    let field = |k: usize| u32::from_be_bytes(data[4 * k..4 * k + 4].try_into().unwrap()) as usize;
    let (header, width, height) = (field(0), field(4), field(5));
    let (lsb_first, bits, row) = (field(7) == 0, field(11), field(12));
    assert_eq!(bits, 32, "32 bits a pixel");
    let start = header + 12 * field(19);
    let pixels = (0..height * width)
        .map(|k| {
            let p = &data[start + (k / width) * row + 4 * (k % width)..][..4];
            match lsb_first {
                true => [p[2], p[1], p[0]],
                false => [p[1], p[2], p[3]],
            }
        })
        .collect();
    (width, height, pixels)
}

fn real_x_input_a_tooltip_shows_while_the_pointer_rests() {
    // The pointer rests on the panel's speed field (whose tooltip says what + and - do) and
    // nothing else happens: egui asks to be drawn again once the tooltip is due, and the
    // window wakes for it. The screen under the field, before the pointer came and 2 s
    // after, differs where the tooltip is drawn. ((184, 306): the field at the default
    // window on the 1280x800 screen.)
    let dir = tempfile::tempdir().unwrap();
    let driver = "xdotool windowfocus --sync $win; xdotool mousemove --sync 700 650; \
                  sleep 1.5; cp \"$screen\" before.xwd; xdotool mousemove --sync 184 306; \
                  sleep 2; cp \"$screen\" after.xwd";
    let Some((_, log)) = run_idle_window(dir.path(), driver, one_window()) else {
        return;
    };
    let (w, _, before) = read_xwd(&dir.path().join("before.xwd"));
    let (_, _, after) = read_xwd(&dir.path().join("after.xwd"));
    // Below the field (which the pointer's hover redraws at once): where the tooltip goes.
    let changed = (318..360)
        .flat_map(|y| (150..450).map(move |x| y * w + x))
        .filter(|&k| before[k] != after[k])
        .count();
    println!("{changed} pixels changed below the speed field");
    assert!(
        changed > 1000,
        "no tooltip: {changed} pixels changed\n{log}"
    );
}

fn real_x_input_show_cracks_at_capped_supersampling_refines_and_idles() {
    // The ray inspector off, show cracks ticked, 16 typed into the supersampling field: the
    // window renders 11x11 (its bound at this size) and says so on a line of its own, which
    // makes the panel taller than the window once the counts' line is two lines long; its
    // scroll bar, drawn all along, takes no more room. The view refines to 11x11, is counted
    // and the window goes idle: no CPU time used, the panel's width unchanged. (The bar went
    // whenever the counts' line was short, "counted once the view settles", and the panel got
    // its width back; the counts brought the bar again, widening the panel a little each frame
    // as the bar faded in: each a new image width, a new view to render, without end.)
    // Positions: the panel at the default window on the 1280x800 screen, the inspector's box
    // at (15, 378); with it off, "show cracks" at (15, 571), the supersampling field at
    // (135, 529). The driver waits (two minutes at most) until the app has used no CPU for 2 s
    // (the last 9 of its CPU times read every quarter second the same), then counts the
    // panel's widths logged over 2 s more.
    let dir = tempfile::tempdir().unwrap();
    let driver = format!(
        "xdotool windowfocus --sync $win; xdotool mousemove --sync 15 378 click 1; \
         sleep 0.5; xdotool mousemove --sync 15 571 click 1; sleep 0.5; \
         xdotool mousemove --sync 135 529 click 1; sleep 0.8; xdotool key ctrl+a; \
         xdotool type 16; xdotool key Return; {IDLE}; idle && echo idle > idle.txt; \
         grep -c 'points wide' app.log > widths-before.txt; sleep 2; \
         grep -c 'points wide' app.log > widths-after.txt"
    );
    let Some((view, log)) = run_idle_window(dir.path(), &driver, one_window()) else {
        return;
    };
    let read = |name: &str| std::fs::read_to_string(dir.path().join(name)).unwrap_or_default();
    assert_eq!(
        read("idle.txt").trim(),
        "idle",
        "the window never went idle\n{log}"
    );
    let (before, after) = (read("widths-before.txt"), read("widths-after.txt"));
    assert_eq!(before, after, "the panel's width changed while idle\n{log}");
    let widths: Vec<f64> = (log.lines())
        .filter_map(|l| l.split("side panel ").nth(1)?.strip_suffix(" points wide"))
        .map(|w| w.parse().unwrap())
        .collect();
    // Its one width: the bar's room is kept whether the rows overflow or not.
    assert_eq!(widths.len(), 1, "{widths:?}\n{log}");
    // The view saved once idle asks for 16x16 with cracks.
    assert!(view.lines().any(|l| l == "spp 16"), "{view}");
    assert!(view.lines().any(|l| l == "cracks on"), "{view}");
}

fn real_x_input_f5_and_copy_as_command_ignore_the_inspectors_crop() {
    // F5 and C, then a click on the image (the inspector's panel opens and crops the image's
    // sides), then C and F5 again: the view saved and the command copied are the same both
    // times, the view's own width, not the cropped one. (Both wrote the cropped width, so a
    // view saved while inspecting rendered narrower than the window's view.)
    let dir = tempfile::tempdir().unwrap();
    let driver = "xdotool windowfocus --sync $win; xdotool key F5; logged 'saved view'; \
                  mv raylab-view-*.view without-inspector.txt; xdotool key c; logged copied; \
                  xdotool mousemove --sync 700 300 click 1; logged 'inspected pixel'; \
                  sleep 1; xdotool key c; logged copied 2";
    let Some((view, log)) = run_idle_window(dir.path(), driver, one_window()) else {
        return;
    };
    let without = std::fs::read_to_string(dir.path().join("without-inspector.txt")).unwrap();
    assert_eq!(view, without, "the view saved while inspecting\n{log}");
    let commands: Vec<&str> = (log.lines())
        .filter_map(|l| Some(&l[l.find("copied to the clipboard: ")?..]))
        .collect();
    assert_eq!(commands.len(), 2, "{log}");
    assert_eq!(
        commands[0], commands[1],
        "the command copied while inspecting"
    );
}

fn real_x_input_the_window_shows_the_headless_render_pixel_for_pixel() {
    // The inspector off (I), the view refined, the screen copied, then F5: the view rendered
    // headless is on the screen pixel for pixel beside the side panel, whose edge lies at a
    // fraction of a point (358.2): the image drawn from there was resampled, 2,768 of its
    // pixels off by up to 7% on the edges.
    let dir = tempfile::tempdir().unwrap();
    let driver = format!(
        "xdotool windowfocus --sync $win; xdotool key i; logged 'ray inspector off'; {IDLE}; \
         idle; cp \"$screen\" screen.xwd"
    );
    let Some((view, log)) = run_idle_window(dir.path(), &driver, one_window()) else {
        return;
    };
    std::fs::write(dir.path().join("saved.view"), &view).unwrap();
    let out = std::process::Command::new(RAYLAB)
        .args(["render", "--view", "saved.view", "-o", "headless.png"])
        .current_dir(dir.path())
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let (w, h, rgba) = common::read_png(&dir.path().join("headless.png"));
    let (sw, sh, screen) = read_xwd(&dir.path().join("screen.xwd"));
    let panel: f64 = (log.lines().rev())
        .find_map(|l| l.split("side panel ").nth(1)?.strip_suffix(" points wide"))
        .and_then(|w| w.parse().ok())
        .unwrap_or_else(|| panic!("{log}"));
    let (w, h) = (w as usize, h as usize);
    // The offset where the most pixels agree, near the panel's edge and the window's top.
    let same_at = |x0: usize, y0: usize| {
        (0..h * w)
            .filter(|&k| {
                let (x, y) = (x0 + k % w, y0 + k / w);
                x < sw && y < sh && screen[y * sw + x] == rgba[4 * k..4 * k + 3]
            })
            .count()
    };
    let x = panel.floor() as usize;
    let best = (x - 1..=x + 2)
        .flat_map(|x0| (0..3).map(move |y0| (x0, y0)))
        .map(|(x0, y0)| (same_at(x0, y0), x0, y0))
        .max()
        .unwrap();
    println!("{w}x{h} headless, panel {panel} points: {best:?} pixels the same");
    assert_eq!(best.0, w * h, "{best:?} of {} pixels\n{log}", w * h);
}

/// This file's tests, by name, for the harness (main.rs).
fn a_scripted_run_idle_before_its_last_frame_still_ends() {
    // `--frames 100` without a script: the view is refined long before its hundredth frame,
    // and after that frame the run draws only on events, as a user's window does. It draws
    // once more to be captured and ends (it had waited for the run's limit, 120 s, and
    // failed with nothing left to wait for).
    if !common::window::xvfb_for("the window test") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let slot = one_window();
    // (Under the run's own limit, which would end it failed; 100 frames on a loaded machine
    // can take a minute.)
    let out = std::process::Command::new("timeout")
        .args(["110", "xvfb-run"])
        .args(slot.server_args())
        .args(["-s", "-screen 0 1280x800x24", RAYLAB, "--frames", "100"])
        .arg("--screenshot")
        .arg(dir.path().join("shot.png"))
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .unwrap();
    let (stdout, stderr) = (common::binary::stdout(&out), common::binary::stderr(&out));
    assert!(out.status.success(), "{}\n{stderr}", out.status);
    let frames = (stdout.split_whitespace())
        .find_map(|kv| kv.strip_prefix("frames="))
        .map(|n| n.parse::<u64>().unwrap());
    assert!(frames.is_some_and(|n| n >= 100), "{stdout}");
}

pub const TESTS: super::Tests = tests![
    a_scripted_run_idle_before_its_last_frame_still_ends,
    real_x_input_a_key_tap_after_idle_moves_only_as_long_as_it_was_held,
    real_x_input_a_tooltip_shows_while_the_pointer_rests,
    real_x_input_show_cracks_at_capped_supersampling_refines_and_idles,
    real_x_input_f5_and_copy_as_command_ignore_the_inspectors_crop,
    real_x_input_the_window_shows_the_headless_render_pixel_for_pixel,
];
