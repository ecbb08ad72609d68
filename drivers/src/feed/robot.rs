//! The robot: a part is taken when it lies at a pick pose of its class
//! within tolerance, has lain there for the settle time, and no other part
//! reaches into the gripper's clearance. One pick takes `pick_s`. The
//! feeders' way ([`RobotMode::AnyInZone`]) takes instead any part lying
//! still and isolated in the pick zone, at whatever pose.

use super::cell::FeedCell;
use super::counts::PickRecord;
use super::robot_mode::{RobotMode, ZONE_MARGIN_M};
use crate::sim::Simulator;
use upm_recipe::angle_error;

/// Slower than this a part lies still, for [`RobotMode::AnyInZone`].
const STILL_M_S: f64 = 5e-3;

impl FeedCell {
    /// Note since when each part has been ready: within tolerance of a
    /// pose ([`RobotMode::AtPose`]), or still in the zone.
    pub(super) fn track_settling(&mut self, sim: &Simulator, t: f64) {
        match self.mode {
            RobotMode::AtPose | RobotMode::External => self.track_at_pose(sim, t),
            RobotMode::AnyInZone => self.track_in_zone(sim, t),
        }
    }

    fn track_in_zone(&mut self, sim: &Simulator, t: f64) {
        let picks = &self.recipe.picks;
        let ([x0, y0], [x1, y1]) = self.pick_box;
        let m = ZONE_MARGIN_M;
        for i in 0..self.slot_id.len() {
            if self.slot_id[i] == 0 {
                continue;
            }
            let Some(p) = sim.part(i) else { continue };
            let [x, y] = p.position;
            let inside = x >= x0 - m && x <= x1 + m && y >= y0 - m && y <= y1 + m;
            let still = p.velocity[0].hypot(p.velocity[1]) < STILL_M_S;
            if !(inside && still) {
                self.within_since[i] = f64::NAN;
                continue;
            }
            // The record's pose: the nearest of the part's class.
            let class = self.recipe.classes[self.slot_class[i]].id;
            let d = |j: usize| (picks[j].position[0] - x).hypot(picks[j].position[1] - y);
            let nearest =
                (0..picks.len()).filter(|&j| picks[j].class == class).min_by(|&a, &b| d(a).total_cmp(&d(b)));
            self.within_pose[i] = nearest.unwrap_or(0);
            if self.within_since[i].is_nan() {
                self.within_since[i] = t;
            }
        }
    }

    /// Note since when each part has lain within tolerance of a pose.
    fn track_at_pose(&mut self, sim: &Simulator, t: f64) {
        let robot = self.recipe.robot;
        for i in 0..self.slot_id.len() {
            if self.slot_id[i] == 0 {
                continue;
            }
            let Some(p) = sim.part(i) else { continue };
            let class = self.recipe.classes[self.slot_class[i]].id;
            let order = self.order[self.slot_class[i]];
            let at = self.recipe.picks.iter().position(|pose| {
                pose.class == class
                    && (p.position[0] - pose.position[0]).hypot(p.position[1] - pose.position[1])
                        <= robot.tolerance
                    && angle_error(p.angle, pose.theta, order).abs() <= robot.tolerance_angle
            });
            match at {
                Some(j) if j == self.within_pose[i] && !self.within_since[i].is_nan() => {}
                Some(j) => (self.within_pose[i], self.within_since[i]) = (j, t),
                None => self.within_since[i] = f64::NAN,
            }
        }
    }

    /// Take one settled part with a clear gripper, poses in turn (or, for
    /// an external robot, each part it posted, if ready where it says).
    pub(super) fn robot_step(&mut self, sim: &mut Simulator, t: f64) {
        if self.mode == RobotMode::External {
            return self.external_picks(sim, t);
        }
        let robot = self.recipe.robot;
        if t < self.busy_until {
            return;
        }
        let poses = self.recipe.picks.len();
        for step in 0..poses {
            let j = (self.next_pose + step) % poses;
            let ready = (0..self.slot_id.len()).find(|&i| {
                (self.within_pose[i] == j || self.mode == RobotMode::AnyInZone) && self.is_ready(sim, i, t)
            });
            let Some(i) = ready else { continue };
            // The feeders' robot takes a part where it lies: its record is
            // against the nearest pose of its class.
            let j = if self.mode == RobotMode::AnyInZone { self.within_pose[i] } else { j };
            if !self.pick(sim, i, j, t) {
                continue;
            }
            self.busy_until = t + robot.pick_s;
            self.busy_s += robot.pick_s;
            self.next_pose = j + 1;
            return;
        }
    }

    /// The picks an external robot posted. The robot is the authority: it
    /// acted on a status some milliseconds old, so the part it names is
    /// taken if it is still on the plate and last lay at that pose (the
    /// pick's record has its errors as they are now); else the post is
    /// refused (counted in the mailbox).
    fn external_picks(&mut self, sim: &mut Simulator, t: f64) {
        let Some(mailbox) = self.mailbox.0.take() else { return };
        for j in 0..self.recipe.picks.len() {
            let id = mailbox.take(j);
            if id == 0 {
                continue;
            }
            let at = (0..self.slot_id.len()).find(|&i| self.slot_id[i] == id && self.within_pose[i] == j);
            let done = at.is_some_and(|i| self.pick(sim, i, j, t));
            mailbox.outcome(done);
        }
        self.mailbox.0 = Some(mailbox);
    }

    /// Part `i` leaves the plate, picked at pose `j`: logged and counted.
    fn pick(&mut self, sim: &mut Simulator, i: usize, j: usize, t: f64) -> bool {
        let (Some(p), pose) = (sim.part(i), self.recipe.picks[j]) else { return false };
        let order = self.order[self.slot_class[i]];
        self.log_pick(PickRecord {
            t,
            part_id: self.slot_id[i],
            class: pose.class,
            pose: j as u32,
            position_error: (p.position[0] - pose.position[0]).hypot(p.position[1] - pose.position[1]),
            angle_error: angle_error(p.angle, pose.theta, order),
            on_plate_s: t - self.arrived_t[i],
        });
        self.take_off(sim, i);
        self.counts.picked += 1;
        true
    }

    /// Whether part `i` is on the plate, has lain ready for the settle
    /// time, and has a clear gripper.
    pub(super) fn is_ready(&self, sim: &Simulator, i: usize, t: f64) -> bool {
        self.slot_id[i] != 0
            && t - self.within_since[i] >= self.recipe.robot.settle_s - 1e-9
            && !self.crowded(sim, i)
    }

    /// Whether another part reaches into part `i`'s gripper clearance.
    fn crowded(&self, sim: &Simulator, i: usize) -> bool {
        let Some(p) = sim.part(i) else { return true };
        let reach = self.reach[self.slot_class[i]] + self.recipe.robot.clearance;
        (0..self.slot_id.len()).filter(|&k| k != i && self.slot_id[k] != 0).any(|k| {
            sim.part(k).is_none_or(|q| {
                let d = (q.position[0] - p.position[0]).hypot(q.position[1] - p.position[1]);
                !(d >= reach + self.reach[self.slot_class[k]])
            })
        })
    }
}
