//! The one clock all message stamps use.

/// CLOCK_MONOTONIC in nanoseconds, the time base of every `stamp_ns` and
/// deadline. Does not allocate (vDSO call). Returns 0 if the clock fails,
/// which validation then sees as a very old message, never a future one.
#[allow(unsafe_code)]
pub fn monotonic_now_ns() -> u64 {
    let mut ts = libc::timespec { tv_sec: 0, tv_nsec: 0 };
    // SAFETY: `ts` is a valid, writable timespec for the duration of the call.
    let rc = unsafe { libc::clock_gettime(libc::CLOCK_MONOTONIC, &mut ts) };
    if rc != 0 {
        return 0;
    }
    let secs = u64::try_from(ts.tv_sec).unwrap_or(0);
    let nanos = u64::try_from(ts.tv_nsec).unwrap_or(0);
    secs.saturating_mul(1_000_000_000).saturating_add(nanos)
}
