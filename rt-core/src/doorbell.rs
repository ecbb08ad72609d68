//! The receiver thread wakes the solver thread through a futex: the
//! receiver rings after handing messages over, the solver sleeps until the
//! ring count moves. Neither side allocates or takes a lock; the only
//! syscalls are FUTEX_WAKE and FUTEX_WAIT on one word (Linux). A ring that
//! lands between the solver's last look and its wait makes the wait return
//! at once (the kernel compares the word first), so none is lost.

use core::sync::atomic::AtomicU32;
use core::sync::atomic::Ordering::{Acquire, Release};

#[derive(Debug, Default)]
pub struct Doorbell(AtomicU32);

impl Doorbell {
    /// The ring count to pass to [`Self::wait`] before looking for work.
    pub fn seen(&self) -> u32 {
        self.0.load(Acquire)
    }

    /// Announce work and wake the waiter, if any.
    pub fn ring(&self) {
        self.0.fetch_add(1, Release);
        // SAFETY: FUTEX_WAKE on a live, aligned u32 that this struct owns.
        unsafe {
            libc::syscall(libc::SYS_futex, self.0.as_ptr(), libc::FUTEX_WAKE | libc::FUTEX_PRIVATE_FLAG, 1);
        }
    }

    /// Sleep until the ring count differs from `seen`, or `timeout_ns`
    /// (CLOCK_MONOTONIC, relative) passes, or a signal arrives.
    pub fn wait(&self, seen: u32, timeout_ns: u64) {
        let timeout = libc::timespec {
            tv_sec: (timeout_ns / 1_000_000_000) as libc::time_t,
            tv_nsec: (timeout_ns % 1_000_000_000) as libc::c_long,
        };
        // SAFETY: FUTEX_WAIT on a live, aligned u32 this struct owns, with a
        // valid timespec; the kernel only reads both.
        unsafe {
            libc::syscall(
                libc::SYS_futex,
                self.0.as_ptr(),
                libc::FUTEX_WAIT | libc::FUTEX_PRIVATE_FLAG,
                seen,
                &timeout as *const libc::timespec,
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;
    use std::time::{Duration, Instant};

    use super::*;

    #[test]
    fn a_ring_wakes_the_waiter_and_none_is_lost() {
        let bell = Arc::new(Doorbell::default());
        // Rung before the wait: the wait returns at once.
        let seen = bell.seen();
        bell.ring();
        let t = Instant::now();
        bell.wait(seen, 5_000_000_000);
        assert!(t.elapsed() < Duration::from_secs(1));
        // Rung while waiting: woken long before the timeout.
        let b = bell.clone();
        let seen = bell.seen();
        let ringer = std::thread::spawn(move || {
            std::thread::sleep(Duration::from_millis(50));
            b.ring();
        });
        let t = Instant::now();
        bell.wait(seen, 5_000_000_000);
        assert!(t.elapsed() < Duration::from_secs(2), "not woken: {:?}", t.elapsed());
        ringer.join().expect("ringer");
        // Not rung: the timeout ends the wait.
        let t = Instant::now();
        bell.wait(bell.seen(), 20_000_000);
        assert!(t.elapsed() >= Duration::from_millis(15));
    }
}
