//! `.view` files from outside: rendered, saved and read back, through a shell as the window's
//! "copy as command" gives them, with every image control and any scene file name.

use crate::common;

use common::binary::{assert_fails, stderr, stdout, write};
use common::read_png;

crate::raylab_runner!();

#[test]
fn view_files_render_and_round_trip() {
    use raylab::view::View;
    let dir = tempfile::tempdir().unwrap();
    let text = "# a view\nscene cornell\ncamera 0.25 -0.1 -2.5 yaw 12.5 pitch -3 fov 61\n\
                light 0.3 -0.6 -0.5\nsize 48 36\nstep shadows\nspp 2\nmethod watertight\ncracks off\n";
    let view = View::parse("v.view", text).unwrap();
    assert_eq!(
        View::parse("again", &view.to_text()).unwrap(),
        view,
        "round trip"
    );
    let path = write(dir.path(), "v.view", text);
    let out = dir.path().join("v.png");
    let o = raylab(&["render", "--view", &path, "-o", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    // The same through flags: the same image.
    let flags = dir.path().join("f.png");
    let o = raylab(&[
        "render",
        "--camera",
        "0.25,-0.1,-2.5",
        "--yaw",
        "12.5",
        "--pitch",
        "-3",
        "--focal",
        &(48.0 / (2.0 * (61f64.to_radians() / 2.0).tan())).to_string(),
        "--light",
        "0.3,-0.6,-0.5",
        "--width",
        "48",
        "--height",
        "36",
        "--step",
        "shadows",
        "--spp",
        "2",
        "--method",
        "watertight",
        "-o",
        flags.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(read_png(&out) == read_png(&flags));
    // Flags that the view sets conflict with it; a bad line names itself.
    let o = raylab(&["render", "--view", &path, "--width", "10", "-o", "x.png"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("--width") && stderr(&o).contains("--view"),
        "{}",
        stderr(&o)
    );
    let bad = write(dir.path(), "bad.view", "scene cornell\n\nzoom 2\n");
    assert_fails(
        &raylab(&["render", "--view", &bad, "-o", "x.png"]),
        2,
        &["bad.view:3:", "zoom"],
    );
}

/// A view's `focal` line is the focal length itself, at the view's width: `inspect` takes it
/// exactly (from a field of view, 500 came back as 499.9999999999999), it round-trips, and
/// it sets the lens with or without a camera line, but not beside a camera's `fov`.
#[test]
fn a_views_focal_length_is_taken_as_written() {
    use raylab::view::View;
    let dir = tempfile::tempdir().unwrap();
    let text = "scene cornell\ncamera 0.1 0 -3 yaw 5 pitch -2\nfocal 500\nsize 640 480\n";
    let view = View::parse("v.view", text).unwrap();
    assert_eq!(view.focal, Some(500.0));
    assert_eq!(View::parse("again", &view.to_text()).unwrap(), view);
    let f_of = |text: &str| -> String {
        let path = write(dir.path(), "f.view", text);
        let o = raylab(&["inspect", "--view", &path, "--pixel", "10,10"]);
        assert!(o.status.success(), "{}", stderr(&o));
        let out = String::from_utf8(o.stdout).unwrap();
        let uvf = out
            .lines()
            .find(|l| l.starts_with("uvf: "))
            .unwrap()
            .to_string();
        uvf.rsplit(' ').next().unwrap().to_string()
    };
    assert_eq!(f_of(text), "500");
    assert_eq!(f_of("scene cornell\nfocal 123.25\nsize 64 48\n"), "123.25");
    // Its field of view instead: within an ulp or so, not the number a user set.
    let fov = 2.0 * (320.0f64 / 500.0).atan().to_degrees();
    let from_fov = f_of(&format!(
        "scene cornell\ncamera 0.1 0 -3 yaw 5 pitch -2 fov {fov}\nsize 640 480\n"
    ));
    assert!(
        (from_fov.parse::<f64>().unwrap() - 500.0).abs() < 1e-9,
        "{from_fov}"
    );
    let both = write(
        dir.path(),
        "both.view",
        "scene cornell\ncamera 0 0 -3 yaw 0 pitch 0 fov 50\nfocal 500\n",
    );
    let o = raylab(&["render", "--view", &both, "-o", "x.png"]);
    assert_fails(&o, 2, &["both.view:3:", "focal and the camera's fov"]);
    let zero = write(dir.path(), "zero.view", "scene cornell\nfocal 0\n");
    let o = raylab(&["render", "--view", &zero, "-o", "x.png"]);
    assert_fails(&o, 2, &["zero.view:2:", "focal 0 px is outside"]);
    // Named as written (1e-400 reads as 0), and one value.
    for (line, said) in [
        ("focal 1e-400", "focal 1e-400 px is outside"),
        ("focal 5 6", "focal needs 1 value, found 2"),
    ] {
        let bad = write(dir.path(), "bad.view", &format!("scene cornell\n{line}\n"));
        let o = raylab(&["render", "--view", &bad, "-o", "x.png"]);
        assert_fails(&o, 2, &["bad.view:2:", said]);
    }
}

#[test]
fn a_view_without_camera_or_light_renders_as_its_scene_does() {
    // A view that names no camera sees its scene from where `--scene` starts it: a `.scene`
    // file's camera and light, the framing of a model, the lab's camera on the box. (It took
    // the lab's camera for each: the model's view looked from inside the box's frame.)
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write(
        d,
        "lit.scene",
        "cornell\ncamera 0.3 0.1 -2 yaw 10 pitch 5 fov 70\nlight 0.5 -0.5 0\n",
    );
    write(
        d,
        "pyramid.obj",
        "v -1 1 -1\nv 1 1 -1\nv 1 1 1\nv 0 -1 0\nf 1 2 3\nf 1 2 4\n",
    );
    for scene in ["lit.scene", "pyramid.obj", "cornell"] {
        let view = write(
            d,
            "v.view",
            &format!("scene {scene}\nsize 40 30\nstep shadows\n"),
        );
        let (a, b) = (d.join("a.png"), d.join("b.png"));
        let o = raylab(&["render", "--view", &view, "-o", a.to_str().unwrap()]);
        assert!(o.status.success(), "{scene}: {}", stderr(&o));
        let scene_path = d.join(scene);
        let scene_arg = match scene {
            "cornell" => scene.to_string(),
            _ => scene_path.display().to_string(),
        };
        let flags = ["--width", "40", "--height", "30", "--step", "shadows", "-o"];
        let mut args = vec!["render", "--scene", &scene_arg];
        args.extend(flags);
        args.push(b.to_str().unwrap());
        let o = raylab(&args);
        assert!(o.status.success(), "{scene}: {}", stderr(&o));
        assert!(
            read_png(&a) == read_png(&b),
            "{scene}: the view's image is not --scene's"
        );
    }
}

#[test]
fn a_views_command_line_renders_the_view_through_a_shell() {
    // "Copy as command": the line a view turns into, run by a POSIX shell, renders what
    // `--view` renders, with a scene path holding a space and a quote, a negative position,
    // a turned camera, a moved light and a field of view.
    let dir = tempfile::tempdir().unwrap();
    let sub = dir.path().join("it's here");
    std::fs::create_dir(&sub).unwrap();
    let scene = write(&sub, "s.scene", "cornell\nsphere 0.3 0.4 0.2 0.25\n");
    let view_text = format!(
        "scene {scene}\ncamera -0.25 -0.1 -2.5 yaw -12.5 pitch 3 fov 61\nlight 0.2 -0.6 -0.5\n\
         size 96 72\nstep shadows\nspp 2\nmethod adaptive\n"
    );
    let view = raylab::view::View::parse("v.view", &view_text).unwrap();
    let command = view.to_command("from command.png");
    assert!(
        command.contains("'") && command.contains("--yaw=-12.5"),
        "{command}"
    );
    // With its focal length given (as the window saves it) instead of its field of view,
    // that flag alone differs, and takes the focal length as written.
    let without_focal = |c: &str| -> String {
        let words = c.split(' ').filter(|w| !w.starts_with("--focal="));
        words.collect()
    };
    let focal_text = view_text.replace(" fov 61\n", "\nfocal 62.5\n");
    let given = raylab::view::View::parse("f.view", &focal_text).unwrap();
    let given = given.to_command("from command.png");
    assert!(given.contains(" --focal=62.5 "), "{given}");
    assert_eq!(without_focal(&given), without_focal(&command));
    let o = common::run_in_shell(&command, dir.path(), env!("CARGO_BIN_EXE_raylab"));
    assert!(o.status.success(), "{command}\n{}", stderr(&o));
    let view_file = write(dir.path(), "v.view", &view_text);
    let from_view = dir.path().join("from view.png");
    let o = raylab(&[
        "render",
        "--view",
        &view_file,
        "-o",
        from_view.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let a = std::fs::read(dir.path().join("from command.png")).unwrap();
    let b = std::fs::read(&from_view).unwrap();
    assert!(a == b, "the command and the view render the same PNG");
    assert_eq!(raylab::view::shell_quote("a'b c"), "'a'\\''b c'");
    assert_eq!(
        raylab::view::shell_quote("plain/path-1.obj"),
        "plain/path-1.obj"
    );
}

#[test]
fn every_image_control_reaches_the_image_through_the_view_file_and_the_command() {
    // The controls table drives the `.view` file, copy-as-command and the flags: each value of
    // each control, set in a view, renders through `--view` and through the view's command
    // line to the same PNG, and the render's report names the value.
    let dir = tempfile::tempdir().unwrap();
    let base = "scene cornell\nsize 40 30\nstep shadows\n";
    let help = stdout(&raylab(&["render", "--help"]));
    for control in &raylab::render::CONTROLS {
        assert!(
            help.contains(&format!("--{}", control.name)),
            "{}",
            control.name
        );
        for value in control.sample_values() {
            // (The base without the control's own line: a view holds each statement once.)
            let others: String = (base.lines())
                .filter(|l| l.split_whitespace().next() != Some(control.name))
                .map(|l| format!("{l}\n"))
                .collect();
            let text = format!("{others}{} {value}\n", control.name);
            let view = raylab::view::View::parse("v.view", &text).unwrap();
            assert_eq!(control.text(&view.settings), value);
            let file = write(dir.path(), "v.view", &view.to_text());
            let (a, b) = (dir.path().join("view.png"), dir.path().join("command.png"));
            let o = raylab(&["render", "--view", &file, "-o", a.to_str().unwrap()]);
            assert!(o.status.success(), "{}", stderr(&o));
            let said = format!("{}={value} ", control.name);
            assert!(stdout(&o).contains(&said), "{said}\n{}", stdout(&o));
            let command = view.to_command(b.to_str().unwrap());
            let words: Vec<&str> = command.split(' ').skip(1).collect();
            let o = raylab(&words);
            assert!(o.status.success(), "{command}\n{}", stderr(&o));
            assert!(stdout(&o).contains(&said), "{command}\n{}", stdout(&o));
            assert!(read_png(&a) == read_png(&b), "{command}");
        }
    }
    // A bad value in a view names the line and what the control takes.
    let bad = write(dir.path(), "bad.view", &format!("{base}spp 0\n"));
    assert_fails(
        &raylab(&["render", "--view", &bad, "-o", "x.png"]),
        2,
        &["bad.view:4:", "supersampling 0 is out of range"],
    );
    let bad = write(dir.path(), "bad.view", &format!("{base}cracks maybe\n"));
    assert_fails(
        &raylab(&["render", "--view", &bad, "-o", "x.png"]),
        2,
        &["bad.view:4:", "cracks is on or off, not 'maybe'"],
    );
}

#[test]
fn any_scene_file_name_round_trips_through_a_view() {
    // Names with runs of spaces, '#', quotes and backslashes: a saved view names the same file
    // (quoted), renders the same image as the scene itself, and a `.scene` mesh path in quotes
    // loads.
    use raylab::view::View;
    let dir = tempfile::tempdir().unwrap();
    let tri = "camera 0 0 -3\ntri -1 -1 2 1 -1 2 0 1 2\n";
    for name in [
        "two  spaces.scene",
        "x#y.scene",
        "say \"hi\" \\ there.scene",
    ] {
        let scene = write(dir.path(), name, tri);
        let decoy = dir.path().join("x"); // what '#' used to cut "x#y.scene" down to
        std::fs::write(&decoy, "camera 0 0 -3\nsphere 0 0 2 1\n").unwrap();
        let mut view = View::parse("v.view", "size 32 24\n").unwrap();
        view.scene = scene.clone();
        let text = view.to_text();
        assert_eq!(View::parse("again", &text).unwrap(), view, "{text}");
        let view_file = write(dir.path(), "v.view", &text);
        let (a, b) = (dir.path().join("a.png"), dir.path().join("b.png"));
        let o = raylab(&["render", "--view", &view_file, "-o", a.to_str().unwrap()]);
        assert!(o.status.success(), "{name}: {}", stderr(&o));
        let o = raylab(&[
            "render",
            "--scene",
            &scene,
            "--width",
            "32",
            "--height",
            "24",
            "-o",
            b.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{name}: {}", stderr(&o));
        assert_eq!(
            std::fs::read(&a).unwrap(),
            std::fs::read(&b).unwrap(),
            "{name}"
        );
    }
    // A mesh path in quotes, and a broken quote named by its line.
    write(
        dir.path(),
        "my mesh.obj",
        "v -1 -1 2\nv 1 -1 2\nv 0 1 2\nf 1 2 3\n",
    );
    let s = write(
        dir.path(),
        "m.scene",
        "camera 0 0 -3\nmesh \"my mesh.obj\" lab # placed\n",
    );
    let out = dir.path().join("m.png");
    let o = raylab(&["render", "--scene", &s, "-o", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let s = write(
        dir.path(),
        "bad.scene",
        "camera 0 0 -3\nmesh \"my mesh.obj\n",
    );
    let o = raylab(&["render", "--scene", &s, "-o", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("bad.scene:2: a quoted word has no closing quote"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn a_huge_yaw_or_pitch_turns_as_its_remainder_of_a_whole_turn() {
    // 1e300° is exactly 0 mod 360 and 1e30° exactly 16: the camera turns so, from the flags,
    // a view and a scene file's camera, as a scene file's `rotate` does (1e300 × π/180 was a
    // rounding of a turn: another direction, another image).
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let inspect = |extra: &[&str]| {
        let mut args = vec![
            "inspect", "--pixel", "32,24", "--width", "64", "--height", "48",
        ];
        args.extend_from_slice(extra);
        let o = raylab(&args);
        assert!(o.status.success(), "{extra:?}: {}", stderr(&o));
        stdout(&o)
    };
    assert_eq!(1e300f64 % 360.0, 0.0);
    assert_eq!(1e30f64 % 360.0, 16.0);
    let level = inspect(&["--yaw", "0", "--pitch", "16"]);
    assert!(level.contains("\nhit: "), "{level}");
    assert_eq!(inspect(&["--yaw=1e300", "--pitch=1e30"]), level);
    assert_eq!(inspect(&["--yaw=-1e300", "--pitch=376"]), level);
    let view = write(
        d,
        "v.view",
        "scene cornell\ncamera 0 0 -3.001 yaw 1e300 pitch 1e30\nsize 64 48\n",
    );
    assert_eq!(inspect_view(&view), level);
    let scene = write(
        d,
        "s.scene",
        "camera 0 0 -3.001 yaw 1e300 pitch 1e30\ncornell\n",
    );
    let by_scene = inspect(&["--scene", &scene]);
    assert_eq!(
        by_scene,
        inspect(&["--scene", &scene, "--yaw", "0", "--pitch", "16"])
    );
}

#[test]
fn inspect_of_a_view_with_cracks_on_grades_its_ray_as_the_window_does() {
    // The rows the window's inspector adds with show cracks on: a moller leak on the box's
    // shared edge at a sample of 4x4 (the cracks view marks it magenta), a sample moller gets
    // right, and none without the cracks view.
    let d = tempfile::tempdir().unwrap();
    let d = d.path();
    let text = "scene cornell\ncamera 0 0 -3.001 yaw 0 pitch 0\nsize 784 698\nstep flat\n\
                spp 4\nmethod moller\ncracks on\n";
    let view = write(d, "cracks.view", text);
    let inspect = |view: &str, at: &str| {
        let o = raylab(&["inspect", "--view", view, "--at", at]);
        assert!(o.status.success(), "{}", stderr(&o));
        stdout(&o)
    };
    let leak = inspect(&view, "610.625,567.625");
    let rows = "hit: none\n";
    assert!(leak.contains(rows), "{leak}");
    let rows = "crack: leak (marked magenta)\ntraced: sample (610.625, 567.625) of the pixel\n\
                exact hit lies: primitive 1, on the edge v1–v2\nmoller hit lies: none\n";
    assert!(leak.ends_with(rows), "{leak}");
    let right = inspect(&view, "400.25,300.75");
    assert!(
        right.contains("\ncrack: not marked (the sample: right)\n"),
        "{right}"
    );
    assert!(
        right.ends_with("\nmoller hit lies: the exact one\n"),
        "{right}"
    );
    let hit = (right.lines())
        .find_map(|l| l.strip_prefix("hit: "))
        .unwrap();
    assert!(
        right.contains(&format!("\nexact hit lies: primitive {hit}, ")),
        "{right}"
    );
    // Its pixel: the first marked sample's ray, as the window's inspector takes it (the
    // centre ray is right there).
    let o = raylab(&["inspect", "--view", &view, "--pixel", "610,567"]);
    assert_eq!(stdout(&o), leak, "{}", stderr(&o));
    // A pixel off the image is named as given (the first pixel past the edge was).
    let o = raylab(&["inspect", "--view", &view, "--pixel", "5000,3"]);
    assert_fails(&o, 2, &["pixel (5000, 3) is outside the 784x698 image"]);
    let without = write(d, "plain.view", &text.replace("cracks on", "cracks off"));
    assert!(!inspect(&without, "610.625,567.625").contains("crack:"));
    let o = raylab(&["inspect", "--view", &without, "--pixel", "610,567"]);
    assert!(
        stdout(&o).starts_with("pixel: 610 567\nuvf: 218.5 218.5 "),
        "{}",
        stdout(&o)
    );
}

/// `raylab inspect` of pixel (32, 24) of the view file `view`.
fn inspect_view(view: &str) -> String {
    let o = raylab(&["inspect", "--pixel", "32,24", "--view", view]);
    assert!(o.status.success(), "{}", stderr(&o));
    stdout(&o)
}
