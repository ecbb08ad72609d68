//! Messages a subscriber never saw, from gaps in one publisher's `seq`
//! (keep one per publisher: two publishers' numbers interleave).
//! iceoryx2 overwrites the oldest sample of a subscriber that falls behind
//! (safe overflow), so the publisher never waits; the gap is how the
//! subscriber learns what it lost. A `seq` that goes back is a restarted
//! publisher, not a loss.

#[derive(Debug, Clone, Copy, Default)]
pub struct SeqGaps {
    last: Option<u64>,
    pub lost: u64,
}

impl SeqGaps {
    pub fn see(&mut self, seq: u64) {
        if let Some(last) = self.last
            && seq > last
        {
            self.lost += seq - last - 1;
        }
        self.last = Some(seq);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gaps_count_and_a_restart_does_not() {
        let mut g = SeqGaps::default();
        for s in [1, 2, 5, 6, 1, 2, 4] {
            g.see(s);
        }
        assert_eq!(g.lost, 2 + 1);
    }
}
