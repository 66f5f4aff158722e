//! Memory in proportion to a `.scene` file: a mesh named by many spellings of its path is
//! one mesh, and copies of a repeated small mesh are flattened only within a room in
//! proportion to the file (peak resident memory measured with GNU time).

use crate::common;

use common::binary::{stderr, write};
use std::process::Command;

/// The peak resident memory (GNU time's) of rendering `scene` at 16x16, in KiB.
fn peak_render_kib(scene: &str) -> u64 {
    let out = std::path::Path::new(scene).with_extension("png");
    let o = Command::new("/usr/bin/time")
        .args(["-f", "peak_kib=%M", env!("CARGO_BIN_EXE_raylab")])
        .args([
            "render", "--scene", scene, "--width", "16", "--height", "16", "-o",
        ])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let err = stderr(&o);
    let line = err.lines().find_map(|l| l.strip_prefix("peak_kib="));
    line.expect("GNU time's report").trim().parse().unwrap()
}

/// A grid of 600 triangles as OBJ text.
fn grid() -> String {
    let mut text = String::new();
    for j in 0..=20 {
        for i in 0..=20 {
            text += &format!(
                "v {} {} {}\n",
                i as f32 * 0.05,
                j as f32 * 0.05,
                (i % 3) as f32 * 0.01
            );
        }
    }
    for k in 0..300 {
        let (i, j) = (k % 20, k / 20);
        let a = 1 + j * 21 + i;
        text += &format!(
            "f {} {} {}\nf {} {} {}\n",
            a,
            a + 1,
            a + 22,
            a,
            a + 22,
            a + 21
        );
    }
    text
}

#[test]
fn memory_stays_in_proportion_to_a_scene_file_of_repeated_meshes() {
    if !common::tool_for("/usr/bin/time", "time", "a memory test") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let size = |paths: &[&str]| -> u64 {
        paths
            .iter()
            .map(|p| std::fs::metadata(p).unwrap().len())
            .sum()
    };
    let base = peak_render_kib(&write(d, "tiny.scene", "tri 0 0 1 1 0 1 0 1 1\n"));
    // A 600-triangle mesh placed 1,000 times under 1,000 spellings of its path: each was a
    // mesh of its own, flattened (880 bytes a byte of input).
    let mesh = write(d, "c.obj", &grid());
    std::fs::create_dir(d.join("d")).unwrap();
    let mut spelled = String::new();
    for k in 0..1000 {
        let path = format!("{}{}c.obj", "./".repeat(k % 40), "d/../".repeat(k / 40));
        spelled += &format!(
            "push\ntranslate {} {} 0\nmesh {path}\npop\n",
            k % 40,
            k / 40
        );
    }
    let spellings = write(d, "spelled.scene", &spelled);
    // 34,952 `cornell` lines: the whole room for flattened copies (2^20 triangles), 120 MB
    // flattened (380 bytes a byte).
    let boxes = write(d, "boxes.scene", &"cornell\n".repeat(34_952));
    for (what, scene, bytes) in [
        (
            "spellings of one mesh",
            &spellings,
            size(&[&spellings, &mesh]),
        ),
        ("cornell lines", &boxes, size(&[&boxes])),
    ] {
        let peak = peak_render_kib(scene);
        let per_byte = (peak.saturating_sub(base) * 1024) as f64 / bytes as f64;
        println!("{what}: {bytes} bytes read, peak {peak} KiB ({base} KiB tiny): {per_byte:.1} bytes a byte");
        assert!(
            per_byte < 100.0,
            "{what}: {per_byte:.1} bytes a byte of input"
        );
    }
    // The room every file has: 1,927 boxes each at its own spot (50 KB), flattened, stay
    // within 100 bytes a byte and 10 MiB.
    let row = write(d, "row.scene", &"translate 1.5 0 0\ncornell\n".repeat(1927));
    let peak = peak_render_kib(&row);
    let above = peak.saturating_sub(base) * 1024;
    println!("a row of boxes: peak {peak} KiB ({base} KiB tiny)");
    assert!(above < 100 * size(&[&row]) + (10 << 20), "{above} bytes");
}
