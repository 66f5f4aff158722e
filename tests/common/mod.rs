//! Helpers shared by the integration tests: a seeded generator, closed test meshes, PNG
//! comparison, and the tool check that skips a test (or fails it under CI=true).
#![allow(dead_code, unused_imports)]

pub mod binary;
pub mod suite;
pub mod window;

use raylab::geometry::Shape;
use raylab::math::Real;

pub use raylab::check::meshes::{cube, icosphere, vertices_and_edge_midpoints, Rng};

/// The Cornell box with `shapes` added in blue (0.2, 0.5, 0.9), over the structure `choice`.
pub fn cornell_with_blue(
    shapes: Vec<Shape<f32>>,
    choice: raylab::accel::AccelChoice,
) -> raylab::render::Stage {
    let n = shapes.len();
    let mut scene = raylab::Scene::cornell();
    scene.shapes.extend(shapes);
    (scene.colors_mut()).extend(std::iter::repeat_n([0.2, 0.5, 0.9], n));
    raylab::render::Stage::new(scene, choice)
}

/// Renders `settings` and, from the same camera, the cracks view, which traces every ray one
/// at a time (and with the adaptive method marks nothing): the two must give the same pixels
/// and the same counts of hits and shadow rays (`at` names the case). The image and its
/// statistics.
pub fn renders_as_per_ray(
    stage: &raylab::render::Stage,
    cam: &raylab::Camera,
    settings: &raylab::render::RenderSettings,
    at: &str,
) -> (Vec<u8>, raylab::render::RenderStats) {
    let per_ray = raylab::render::RenderSettings {
        cracks: true,
        ..*settings
    };
    let (a, sa) = raylab::render::render_image(stage, cam, settings).unwrap();
    let (b, sb) = raylab::render::render_image(stage, cam, &per_ray).unwrap();
    assert!(a == b, "{at}: images differ");
    assert_eq!((sa.hits, sa.shadow_rays), (sb.hits, sb.shadow_rays), "{at}");
    (a, sa)
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
    shapes.iter().map(|s| s.scene_line() + "\n").collect()
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

/// The same hit from two paths that must agree (instanced and flattened, say): the same
/// primitive for every method, the same t and barycentrics for the inexact ones. The adaptive
/// method's t is the f32 t where that is certain, and which f32 computation is certain depends
/// on the box bounds the path uses: there the same hit point within f32 rounding of the
/// inputs. (In f64: directions may be near f32's limits.)
pub fn same_hit(
    method: raylab::geometry::Method,
    ray: &raylab::geometry::Ray,
    got: Option<raylab::geometry::Hit>,
    want: Option<raylab::geometry::Hit>,
    what: &str,
) {
    if method != raylab::geometry::Method::Adaptive {
        assert_eq!(got, want, "{what}");
        return;
    }
    assert_eq!(got.map(|h| h.prim), want.map(|h| h.prim), "{what}");
    if let (Some(g), Some(w)) = (got, want) {
        let len = ray
            .d
            .iter()
            .map(|c| (*c as f64).powi(2))
            .sum::<f64>()
            .sqrt();
        let scale = 1.0 + ray.o.iter().fold(0f64, |m, c| m.max((*c as f64).abs()));
        let off = (g.t as f64 - w.t as f64).abs() * len;
        assert!(
            off <= 1e-5 * (scale + (w.t as f64).abs() * len),
            "{what}: {g:?} {w:?}"
        );
    }
}

/// Packets of 8 rays from one origin through `scene`'s instances: every lane the packet
/// decides names the primitive the flattened scene's per-ray query names (`what` says which
/// case failed). Returns the lanes decided and the lanes in all.
pub fn check_instance_packets(
    scene: &raylab::accel::Accel,
    flat: &raylab::accel::Accel,
    o: [f32; 3],
    dirs: &[[f32; 3]; 8],
    what: &str,
) -> (usize, usize) {
    use raylab::accel::testing::max_component;
    use raylab::geometry::{Method, Ray};
    use raylab::math::lanes::f32x8;
    let d: [f32x8; 3] = [0, 1, 2].map(|k| f32x8::from(dirs.map(|d| d[k])));
    let found = scene
        .closest_packet(o, None, &d, max_component(&d))
        .expect("a BVH and no other shapes");
    let mut decided = 0;
    for (l, dir) in dirs.iter().enumerate() {
        if found.ambiguous & (1 << l) != 0 {
            continue;
        }
        decided += 1;
        let want = flat
            .closest_hit(&Ray::new(o, *dir), Method::Adaptive, 0.0, f32::INFINITY)
            .map_or(u32::MAX, |h| h.prim);
        assert_eq!(found.prim[l], want, "{what}: lane {l} of {o:?} {dirs:?}");
    }
    (decided, 8)
}
