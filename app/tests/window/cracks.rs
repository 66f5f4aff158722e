//! The window's cracks view: its counts against every ray graded headless, and N / Shift+N
//! stepping through the marked pixels in the ray inspector, the panel's crop included.
//!
//! Needs `xvfb-run` and a Vulkan driver (Mesa's lavapipe works without a GPU). Where they are
//! missing the test says so loudly and skips, except under CI=true, where it must run.

use crate::common;

use super::inspector::{assert_inspector_shows, inspect_headless};
use common::window::{graded_pixels, run_window_with, Around};
use raylab::geometry::Method;
use raylab::render::{render_image, LabStep, RenderSettings};
use raylab::Scene;

/// The window under test.
const RAYLAB: &str = env!("CARGO_BIN_EXE_raylab");

/// Two triangles sharing their edge v1–v2, which lies in the plane x = 0, seen from
/// (0, 0, −3): at an odd image width every camera ray of the middle column lies in that plane
/// and crosses the shared edge exactly, and f32 Möller–Trumbore, rounding u + v to either side
/// of 1 in both triangles, lets some of them through.
const SHARED_EDGE: &str = "camera 0 0 -3\n\
                           tri -0.8 0.1 0.05 0 -0.7 0.3 0 0.6 -0.2\n\
                           tri 0.9 -0.05 0.1 0 -0.7 0.3 0 0.6 -0.2\n";

/// Writes the shared edge (`edge.scene`) and a view of it into `dir`: 321x241, flat, moller,
/// cracks on, `spp` samples a pixel per axis. The view's path.
fn shared_edge_view(dir: &std::path::Path, spp: u32) -> std::path::PathBuf {
    std::fs::write(dir.join("edge.scene"), SHARED_EDGE).unwrap();
    let view = dir.join("edge.view");
    std::fs::write(
        &view,
        format!(
            "scene edge.scene\ncamera 0 0 -3 yaw 0 pitch 0\nsize 321 241\nstep flat\n\
             spp {spp}\nmethod moller\ncracks on\n"
        ),
    )
    .unwrap();
    view
}

fn next_crack_where_only_wrong_primitives_are_counted_says_so() {
    // Watertight on the Cornell box at 3x3 samples: no leak, no false hit, some samples
    // naming another primitive than the exact one, which a method's cracks view counts but
    // does not mark. N finds no marked pixel and says why, not that every sample is right.
    let dir = tempfile::tempdir().unwrap();
    let view = dir.path().join("box.view");
    let text = "scene cornell\ncamera 0 0 -3.001 yaw 0 pitch 0\nsize 784 698\nstep shadows\n\
                spp 3\nmethod watertight\ncracks on\n";
    std::fs::write(&view, text).unwrap();
    let script = format!("0 drop {}\n600 key N down\n650 key N up\n", view.display());
    let Some(run) = run_window_with(RAYLAB, &script, dir.path(), &[], Around::Nothing) else {
        return;
    };
    let count = |name: &str| -> u64 { run.fields[name].parse().unwrap() };
    let (leaks, false_hits, wrong) = (count("leaks"), count("false_hits"), count("wrong"));
    assert_eq!(
        (leaks, false_hits),
        (0, 0),
        "the case needs no marked crack"
    );
    assert!(wrong > 0, "the case needs wrong primitives");
    let status = (run.stdout.lines())
        .find_map(|l| l.strip_prefix("status: "))
        .unwrap_or_default();
    assert_eq!(
        status,
        format!(
            "no marked cracks in this frame: watertight neither leaks nor hits falsely; {} \
             another primitive than the exact one (counted, not marked)",
            raylab::words::count(wrong as usize, "sample names", "samples name")
        ),
        "{}",
        run.stderr
    );
}

