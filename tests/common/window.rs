//! The window tests' harness: a scripted run of a window binary under Xvfb (with real X input
//! beside it, or a desktop DPI change), its final line and screenshot, and the comparison
//! with a headless render. Shared by raylab's window tests (app/) and the lab crate's.

use super::read_png;
use glam::DVec3;
use raylab::render::{render_image, LabStep, RenderSettings};
use raylab::{Camera, Scene};
use std::collections::HashMap;
use std::os::unix::process::CommandExt;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Mean absolute channel difference and the fraction of pixels off by more than 8, between
/// the window's image rectangle (sampled at the nearest pixel) and a render of `w`×`h`.
pub fn compare(
    shot: &(u32, u32, Vec<u8>),
    rect: [f64; 4],
    render: &[u8],
    w: u32,
    h: u32,
) -> (f64, f64) {
    let (sw, _, px) = shot;
    let mut sum = 0u64;
    let mut off = 0usize;
    for j in 0..h {
        for i in 0..w {
            let x = (rect[0] + (i as f64 + 0.5) * rect[2] / w as f64) as u32;
            let y = (rect[1] + (j as f64 + 0.5) * rect[3] / h as f64) as u32;
            let a = &px[4 * (y * sw + x) as usize..][..3];
            let b = &render[4 * (j * w + i) as usize..][..3];
            let d: Vec<u64> = (0..3)
                .map(|c| (a[c] as i64 - b[c] as i64).unsigned_abs())
                .collect();
            sum += d.iter().sum::<u64>();
            if d.iter().any(|&x| x > 8) {
                off += 1;
            }
        }
    }
    let n = (w * h) as f64;
    (sum as f64 / (3.0 * n), off as f64 / n)
}

/// What a scripted run printed and saved.
pub struct Run {
    pub fields: HashMap<String, String>,
    /// The ray inspector's fields (`inspector name: value` lines), if it was used.
    pub inspector: HashMap<String, String>,
    pub shot: (u32, u32, Vec<u8>),
    /// Everything the run printed (the final line, the status, the cracks' counts, ...).
    pub stdout: String,
    pub stderr: String,
}

impl Run {
    pub fn nums(&self, k: &str) -> Vec<f64> {
        let value = self.fields.get(k);
        value
            .unwrap_or_else(|| panic!("no {k}: the run printed no final line\n{}", self.stderr))
            .split([',', 'x'])
            .map(|x| x.parse().unwrap())
            .collect()
    }

    /// The size of the view F5 writes at the run's end, of which the image shown is a crop
    /// [`Run::view_offset`] columns from its left (where the inspector's panel crops it).
    pub fn view_size(&self) -> (u32, u32) {
        let size = self.nums("size");
        let offset = self.view_offset();
        (size[0] as u32 + 2 * offset, size[1] as u32)
    }

    /// How many columns of the view lie left of the image shown (the inspector names the
    /// view's pixels).
    pub fn view_offset(&self) -> u32 {
        self.nums("view_offset")[0] as u32
    }

    /// The camera the window ended with, its render size and the image rectangle.
    pub fn camera(&self) -> (Camera, u32, u32, [f64; 4]) {
        let pos = self.nums("camera");
        let (yaw, pitch, focal) = (
            self.nums("yaw")[0],
            self.nums("pitch")[0],
            self.nums("focal")[0],
        );
        let size = self.nums("size");
        let r = self.nums("rect");
        let cam = Camera::from_yaw_pitch(
            DVec3::new(pos[0], pos[1], pos[2]),
            yaw.to_radians(),
            pitch.to_radians(),
            focal,
        )
        .unwrap();
        (
            cam,
            size[0] as u32,
            size[1] as u32,
            [r[0], r[1], r[2], r[3]],
        )
    }
}

/// Whether `xvfb-run` is installed for `test` ([`super::tool_for`]: where it is not, the test
/// says so and skips, or under CI=true fails).
pub fn xvfb_for(test: &str) -> bool {
    super::tool_for("xvfb-run", "xvfb xauth mesa-vulkan-drivers", test)
}

