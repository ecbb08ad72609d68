//! Shared settings of the workspace integration tests (the tests are in
//! `tests/`).

use core::mem::{MaybeUninit, size_of};

use ipc_types::PROTOCOL_VERSION;
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

/// The payload whose bytes are `bytes` (repeated if shorter than the type).
/// Every payload is plain integers/floats without padding, so every byte
/// pattern is a valid value: that is exactly the property under test.
pub fn from_bytes<T: Copy>(bytes: &[u8]) -> T {
    let mut out = MaybeUninit::<T>::uninit();
    let n = size_of::<T>();
    let filled: Vec<u8> = bytes.iter().copied().cycle().take(n).collect();
    assert_eq!(filled.len(), n);
    // SAFETY: `filled` holds exactly size_of::<T>() bytes and every bit
    // pattern is a valid T (only u32/u64/f64 fields, no padding).
    unsafe {
        core::ptr::copy_nonoverlapping(filled.as_ptr(), out.as_mut_ptr().cast::<u8>(), n);
        out.assume_init()
    }
}

/// Overwrite the leading `protocol_version` and `count` words so that the
/// random body is actually walked by validate() instead of failing early.
pub fn patch_header(bytes: &mut [u8], count: u32) {
    bytes[0..4].copy_from_slice(&PROTOCOL_VERSION.to_ne_bytes());
    bytes[4..8].copy_from_slice(&count.to_ne_bytes());
}