fn real_x_input_next_crack_steps_through_the_counted_cracks() {
    // The cracks view of moller on the shared edge (a dropped view: 321x241, flat, one
    // sample): the counts the panel shows are those of grading every pixel's ray headless;
    // real presses of N, N and Shift+N select the first, the second and again the first
    // marked pixel in reading order, and the inspector says the exact hit lies on the edge.
    let dir = tempfile::tempdir().unwrap();
    let view = shared_edge_view(dir.path(), 1);
    let script = format!("200 drop {}\n200 await driver-done\n", view.display());
    // (Each press once the view is loaded and the step before said; a step waits for its
    // frame's count.)
    let driver = "xdotool windowfocus --sync $win; logged 'loaded view'; xdotool key n; \
                  logged '] crack '; xdotool key n; logged '] crack ' 2; \
                  xdotool key shift+n; logged '] crack ' 3";
    let Some(run) = run_window_with(RAYLAB, &script, dir.path(), &[], Around::RealInput(driver))
    else {
        return;
    };
    let f = &run.fields;
    assert_eq!(
        (
            f["method"].as_str(),
            f["cracks"].as_str(),
            f["size"].as_str()
        ),
        ("moller", "on", "321x241"),
        "{}",
        run.stderr
    );
    // Every pixel's centre ray graded headless, as `raylab check` grades an answer.
    let scene_path = dir.path().join("edge.scene");
    let scene = Scene::open(scene_path.to_str().unwrap(), raylab::scene::ObjFrame::Lab).unwrap();
    let stage = raylab::render::Stage::from(scene);
    let (camera, w, h, _) = run.camera();
    let (counts, marked) = graded_pixels(&stage, &camera, (w, h), Method::Moller);
    let count = |name| counts.get(name).copied().unwrap_or(0);
    let expected = [
        ("leaks", count("leak")),
        ("false_hits", count("false hit")),
        ("wrong", count("wrong primitive")),
        ("ties", count("tie")),
        ("marked", marked.len() as u64),
    ];
    for (field, n) in expected {
        assert_eq!(f[field], n.to_string(), "{field}\n{}", run.stdout);
    }
    assert!(
        !marked.is_empty(),
        "moller lets rays through the shared edge"
    );
    assert!(
        marked.iter().all(|&(i, ..)| i == 160),
        "on the middle column only: {marked:?}"
    );
    let line = format!(
        "cracks: leaks {} · false hits {} · wrong {} · ties {} (of 77,361 px)",
        count("leak"),
        count("false hit"),
        count("wrong primitive"),
        count("tie")
    );
    assert!(run.stdout.contains(&line), "{line}\n{}", run.stdout);
    // The marks are the renderer's: its cracks view paints exactly these pixels.
    let settings = RenderSettings {
        width: w,
        height: h,
        method: Method::Moller,
        cracks: true,
        ..Default::default()
    };
    let (image, _) = render_image(&stage, &camera, &settings).unwrap();
    let magenta = raylab::render::CRACK.map(raylab::render::linear_to_srgb8);
    let painted: Vec<(u32, u32)> = (0..w * h)
        .filter(|k| image[4 * *k as usize..][..3] == magenta)
        .map(|k| (k % w, k / w))
        .collect();
    let listed: Vec<(u32, u32)> = marked.iter().map(|&(i, j, _)| (i, j)).collect();
    assert_eq!(painted, listed);
    // N, N, Shift+N: the first marked pixel, the second, the first again (one step a press).
    let log = &run.stderr;
    let n = marked.len();
    let steps: Vec<&str> = (log.lines())
        .filter_map(|l| Some(l.split_once("] crack ")?.1))
        .collect();
    let said = |k: usize| {
        let (i, j, _) = marked[k];
        format!("{} of {n}: pixel ({i}, {j}): ", k + 1)
    };
    assert_eq!(steps.len(), 3, "{log}");
    for (step, k) in steps.iter().zip([0, 1, 0]) {
        assert!(step.starts_with(&said(k)), "{step} is not {}", said(k));
    }
    let (i, j, verdict) = marked[0];
    let ins = &run.inspector;
    assert_eq!(ins["pixel"], format!("{i} {j}"), "{ins:?}");
    assert_eq!(
        ins["crack"],
        format!("{verdict} (marked magenta)"),
        "{ins:?}"
    );
    assert_eq!(ins["traced"], format!("the pixel's centre ({i}.5, {j}.5)"));
    // Exactly on the shared edge (the exact search's tie goes to primitive 0).
    assert_eq!(
        ins["exact hit lies"], "primitive 0, on the edge v1–v2",
        "{ins:?}"
    );
}

