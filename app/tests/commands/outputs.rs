//! Outputs never destroy a file: an output that is one of the run's inputs is refused before
//! any work, and an interrupted, killed or failed run leaves the previous file as it was, with
//! no partial file beside it. Real files, real links and real signals.

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

fn raylab(args: &[&str]) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_raylab"));
    c.args(args)
        .env("RUST_LOG", "warn")
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    c
}

/// Runs to the end (a run over 60 s is a hang: killed, and the test fails).
fn run(args: &[&str]) -> Output {
    let mut child = raylab(args).spawn().expect("run raylab");
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > Duration::from_secs(60) {
            child.kill().unwrap();
            panic!("raylab {args:?} hung for 60 s");
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    child.wait_with_output().unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The names in `dir`, sorted.
fn listing(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

fn write(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, bytes).unwrap();
    p
}

/// A refused run: exit 2, a message naming the output and the input it is, nothing written.
fn assert_refused(o: &Output, input: &Path) {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("refusing to overwrite an input"), "{err}");
    let name = input.file_name().unwrap().to_str().unwrap();
    assert!(err.contains(name), "'{name}' not in: {err}");
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn an_output_that_is_an_input_is_refused_and_the_input_kept() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let mtl = b"newmtl red\nKd 0.8 0.1 0.1\n";
    let obj = b"mtllib m.mtl\nusemtl red\nv -1 -1 2\nv 1 -1 2\nv 0 1 2\nf 1 2 3\n";
    let scene = b"camera 0 0 -3\nmesh tri.obj\nmesh tri.obj\n";
    let view = b"scene s.scene\ncamera 0 0 -3 yaw 0 pitch 0\nsize 32 24\n";
    let mtl_path = write(d, "m.mtl", mtl);
    let obj_path = write(d, "tri.obj", obj);
    let scene_path = write(d, "s.scene", scene);
    let view_path = write(d, "v.view", view);
    std::os::unix::fs::symlink("s.scene", d.join("link.png")).unwrap();
    std::fs::hard_link(&obj_path, d.join("hard.png")).unwrap();
    let s = scene_path.to_str().unwrap();
    let v = view_path.to_str().unwrap();
    let scene_to = |out: &str| -> Vec<String> {
        [
            "render", "--scene", s, "--width", "32", "--height", "24", "-o", out,
        ]
        .map(String::from)
        .to_vec()
    };
    let view_to = |out: &str| -> Vec<String> {
        ["render", "--view", v, "-o", out]
            .map(String::from)
            .to_vec()
    };
    let at = |name: &str| d.join(name).to_str().unwrap().to_string();
    let cases: Vec<(Vec<String>, &Path)> = vec![
        // The scene itself, by its path and by another spelling of it.
        (scene_to(s), &scene_path),
        (scene_to(&format!("{}/./s.scene", d.display())), &scene_path),
        // Its mesh and the mesh's material library.
        (scene_to(&at("tri.obj")), &obj_path),
        (scene_to(&at("m.mtl")), &mtl_path),
        // A link to the scene, a hard link to the mesh.
        (scene_to(&at("link.png")), &scene_path),
        (scene_to(&at("hard.png")), &obj_path),
        // The view, and the scene a view names.
        (view_to(v), &view_path),
        (view_to(s), &scene_path),
    ];
    for (args, input) in &cases {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let o = run(&args);
        assert_refused(&o, input);
        // Every input is as it was, and nothing was added beside them.
        assert_eq!(std::fs::read(&scene_path).unwrap(), scene, "{args:?}");
        assert_eq!(std::fs::read(&obj_path).unwrap(), obj, "{args:?}");
        assert_eq!(std::fs::read(&mtl_path).unwrap(), mtl, "{args:?}");
        assert_eq!(std::fs::read(&view_path).unwrap(), view, "{args:?}");
        assert_eq!(
            listing(d),
            ["hard.png", "link.png", "m.mtl", "s.scene", "tri.obj", "v.view"],
            "{args:?}"
        );
    }
    // The link is still a link, and an output beside the inputs is written.
    assert!(std::fs::symlink_metadata(d.join("link.png"))
        .unwrap()
        .file_type()
        .is_symlink());
    let out = d.join("out.png");
    let args = scene_to(out.to_str().unwrap());
    let o = run(&args.iter().map(String::as_str).collect::<Vec<_>>());
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(&std::fs::read(&out).unwrap()[1..4], b"PNG");
}

#[test]
fn an_output_through_a_link_replaces_the_file_and_keeps_the_link() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let old = write(d, "old.png", b"previous image");
    std::os::unix::fs::symlink("old.png", d.join("link.png")).unwrap();
    let o = run(&[
        "render",
        "--width",
        "16",
        "--height",
        "12",
        "-o",
        d.join("link.png").to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(std::fs::symlink_metadata(d.join("link.png"))
        .unwrap()
        .file_type()
        .is_symlink());
    assert_eq!(&std::fs::read(&old).unwrap()[1..4], b"PNG");
    assert_eq!(listing(d), ["link.png", "old.png"]);
}

/// A render of the Cornell box long enough to be stopped mid-way (several seconds).
fn long_render(out: &Path, aov: bool) -> Child {
    let mut args = vec![
        "render", "--width", "4000", "--height", "3000", "--spp", "4", "--step", "shadows", "-o",
    ];
    args.push(out.to_str().unwrap());
    if aov {
        args.push("--aov");
    }
    raylab(&args).spawn().expect("run raylab")
}

fn signal(child: &Child, sig: &str) {
    let ok = Command::new("kill")
        .args([sig, &child.id().to_string()])
        .status()
        .unwrap();
    assert!(ok.success());
}

#[test]
fn a_stopped_or_killed_render_leaves_the_previous_image_and_nothing_else() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let previous = b"\x89PNG previous image".to_vec();
    for (sig, aov) in [("-INT", false), ("-TERM", true), ("-KILL", false)] {
        let out = write(d, "image.png", &previous);
        let child = long_render(&out, aov);
        // Past the loading, into the render.
        std::thread::sleep(Duration::from_millis(1500));
        signal(&child, sig);
        let start = Instant::now();
        let o = child.wait_with_output().unwrap();
        assert!(
            start.elapsed() < Duration::from_secs(30),
            "{sig}: slow to stop"
        );
        match sig {
            "-KILL" => assert_eq!(o.status.code(), None, "{sig}: killed"),
            _ => {
                assert_eq!(o.status.code(), Some(130), "{sig}: {}", stderr(&o));
                assert!(stderr(&o).contains("nothing written"), "{}", stderr(&o));
            }
        }
        assert_eq!(std::fs::read(&out).unwrap(), previous, "{sig}");
        assert_eq!(listing(d), ["image.png"], "{sig}");
    }
}

/// `raylab render` of a 16x12 image with `extra` flags to `out`.
fn render_16x12(extra: &[&str], out: &str) -> Output {
    let size = ["render", "--width", "16", "--height", "12"];
    run(&[&size[..], extra, &["-o", out]].concat())
}

#[test]
fn aovs_with_dev_null_as_out_go_there_too() {
    // Beside /dev/null they were files made in /dev (/dev/null.prim.npy, ...).
    let beside = ["prim", "t", "normal"].map(|w| format!("/dev/null.{w}.npy"));
    let made_before = beside.iter().any(|p| Path::new(p).exists());
    let o = render_16x12(&["--aov"], "/dev/null");
    let made = beside
        .iter()
        .filter(|p| Path::new(p).exists())
        .collect::<Vec<_>>();
    if !made_before {
        for p in &made {
            let _ = std::fs::remove_file(p);
        }
    }
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(made_before || made.is_empty(), "made {made:?}");
    let said = String::from_utf8_lossy(&o.stdout);
    assert!(
        !said.contains("wrote /dev/null"),
        "the image's line names it: {said}"
    );
}

#[test]
fn a_failing_aov_output_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let previous = b"previous image".to_vec();
    let out = write(d, "image.png", &previous);
    // The normals' array cannot be written: a directory stands at its path.
    std::fs::create_dir(d.join("image.normal.npy")).unwrap();
    let o = render_16x12(&["--aov"], out.to_str().unwrap());
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("image.normal.npy"), "{}", stderr(&o));
    assert_eq!(std::fs::read(&out).unwrap(), previous);
    assert_eq!(listing(d), ["image.normal.npy", "image.png"]);
    // In a directory that cannot be written, the same: refused before the render.
    let locked = d.join("locked");
    std::fs::create_dir(&locked).unwrap();
    let inside = write(&locked, "image.png", &previous);
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(&locked, std::fs::Permissions::from_mode(0o555)).unwrap();
    let o = render_16x12(&[], inside.to_str().unwrap());
    std::fs::set_permissions(&locked, std::fs::Permissions::from_mode(0o755)).unwrap();
    // (Root writes anywhere: then the render succeeds and replaces the file whole.)
    match o.status.code() {
        Some(2) => assert_eq!(std::fs::read(&inside).unwrap(), previous),
        _ => assert_eq!(&std::fs::read(&inside).unwrap()[1..4], b"PNG"),
    }
    assert_eq!(listing(&locked), ["image.png"]);
}