/// What runs beside the app on the display.
pub enum Around<'a> {
    Nothing,
    /// An XSETTINGS manager (xsettingsd) whose Xft/DPI goes from 96 to `dpi` `at_ms` after
    /// the app's first image on screen (where its script's clock starts): the desktop's HiDPI
    /// change, which winit reports as `ScaleFactorChanged`.
    DpiChange {
        at_ms: u32,
        dpi: u32,
    },
    /// A shell snippet that drives the running app with real X input (xdotool), started
    /// once the app's first image is on screen (the window's id in `$win`, the app's log in
    /// `$log`; [`LOGGED`] waits for a line of it), in the run's directory. Once it has
    /// finished (and 0.3 s more, for its last events to reach the app), the file
    /// `driver-done` appears there: a script's `await driver-done` holds the run that long.
    RealInput(&'a str),
    /// [`Around::RealInput`] with the app opening this file instead of the Cornell box.
    RealInputOn(&'a str, &'a std::path::Path),
    /// [`Around::RealInput`] with no other window running beside it ([`window_alone`]): for a
    /// driver whose checks rest on how long a key was held, which another window's frames
    /// could cut short (a press and its release taken in one late batch of events).
    RealInputAlone(&'a str),
    /// Nothing beside the app, which starts with these arguments.
    Args(&'a [&'a str]),
}

/// A shell function for drivers: `logged TEXT [N]` returns once the app's log (the file
/// `$log`) holds TEXT on N lines (1 if not given); failing, and saying so, once the app (its
/// process id `$app`) has ended or after 60 s, which fails the test (a step that never came
/// is not a wait: the steps after it test something else). A driver waits with it for what
/// the app has done, where a fixed sleep would have to last as long as the slowest machine
/// takes.
pub const LOGGED: &str = "logged() { n=0; \
     until [ \"$(grep -cF -- \"$1\" \"$log\" 2>/dev/null)\" -ge \"${2:-1}\" ] 2>/dev/null; do \
     if [ $n -ge 1200 ] || ! kill -0 $app 2>/dev/null; then \
     echo \"driver: not logged: $1\" >&2; return 1; fi; \
     sleep 0.05; n=$((n+1)); done; }";

/// What [`LOGGED`] says where it gives up.
pub const NOT_LOGGED: &str = "driver: not logged: ";

/// Sets `$win` to the app's window once its first image is on screen (searched for then:
/// `xdotool search --sync` looks again only every half second), where the app still runs.
pub const FIND_WINDOW: &str =
    "kill -0 $app 2>/dev/null && win=$(xdotool search --sync --name '^raylab')";

/// The screen of the runs' X server where a test names no other: a common laptop's.
pub const SCREEN: (u32, u32) = (1280, 800);

/// How many windows run at once: five, each on its own X server (the window tests' harness
/// runs at least as many tests at once). A run mostly waits for its driver (five windows used
/// 1.6 of two cores), and its driver waits for what the app logs, not for fixed times, so other
/// windows beside it slow it down without changing what it sees; a test whose checks do rest
/// on timing takes [`window_alone`].
pub const WINDOWS_AT_ONCE: usize = 5;

/// Which of the [`WINDOWS_AT_ONCE`] slots are taken, and how many tests wait for all of them
/// (a test that wants one waits behind them, so that one that wants all is not starved).
struct Slots {
    taken: [bool; WINDOWS_AT_ONCE],
    waiting_for_all: usize,
}

static SLOTS: std::sync::Mutex<Slots> = std::sync::Mutex::new(Slots {
    taken: [false; WINDOWS_AT_ONCE],
    waiting_for_all: 0,
});
static SLOT_FREED: std::sync::Condvar = std::sync::Condvar::new();

/// A test's hold on the window slots (one, or all of them), given back when dropped. Each slot
/// has X server numbers of its own, so two runs never race for one.
pub struct WindowSlot {
    taken: Vec<usize>,
}

/// Holds one window slot: for a test that starts its window itself.
pub fn one_window() -> WindowSlot {
    take_slots(1)
}

/// Holds every window slot: for a test whose checks rest on timing (how long a key was held),
/// which another window's load could upset.
pub fn window_alone() -> WindowSlot {
    take_slots(WINDOWS_AT_ONCE)
}