fn real_x_input_a_crack_on_the_status_line_gives_way_when_the_view_moves() {
    // N steps to the first crack of moller on the shared edge; then D moves the camera. The
    // status line tells of the pixel the inspector follows, no longer of the crack (it kept
    // "crack 1 of ..." over a frame where that pixel may show none).
    let dir = tempfile::tempdir().unwrap();
    let view = shared_edge_view(dir.path(), 1);
    let script = format!("200 drop {}\n200 await driver-done\n", view.display());
    let driver = "xdotool windowfocus --sync $win; logged 'loaded view'; xdotool key n; \
                  logged '] crack '; xdotool keydown d; logged 'D down'; sleep 0.3; \
                  xdotool keyup d";
    let Some(run) = run_window_with(RAYLAB, &script, dir.path(), &[], Around::RealInput(driver))
    else {
        return;
    };
    assert!(run.stderr.contains("] crack 1 of "), "{}", run.stderr);
    assert!(run.nums("camera")[0] > 0.1, "D moved right\n{}", run.stderr);
    let status = (run.stdout.lines()).find_map(|l| l.strip_prefix("status: "));
    let pixel = &run.inspector["pixel"].replace(' ', ", ");
    assert!(
        status.is_some_and(|s| s.starts_with(&format!("inspected pixel ({pixel}): "))),
        "the status line says {status:?}, the inspector pixel {pixel}\n{}",
        run.stdout
    );
}

