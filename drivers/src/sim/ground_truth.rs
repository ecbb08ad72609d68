//! The simulator's own state interface, as ros2_control's mock hardware
//! exposes state interfaces: every `every` ticks it writes its parts' true
//! poses and velocities as `PartStates` into a wait-free triple buffer
//! whose reader the caller holds (the core's io thread publishes it for
//! the simulated camera). It is written where the simulator steps — on the
//! motor thread, or on a simulated fieldbus chain's — so the motor loop
//! carries no simulator hook.

use core::fmt;

use ipc_types::{PartState as WirePart, PartStates, monotonic_now_ns};

use super::Simulator;

/// Where the simulator writes its ground truth, and how often.
pub(crate) struct GroundTruthPort {
    every: u64,
    /// Each part's id, class and outline on the wire, in part order.
    templates: Vec<WirePart>,
    out: triple_buffer::Input<PartStates>,
}

/// A simulator's port, if one was asked for. A clone of the simulator does
/// not publish: the reader belongs to the original.
#[derive(Default)]
pub(crate) struct GroundTruthSlot(Option<GroundTruthPort>);

impl Clone for GroundTruthSlot {
    fn clone(&self) -> Self {
        Self(None)
    }
}

impl fmt::Debug for GroundTruthSlot {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.0 {
            Some(p) => write!(f, "GroundTruthSlot(every {} ticks, {} parts)", p.every, p.templates.len()),
            None => f.write_str("GroundTruthSlot(none)"),
        }
    }
}

impl Simulator {
    /// The parts' truth in `out`: each part's `templates` entry (id, class,
    /// outline; or id i + 1 as a point) with its pose and velocity now.
    /// Allocation-free.
    pub fn write_ground_truth(&self, templates: &[WirePart], out: &mut PartStates) {
        out.clear();
        for i in (0..self.part_count()).filter(|&i| !self.is_parked(i)) {
            let Some(p) = self.part(i) else { continue };
            let fallback = WirePart::new(i as u32 + 1, 0, 0, [0.0; 3], [0.0; 3]);
            let mut s = templates.get(i).copied().unwrap_or(fallback);
            if let Some(cell) = self.cell() {
                s.id = cell.id_of(i);
            }
            [s.x, s.y, s.theta] = [p.position[0], p.position[1], p.angle];
            [s.vx, s.vy, s.omega] = [p.velocity[0], p.velocity[1], p.angular_velocity];
            // The wire holds as many parts as the simulator or more.
            let _ = out.push(s);
        }
    }

    /// From now on, every `every` ticks (at least 1), write the ground truth
    /// into a triple buffer and publish it; returns its reader. Start-up
    /// only (it allocates).
    pub fn publish_ground_truth(
        &mut self,
        every: u64,
        templates: Vec<WirePart>,
    ) -> triple_buffer::Output<PartStates> {
        let (out, reader) = triple_buffer::triple_buffer(&PartStates::new());
        self.ground_truth.0 = Some(GroundTruthPort { every: every.max(1), templates, out });
        reader
    }

    /// After a tick: publish the truth if it is due.
    pub(super) fn publish_ground_truth_if_due(&mut self) {
        let Some(mut port) = self.ground_truth.0.take() else { return };
        let tick = self.counters.ticks;
        if tick.is_multiple_of(port.every) {
            let msg = port.out.input_buffer_mut();
            self.write_ground_truth(&port.templates, msg);
            msg.seq = tick;
            msg.stamp_ns = monotonic_now_ns();
            port.out.publish();
        }
        self.ground_truth.0 = Some(port);
    }
}
