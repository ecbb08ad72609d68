//! The motor loop, ros2_control style: every tick is read → update → write
//! through a [`PlateDriver`]. It sees only the driver and the motion
//! hand-over; it never allocates, locks, logs or calls into iceoryx2.

use core::sync::atomic::Ordering::Relaxed;
use std::sync::Arc;

use ipc_types::CoreState;

use super::clock::Clock;
use super::handoff::MotionReader;
use super::samples::MotorSample;
use super::shared::CoreShared;
use crate::driver::{ActuatorCommand, PlateDriver, PlateState};
use crate::motion::{PlateSample, Pose, Rig};

/// What the loop did in one tick.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TickOutcome {
    /// Keep ticking.
    Continue,
    /// Stop was requested and the plate is home: the loop is done.
    Stopped,
}

/// Copies what a driver knows beyond the plate (a simulator's parts) into
/// a message. Called on the motor thread: it must not allocate or block.
pub type TruthFill<D> = Box<dyn FnMut(&D, &mut ipc_types::PartStates) + Send>;

/// Every `every` ticks, `fill` writes the driver's ground truth into the
/// back buffer of a triple buffer the io thread publishes from.
pub struct TruthTap<D> {
    pub every: u64,
    pub fill: TruthFill<D>,
    pub out: triple_buffer::Input<ipc_types::PartStates>,
}

impl<D> core::fmt::Debug for TruthTap<D> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("TruthTap").field("every", &self.every).finish_non_exhaustive()
    }
}

/// The motor thread's state. Built (allocating) at start-up; `tick` is the
/// only call on the critical path.
#[derive(Debug)]
pub struct MotorLoop<D: PlateDriver> {
    driver: D,
    rig: Rig,
    reader: MotionReader,
    shared: Arc<CoreShared>,
    samples: rtrb::Producer<MotorSample>,
    parts_max_age_ns: u64,
    request_max_age_ns: u64,
    tick_s: f64,
    /// Tick within the current cycle; 0 at a boundary (plate home).
    phase: u64,
    mode: CoreState,
    setpoint: PlateSample,
    cmd: ActuatorCommand,
    state: PlateState,
    frame_to_active_ns: u64,
    dropped_samples: u64,
    truth: Option<TruthTap<D>>,
    ticks: u64,
}

impl<D: PlateDriver> MotorLoop<D> {
    pub fn new(
        driver: D,
        rig: Rig,
        reader: MotionReader,
        shared: Arc<CoreShared>,
        samples: rtrb::Producer<MotorSample>,
        parts_max_age_ns: u64,
        request_max_age_ns: u64,
    ) -> Self {
        let tick_s = driver.tick_period();
        shared.set_state(CoreState::Idle);
        Self {
            driver,
            rig,
            reader,
            shared,
            samples,
            parts_max_age_ns,
            request_max_age_ns,
            tick_s,
            phase: 0,
            mode: CoreState::Idle,
            setpoint: PlateSample::default(),
            cmd: ActuatorCommand::HOME,
            state: PlateState::default(),
            frame_to_active_ns: 0,
            dropped_samples: 0,
            truth: None,
            ticks: 0,
        }
    }

    /// Publish the driver's ground truth through `tap` (start-up only).
    pub fn set_truth_tap(&mut self, tap: TruthTap<D>) {
        self.truth = Some(tap);
    }

    pub fn driver(&self) -> &D {
        &self.driver
    }

    pub fn driver_mut(&mut self) -> &mut D {
        &mut self.driver
    }

    pub fn mode(&self) -> CoreState {
        self.mode
    }

    /// Last driver reading.
    pub fn plate_state(&self) -> &PlateState {
        &self.state
    }

    /// Samples lost because the io thread fell a full ring behind.
    pub fn dropped_samples(&self) -> u64 {
        self.dropped_samples
    }