fn real_x_input_next_crack_inspects_the_marked_samples_ray() {
    // The cracks view of moller on the shared edge at 3x3 samples a pixel: a real press of N
    // selects the first marked pixel, and every field the inspector shows is that of the
    // marked sample's ray, not of the pixel's centre ray: (u, v, f), the hit, t and the linear
    // system are the library's inspection of the sample's position, and the hit shown is the
    // answer the crack row says moller gave (a leak: none).
    let dir = tempfile::tempdir().unwrap();
    let view = shared_edge_view(dir.path(), 3);
    let script = format!("200 drop {}\n200 await driver-done\n", view.display());
    let driver = "xdotool windowfocus --sync $win; logged 'loaded view'; xdotool key n; \
                  logged '] crack '; xdotool key F5; logged 'saved view'";
    let Some(run) = run_window_with(RAYLAB, &script, dir.path(), &[], Around::RealInput(driver))
    else {
        return;
    };
    let log = &run.stderr;
    assert_eq!(
        (run.fields["method"].as_str(), run.fields["spp"].as_str()),
        ("moller", "3"),
        "{log}"
    );
    let ins = &run.inspector;
    assert!(
        ins.get("crack")
            .is_some_and(|c| c.ends_with("(marked magenta)")),
        "N inspected a marked pixel: {ins:?}\n{log}"
    );
    // The traced sample, as the crack rows name it: off the pixel's centre.
    let traced = &ins["traced"];
    let (x, y) = (traced.strip_prefix("sample ("))
        .and_then(|t| t.strip_suffix(") of the pixel"))
        .and_then(|t| t.split_once(", "))
        .map(|(x, y)| {
            (
                x.parse::<f32>().unwrap() as f64,
                y.parse::<f32>().unwrap() as f64,
            )
        })
        .unwrap_or_else(|| panic!("a sample is traced: {traced}"));
    let pixel = format!("{} {}", x.floor(), y.floor());
    assert_eq!(ins["pixel"], pixel, "{ins:?}");
    // The marked pixel stays in sight inside the ring drawn round it (a dot at its centre
    // hid it).
    let (_, shown_w, _, rect) = run.camera();
    let scale = rect[2] / shown_w as f64;
    let on_screen = |v: f64, start: f64| (start + (v.floor() + 0.5) * scale) as usize;
    let (sx, sy) = (
        on_screen(x - run.view_offset() as f64, rect[0]),
        on_screen(y, rect[1]),
    );
    let (sw, _, px) = &run.shot;
    let seen = &px[4 * (sy * *sw as usize + sx)..][..3];
    // (Magenta, blended a little with its neighbours by the texture's filtering.)
    let (r, g, b) = (seen[0] as i32, seen[1] as i32, seen[2] as i32);
    assert!(
        r > g + 100 && b > g + 100,
        "the marked pixel ({sx}, {sy}) on screen is magenta: {seen:?}"
    );
    let centre = (x.floor() + 0.5, y.floor() + 0.5);
    assert_ne!((x, y), centre, "the marked sample is not the centre one");
    let (camera, ..) = run.camera();
    let (w, h) = run.view_size();
    let uv = format!("{} {}", x - w as f64 / 2.0, y - h as f64 / 2.0);
    assert!(
        ins["uvf"].starts_with(&format!("{uv} ")),
        "(u, v) {} are the sample's {uv}, not the centre's",
        ins["uvf"]
    );
    // The hit shown is moller's answer the crack row gives, not the exact one.
    let exact = ins["exact hit lies"].split(',').next().unwrap();
    let given = &ins["moller hit lies"];
    let hit = match given.as_str() {
        "none" => "none".to_string(),
        g => (g
            .strip_prefix("primitive ")
            .and_then(|g| g.split(',').next()))
        .unwrap_or_else(|| panic!("{g}"))
        .to_string(),
    };
    assert_eq!(ins["hit"], hit, "{ins:?}");
    assert_ne!(format!("primitive {}", ins["hit"]), exact, "{ins:?}");
    if ins["crack"].starts_with("leak") {
        assert_eq!(ins["hit"], "none", "a leak: moller meets nothing there");
    }
    // Every field is the library's for the ray through that position.
    let settings = RenderSettings {
        width: w,
        height: h,
        step: LabStep::Flat,
        spp: 3,
        method: Method::Moller,
        ..Default::default()
    };
    let scene_path = dir.path().join("edge.scene");
    let scene = Scene::open(scene_path.to_str().unwrap(), raylab::scene::ObjFrame::Lab).unwrap();
    let expected =
        raylab::render::inspect::inspect_at(&scene.into(), &camera, &settings, x, y).unwrap();
    assert_inspector_shows(ins, &expected.to_string());
    // And `raylab inspect --at` of the traced position, with the view F5 saved, headless.
    let saved = (std::fs::read_dir(dir.path()).unwrap())
        .map(|e| e.unwrap().path())
        .find(|p| {
            p.file_name()
                .is_some_and(|n| n.to_string_lossy().starts_with("raylab-view"))
        })
        .unwrap_or_else(|| panic!("F5 saved no view\n{log}"));
    // And `--pixel` of its pixel: the pixel's first marked sample, as the window takes it.
    for ray in [
        ["--at", &format!("{x},{y}")],
        ["--pixel", &ins["pixel"].replace(' ', ",")],
    ] {
        let headless = inspect_headless(&ray, &saved);
        assert!(headless.contains("\ncrack: "), "the crack rows: {headless}");
        assert_inspector_shows(ins, &headless);
    }
}