/// A render's whole set of files is written before its report: a reader of the report that
/// is gone (a closed pipe) ends the run after the files, not between them.
#[test]
fn a_closed_stdout_ends_the_run_after_the_whole_aov_set() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let out = d.join("x.png");
    let args = ["render", "--width", "32", "--height", "24", "--aov", "-o"];
    let mut child = raylab(&[&args[..], &[out.to_str().unwrap()]].concat())
        .spawn()
        .unwrap();
    // The reader goes away before raylab reports.
    drop(child.stdout.take());
    let o = child.wait_with_output().unwrap();
    assert_eq!(o.status.code(), Some(141), "{}", stderr(&o));
    assert_eq!(
        listing(d),
        ["x.normal.npy", "x.png", "x.prim.npy", "x.t.npy"]
    );
    let t = std::fs::read(d.join("x.t.npy")).unwrap();
    assert_eq!(t.len(), 128 + 4 * 32 * 24);
}

#[test]
fn a_dangling_link_is_written_through_and_a_255_byte_name_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::create_dir(d.join("out")).unwrap();
    std::os::unix::fs::symlink("out/target.png", d.join("link.png")).unwrap();
    let link = d.join("link.png");
    let o = run(&[
        "render",
        "--width",
        "16",
        "--height",
        "12",
        "-o",
        link.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let meta = std::fs::symlink_metadata(&link).unwrap();
    assert!(meta.file_type().is_symlink(), "the link is kept");
    assert_eq!(
        &std::fs::read(d.join("out/target.png")).unwrap()[1..4],
        b"PNG"
    );
    assert_eq!(listing(d), ["link.png", "out"]);
    assert_eq!(listing(&d.join("out")), ["target.png"]);
    // The longest name a directory holds (255 bytes): its temporary name fits too.
    let name = format!("{}.png", "a".repeat(251));
    let long = d.join(&name);
    let o = run(&[
        "render",
        "--width",
        "16",
        "--height",
        "12",
        "-o",
        long.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(listing(d), [name.as_str(), "link.png", "out"]);
}

/// A suite and a class of one submission in `d`, for `raylab grade`.
fn suite_and_class(d: &Path) -> (String, String) {
    let suite = d.join("suite");
    let o = run(&["suite", "export", suite.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    std::fs::create_dir_all(d.join("class/ada")).unwrap();
    let class = d.join("class");
    (
        suite.to_str().unwrap().to_string(),
        class.to_str().unwrap().to_string(),
    )
}

/// Every output is checked before any work: a name that can only be a directory's (`a.png/`)
/// and a missing directory are refused first, naming the path once (and the directory: it
/// was "No such file or directory").
#[test]
fn every_output_is_checked_before_any_work_and_its_error_said_once() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let (suite, class) = suite_and_class(d);
    // A program that leaves a mark: it never ran if the mark is missing.
    let ran = d.join("RAN");
    let program = format!("touch '{}'; true {{scene}} {{rays}}", ran.display());
    let program = program.as_str();
    let missing = d.join("missing/dir/o.png");
    let missing = missing.to_str().unwrap();
    let slash = format!("{}/a.png/", d.display());
    let csv_slash = format!("{}/rows.csv/", d.display());
    let csv_missing = format!("{}/missing/rows.csv", d.display());
    let no_dir = format!(
        "there is no directory {}/missing/dir to write it in",
        d.display()
    );
    let no_csv_dir = format!(
        "there is no directory {}/missing to write it in",
        d.display()
    );
    let bad_scene = ["--scene", "no-such.scene"];
    let cases: Vec<(Vec<&str>, &str, &str)> = vec![
        (
            ["render", "-o", &slash].to_vec(),
            &slash,
            "names a directory",
        ),
        (
            ["render", "--aov", "-o", &slash].to_vec(),
            &slash,
            "names a directory",
        ),
        (["render", "-o", missing].to_vec(), missing, &no_dir),
        (
            ["check", "--image", &slash, "--program", program].to_vec(),
            &slash,
            "names a directory",
        ),
        (
            ["check", "--image", missing, "--program", program].to_vec(),
            missing,
            &no_dir,
        ),
        (
            [
                "grade",
                &class,
                "--suite",
                &suite,
                "--program",
                program,
                "--csv",
                &csv_slash,
            ]
            .to_vec(),
            &csv_slash,
            "names a directory",
        ),
        (
            [
                "grade",
                &class,
                "--suite",
                &suite,
                "--program",
                program,
                "--csv",
                &csv_missing,
            ]
            .to_vec(),
            &csv_missing,
            &no_csv_dir,
        ),
    ];
    for (args, path, why) in cases {
        // (A scene that cannot be read: the output is said first.)
        let args = match args[0] {
            "grade" => args,
            _ => [&args[..], &bad_scene].concat(),
        };
        let o = run(&args);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert_eq!(err.lines().count(), 1, "{args:?}: {err}");
        assert!(err.contains(path) && err.contains(why), "{args:?}: {err}");
        assert!(err.matches("os error").count() <= 1, "{err}");
        assert!(!ran.exists(), "{args:?}: the program ran");
    }
    // A file where the suite's directory goes: said once, with its path.
    let file = write(d, "afile", b"not a directory");
    let o = run(&["suite", "export", file.to_str().unwrap()]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert_eq!(
        err.trim_end(),
        format!("error: {}: Not a directory (os error 20)", file.display())
    );
    assert_eq!(listing(d), ["afile", "class", "suite"]);
}

/// The first `.npy` temporary file in `dir` that has grown past its header: the arrays'
/// pass is writing (the outputs' check before the work makes empty ones, at once removed).
fn wait_for_arrays_being_written(dir: &Path) {
    let start = Instant::now();
    loop {
        let writing = std::fs::read_dir(dir).unwrap().flatten().any(|e| {
            let name = e.file_name().to_string_lossy().into_owned();
            let grown = e.metadata().is_ok_and(|m| m.len() > 128);
            name.contains(".npy.raylab-") && name.ends_with(".tmp") && grown
        });
        if writing {
            return;
        }
        assert!(start.elapsed() < Duration::from_secs(120), "no AOV written");
        std::thread::sleep(Duration::from_millis(1));
    }
}

/// Sets a file's last modification `ago` back from now.
fn age(path: &Path, ago: Duration) {
    let file = std::fs::File::options().write(true).open(path).unwrap();
    file.set_modified(std::time::SystemTime::now() - ago)
        .unwrap();
}

/// The temporary files of a run killed while writing are removed by a later write into their
/// directory once stale (unlocked, this user's, unmodified for an hour); a locked one
/// (another process still writing, whatever its pid namespace or host) or a recent one is
/// left.
#[test]
fn a_killed_runs_stale_temporary_files_are_removed_by_a_later_write() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let out = d.join("x.png");
    let is_temp = |n: &String| n.starts_with('.') && n.ends_with(".tmp");
    let child = long_render(&out, true);
    wait_for_arrays_being_written(d);
    signal(&child, "-KILL");
    child.wait_with_output().unwrap();
    let left: Vec<String> = listing(d).into_iter().filter(is_temp).collect();
    // The PNG's and the three arrays'.
    assert_eq!(
        left.len(),
        4,
        "a killed run leaves its temporary files: {left:?}"
    );
    let render = [
        "render",
        "--width",
        "16",
        "--height",
        "12",
        "-o",
        out.to_str().unwrap(),
    ];
    // Recent: left (its writer may not have locked it yet).
    let o = run(&render);
    assert!(o.status.success(), "{}", stderr(&o));
    let after: Vec<String> = listing(d).into_iter().filter(is_temp).collect();
    assert_eq!(after, left);
    // An hour old and unlocked: removed. Another's, as old but locked: left.
    let hour = Duration::from_secs(60 * 60 + 60);
    for name in &left {
        age(&d.join(name), hour);
    }
    let live = format!(".y.png.raylab-{}-0.tmp", std::process::id());
    write(d, &live, b"another process's, still writing");
    age(&d.join(&live), hour);
    let held = std::fs::File::open(d.join(&live)).unwrap();
    held.lock().unwrap();
    let o = run(&render);
    assert!(o.status.success(), "{}", stderr(&o));
    let after: Vec<String> = listing(d).into_iter().filter(is_temp).collect();
    assert_eq!(after, [live]);
    // Its lock released (its writer gone), the next write removes it.
    drop(held);
    let o = run(&render);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(listing(d), ["x.png"]);
}

/// Ctrl+C (SIGINT) or SIGTERM during the arrays' pass stops the run at its next band: exit 130,
/// nothing written, the previous files as they were.
#[test]
fn a_render_stopped_while_writing_its_arrays_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let previous = b"\x89PNG previous image".to_vec();
    for sig in ["-INT", "-TERM"] {
        let out = write(d, "image.png", &previous);
        // A quick image, then the arrays of 12 megapixels in bands of one.
        let child = raylab(&[
            "render",
            "--width",
            "4000",
            "--height",
            "3000",
            "--aov",
            "-o",
            out.to_str().unwrap(),
        ])
        .spawn()
        .unwrap();
        wait_for_arrays_being_written(d);
        signal(&child, sig);
        let o = child.wait_with_output().unwrap();
        assert_eq!(o.status.code(), Some(130), "{sig}: {}", stderr(&o));
        assert!(stderr(&o).contains("nothing written"), "{}", stderr(&o));
        assert_eq!(std::fs::read(&out).unwrap(), previous, "{sig}");
        assert_eq!(listing(d), ["image.png"], "{sig}");
    }
}

/// Exports into one new directory at once: each succeeds, whichever writes first; a
/// directory holding only another export's temporary file (its README being written) is
/// one being exported, not a foreign one.
#[test]
fn exports_into_one_new_directory_at_once_all_succeed() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let single = d.join("single");
    assert!(run(&["suite", "export", single.to_str().unwrap()])
        .status
        .success());
    let families = listing(&single);
    let writing = d.join("writing");
    std::fs::create_dir(&writing).unwrap();
    let temp = format!(".README.md.raylab-{}-0.tmp", std::process::id());
    write(&writing, &temp, b"# raylab's hard");
    let o = run(&["suite", "export", writing.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let mut expected = families.clone();
    expected.insert(0, temp);
    assert_eq!(listing(&writing), expected);
    for round in 0..8 {
        let suite = d.join(format!("suite{round}"));
        let children: Vec<Child> = (0..3)
            .map(|_| {
                raylab(&["suite", "export", suite.to_str().unwrap()])
                    .spawn()
                    .unwrap()
            })
            .collect();
        for child in children {
            let o = child.wait_with_output().unwrap();
            assert!(o.status.success(), "round {round}: {}", stderr(&o));
        }
        assert_eq!(listing(&suite), families, "round {round}");
    }
}

/// `grade` writes its records before its table: a reader of the table that is gone ends the
/// run after them.
#[test]
fn a_closed_stdout_ends_a_grading_after_its_records() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let (suite, class) = suite_and_class(d);
    let csv = d.join("rows.csv");
    let args = ["grade", &class, "--suite", &suite, "--family", "1"];
    let program = [
        "--program",
        "true {scene} {rays}",
        "--csv",
        csv.to_str().unwrap(),
    ];
    let mut child = raylab(&[&args[..], &program].concat()).spawn().unwrap();
    drop(child.stdout.take());
    let o = child.wait_with_output().unwrap();
    assert_eq!(o.status.code(), Some(141), "{}", stderr(&o));
    let rows = std::fs::read_to_string(&csv).unwrap();
    assert_eq!(rows.lines().count(), 2, "{rows}");
    assert!(
        rows.lines().nth(1).unwrap().starts_with("ada,01-"),
        "{rows}"
    );
}
