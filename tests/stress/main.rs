//! The numerical-stability stress suite (issue 5), library level: property
//! tests and fixed nasty cases over geometry, cameras and rendering, texture
//! patterns and the polygon stream. For every case the result is either output
//! meeting the invariant named in the test, or a clear error: never a panic, a
//! hang, or a non-finite value. The command-line half is `tests/cli/stress.rs`.
//!
//! Run it alone with `cargo test --test stress`. Every proptest runs a fixed
//! number of cases ([`CASES`]) so that the suite stays under a minute in a
//! debug build on two cores.

mod camera;
mod geometry;
mod stream;
mod texture;

/// Cases per property test: enough to sweep each range (scales over 15
/// decades, tilts over 12) several times, few enough for a quick `cargo test`.
pub const CASES: u32 = 48;

/// The proptest configuration shared by the suite: [`CASES`] cases, and no
/// failure-persistence files (shrunk failures are committed as named
/// regression tests instead).
pub fn config() -> proptest::test_runner::Config {
    proptest::test_runner::Config {
        cases: CASES,
        failure_persistence: None,
        ..proptest::test_runner::Config::default()
    }
}