    /// One tick at time `now_ns`.
    pub fn tick(&mut self, now_ns: u64) -> TickOutcome {
        // read
        if self.driver.read(&mut self.state).is_err() {
            self.shared.driver_faults.fetch_add(1, Relaxed);
        }
        self.shared.driver_clamped.store(self.state.clamped + self.state.rejected, Relaxed);
        // update: decisions only at a cycle boundary, where the plate is home
        if self.phase == 0 && self.at_boundary(now_ns) == TickOutcome::Stopped {
            self.driver.hold();
            self.driver.advance();
            self.shared.ticks.fetch_add(1, Relaxed);
            return TickOutcome::Stopped;
        }
        // write
        if self.mode == CoreState::Running {
            let motion = &self.reader.current().motion;
            let mut next = motion.sample_tick(self.phase + 1);
            // Feed-forward acceleration is the tick average, which is what a
            // zero-order-held force produces.
            let h = self.tick_s;
            next.acceleration.x = (next.velocity.x - self.setpoint.velocity.x) / h;
            next.acceleration.y = (next.velocity.y - self.setpoint.velocity.y) / h;
            next.acceleration.theta = (next.velocity.theta - self.setpoint.velocity.theta) / h;
            self.rig.command(&next, &mut self.cmd);
            if self.driver.write(&self.cmd).is_err() {
                self.shared.driver_faults.fetch_add(1, Relaxed);
            }
            self.setpoint = next;
            self.phase = (self.phase + 1) % motion.cycle_ticks().max(1);
            self.shared.set_pose(&next.pose);
        } else {
            self.driver.hold();
        }
        self.driver.advance();
        self.shared.ticks.fetch_add(1, Relaxed);
        self.ticks += 1;
        if let Some(tap) = &mut self.truth
            && self.ticks.is_multiple_of(tap.every.max(1))
        {
            let msg = tap.out.input_buffer_mut();
            msg.seq = self.ticks;
            msg.stamp_ns = now_ns;
            (tap.fill)(&self.driver, msg);
            tap.out.publish();
        }
        TickOutcome::Continue
    }

    fn at_boundary(&mut self, now_ns: u64) -> TickOutcome {
        let sh = &*self.shared;
        if sh.stop.load(Relaxed) {
            sh.set_pose(&Pose::HOME);
            sh.motor_done.store(true, Relaxed);
            return TickOutcome::Stopped;
        }
        if self.reader.take_newest() {
            sh.schedule_swaps.fetch_add(1, Relaxed);
            let frame = self.reader.current().frame_stamp_ns;
            self.frame_to_active_ns = if frame > 0 { now_ns.saturating_sub(frame).max(1) } else { 0 };
        }
        let playable = self.reader.current().motion.cycle_ticks() > 0;
        let next = if !playable {
            CoreState::Idle
        } else if sh.inputs_stale(now_ns, self.parts_max_age_ns, self.request_max_age_ns) {
            CoreState::Hold
        } else {
            CoreState::Running
        };
        if next == CoreState::Hold && self.mode != CoreState::Hold {
            sh.hold_events.fetch_add(1, Relaxed);
        }
        if next == CoreState::Running {
            sh.cycle.fetch_add(1, Relaxed);
        } else {
            sh.set_pose(&Pose::HOME);
        }
        self.mode = next;
        sh.set_state(next);
        self.setpoint = PlateSample::default();
        TickOutcome::Continue
    }

    /// Push this tick's latency sample (drops and counts it if the ring is
    /// full; never blocks).
    pub fn record(&mut self, wakeup_ns: u64, tick_ns: u64) {
        let s = MotorSample { wakeup_ns, tick_ns, frame_to_active_ns: self.frame_to_active_ns };
        self.frame_to_active_ns = 0;
        if self.samples.push(s).is_err() {
            self.dropped_samples += 1;
        }
    }

    /// The motor thread body: absolute deadlines every `period_ns` on
    /// `clock` until stopped. A tick ending past the next deadline skips to
    /// the next future one; skipped periods are counted as overruns. The
    /// motion advances one tick per tick played, so it stays closed (it
    /// only stretches in wall time when periods are skipped).
    pub fn run<C: Clock>(&mut self, clock: &C, period_ns: u64) {
        let mut deadline = clock.now_ns() + period_ns;
        loop {
            clock.sleep_until(deadline);
            let woke = clock.now_ns();
            let outcome = self.tick(woke);
            let done = clock.now_ns();
            self.record(woke.saturating_sub(deadline), done.saturating_sub(woke));
            if outcome == TickOutcome::Stopped {
                return;
            }
            deadline += period_ns;
            if done > deadline {
                // Missed deadlines are skipped, not caught up in a burst (as
                // cyclictest does): the next tick waits for the next future
                // deadline, the motion continues from the next tick, and
                // every skipped period counts as an overrun.
                let missed = (done - deadline) / period_ns + 1;
                deadline += missed * period_ns;
                self.shared.overruns.fetch_add(missed, Relaxed);
            }
        }
    }
}
