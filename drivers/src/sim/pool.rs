//! Parts the simulator holds off the plate: a feed cell's parts before
//! they arrive and after the robot took them. A parked part's lane is not
//! live (no friction, no fence), it rests far outside the plate on a spot
//! of its own (no contact), and the ground truth leaves it out. Parking
//! and placing allocate nothing.

use super::Simulator;
use super::part::PartState;

/// Parking spots lie on a row this far beyond the plate's +x edge, this
/// far apart: wider than any part the simulator holds.
const PARK_BEYOND_M: f64 = 10.0;
const PARK_SPACING_M: f64 = 1.0;

impl Simulator {
    /// Take part `i` off the plate. Returns false if `i` is out of range.
    pub fn park(&mut self, i: usize) -> bool {
        let Some(&l) = self.lanes.lane.get(i) else { return false };
        let x = self.cfg.plate_half_extent[0] + PARK_BEYOND_M + i as f64 * PARK_SPACING_M;
        let rest = PartState { position: [x, 0.0], stuck: true, ..PartState::default() };
        self.lanes.store(l, &rest);
        let (g, k) = (&mut self.lanes.groups[l / super::W], l % super::W);
        g.live[k] = false;
        g.lim_x[k] = f64::INFINITY;
        g.lim_y[k] = f64::INFINITY;
        self.parked[i] = true;
        self.broadphase.valid = false;
        true
    }

    /// Put parked part `i` on the plate at rest at `position`, turned by
    /// `angle`. Returns false if `i` is out of range, not parked, or the
    /// pose is not finite.
    pub fn place(&mut self, i: usize, position: [f64; 2], angle: f64) -> bool {
        let finite = position.iter().all(|v| v.is_finite()) && angle.is_finite();
        if !(finite && self.parked.get(i).copied().unwrap_or(false)) {
            return false;
        }
        let l = self.lanes.lane[i];
        let lim = super::contact::fence_limits(&self.bodies[i], self.cfg.plate_half_extent);
        let (g, k) = (&mut self.lanes.groups[l / super::W], l % super::W);
        g.live[k] = true;
        [g.lim_x[k], g.lim_y[k]] = lim;
        self.lanes.store(l, &PartState { position, angle, stuck: true, ..PartState::default() });
        self.parked[i] = false;
        self.broadphase.valid = false;
        self.update_friction();
        true
    }

    /// Whether part `i` is off the plate (out of range: true).
    pub fn is_parked(&self, i: usize) -> bool {
        self.parked.get(i).copied().unwrap_or(true)
    }

    /// How far part `i`'s outline reaches from its position (m).
    pub fn part_reach(&self, i: usize) -> Option<f64> {
        self.bodies.get(i).map(|b| b.radius)
    }
}

#[cfg(test)]
mod tests {
    use crate::sim::{BodyShape, PartSpec, SimConfig, Simulator};

    fn two_discs() -> Simulator {
        let disc = |x| PartSpec {
            shape: BodyShape::Disc { radius: 0.02 },
            mass: 0.04,
            position: [x, 0.0],
            angle: 0.0,
        };
        Simulator::new(SimConfig::default(), &[disc(-0.3), disc(0.3)]).expect("sim")
    }

    #[test]
    fn a_parked_part_stays_put_off_the_plate_and_a_placed_one_moves_again() {
        let mut sim = two_discs();
        assert!(sim.park(0) && sim.is_parked(0) && !sim.is_parked(1));
        let parked = sim.part(0).expect("part 0");
        for _ in 0..100 {
            sim.step();
        }
        assert_eq!(sim.part(0), Some(parked), "a parked part never moves");
        assert!(parked.position[0] > 10.0, "off the plate");
        assert!(sim.place(0, [0.1, 0.2], 0.5) && !sim.is_parked(0));
        assert_eq!(sim.part(0).map(|p| (p.position, p.angle)), Some(([0.1, 0.2], 0.5)));
        assert!(!sim.place(0, [0.0, 0.0], 0.0), "only a parked part is placed");
        assert!(!sim.place(7, [0.0, 0.0], 0.0) && !sim.park(7), "out of range");
        assert!(sim.park(1) && !sim.place(1, [f64::NAN, 0.0], 0.0), "not finite");
    }
}
