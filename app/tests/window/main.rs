//! The real window under Xvfb, in one test binary of its own: its tests run three windows at a
//! time, each on an X server of its own, one alone where its checks rest on timing
//! (`common::window::WINDOWS_AT_ONCE`), and nothing else of the test run beside them. A file is
//! a module (`cargo test -p raylab-app --test window panel::`).
//!
//! The harness is libtest-mimic's, not libtest's: libtest runs a test a core, and a window
//! run mostly waits for its driver (two cores run three windows with room to spare), so this
//! one runs at least [`WINDOWS_AT_ONCE`] tests at once unless `--test-threads` says otherwise.
//! Each file lists its tests in `TESTS` and denies dead code, so a test left out of its list
//! does not compile. Their output is not captured.

#[path = "../../../tests/common/mod.rs"]
mod common;

/// A file's tests by name: `tests![a, b]` is `&[("a", a), ("b", b)]`.
macro_rules! tests {
    ($($test:ident),* $(,)?) => {
        &[$((stringify!($test), $test as fn())),*]
    };
}

mod files;
mod idle;
mod input;
mod inspector;
mod inspector_clicks;
mod layout;
mod panel;
mod sizes;

use common::window::WINDOWS_AT_ONCE;
use libtest_mimic::{Arguments, Trial};

/// A file's tests, by name.
type Tests = &'static [(&'static str, fn())];

fn main() {
    let files: &[(&str, Tests)] = &[
        ("files", files::TESTS),
        ("idle", idle::TESTS),
        ("input", input::TESTS),
        ("inspector", inspector::TESTS),
        ("inspector_clicks", inspector_clicks::TESTS),
        ("layout", layout::TESTS),
        ("panel", panel::TESTS),
        ("sizes", sizes::TESTS),
    ];
    let trials = files.iter().flat_map(|(file, tests)| {
        tests.iter().map(move |&(name, test)| {
            Trial::test(format!("{file}::{name}"), move || {
                test();
                Ok(())
            })
        })
    });
    let mut args = Arguments::from_args();
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    args.test_threads.get_or_insert(cores.max(WINDOWS_AT_ONCE));
    libtest_mimic::run(&args, trials.collect()).exit();
}
