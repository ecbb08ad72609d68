//! Shared settings of the workspace integration tests (the tests are in
//! `tests/`).

use proptest::test_runner::{Config, FileFailurePersistence};

/// Environment variable that sets the number of cases of every fuzz
/// property (e.g. `UPM_FUZZ_CASES=1000000` for the recorded runs).
pub const FUZZ_CASES_VAR: &str = "UPM_FUZZ_CASES";

/// Cases for one fuzz property: `UPM_FUZZ_CASES` if set, else `ci_default`
/// (kept small so the README test command stays quick). `weight` scales
/// the count down for properties whose cases are expensive (1 = full).
pub fn fuzz_cases(ci_default: u32, weight: u32) -> u32 {
    let cases = match std::env::var(FUZZ_CASES_VAR) {
        Ok(v) => {
            v.trim().parse::<u32>().unwrap_or_else(|_| panic!("{FUZZ_CASES_VAR}={v:?} is not a case count"))
        }
        Err(_) => ci_default,
    };
    (cases / weight.max(1)).max(1)
}

/// A proptest config for a fuzz property: `fuzz_cases` cases, no shrinking
/// time limit, failing inputs saved next to the test (`*.regressions`).
pub fn fuzz_config(ci_default: u32, weight: u32) -> Config {
    Config {
        cases: fuzz_cases(ci_default, weight),
        max_shrink_iters: 4096,
        failure_persistence: Some(Box::new(FileFailurePersistence::WithSource("regressions"))),
        ..Config::default()
    }
}
