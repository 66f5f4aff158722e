//! The built-in Cornell box against the lab's own numbers, and the core's independence from
//! the window stack.

use raylab::geometry::Shape;
use raylab::Scene;

/// The lab's `LoadTestModel`, in f32 and in its order: room, short block, tall block.
fn lab_triangles() -> Vec<([[f32; 3]; 3], [f32; 3])> {
    let l = 555.0f32;
    let (red, yellow, green) = ([0.75, 0.15, 0.15], [0.75, 0.75, 0.15], [0.15, 0.75, 0.15]);
    let (cyan, blue, purple) = ([0.15, 0.75, 0.75], [0.15, 0.15, 0.75], [0.75, 0.15, 0.75]);
    let white = [0.75f32, 0.75, 0.75];
    let mut tris = Vec::new();
    let (a, b, c, d) = ([l, 0.0, 0.0], [0.0, 0.0, 0.0], [l, 0.0, l], [0.0, 0.0, l]);
    let (e, f, g, h) = ([l, l, 0.0], [0.0, l, 0.0], [l, l, l], [0.0, l, l]);
    for (t, col) in [
        ([c, b, a], green),
        ([c, d, b], green),
        ([a, e, c], purple),
        ([c, e, g], purple),
        ([f, b, d], yellow),
        ([h, f, d], yellow),
        ([e, f, g], cyan),
        ([f, h, g], cyan),
        ([g, d, c], white),
        ([g, h, d], white),
    ] {
        tris.push((t, col));
    }
    let block = |corners: [[f32; 2]; 4], height: f32, col: [f32; 3], tris: &mut Vec<_>| {
        let [a, b, c, d] = corners.map(|p| [p[0], 0.0, p[1]]);
        let [e, f, g, h] = corners.map(|p| [p[0], height, p[1]]);
        for t in [
            [e, b, a],
            [e, f, b],
            [f, d, b],
            [f, h, d],
            [h, c, d],
            [h, g, c],
            [g, e, c],
            [e, a, c],
            [g, f, e],
            [g, h, f],
        ] {
            tris.push((t, col));
        }
    };
    block(
        [[290.0, 114.0], [130.0, 65.0], [240.0, 272.0], [82.0, 225.0]],
        165.0,
        red,
        &mut tris,
    );
    block(
        [
            [423.0, 247.0],
            [265.0, 296.0],
            [472.0, 406.0],
            [314.0, 456.0],
        ],
        330.0,
        blue,
        &mut tris,
    );
    // v *= 2/L; v -= (1,1,1); v.x *= -1; v.y *= -1 — in f32, in this order.
    for (t, _) in &mut tris {
        for v in t.iter_mut() {
            for c in v.iter_mut() {
                *c *= 2.0 / l;
                *c -= 1.0;
            }
            v[0] *= -1.0;
            v[1] *= -1.0;
        }
    }
    tris
}

#[test]
fn cornell_box_is_the_labs_30_triangles_bit_for_bit() {
    let scene = Scene::cornell();
    let lab = lab_triangles();
    assert_eq!(scene.len(), 30);
    assert_eq!(lab.len(), 30);
    for (k, ((tri, col), (shape, scene_col))) in lab
        .iter()
        .zip(scene.shapes.iter().zip(scene.colors()))
        .enumerate()
    {
        assert_eq!(*shape, Shape::from(*tri), "triangle {k}");
        assert_eq!(scene_col, col, "colour of triangle {k}");
    }
    assert_eq!(scene.light.position, [0.0, -0.5, -0.7]);
    assert_eq!(scene.light.power, [14.0; 3]);
    assert_eq!(scene.ambient, [0.5; 3]);
    assert!(scene.warnings.is_empty());
    let (lo, hi) = scene.bounds().unwrap();
    assert_eq!((lo, hi), ([-1.0; 3], [1.0; 3]));
}

#[test]
fn shipped_asset_matches_the_shared_scene_when_present() {
    let shared =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/scenes/cornell_lab.obj");
    let Ok(text) = std::fs::read_to_string(&shared) else {
        eprintln!("SKIPPED: {} not present", shared.display());
        return;
    };
    assert_eq!(text, raylab::scene::cornell::OBJ);
}

