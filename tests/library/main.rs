//! The library's integration tests, one binary: one link instead of one per file, and the test
//! harness's threads shared by every file's tests. A file is a module; `cargo test --test
//! library NAME` runs the tests whose path contains NAME (`hard_cases::`, `fuzz::`). The two
//! tests that read the adaptive method's global level counters (tests/levels.rs,
//! tests/zero_area_filter.rs) keep binaries of their own: other tests would count too.

#[path = "../common/mod.rs"]
mod common;

mod accel;
mod camera;
mod controller;
mod far_and_grazing;
mod fuzz;
mod hard_cases;
mod instances;
mod instances_at_any_scale;
mod instances_stored;
mod intersection;
mod lab_code;
mod packet;
mod pinned_images;
mod render;
mod render_paths;
mod rounded_t;
mod scene;
mod scene_bounds;
mod scene_file;
mod scene_mesh_identity;
mod scene_zero_area;
mod shading_point;
mod shadows;
mod shapes;
mod sphere_packets;
mod transform;

/// A property test's configuration: `default` cases a run, or `PROPTEST_CASES` where it is set
/// (a longer run: `PROPTEST_CASES=400000 cargo test --test library fuzz::`). Proptest reads
/// that variable only for a test that sets no count of its own.
pub fn cases(default: u32) -> proptest::test_runner::Config {
    let cases = std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|n| n.parse().ok());
    proptest::test_runner::Config::with_cases(cases.unwrap_or(default))
}
