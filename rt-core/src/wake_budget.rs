//! A wake-up budget for the receiver thread.

use core::time::Duration;

/// Caps the event-mode receiver's wake-ups. It runs at SCHED_FIFO, so a
/// client notifying in a tight loop would otherwise keep it busy on the
/// motor's CPU and starve that CPU's normal threads. Real clients notify a
/// few times per millisecond at most (a 1 kHz camera and planner).
pub(crate) struct WakeBudget {
    window_start: std::time::Instant,
    wakes: u32,
}

impl WakeBudget {
    /// Wake-ups allowed per window before the thread sleeps out the rest.
    const PER_WINDOW: u32 = 32;
    const WINDOW: Duration = Duration::from_millis(1);

    pub(crate) fn new() -> Self {
        Self { window_start: std::time::Instant::now(), wakes: 0 }
    }

    /// Count one wake-up; over budget, sleep until the window ends.
    pub(crate) fn pace(&mut self) {
        let elapsed = self.window_start.elapsed();
        if elapsed >= Self::WINDOW {
            *self = Self::new();
        }
        self.wakes += 1;
        if self.wakes > Self::PER_WINDOW {
            std::thread::sleep(Self::WINDOW.saturating_sub(elapsed));
            *self = Self::new();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_burst_over_budget_sleeps_out_the_window() {
        let start = std::time::Instant::now();
        let mut budget = WakeBudget::new();
        for _ in 0..=WakeBudget::PER_WINDOW {
            budget.pace();
        }
        // Either the burst slept out its window or the window ran out on its
        // own: at least one window has passed. Without the cap, 33 calls take
        // microseconds.
        assert!(start.elapsed() >= WakeBudget::WINDOW);
    }
}
