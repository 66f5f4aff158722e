//! The unit tests: tests of items private to their modules, written beside them and compiled
//! into the library under the feature `unit-tests`, which `cargo test` turns on (the library's
//! dev-dependency on itself) and nothing else should. tests/unit.rs runs them as libtest runs
//! tests (`cargo test --test unit accel::bvh::`), so that `cargo test` compiles the library
//! once instead of a second time for `cfg(test)`.
//!
//! Each test module lists its tests in `TESTS`, and the list of lists is below; the modules
//! deny dead code, so a test left out of its module's list, or a list left out of this one,
//! does not compile.

/// A module's tests, by name.
pub type Tests = &'static [(&'static str, fn())];

/// Every unit test: its path in the library (module and name) and the test.
pub fn all() -> Vec<(String, fn())> {
    let modules: &[(&str, Tests)] = &[
        ("accel", crate::accel::tests::TESTS),
        ("accel::bvh", crate::accel::bvh::tests::TESTS),
        (
            "accel::bvh::wide_nodes",
            crate::accel::bvh::tests::wide_nodes::TESTS,
        ),
        ("accel::bvh::build", crate::accel::bvh::build::tests::TESTS),
        ("accel::instances", crate::accel::instances::tests::TESTS),
        ("accel::spheres", crate::accel::spheres::tests::TESTS),
        ("accel::flat", crate::accel::flat::tests::TESTS),
        ("accel::packet", crate::accel::packet::tests::TESTS),
        ("accel::prepared", crate::accel::prepared::tests::TESTS),
        ("accel::frame::far", crate::accel::frame::far::tests::TESTS),
        (
            "geometry::adaptive",
            crate::geometry::adaptive::tests::TESTS,
        ),
        ("geometry::exact", crate::geometry::exact::tests::TESTS),
        (
            "geometry::shapes::sphere",
            crate::geometry::shapes::sphere::tests::TESTS,
        ),
        (
            "geometry::shapes::sphere::lanes",
            crate::geometry::shapes::sphere::lanes::tests::TESTS,
        ),
        ("input::output", crate::input::output::tests::TESTS),
        #[cfg(target_arch = "x86_64")]
        ("math::lanes", crate::math::lanes::tests::TESTS),
        ("math::interval", crate::math::interval::tests::TESTS),
        ("math::real", crate::math::real::tests::TESTS),
        ("render::aov", crate::render::aov::tests::TESTS),
        ("render::settings", crate::render::settings::tests::TESTS),
        ("render::shade", crate::render::shade::tests::TESTS),
        ("scene", crate::scene::tests::TESTS),
        ("scene::bounds", crate::scene::bounds::tests::TESTS),
        ("words", crate::words::tests::TESTS),
    ];
    let named = modules.iter().flat_map(|(module, tests)| {
        (tests.iter()).map(move |(name, test)| (format!("{module}::{name}"), *test))
    });
    named.collect()
}
