//! The plate's path through one cycle as a [`PlateFollow`] model has it:
//! exactly its command, or its drives' servo on the tick setpoints.

use super::plate_follow::PlateFollow;
use super::{PlateMotion, Pose, Twist};

/// The plate through one cycle of `motion`, `substeps` pieces per tick:
/// each call to [`PlatePath::next`] gives pose and twist at the middle of
/// the next piece. No allocation.
pub(crate) struct PlatePath<'a> {
    motion: &'a PlateMotion,
    follow: PlateFollow,
    substeps: u64,
    piece: u64,
    /// Piece length (s) and the tick's setpoints at its start and end.
    h: f64,
    from: ([f64; 3], [f64; 3]),
    to: ([f64; 3], [f64; 3]),
    /// The servo plate's pose and velocity at the current piece's start.
    q: [f64; 3],
    qv: [f64; 3],
}

fn dof(motion: &PlateMotion, tick: u64) -> ([f64; 3], [f64; 3]) {
    let s = motion.sample_tick(tick);
    ([s.pose.x, s.pose.y, s.pose.theta], [s.velocity.x, s.velocity.y, s.velocity.theta])
}

impl<'a> PlatePath<'a> {
    pub(crate) fn new(motion: &'a PlateMotion, follow: PlateFollow, substeps: u64) -> Self {
        let tick_s = motion.cycle_duration() / motion.cycle_ticks().max(1) as f64;
        let h = tick_s / substeps.max(1) as f64;
        let from = dof(motion, 0);
        Self { motion, follow, substeps: substeps.max(1), piece: 0, h, from, to: from, q: from.0, qv: from.1 }
    }

    pub(crate) fn next(&mut self) -> (Pose, Twist) {
        let (tick, sub) = (self.piece / self.substeps, self.piece % self.substeps);
        self.piece += 1;
        let Some((w, zeta)) = (match self.follow {
            PlateFollow::Exact => None,
            PlateFollow::Servo { bandwidth_hz, damping } => {
                Some((core::f64::consts::TAU * bandwidth_hz, damping))
            }
        }) else {
            let s = self.motion.sample((self.piece as f64 - 0.5) * self.h);
            return (s.pose, s.velocity);
        };
        if sub == 0 {
            // `to` starts at tick 0's setpoint.
            self.from = self.to;
            self.to = dof(self.motion, tick + 1);
        }
        let tick_s = self.h * self.substeps as f64;
        let (kp, kd) = (w * w, 2.0 * zeta * w);
        let (from, to) = (self.from, self.to);
        let acc = |q: &[f64; 3], qv: &[f64; 3], f: f64| -> [f64; 3] {
            core::array::from_fn(|i| {
                let feed = (to.1[i] - from.1[i]) / tick_s;
                let r = from.0[i] + (to.0[i] - from.0[i]) * f;
                let rv = from.1[i] + (to.1[i] - from.1[i]) * f;
                feed + kp * (r - q[i]) + kd * (rv - qv[i])
            })
        };
        // Midpoint rule: the piece's middle is also where friction is read.
        let f0 = sub as f64 / self.substeps as f64;
        let a0 = acc(&self.q, &self.qv, f0);
        let qm: [f64; 3] = core::array::from_fn(|i| self.q[i] + 0.5 * self.h * self.qv[i]);
        let qvm: [f64; 3] = core::array::from_fn(|i| self.qv[i] + 0.5 * self.h * a0[i]);
        let am = acc(&qm, &qvm, f0 + 0.5 / self.substeps as f64);
        for i in 0..3 {
            self.q[i] += self.h * qvm[i];
            self.qv[i] += self.h * am[i];
        }
        (Pose { x: qm[0], y: qm[1], theta: qm[2] }, Twist { x: qvm[0], y: qvm[1], theta: qvm[2] })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{MotionParams, ScheduleEntry};

    /// Largest gap in x, y (m) between the servo plate and the command
    /// at the pieces' middles over one cycle.
    fn worst_gap(bandwidth_hz: f64) -> f64 {
        let mut m = PlateMotion::new(MotionParams::default()).expect("motion");
        let entries =
            [ScheduleEntry { center: [-1.0, 0.5], k: 0.6 }, ScheduleEntry { center: [1.0, -0.5], k: -0.4 }];
        m.set_schedule(&entries).expect("playable");
        let follow = PlateFollow::Servo { bandwidth_hz, damping: 0.7 };
        let (mut servo, mut exact) =
            (PlatePath::new(&m, follow, 32), PlatePath::new(&m, PlateFollow::Exact, 32));
        let mut worst = 0.0f64;
        for _ in 0..m.cycle_ticks() * 32 {
            let ((p, _), (q, _)) = (servo.next(), exact.next());
            worst = worst.max((p.x - q.x).abs()).max((p.y - q.y).abs());
        }
        worst
    }

    #[test]
    fn a_servo_plate_strays_by_microns() {
        // The motion's displacement is 2 mm; a 1 kHz drive strays by
        // microns. A stiffer one holds to its linear reference more
        // tightly, which is itself off the curved command: not less.
        let gap = worst_gap(1000.0);
        assert!(gap > 1e-7 && gap < 2e-5, "{gap}");
    }

    #[test]
    fn an_exact_plate_is_the_command() {
        let mut m = PlateMotion::new(MotionParams::default()).expect("motion");
        m.set_schedule(&[ScheduleEntry { center: [0.5, 0.2], k: 0.5 }]).expect("playable");
        let mut path = PlatePath::new(&m, PlateFollow::Exact, 4);
        let h = m.cycle_duration() / (4 * m.cycle_ticks()) as f64;
        for i in 0..4 * m.cycle_ticks() {
            let s = m.sample((i as f64 + 0.5) * h);
            assert_eq!(path.next(), (s.pose, s.velocity));
        }
    }
}