fn real_x_input_next_crack_reaches_the_cracks_the_inspectors_panel_crops() {
    // N opens the inspector's panel, which crops the image's sides: the count is still the
    // whole view's, and N steps through every crack it marks, those under the panel too.
    // (The count was the crop's: cramer's nine marked pixels on the box became two, seven of
    // them out of N's reach, and a false hit cropped away became "no cracks in this frame".)
    let dir = tempfile::tempdir().unwrap();
    let script = "0 set method cramer\n0 set spp 1\n0 set cracks on\n0 await driver-done\n";
    // (N before the count waits for it.) Then I closes the panel and opens it again: each
    // frame is the view counted already, and is not counted again (a step to the next crack
    // waited seconds for a count of the view framed anew).
    let driver = "xdotool windowfocus --sync $win; xdotool key n; logged '] crack '; \
                  xdotool key shift+n; logged '] crack ' 2; xdotool key i; \
                  logged 'ray inspector off'; logged 'counted of the same view'; \
                  xdotool key i; logged 'ray inspector on'; logged 'counted of the same view' 2";
    let env = [(
        "RUST_LOG",
        "raylab=info,raylab_app::window::cracks=debug,egui=warn",
    )];
    let Some(run) = run_window_with(RAYLAB, script, dir.path(), &env, Around::RealInput(driver))
    else {
        return;
    };
    let log = &run.stderr;
    let (camera, w, h, _) = run.camera();
    let offset: u32 = run.fields["view_offset"].parse().unwrap();
    assert!(offset > 0, "the panel crops the image\n{log}");
    let stage = raylab::render::Stage::from(Scene::cornell());
    let view = (w + 2 * offset, h);
    let (counts, marked) = graded_pixels(&stage, &camera, view, Method::Cramer);
    assert_eq!(run.fields["marked"], marked.len().to_string(), "{log}");
    let leaks = counts.get("leak").copied().unwrap_or(0);
    assert_eq!(run.fields["leaks"], leaks.to_string(), "{log}");
    let under = |i: u32| i < offset || i >= offset + w;
    let beside = marked.iter().filter(|&&(i, ..)| under(i)).count();
    assert!(
        beside > 0,
        "a marked pixel under the panel: {marked:?}, offset {offset}"
    );
    let (i, j, _) = marked[0];
    let said = format!("crack 1 of {}: pixel ({i}, {j})", marked.len());
    assert!(log.contains(&said), "{said}\n{log}");
    // Shift+N from the first: the last, said to lie under the panel where it does, after
    // what the crack is (the status line cut that off behind the panel's note).
    let (i, j, _) = *marked.last().unwrap();
    let said = format!("crack {0} of {0}: pixel ({i}, {j}): ", marked.len());
    let line = (log.lines().find(|l| l.contains(&said))).unwrap_or_else(|| panic!("{said}\n{log}"));
    let what = &line[line.find(&said).unwrap() + said.len()..];
    assert!(
        what.starts_with("leak by cramer") || what.starts_with("false hit"),
        "{line}"
    );
    let note = " (under the inspector's panel: a wider window shows its ring)";
    assert_eq!(line.ends_with(note), under(i), "{line}");
    // The inspector says so at its top too, naming the side (the status line cut it off).
    let side = match (under(i), i < offset) {
        (false, _) => "none",
        (true, true) => "left",
        (true, false) => "right",
    };
    assert_eq!(run.fields["inspected_cropped"], side, "{log}");
}

fn real_x_input_a_no_cracks_status_goes_once_the_view_moves() {
    // "No marked cracks in this frame" tells of the frame shown: once the camera moves it is
    // cleared (it stayed, naming moller after the method had become cramer).
    let dir = tempfile::tempdir().unwrap();
    let view = dir.path().join("box.view");
    let text = "scene cornell\ncamera 0 0 -3.001 yaw 0 pitch 0\nsize 320 240\nstep flat\n\
                spp 1\nmethod watertight\ncracks on\n";
    std::fs::write(&view, text).unwrap();
    let script = format!("0 drop {}\n0 await driver-done\n", view.display());
    let driver = "xdotool windowfocus --sync $win; logged 'loaded view'; xdotool key n; \
                  logged 'cracks in this frame'; xdotool keydown w; logged 'W down'; sleep 0.3; \
                  xdotool keyup w; sleep 0.5";
    let Some(run) = run_window_with(RAYLAB, &script, dir.path(), &[], Around::RealInput(driver))
    else {
        return;
    };
    let log = &run.stderr;
    assert!(
        log.contains("cracks in this frame"),
        "N said so first\n{log}"
    );
    let status = (run.stdout.lines()).find_map(|l| l.strip_prefix("status: "));
    assert!(
        status.is_none_or(|s| !s.contains("cracks in this frame")),
        "{status:?}\n{log}"
    );
    assert!(run.nums("camera")[2] > -3.0, "W moved the camera\n{log}");
}

/// This file's tests, by name, for the harness (main.rs).
pub const TESTS: super::Tests = tests![
    next_crack_where_only_wrong_primitives_are_counted_says_so,
    real_x_input_next_crack_steps_through_the_counted_cracks,
    real_x_input_a_crack_on_the_status_line_gives_way_when_the_view_moves,
    real_x_input_next_crack_inspects_the_marked_samples_ray,
    real_x_input_next_crack_reaches_the_cracks_the_inspectors_panel_crops,
    real_x_input_a_no_cracks_status_goes_once_the_view_moves,
];
