//! The robot: a part is taken when it lies at a pick pose of its class
//! within tolerance, has lain there for the settle time, and no other part
//! reaches into the gripper's clearance. One pick takes `pick_s`.

use super::cell::FeedCell;
use super::counts::PickRecord;
use crate::sim::Simulator;
use upm_recipe::angle_error;

impl FeedCell {
    /// Note since when each part has lain within tolerance of a pose.
    pub(super) fn track_settling(&mut self, sim: &Simulator, t: f64) {
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

    /// Take one settled part with a clear gripper, poses in turn.
    pub(super) fn robot_step(&mut self, sim: &mut Simulator, t: f64) {
        let robot = self.recipe.robot;
        if t < self.busy_until {
            return;
        }
        let poses = self.recipe.picks.len();
        for step in 0..poses {
            let j = (self.next_pose + step) % poses;
            let ready = (0..self.slot_id.len()).find(|&i| {
                self.slot_id[i] != 0
                    && self.within_pose[i] == j
                    && t - self.within_since[i] >= robot.settle_s - 1e-9
                    && !self.crowded(sim, i)
            });
            let Some(i) = ready else { continue };
            let (Some(p), pose) = (sim.part(i), self.recipe.picks[j]) else { continue };
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
            self.busy_until = t + robot.pick_s;
            self.next_pose = j + 1;
            return;
        }
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