#[test]
fn obj_polygons_are_triangulated_and_colours_read() {
    let obj = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 1.5 0\nusemtl a\nf 1 2 3 5 4\nusemtl b\nf -5 -4 -3\n";
    let mtl = "newmtl a\nKd 0.2 0.4 0.6\nnewmtl b\nKd 2 -1 0.5\n";
    let scene = raylab::scene::load_obj_str("t.obj", obj, raylab::scene::ObjFrame::Lab, |name| {
        assert_eq!(name, "m.mtl");
        Ok(mtl.to_string())
    })
    .unwrap();
    assert_eq!(scene.len(), 4, "a pentagon fans into 3 triangles, plus one");
    assert_eq!(scene.colors()[0], [0.2, 0.4, 0.6]);
    assert_eq!(
        scene.colors()[3],
        [1.0, 0.0, 0.5],
        "Kd is clamped to [0, 1]"
    );
    assert_eq!(
        scene.shapes[3],
        Shape::from([[0.0; 3], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]])
    );
}

#[test]
fn the_core_never_imports_the_window_stack() {
    // The library's package (the repository root) must not depend on winit, egui, pixels or
    // wgpu, so no file of it can import them; the window lives in app/. Read the manifest's
    // dependency tables (any section whose name ends in "dependencies").
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let manifest = std::fs::read_to_string(root.join("Cargo.toml")).unwrap();
    let mut in_dependencies = false;
    let mut listed = 0;
    for line in manifest.lines().map(str::trim) {
        if line.starts_with('[') {
            in_dependencies = line.trim_end_matches(']').ends_with("dependencies");
            continue;
        }
        if !in_dependencies || line.is_empty() || line.starts_with('#') {
            continue;
        }
        let name = line.split(['=', ' ', '.']).next().unwrap();
        for krate in ["winit", "egui", "pixels", "wgpu"] {
            assert!(!name.contains(krate), "the library depends on {name}");
        }
        listed += 1;
    }
    assert!(listed >= 10, "read {listed} dependencies");
    // And the window's package does depend on them: the split is where the manifests say.
    let app = std::fs::read_to_string(root.join("app/Cargo.toml")).unwrap();
    for krate in ["winit", "egui", "wgpu"] {
        assert!(
            app.lines().any(|l| l.starts_with(krate)),
            "app/ lists {krate}"
        );
    }
}

#[test]
fn y_up_models_are_turned_into_the_lab_frame() {
    let obj = "v 1 2 3\nv 4 5 6\nv 7 8 10\nf 1 2 3\n";
    let no_mtl = |_: &str| Err("none".to_string());
    let lab =
        raylab::scene::load_obj_str("t.obj", obj, raylab::scene::ObjFrame::Lab, no_mtl).unwrap();
    let yup =
        raylab::scene::load_obj_str("t.obj", obj, raylab::scene::ObjFrame::YUp, no_mtl).unwrap();
    assert_eq!(
        lab.shapes[0],
        Shape::from([[1.0, 2.0, 3.0], [4.0, 5.0, 6.0], [7.0, 8.0, 10.0]])
    );
    assert_eq!(
        yup.shapes[0],
        Shape::from([[1.0, -2.0, -3.0], [4.0, -5.0, -6.0], [7.0, -8.0, -10.0]])
    );
    // A face towards +z in the file (counter-clockwise seen from there, as an OBJ model's
    // front) faces the lab's camera, which looks along +z: its normal points to -z.
    let front = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    let yup =
        raylab::scene::load_obj_str("t.obj", front, raylab::scene::ObjFrame::YUp, no_mtl).unwrap();
    let Shape::Triangle(t) = yup.shapes[0] else {
        panic!("a triangle")
    };
    let [a, b, c] = t.0.map(glam::Vec3::from);
    assert_eq!((b - a).cross(c - a).normalize(), glam::Vec3::NEG_Z);
}

fn load_lab(obj: &str, mtl: &str) -> Result<Scene, String> {
    let mtl = mtl.to_string();
    raylab::scene::load_obj_str("t.obj", obj, raylab::scene::ObjFrame::Lab, move |_| {
        Ok(mtl.clone())
    })
    .map_err(|e| e.to_string())
}

