//! The library's unit tests (src/unit_tests.rs), compiled into it under the feature
//! `unit-tests` and run here as libtest runs tests: `cargo test --test unit accel::bvh::`.

use libtest_mimic::{Arguments, Trial};

fn main() {
    let trials = (raylab::unit_tests::all().into_iter())
        .map(|(name, test)| {
            Trial::test(name, move || {
                test();
                Ok(())
            })
        })
        .collect();
    libtest_mimic::run(&Arguments::from_args(), trials).exit();
}