fn take_slots(n: usize) -> WindowSlot {
    let mut slots = SLOTS.lock().unwrap_or_else(|e| e.into_inner());
    let all = n == WINDOWS_AT_ONCE;
    if all {
        slots.waiting_for_all += 1;
    }
    loop {
        let free: Vec<usize> = (0..WINDOWS_AT_ONCE).filter(|&i| !slots.taken[i]).collect();
        if free.len() >= n && (all || slots.waiting_for_all == 0) {
            let taken = free[..n].to_vec();
            for &i in &taken {
                slots.taken[i] = true;
            }
            if all {
                slots.waiting_for_all -= 1;
            }
            return WindowSlot { taken };
        }
        slots = SLOT_FREED.wait(slots).unwrap_or_else(|e| e.into_inner());
    }
}

impl WindowSlot {
    /// `xvfb-run` on an X server of this slot's own.
    pub fn xvfb_run(&self) -> Command {
        let mut command = Command::new("xvfb-run");
        command.args(self.server_args());
        command
    }

    /// `xvfb-run`'s arguments for a server number of this slot's own: from 100 + 20 × slot up
    /// (`-a` skips one left in use).
    pub fn server_args(&self) -> [String; 3] {
        let first = 100 + 20 * self.taken[0];
        ["-a".into(), "-n".into(), first.to_string()]
    }
}

impl Drop for WindowSlot {
    fn drop(&mut self) {
        let mut slots = SLOTS.lock().unwrap_or_else(|e| e.into_inner());
        for &i in &self.taken {
            slots.taken[i] = false;
        }
        SLOT_FREED.notify_all();
    }
}

/// Runs the window binary `exe` under Xvfb with `script` and something running beside it
/// ([`Around`]); None (after saying so) where Xvfb is missing.
pub fn run_window_with(
    exe: &str,
    script: &str,
    dir: &std::path::Path,
    env: &[(&str, &str)],
    around: Around,
) -> Option<Run> {
    run_window_on(exe, SCREEN, script, dir, env, around)
}

