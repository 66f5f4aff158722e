//! The real window under Xvfb, in one test binary of its own: its tests run five windows at a
//! time, each on an X server of its own, one alone where its checks rest on timing
//! (`common::window::WINDOWS_AT_ONCE`), and nothing else of the test run beside them. A file is
//! a module (`cargo test -p raylab-app --test window panel::`).
//!
//! The harness is libtest-mimic's, not libtest's: libtest runs a test a core, and a window
//! run mostly waits for its driver (two cores run five windows with room to spare), so this
//! one runs at least [`WINDOWS_AT_ONCE`] tests at once unless `--test-threads` (or
//! `RUST_TEST_THREADS`) says otherwise.
//! Each file lists its tests in `TESTS` and dead code is denied, so a test left out of its
//! list does not compile; a `#[test]` attribute, which this harness would never run, fails
//! the first test below. Their output is not captured.

#![deny(dead_code)]

#[path = "../../../tests/common/mod.rs"]
mod common; // (it allows dead code: the binaries use parts of it)

/// A file's tests by name: `tests![a, b]` is `&[("a", a), ("b", b)]`.
macro_rules! tests {
    ($($test:ident),* $(,)?) => {
        &[$((stringify!($test), $test as fn())),*]
    };
}

mod cracks;
mod files;
mod idle;
mod input;
mod inspector;
mod inspector_clicks;
mod layout;
mod panel;
mod sizes;
mod views;

use common::window::WINDOWS_AT_ONCE;
use libtest_mimic::{Arguments, Trial};

/// A file's tests, by name.
type Tests = &'static [(&'static str, fn())];

/// Each file: its module's name, its tests and its text (for the check of `#[test]`).
const FILES: &[(&str, Tests, &str)] = &[
    ("cracks", cracks::TESTS, include_str!("cracks.rs")),
    ("files", files::TESTS, include_str!("files.rs")),
    ("idle", idle::TESTS, include_str!("idle.rs")),
    ("input", input::TESTS, include_str!("input.rs")),
    ("inspector", inspector::TESTS, include_str!("inspector.rs")),
    (
        "inspector_clicks",
        inspector_clicks::TESTS,
        include_str!("inspector_clicks.rs"),
    ),
    ("layout", layout::TESTS, include_str!("layout.rs")),
    ("panel", panel::TESTS, include_str!("panel.rs")),
    ("sizes", sizes::TESTS, include_str!("sizes.rs")),
    ("views", views::TESTS, include_str!("views.rs")),
];

fn main() {
    // A test marked `#[test]` is compiled out of this harness's binary, silently.
    let none_left_out = Trial::test("harness::no_test_is_marked_for_libtest", || {
        let marked: Vec<&str> = (FILES.iter())
            .filter(|(_, _, text)| text.contains(concat!("#[", "test]")))
            .map(|(file, _, _)| *file)
            .collect();
        match marked.is_empty() {
            true => Ok(()),
            false => Err(format!("{marked:?}: list the test in the file's TESTS instead").into()),
        }
    });
    let tests = FILES.iter().flat_map(|(file, tests, _)| {
        tests.iter().map(move |&(name, test)| {
            Trial::test(format!("{file}::{name}"), move || {
                test();
                Ok(())
            })
        })
    });
    let mut args = Arguments::from_args();
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let asked = std::env::var("RUST_TEST_THREADS")
        .ok()
        .and_then(|n| n.parse().ok());
    args.test_threads = args
        .test_threads
        .or(asked)
        .or(Some(cores.max(WINDOWS_AT_ONCE)));
    let trials = std::iter::once(none_left_out).chain(tests).collect();
    libtest_mimic::run(&args, trials).exit();
}
