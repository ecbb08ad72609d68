//! Arrivals: a Poisson stream at the recipe's rate, each landing at rest
//! at a random spot of the infeed region where it touches no part.

use core::f64::consts::TAU;

use super::cell::FeedCell;
use crate::rng::SplitMix64;
use crate::sim::Simulator;

/// Spots tried per arrival before it waits for the next millisecond.
const TRIES: usize = 16;
/// Least gap between an arriving part and any other (m).
const ARRIVAL_GAP_M: f64 = 2e-3;

/// Seconds to the next arrival at `rate_per_min`.
fn interval(rng: &mut SplitMix64, rate_per_min: f64) -> f64 {
    -(1.0 - rng.uniform()).ln() * 60.0 / rate_per_min
}

impl FeedCell {
    /// The first arrival, at build.
    pub(super) fn schedule_first_arrival(&mut self) {
        self.next_arrival = interval(&mut self.rng, self.recipe.infeed.rate_per_min);
    }

    /// Land the next part if it is due and there is room; one a step.
    pub(super) fn infeed_step(&mut self, sim: &mut Simulator, t: f64) {
        let infeed = self.recipe.infeed;
        if t < self.next_arrival || self.counts.on_plate >= infeed.max_on_plate {
            return;
        }
        let total = self.cumulative_share.last().copied().unwrap_or(0.0);
        let u = self.rng.uniform() * total;
        let class = self.cumulative_share.iter().position(|&c| u < c).unwrap_or(0);
        let Some(slot) =
            (0..self.slot_id.len()).find(|&i| self.slot_class[i] == class && self.slot_id[i] == 0)
        else {
            return;
        };
        let r = self.reach[class];
        let [x0, y0, x1, y1] = infeed.region;
        for _ in 0..TRIES {
            let x = x0 + r + self.rng.uniform() * (x1 - x0 - 2.0 * r);
            let y = y0 + r + self.rng.uniform() * (y1 - y0 - 2.0 * r);
            let angle = self.rng.uniform() * TAU;
            if self.touches_any(sim, [x, y], r + ARRIVAL_GAP_M) {
                continue;
            }
            if sim.place(slot, [x, y], angle) {
                self.slot_id[slot] = self.next_id;
                self.next_id = self.next_id.wrapping_add(1).max(1);
                self.arrived_t[slot] = t;
                self.counts.arrived += 1;
                self.counts.on_plate += 1;
                self.next_arrival += interval(&mut self.rng, infeed.rate_per_min);
                return;
            }
        }
        self.counts.arrivals_blocked += 1;
    }

    /// Whether a part on the plate comes within `reach` (plus its own) of `at`.
    pub(super) fn touches_any(&self, sim: &Simulator, at: [f64; 2], reach: f64) -> bool {
        (0..self.slot_id.len()).filter(|&i| self.slot_id[i] != 0).any(|i| {
            sim.part(i).is_none_or(|p| {
                let d = (p.position[0] - at[0]).hypot(p.position[1] - at[1]);
                !(d >= reach + self.reach[self.slot_class[i]])
            })
        })
    }
}