/// [`run_window_with`] on an X screen of `screen` pixels. The run's environment is a plain X
/// server's: no Wayland display, no XDG_RUNTIME_DIR.
pub fn run_window_on(
    exe: &str,
    screen: (u32, u32),
    script: &str,
    dir: &std::path::Path,
    env: &[(&str, &str)],
    around: Around,
) -> Option<Run> {
    let slot = match around {
        Around::RealInputAlone(_) => window_alone(),
        _ => one_window(),
    };
    let (driver, model) = match around {
        Around::RealInput(d) | Around::RealInputAlone(d) => (Some(d), None),
        Around::RealInputOn(d, m) => (Some(d), Some(m)),
        _ => (None, None),
    };
    if driver.is_some() && !super::tool_for("xdotool", "xdotool", "the real-input window test") {
        return None;
    }
    let args: &[&str] = match around {
        Around::Args(args) => args,
        _ => &[],
    };
    let dpi_change = match around {
        Around::DpiChange { at_ms, dpi } => Some((at_ms, dpi)),
        _ => None,
    };
    if dpi_change.is_some() && !super::tool_for("xsettingsd", "xsettingsd", "the HiDPI change test")
    {
        return None;
    }
    if !xvfb_for("the window test") {
        return None;
    }
    let script_path = dir.join("script.txt");
    std::fs::write(&script_path, script).unwrap();
    let shot_path = dir.join("shot.png");
    let mut command = slot.xvfb_run();
    let screen_arg = format!("-screen 0 {}x{}x24", screen.0, screen.1);
    command.args(["-s", &screen_arg]);
    if let Some((at_ms, dpi)) = dpi_change {
        let conf = dir.join("xsettings.conf");
        std::fs::write(&conf, "Xft/DPI 98304\n").unwrap();
        // The manager first, then the app; the change while the app runs; the app's exit
        // status is the run's.
        let wrapper = format!(
            "log='{log}'; {LOGGED}; xsettingsd -c '{conf}' 2>/dev/null & xs=$!; sleep 0.5; \
             \"$@\" 2>\"$log\" & app=$!; logged 'first image on screen'; \
             sleep {delay}; echo 'Xft/DPI {value}' > '{conf}'; kill -HUP $xs; \
             wait $app; status=$?; kill $xs; cat \"$log\" >&2; exit $status",
            log = dir.join("app.log").display(),
            conf = conf.display(),
            delay = at_ms as f64 / 1000.0,
            value = dpi * 1024,
        );
        command.args(["sh", "-c", &wrapper, "sh"]);
    }
    if let Some(driver) = driver {
        // The app, then the driver once its window is there; the app's exit status is the
        // run's.
        // The driver starts once the app logs its first image on screen (a fresh CI machine
        // under lavapipe, with other window tests running, can take seconds to draw one):
        // input sent earlier would meet no image (and a file edited before the app's watcher
        // first looked at it, a quarter second after the start, would go unseen). The log goes
        // on to stderr afterwards.
        let log = dir.join("app.log");
        let wrapper = format!(
            "log='{log}'; {LOGGED}; \"$@\" 2>\"$log\" & app=$!; \
             logged 'first image on screen'; {FIND_WINDOW}; sleep 0.5; \
             {driver}; sleep 0.3; : > driver-done; wait $app; status=$?; \
             cat \"$log\" >&2; exit $status",
            log = log.display()
        );
        command.args(["sh", "-c", &wrapper, "sh"]);
    }
    command.arg(exe);
    if let Some(model) = model {
        command.arg(model);
    }
    command.args(args);
    let mut child = command
        .args(["--frames", "5", "--screenshot"])
        .arg(&shot_path)
        .arg("--script")
        .arg(&script_path)
        // (egui's warnings too: a test can hold the window to none.)
        .env("RUST_LOG", "raylab=info,egui=warn")
        .env_remove("XDG_RUNTIME_DIR")
        .env_remove("WAYLAND_DISPLAY")
        .env_remove("WAYLAND_SOCKET")
        .envs(env.iter().copied())
        .current_dir(dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .process_group(0)
        .spawn()
        .expect("start xvfb-run");
    let start = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        if start.elapsed() > Duration::from_secs(300) {
            // What was still running (which of the app, the driver's commands) and what the
            // app logged, then its whole process group: xvfb-run, Xvfb, the app and the driver.
            let running = processes_in_group(child.id());
            let log = std::fs::read_to_string(dir.join("app.log")).unwrap_or_default();
            let group = format!("-{}", child.id());
            let _ = Command::new("kill").args(["-KILL", "--", &group]).status();
            panic!("the window run hung for 300 s\nstill running:\n{running}\napp log:\n{log}");
        }
        std::thread::sleep(Duration::from_millis(100));
    };
    let out = child.wait_with_output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(
        status.success(),
        "exit {status}\nstdout: {stdout}\nstderr: {stderr}"
    );
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(!stderr.contains(NOT_LOGGED), "{stderr}");
    // raylab-final camera=x,y,z yaw=.. pitch=.. focal=.. size=WxH rect=x,y,w,h step=.. spp=..
    // method=.. cracks=.. (every image control) .. scene=..
    // (No final line where the run was quit early: Esc twice.)
    let fields = stdout
        .lines()
        .find(|l| l.starts_with("raylab-final"))
        .map(|line| {
            line.split_whitespace()
                .skip(1)
                .filter_map(|kv| kv.split_once('='))
                .map(|(k, v)| (k.to_string(), v.to_string()))
                .collect()
        })
        .unwrap_or_default();
    let inspector = stdout
        .lines()
        .filter_map(|l| l.strip_prefix("inspector ")?.split_once(": "))
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect();
    Some(Run {
        fields,
        inspector,
        shot: match shot_path.exists() {
            true => read_png(&shot_path),
            false => (0, 0, Vec::new()),
        },
        stdout,
        stderr,
    })
}

/// The processes of process group `group`, one a line: pid, state, seconds running, command.
fn processes_in_group(group: u32) -> String {
    let out = Command::new("ps")
        .args(["-e", "-o", "pgid=,pid=,stat=,etimes=,args="])
        .output();
    let text = out.map(|o| String::from_utf8_lossy(&o.stdout).into_owned());
    let lines = text.unwrap_or_default();
    let in_group = lines.lines().filter_map(|l| {
        let (pgid, rest) = l.trim_start().split_once(' ')?;
        (pgid.parse() == Ok(group)).then(|| rest.trim_start().to_string())
    });
    in_group.collect::<Vec<_>>().join("\n")
}