#[test]
fn one_mtllib_line_may_name_several_libraries_or_one_with_a_space() {
    // `mtllib a.mtl b.mtl` names two libraries (the format allows several); a library whose
    // name has a space loads by its whole name; of two, a missing one is skipped and said.
    let libraries = |name: &str| match name {
        "a.mtl" => Ok("newmtl red\nKd 1 0 0\n".to_string()),
        "b.mtl" => Ok("newmtl blue\nKd 0 0 1\n".to_string()),
        "my lib.mtl" => Ok("newmtl red\nKd 0 1 0\n".to_string()),
        other => Err(format!("{other}: No such file or directory")),
    };
    let tris = "v 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl red\nf 1 2 3\nusemtl blue\nf 1 2 3\n";
    let load = |mtllib: &str| {
        let obj = format!("mtllib {mtllib}\n{tris}");
        raylab::scene::load_obj_str("t.obj", &obj, raylab::scene::ObjFrame::Lab, libraries).unwrap()
    };
    let both = load("a.mtl b.mtl");
    assert!(both.warnings.is_empty(), "{:?}", both.warnings);
    assert_eq!(both.colors(), [[1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]);
    let spaced = load("my lib.mtl");
    assert_eq!(spaced.colors()[0], [0.0, 1.0, 0.0]);
    let one_gone = load("a.mtl gone.mtl");
    assert_eq!(one_gone.colors()[0], [1.0, 0.0, 0.0]);
    let said = one_gone.warnings.join("\n");
    assert!(
        said.contains("t.obj:1: material library skipped: gone.mtl: No such file"),
        "{said}"
    );
    // Neither word a library: the whole name is the one said missing.
    let none = load("x.mtl y.mtl").warnings.join("\n");
    assert!(
        none.contains("skipped: x.mtl y.mtl: No such file"),
        "{none}"
    );
}

#[test]
fn a_library_named_many_times_is_read_once_and_parsed_once() {
    // One library named four times on one line, and by another spelling (a link, `./`) on
    // a second: read once a name, parsed once (its one note said once), its colour taken.
    // (Each name was parsed again: 200 names of a 4.5 MB library took 44 s.)
    let reads = std::cell::Cell::new(0);
    let obj = "mtllib m.mtl m.mtl m.mtl m.mtl\nmtllib ./m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\n\
               usemtl a\nf 1 2 3\n";
    let scene = raylab::scene::load_obj_str("t.obj", obj, raylab::scene::ObjFrame::Lab, |name| {
        reads.set(reads.get() + 1);
        match name {
            "m.mtl" | "./m.mtl" => Ok("newmtl a\nKd 1 0 0 0.5\n".to_string()),
            _ => Err(format!("{name}: No such file")),
        }
    })
    .unwrap();
    assert_eq!(scene.colors()[0], [1.0, 0.0, 0.0]);
    let notes = (scene.warnings.iter()).filter(|w| w.contains("Kd takes 3 numbers"));
    assert_eq!(notes.count(), 1, "{:?}", scene.warnings);
    // The whole line's name (no such file), then m.mtl, then ./m.mtl: once each.
    assert_eq!(reads.get(), 3, "{:?}", scene.warnings);
}

#[test]
fn obj_statements_that_draw_nothing_are_skipped_and_counted() {
    // Polylines and points were once filled as triangles; curves and surfaces mean nothing to
    // a raycaster. All are skipped, with one warning that counts them.
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 5 5 5\nl 1 2 3\nl 2 4\np 1 2 3\ncstype bspline\n\
               curv 0 1 1 2 3\nend\nf 1 2 3\n";
    let scene = load_lab(obj, "").unwrap();
    assert_eq!(scene.len(), 1, "only the face is drawn");
    let warning = scene.warnings.join("\n");
    assert!(
        warning.contains("t.obj: skipped 2 polyline (l), 1 point (p), 3 curve/surface"),
        "{warning}"
    );
}

#[test]
fn obj_whitespace_comments_weights_and_negative_indices() {
    // TABs wherever a space may be (tobj once refused `usemtl<TAB>name`), comments after a
    // statement, a weight w divided out (in f64, rounded once), colours after x y z ignored,
    // negative indices counted back from the last vertex.
    let obj = "mtllib\tm.mtl # the library\nv\t0 0 0\nv 3 0 0 3\nv 0 1 0 0.5 0.5 0.5\n\
               v 0.1 0.2 0.3 0.7\nusemtl\tred\nf\t-4 -3 -2 # a face\nf 1 2 4\n";
    let scene = load_lab(obj, "newmtl red\nKd 1 0 0\n").unwrap();
    assert_eq!(scene.len(), 2);
    assert_eq!(
        scene.shapes[0],
        Shape::from([[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    );
    let w = [0.1f64, 0.2, 0.3].map(|c| (c as f32 as f64 / 0.7f32 as f64) as f32);
    assert_eq!(scene.shapes[1], Shape::from([[0.0; 3], [1.0, 0.0, 0.0], w]));
    assert_eq!(scene.colors(), vec![[1.0, 0.0, 0.0]; 2]);
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
}

#[test]
fn every_obj_and_mtl_problem_names_its_line() {
    let tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    let cases: &[(String, &str)] = &[
        // What tobj reported without a line, or misread.
        (format!("v 1e30 1e30 1e30 1e-30\n{tri}f 1 2 3\n"), "t.obj:1: coordinate 1e30 divided by w"),
        (format!("v 1 1 1 0\n{tri}f 1 2 3\n"), "t.obj:1: the weight w is 0"),
        (format!("v 1 1 1 1e-300\n{tri}f 1 2 3\n"), "t.obj:1: w = 1e-300 rounds to 0 in f32"),
        (format!("v 1 1 1 1e-400\n{tri}f 1 2 3\n"), "t.obj:1: w = 1e-400 rounds to 0 in f32"),
        (format!("v 1 1 1 -0e5\n{tri}f 1 2 3\n"), "t.obj:1: the weight w is 0"),
        (format!("{tri}v 1 2 3 4 5\nf 1 2 3\n"), "t.obj:4: vertex takes 3 numbers"),
        (format!("{tri}v 1 2 3 4 5 6 7\nf 1 2 3\n"), "t.obj:4: vertex takes 3 numbers"),
        (format!("{tri}v 1 2 3 r g b\nf 1 2 3\n"), "t.obj:4: colour component 'r'"),
        (format!("{tri}usemtl\nf 1 2 3\n"), "t.obj:4: usemtl needs a name"),
        (format!("mtllib   \n{tri}f 1 2 3\n"), "t.obj:1: mtllib needs a name"),
        (format!("{tri}f 1 2 -9223372036854775808\n"), "t.obj:4: face '-9223372036854775808': vertex index -9223372036854775808 is out of range (3 vertices"),
        (format!("{tri}f 1 2 -9223372036854775809\n"), "t.obj:4: face '-9223372036854775809': vertex index"),
        (format!("{tri}f 1 2 18446744073709551617\n"), "out of range"),
        (format!("{tri}vt 0 0\nf 1/1 2/2 3/1\n"), "t.obj:5: face '2/2': texture index 2 is out of range (1 texture coordinates"),
        (format!("{tri}vn 0 0 1\nf 1//1 2//1 3//-2\n"), "t.obj:5: face '3//-2': normal index -2"),
        (format!("{tri}vt 0 0\nvn 0 0 1\nf 1/1/1/1 2 3\n"), "t.obj:6: face '1/1/1/1': more than 3"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0 # 1e39\nv 0 1 1e39\nf 1 2 3\n".to_string(), "t.obj:4: coordinate '1e39'"),
        (format!("{tri}f 1 2 3\nl 1 2 9\n"), "no such failure"),
        (format!("{tri}\u{feff}f 1 2 3\n"), "t.obj:4: a byte-order mark (U+FEFF) past"),
    ];
    for (obj, needle) in cases {
        match load_lab(obj, "") {
            Err(e) => assert!(e.contains(needle), "{obj:?}: {e}"),
            // A polyline is skipped, so its index is never an error.
            Ok(scene) => assert_eq!(*needle, "no such failure", "{obj:?}: {:?}", scene.len()),
        }
    }
    // Material libraries: tobj's refusals become a warning with the library's line.
    let obj = format!("mtllib m.mtl\n{tri}usemtl a\nf 1 2 3\n");
    for (mtl, needle) in [
        (
            "newmtl a\nKd 1 0 0\nnewmtl\n",
            "m.mtl:3: newmtl needs a name",
        ),
        ("newmtl a\n\nNs x\n", "m.mtl:3: tobj: material parse error"),
        ("newmtl a\nKd 1 0\n", "m.mtl:2: Kd needs 3 numbers"),
        // (A word that is no number is named, not counted out.)
        (
            "newmtl a\nKd 0x1 0 0\n",
            "m.mtl:2: Kd: '0x1' is not a number",
        ),
        ("newmtl a\nillum\n", "m.mtl:2: tobj"),
        ("newmtl a\nmap_Kd", "m.mtl:2: tobj"),
    ] {
        let scene = load_lab(&obj, mtl).unwrap();
        let warning = scene.warnings.join("\n");
        assert!(warning.contains(needle), "{mtl:?}: {warning}");
        assert_eq!(
            scene.colors()[0],
            [0.75; 3],
            "the faces take the default colour"
        );
    }
    // A Kd the faces cannot show as written: said with its line; not finite, the default
    // colour; outside 0…1, clamped (a `.scene` file's `color` refuses both).
    for (kd, needle, colour) in [
        (
            "nan 1 1",
            "m.mtl:2: Kd nan 1 1 is not finite: the material's faces take the default colour",
            [0.75; 3],
        ),
        ("1e39 0 0", "m.mtl:2: Kd 1e39 0 0 is not finite", [0.75; 3]),
        (
            "-1 0.5 2",
            "m.mtl:2: Kd -1 0.5 2 is outside 0…1: clamped",
            [0.0, 0.5, 1.0],
        ),
        // (A fourth number, which tobj drops, is said.)
        (
            "0.5 0.5 0.5 0.9",
            "m.mtl:2: Kd takes 3 numbers: '0.9' after them ignored",
            [0.5; 3],
        ),
    ] {
        let scene = load_lab(&obj, &format!("newmtl a\nKd {kd}\n")).unwrap();
        let warning = scene.warnings.join("\n");
        assert!(warning.contains(needle), "{kd}: {warning}");
        assert_eq!(scene.warnings.len(), 1, "{kd}: {warning}");
        assert_eq!(scene.colors()[0], colour, "{kd}");
    }
    // A name no library defines: its faces are grey, and the user is told which.
    let scene = load_lab(
        &format!("mtllib m.mtl\n{tri}usemtl nosuch\nf 1 2 3\n"),
        "newmtl a\nKd 1 0 0\n",
    )
    .unwrap();
    assert!(
        scene
            .warnings
            .join("\n")
            .contains("usemtl names 1 material(s) no library defines (nosuch)"),
        "{:?}",
        scene.warnings
    );
    // An empty library, or none named: the same, as grey faces would otherwise be silent.
    for obj in [
        format!("mtllib m.mtl\n{tri}usemtl red\nf 1 2 3\n"),
        format!("{tri}usemtl red\nf 1 2 3\n"),
    ] {
        let scene = load_lab(&obj, "").unwrap();
        let warnings = scene.warnings.join("\n");
        assert!(
            warnings.contains("usemtl names 1 material(s) no library defines (red)"),
            "{obj:?}: {warnings}"
        );
        assert_eq!(scene.colors()[0], [0.75; 3], "{obj:?}");
    }
    // A library that cannot be read: its own warning says why, at its `mtllib` line, and no
    // other.
    let obj = format!("mtllib gone.mtl\n{tri}usemtl red\nf 1 2 3\n");
    let scene = raylab::scene::load_obj_str("t.obj", &obj, raylab::scene::ObjFrame::Lab, |_| {
        Err("gone.mtl: No such file or directory".to_string())
    })
    .unwrap();
    assert_eq!(scene.warnings.len(), 1, "{:?}", scene.warnings);
    assert!(
        scene.warnings[0].starts_with("t.obj:1: material library skipped: gone.mtl: No such file"),
        "{:?}",
        scene.warnings
    );
}

#[test]
fn one_loader_takes_the_same_names_everywhere() {
    use raylab::scene::{ObjFrame, CORNELL};
    use raylab::view::View;
    assert_eq!(
        Scene::open(CORNELL, ObjFrame::YUp).unwrap(),
        Scene::cornell()
    );
    let dir = tempfile::tempdir().unwrap();
    let scene_file = dir.path().join("s.scene");
    std::fs::write(&scene_file, "tri -1 -1 2 1 -1 2 0 1 2\n").unwrap();
    let by_name = Scene::open(scene_file.to_str().unwrap(), ObjFrame::YUp).unwrap();
    assert_eq!(by_name, Scene::load(&scene_file, ObjFrame::YUp).unwrap());
    assert!(Scene::open("no-such-file.scene", ObjFrame::YUp)
        .unwrap_err()
        .contains("no-such-file.scene"));
    // A view's scene: as written where it exists from here, else beside the view file.
    let view_file = dir.path().join("v.view");
    let view = |scene: &str| View::parse("v.view", &format!("scene {scene}\n")).unwrap();
    assert_eq!(
        view("s.scene").scene_path(&view_file),
        scene_file.display().to_string()
    );
    assert_eq!(view(CORNELL).scene_path(&view_file), CORNELL);
    let absolute = scene_file.display().to_string();
    assert_eq!(view(&absolute).scene_path(&view_file), absolute);
    assert_eq!(view("gone.scene").scene_path(&view_file), "gone.scene");
}

#[test]
fn a_view_out_of_range_names_its_line() {
    use raylab::view::View;
    let text = "scene cornell\n\nsize 20000 10\n";
    let e = View::parse("v.view", text).unwrap_err().to_string();
    assert!(e.starts_with("v.view:3:") && e.contains("size"), "{e}");
    let text = "size 64 48\nstep shadows\nspp 100000\n";
    let e = View::parse("v.view", text).unwrap_err().to_string();
    assert!(e.starts_with("v.view:3:") && e.contains("spp"), "{e}");
    assert!(View::parse("v.view", "size 64 48\nspp 4\n").is_ok());
    // An empty file, or one of comments, is not a view of the defaults.
    for empty in ["", "\n\n", "# saved by hand\n\n"] {
        let e = View::parse("v.view", empty).unwrap_err().to_string();
        assert!(
            e.starts_with("v.view:") && e.contains("not one statement"),
            "{e}"
        );
    }
    // A statement given twice: the last had won unseen.
    let e = View::parse("v.view", "scene a.obj\nsize 64 48\nscene b.obj\n").unwrap_err();
    let e = e.to_string();
    assert!(
        e.starts_with("v.view:3: a second `scene` (the first on line 1)"),
        "{e}"
    );
    // A quoted word on a camera line is refused, not read as other words (a comment that
    // dropped the yaw, a line break that made a second statement).
    for camera in [
        "camera \"0 0 -3 #\" yaw 45",
        "camera \"0 0 -3\\ncamera 1 2 3\"",
    ] {
        let e = View::parse("v.view", &format!("size 64 48\n{camera}\n")).unwrap_err();
        let e = e.to_string();
        assert!(
            e.starts_with("v.view:2:") && e.contains("none quoted"),
            "{e}"
        );
    }
    let view = View::parse("v.view", "camera 0 0 -3 yaw 45\n").unwrap();
    assert_eq!(view.camera.map(|c| c.yaw), Some(45.0));
    // Without a camera line, none: written back without one, not as the lab's.
    let view = View::parse("v.view", "scene m.obj\nsize 64 48\n").unwrap();
    assert_eq!((view.camera, view.light), (None, None));
    let text = view.to_text();
    assert!(
        !text.contains("camera") && !text.contains("light"),
        "{text}"
    );
    assert_eq!(View::parse("again", &text).unwrap(), view);
    let command = view.to_command("out.png");
    assert!(
        !command.contains("--camera") && !command.contains("--focal"),
        "{command}"
    );
}

#[test]
fn an_obj_triangle_out_of_range_names_its_face_line() {
    // A lone model's triangle beyond ±2³⁸ is refused naming the face's line (a polygon's
    // second fan triangle included), where it named only the triangle's index; a `.scene`
    // file may place such a mesh scaled into range.
    let no_mtl = |_: &str| -> Result<String, String> { Err("none".into()) };
    let load = |text: &str| {
        raylab::scene::load_obj_str("t.obj", text, raylab::scene::ObjFrame::Lab, no_mtl)
    };
    let obj = "# far\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1e12 0 0\nf 1 2 3\n\nf 2 3 1 4\n";
    let e = load(obj).unwrap_err().to_string();
    assert!(
        e.starts_with("t.obj:8: triangle 2 ") && e.contains("1000000000000"),
        "{e}"
    );
    assert!(e.contains("beyond ±2.74877906944e11"), "{e}");
    // At the range's end it loads.
    let at_end = obj.replace("1e12", "274877906944");
    assert!(load(&at_end).is_ok());
}

#[test]
fn a_file_not_named_obj_that_fails_as_one_says_how_it_was_read() {
    // Any name but `.scene` is read as an OBJ: a README opened by mistake failed on its line
    // 122 with "vertex takes 3 numbers", not saying why its words were vertices.
    let dir = tempfile::tempdir().unwrap();
    let notes = dir.path().join("notes.md");
    std::fs::write(&notes, "# notes\nv is a vertex: v x y z\n").unwrap();
    let e = Scene::load(&notes, raylab::scene::ObjFrame::YUp).unwrap_err();
    assert!(e.contains("notes.md:2: "), "{e}");
    assert!(
        e.ends_with(" (read as an OBJ file: a scene file's name ends in .scene)"),
        "{e}"
    );
    let obj = dir.path().join("bad.obj");
    std::fs::write(&obj, "v 1 2\n").unwrap();
    let e = Scene::load(&obj, raylab::scene::ObjFrame::YUp).unwrap_err();
    assert!(
        e.contains("bad.obj:1: ") && !e.contains("read as an OBJ"),
        "{e}"
    );
    // A view named as a mesh: it is opened on its own, and names its scene itself.
    std::fs::write(dir.path().join("v.view"), "scene cornell\nsize 64 48\n").unwrap();
    let scene = dir.path().join("s.scene");
    std::fs::write(&scene, "mesh v.view\n").unwrap();
    let e = Scene::load(&scene, raylab::scene::ObjFrame::YUp).unwrap_err();
    assert!(e.contains("a .view is opened on its own"), "{e}");
    // A scene file named as a mesh (it was told that a scene file's name ends in .scene).
    std::fs::write(dir.path().join("t.scene"), "cornell\n").unwrap();
    std::fs::write(&scene, "mesh t.scene\n").unwrap();
    let e = Scene::load(&scene, raylab::scene::ObjFrame::YUp).unwrap_err();
    assert!(
        e.ends_with(
            "a `mesh` line places a model, an OBJ file; a .scene file is opened on its own)"
        ),
        "{e}"
    );
    // A file not read (missing, a directory) was read as nothing: no hint of how.
    for unread in [dir.path().join("missing"), dir.path().to_path_buf()] {
        let e = Scene::load(&unread, raylab::scene::ObjFrame::YUp).unwrap_err();
        assert!(!e.contains("read as an OBJ"), "{e}");
    }
}

#[test]
fn latin1_comments_and_names_in_an_obj_load_and_other_bytes_are_refused_by_line() {
    // Exporters write object and group names (and comments) in Latin-1: "caf\xe9" refused
    // the whole model as "not a text OBJ file". Only names and comments may be: a vertex line
    // with such a byte is refused, naming its line.
    let dir = tempfile::tempdir().unwrap();
    let obj = dir.path().join("named.obj");
    let mut text = b"# caf\xe9\no caf\xe9\ng\tm\xfcller\n".to_vec();
    text.extend_from_slice(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    std::fs::write(&obj, &text).unwrap();
    let scene = Scene::load(&obj, raylab::scene::ObjFrame::YUp).unwrap();
    assert_eq!(scene.len(), 1);
    let bad = dir.path().join("bad.obj");
    std::fs::write(&bad, b"v 0 0 0\nv 1 0 0\xe9\nv 0 1 0\nf 1 2 3\n").unwrap();
    let e = Scene::load(&bad, raylab::scene::ObjFrame::YUp).unwrap_err();
    assert!(e.contains("bad.obj:2: not a text OBJ file"), "{e}");
}
