//! The cell's state interface: every so many steps it writes its counters,
//! each pick pose's state and its latest picks as a `FeedStatus` into a
//! wait-free triple buffer whose reader the caller holds (the core's io
//! thread publishes it on `upm/feed`). Written where the cell steps, so it
//! never allocates.

use ipc_types::{FeedStatus, PickEvent, PickPoseState, monotonic_now_ns};

use super::cell::FeedCell;
use super::pick_mailbox::PickMailbox;
use super::robot_mode::RobotMode;
use super::status_port::StatusPort;
use crate::sim::Simulator;

/// A part on the plate longer than this is stuck (s).
pub const STUCK_AFTER_S: f64 = 120.0;

impl FeedCell {
    /// From now on, every `every_ms` of the cell's clock (at least 1),
    /// write the cell's status into a triple buffer; returns its reader, or
    /// None if `sim` has no feed cell. Start-up only (it allocates).
    pub fn publish_status(sim: &mut Simulator, every_ms: u64) -> Option<triple_buffer::Output<FeedStatus>> {
        let cell = sim.cell_mut()?.as_any_mut().downcast_mut::<Self>()?;
        let (out, reader) = triple_buffer::triple_buffer(&FeedStatus::new());
        cell.status.0 = Some(StatusPort { every: every_ms.max(1), steps: 0, out });
        Some(reader)
    }

    /// The mailbox an external robot's picks go to; None if `sim` has no
    /// feed cell or its robot is not [`RobotMode::External`]. Start-up only.
    pub fn accept_picks(sim: &mut Simulator) -> Option<std::sync::Arc<PickMailbox>> {
        let cell = sim.cell_mut()?.as_any_mut().downcast_mut::<Self>()?;
        if cell.mode != RobotMode::External {
            return None;
        }
        let mailbox = std::sync::Arc::new(PickMailbox::default());
        cell.mailbox.0 = Some(mailbox.clone());
        Some(mailbox)
    }

    /// The cell's status now into `out` (its `recent` picks are left as they
    /// are). Allocation-free.
    pub fn write_status(&self, sim: &Simulator, out: &mut FeedStatus) {
        let t = sim.time();
        let c = self.counts;
        [out.arrived, out.picked, out.lost, out.arrivals_blocked] =
            [c.arrived, c.picked, c.lost, c.arrivals_blocked];
        out.on_plate = c.on_plate;
        out.stuck = self.on_plate_longer_than(t, STUCK_AFTER_S);
        out.stuck_after_s = STUCK_AFTER_S;
        out.collisions = u32::try_from(sim.counters().collisions).unwrap_or(u32::MAX);
        out.time_s = t;
        // An external robot's cycle is its own: the cell does not see it.
        out.robot_busy_s = (self.busy_s - (self.busy_until - t).max(0.0)).max(0.0);
        out.clear();
        for (j, pose) in self.recipe.picks.iter().enumerate() {
            let at = self.part_at_pose(j);
            let ready = at.is_some_and(|i| self.is_ready(sim, i, t));
            let state = PickPoseState {
                class: pose.class,
                part_id: at.map_or(0, |i| self.slot_id[i]),
                ready: u32::from(ready),
                reserved: 0,
                x: pose.position[0],
                y: pose.position[1],
                theta: pose.theta,
            };
            // More poses than the wire holds are not described.
            let _ = out.push(state);
        }
    }

    /// The part lying within tolerance of pose `j`, if any.
    fn part_at_pose(&self, j: usize) -> Option<usize> {
        if self.mode == RobotMode::AnyInZone {
            return None;
        }
        (0..self.slot_id.len())
            .find(|&i| self.slot_id[i] != 0 && self.within_pose[i] == j && !self.within_since[i].is_nan())
    }

    /// After a step: write the status if it is due.
    pub(super) fn publish_status_if_due(&mut self, sim: &Simulator) {
        let Some(mut port) = self.status.0.take() else { return };
        port.steps += 1;
        if port.steps.is_multiple_of(port.every) {
            let msg = port.out.input_buffer_mut();
            self.write_status(sim, msg);
            msg.recent_count = 0;
            let newest = self.counts.picked;
            let n = newest.min(ipc_types::FEED_RECENT_PICKS as u64).min(self.picks_kept() as u64);
            for number in newest + 1 - n..=newest {
                if let Some(p) = self.pick_numbered(number) {
                    msg.push_pick(p);
                }
            }
            msg.seq = port.steps / port.every;
            msg.stamp_ns = monotonic_now_ns();
            port.out.publish();
        }
        self.status.0 = Some(port);
    }
}

impl FeedCell {
    /// Pick `number` (1: the first) as the wire carries it, if still kept.
    pub fn pick_numbered(&self, number: u64) -> Option<PickEvent> {
        let kept = self.picks_kept() as u64;
        let newest = self.counts.picked;
        if number == 0 || number > newest || newest - number >= kept {
            return None;
        }
        let r = self.pick_record((kept - 1 - (newest - number)) as usize)?;
        Some(PickEvent {
            number,
            part_id: r.part_id,
            class: r.class,
            pose: r.pose,
            reserved: 0,
            time_s: r.t,
            position_error_m: r.position_error,
            angle_error_rad: r.angle_error,
            on_plate_s: r.on_plate_s,
        })
    }
}