/// Renders `scene` headless from the run's final camera at the size the window showed (the
/// window's final quality: indirect light, 2×2 samples) and compares it with the screenshot's
/// image rectangle: (mean difference per channel, fraction of pixels off). Also returns the
/// headless image.
pub fn against_headless(run: &Run, scene: &Scene) -> (f64, f64, Vec<u8>, u32, u32) {
    let (camera, w, h, rect) = run.camera();
    let settings = RenderSettings {
        width: w,
        height: h,
        step: LabStep::Indirect,
        spp: 2,
        ..Default::default()
    };
    let (expected, _) = render_image(&scene.clone().into(), &camera, &settings).unwrap();
    let (mean, off) = compare(&run.shot, rect, &expected, w, h);
    (mean, off, expected, w, h)
}

/// A pixel the cracks view marks: its column, row and verdict.
pub type Marked = (u32, u32, &'static str);

/// Each pixel's centre ray of a `w`×`h` image from `camera`, answered by `method` and graded
/// against the exact answer as `raylab check` grades: how many got each verdict (by name), and
/// the pixels the cracks view marks (the answer hits where the exact ray misses, or the
/// reverse) in reading order, with their verdicts.
pub fn graded_pixels(
    stage: &raylab::render::Stage,
    camera: &Camera,
    (w, h): (u32, u32),
    method: raylab::geometry::Method,
) -> (HashMap<&'static str, u64>, Vec<Marked>) {
    let shapes: Vec<_> = stage.scene().all_shapes().collect();
    let rays = camera.ray_generator(w, h);
    let mut counts: HashMap<&str, u64> = HashMap::new();
    let mut marked = Vec::new();
    for j in 0..h {
        for i in 0..w {
            let ray = rays.ray_through(i as f32 + 0.5, j as f32 + 0.5);
            let answer = |m| stage.accel().closest_hit(&ray, m, 0.0, f32::INFINITY);
            let (given, exact) = (answer(method), answer(raylab::geometry::Method::Adaptive));
            let verdict = raylab::check::code::verdict(&shapes, &ray, exact, given);
            *counts.entry(verdict.name()).or_default() += 1;
            if given.is_some() != exact.is_some() {
                marked.push((i, j, verdict.name()));
            }
        }
    }
    (counts, marked)
}

/// The distance from point `p` to segment a–b.
pub fn segment_distance(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (ab, ap) = ([b[0] - a[0], b[1] - a[1]], [p[0] - a[0], p[1] - a[1]]);
    let len2 = (ab[0] * ab[0] + ab[1] * ab[1]).max(1e-12);
    let s = ((ap[0] * ab[0] + ap[1] * ab[1]) / len2).clamp(0.0, 1.0);
    ((ap[0] - s * ab[0]).powi(2) + (ap[1] - s * ab[1]).powi(2)).sqrt()
}

/// Of the pixels of a `w`×`h` render whose centres `keep` (image coordinates), how many there
/// are and how many the window's image rectangle `rect` in `shot` shows off by more than 8
/// (sampled as [`compare`] samples).
pub fn pixels_off_where(
    shot: &(u32, u32, Vec<u8>),
    rect: [f64; 4],
    render: &[u8],
    (w, h): (u32, u32),
    keep: impl Fn([f64; 2]) -> bool,
) -> (u32, u32) {
    let (sw, _, px) = shot;
    let (mut kept, mut off) = (0, 0);
    for j in 0..h {
        for i in 0..w {
            let p = [i as f64 + 0.5, j as f64 + 0.5];
            if !keep(p) {
                continue;
            }
            kept += 1;
            let x = (rect[0] + p[0] * rect[2] / w as f64) as u32;
            let y = (rect[1] + p[1] * rect[3] / h as f64) as u32;
            let shown = &px[4 * (y * sw + x) as usize..][..3];
            let want = &render[4 * (j * w + i) as usize..][..3];
            off += (0..3).any(|c| (shown[c] as i32 - want[c] as i32).abs() > 8) as u32;
        }
    }
    (kept, off)
}
