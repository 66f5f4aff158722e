//! Helpers shared by the integration tests: a seeded generator, closed test meshes, PNG
//! comparison, and the tool check that skips a test (or fails it under CI=true).
#![allow(dead_code)]

pub mod suite;

use raylab::geometry::Shape;
use raylab::math::Real;

/// SplitMix64: a tiny seeded generator so every test run sees the same cases.
pub struct Rng(pub u64);

impl Rng {
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }
}

/// An axis-aligned cube [offset, offset + size]³, each face an n×n grid of quads split into
/// two triangles along alternating diagonals. With n and size powers of two and an offset on
/// the same grid, every vertex and every edge midpoint is exact in f32.
pub fn cube(n: usize, size: f32, offset: [f32; 3]) -> Vec<Shape<f32>> {
    let mut tris = Vec::new();
    let step = size / n as f32;
    for axis in 0..3 {
        for side in [0.0f32, 1.0] {
            let (a1, a2) = ((axis + 1) % 3, (axis + 2) % 3);
            let p = |u: usize, v: usize| {
                let mut q = [0.0f32; 3];
                q[axis] = offset[axis] + side * size;
                q[a1] = offset[a1] + u as f32 * step;
                q[a2] = offset[a2] + v as f32 * step;
                q
            };
            for u in 0..n {
                for v in 0..n {
                    let (p00, p10, p01, p11) = (p(u, v), p(u + 1, v), p(u, v + 1), p(u + 1, v + 1));
                    if (u + v) % 2 == 0 {
                        tris.push(Shape::Triangle([p00, p10, p11]));
                        tris.push(Shape::Triangle([p00, p11, p01]));
                    } else {
                        tris.push(Shape::Triangle([p00, p10, p01]));
                        tris.push(Shape::Triangle([p10, p11, p01]));
                    }
                }
            }
        }
    }
    tris
}

/// An icosphere: the icosahedron subdivided `levels` times, vertices pushed to the sphere in
/// f32. Shared vertices are the same f32 values in every triangle that uses them.
pub fn icosphere(levels: u32, radius: f32, centre: [f32; 3]) -> Vec<Shape<f32>> {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let mut verts: Vec<[f64; 3]> = vec![
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ];
    let mut faces: Vec<[usize; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..levels {
        let mut mid = std::collections::HashMap::new();
        let mut next = Vec::new();
        let mut midpoint = |a: usize, b: usize, verts: &mut Vec<[f64; 3]>| {
            *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                let (p, q) = (verts[a], verts[b]);
                verts.push([
                    (p[0] + q[0]) / 2.0,
                    (p[1] + q[1]) / 2.0,
                    (p[2] + q[2]) / 2.0,
                ]);
                verts.len() - 1
            })
        };
        for f in &faces {
            let ab = midpoint(f[0], f[1], &mut verts);
            let bc = midpoint(f[1], f[2], &mut verts);
            let ca = midpoint(f[2], f[0], &mut verts);
            next.extend([[f[0], ab, ca], [f[1], bc, ab], [f[2], ca, bc], [ab, bc, ca]]);
        }
        faces = next;
    }
    let pts: Vec<[f32; 3]> = verts
        .iter()
        .map(|v| {
            let len = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            [0, 1, 2].map(|k| (centre[k] as f64 + v[k] / len * radius as f64) as f32)
        })
        .collect();
    faces
        .iter()
        .map(|f| Shape::Triangle([pts[f[0]], pts[f[1]], pts[f[2]]]))
        .collect()
}

/// Every vertex and every edge midpoint (computed in f32) of a triangle mesh.
pub fn vertices_and_edge_midpoints(mesh: &[Shape<f32>]) -> Vec<[f32; 3]> {
    let mut out = Vec::new();
    for s in mesh {
        if let Shape::Triangle(v) = s {
            for k in 0..3 {
                let (a, b) = (v[k], v[(k + 1) % 3]);
                out.push(a);
                out.push([0, 1, 2].map(|c| (a[c] + b[c]) * 0.5));
            }
        }
    }
    out.sort_by(|a, b| a.partial_cmp(b).unwrap());
    out.dedup();
    out
}

/// Decodes an RGBA8 PNG: (width, height, pixels).
pub fn read_png(path: &std::path::Path) -> (u32, u32, Vec<u8>) {
    let dec = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut reader = dec.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).unwrap();
    buf.truncate(info.buffer_size());
    assert_eq!(info.color_type, png::ColorType::Rgba);
    (info.width, info.height, buf)
}

/// Runs `command`, a shell line naming `raylab`, with `sh -c` in `dir`, the directory of
/// `raylab` (the built binary, `env!("CARGO_BIN_EXE_raylab")`) first on PATH, as a user pastes
/// a copied command.
pub fn run_in_shell(command: &str, dir: &std::path::Path, raylab: &str) -> std::process::Output {
    let bin = std::path::Path::new(raylab);
    let path = format!(
        "{}:{}",
        bin.parent().expect("the binary's directory").display(),
        std::env::var("PATH").unwrap_or_default()
    );
    std::process::Command::new("sh")
        .args(["-c", command])
        .env("PATH", path)
        .current_dir(dir)
        .output()
        .expect("run sh")
}

/// How many pixels of two RGBA images of one size differ by more than 8 in some channel, and
/// how many pixels there are.
pub fn pixels_off(a: &(u32, u32, Vec<u8>), b: &(u32, u32, Vec<u8>)) -> (usize, usize) {
    assert_eq!((a.0, a.1), (b.0, b.1), "the same size");
    let off = (a.2.chunks(4).zip(b.2.chunks(4)))
        .filter(|(p, q)| (0..3).any(|c| (p[c] as i32 - q[c] as i32).abs() > 8))
        .count();
    (off, (a.0 * a.1) as usize)
}

/// Shapes as `.scene` text (`tri …` / `sphere …` per line; Rust's shortest round-trip
/// numbers, so they parse back to the same bits in the same precision).
pub fn scene_text<T: Real>(shapes: &[Shape<T>]) -> String {
    let mut text = String::new();
    for s in shapes {
        match s {
            Shape::Triangle(v) => {
                let nums: Vec<String> = v.iter().flatten().map(|x| x.to_string()).collect();
                text += &format!("tri {}\n", nums.join(" "));
            }
            Shape::Sphere { centre: c, radius } => {
                text += &format!("sphere {} {} {} {radius}\n", c[0], c[1], c[2]);
            }
        }
    }
    text
}

/// Whether the tool `command` (found on PATH, or a path) is there for `test`. Without it the
/// test says SKIPPED and is skipped, except under `CI=true`, where .ci/run must have installed
/// it (`package` says which Debian package) and its absence fails the test.
pub fn tool_for(command: &str, package: &str, test: &str) -> bool {
    let there = std::process::Command::new("sh")
        .args(["-c", &format!("command -v {command}")])
        .stdout(std::process::Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    if !there {
        assert!(
            std::env::var("CI").is_err(),
            "CI=true but {command} is missing: .ci/run must install {package}"
        );
        eprintln!(
            "\n*** SKIPPED {test}: {command} is not installed (apt-get install {package}) ***\n"
        );
    }
    there
}
