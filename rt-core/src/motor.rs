//! The motor loop, ros2_control style: every tick is read → update → write
//! through a [`PlateDriver`]. It sees only the driver and the motion
//! hand-over; it never allocates, locks, logs or calls into iceoryx2.

use core::sync::atomic::Ordering::Relaxed;
use std::sync::Arc;

use ipc_types::{CoreState, HealthCause};

use super::clock::Clock;
use super::handoff::MotionReader;
use super::params::CoreParams;
use super::samples::MotorSample;
use super::shared::CoreShared;
use upm_hardware::{ActuatorCommand, PlateDriver, PlateState, ReadError, WriteError};
use upm_motion::{InertiaEstimate, InertiaParams, PlateSample, Pose, Rig, next_command};

/// What the loop did in one tick.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TickOutcome {
    /// Keep ticking.
    Continue,
    /// Stop was requested and the plate is home: the loop is done.
    Stopped,
}

/// When the motor holds the plate, and how it feeds forward.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MotorPolicy {
    /// Part states older than this put the core in hold.
    pub parts_max_age_ns: u64,
    /// Requests older than this put the core in hold.
    pub request_max_age_ns: u64,
    /// Consecutive healthy driver reads that end a driver-fault hold by
    /// themselves; 0 = only an operator's resume ends it.
    pub auto_resume_ticks: u64,
    /// Scale the feed-forward to the plate the drives show
    /// ([`InertiaEstimate`]); None: the model's.
    pub inertia_adaptation: Option<InertiaParams>,
}

impl MotorPolicy {
    pub fn from_params(p: &CoreParams) -> Self {
        let auto_resume_ticks = if p.safety.auto_resume_ns == 0 {
            0
        } else {
            p.safety.auto_resume_ns.div_ceil(p.tick_ns()).max(1)
        };
        Self {
            parts_max_age_ns: p.safety.parts_max_age_ns,
            request_max_age_ns: p.safety.request_max_age_ns,
            auto_resume_ticks,
            inertia_adaptation: p.inertia_adaptation,
        }
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
    policy: MotorPolicy,
    tick_s: f64,
    /// Tick within the current cycle; 0 at a boundary (plate home).
    phase: u64,
    mode: CoreState,
    setpoint: PlateSample,
    cmd: ActuatorCommand,
    state: PlateState,
    frame_to_active_ns: u64,
    dropped_samples: u64,
    /// Holding because the driver reported a fault.
    fault_hold: bool,
    /// Healthy reads since the last driver fault.
    healthy_reads: u64,
    inertia: Option<InertiaEstimate>,
    /// The last tick wrote `cmd` while running: this tick's reading is its
    /// result.
    wrote: bool,
    #[cfg(feature = "fault-injection")]
    inject: super::fault_injection::FaultPlan,
}

impl<D: PlateDriver> MotorLoop<D> {
    pub fn new(
        driver: D,
        rig: Rig,
        reader: MotionReader,
        shared: Arc<CoreShared>,
        samples: rtrb::Producer<MotorSample>,
        policy: MotorPolicy,
    ) -> Self {
        let tick_s = driver.tick_period();
        shared.set_state(CoreState::Idle);
        Self {
            driver,
            rig,
            reader,
            shared,
            samples,
            policy,
            tick_s,
            phase: 0,
            mode: CoreState::Idle,
            setpoint: PlateSample::default(),
            cmd: ActuatorCommand::HOME,
            state: PlateState::default(),
            frame_to_active_ns: 0,
            dropped_samples: 0,
            fault_hold: false,
            healthy_reads: 0,
            inertia: policy.inertia_adaptation.map(InertiaEstimate::new),
            wrote: false,
            #[cfg(feature = "fault-injection")]
            inject: super::fault_injection::FaultPlan::from_env(),
        }
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
        let read = self.driver.read(&mut self.state);
        #[cfg(feature = "fault-injection")]
        let read = self.inject.driver_read(read, now_ns);
        self.shared.driver_clamped.store(self.state.clamped, Relaxed);
        self.shared.driver_rejected.store(self.state.rejected, Relaxed);
        self.shared.driver.store(&self.driver.health());
        self.observe_drives(read.is_ok());
        // update: a fault holds at once; otherwise decisions only at a cycle
        // boundary, where the plate is home
        if self.holds_for_fault(read) {
            return self.hold_tick();
        }
        if self.phase == 0 && self.at_boundary(now_ns) == TickOutcome::Stopped {
            self.driver.hold();
            self.driver.advance();
            self.shared.ticks.fetch_add(1, Relaxed);
            return TickOutcome::Stopped;
        }
        // write
        if self.mode == CoreState::Running {
            let motion = &self.reader.current().motion;
            let from = self.setpoint;
            next_command(&self.rig, motion, self.tick_s, self.phase, &mut self.setpoint, &mut self.cmd);
            if let Some(e) = &mut self.inertia {
                e.predict(&from, &self.setpoint, self.tick_s);
            }
            self.phase = (self.phase + 1) % motion.cycle_ticks().max(1);
            self.shared.set_pose(&self.setpoint.pose);
            match self.driver.write(&self.cmd) {
                Err(WriteError::Fault) => {
                    self.enter_fault_hold(HealthCause::DriverWriteFault);
                    self.driver.hold();
                }
                Err(WriteError::NonFinite { .. }) => {}
                Ok(()) => self.wrote = true,
            }
        } else {
            self.driver.hold();
        }
        self.driver.advance();
        self.finish_tick();
        TickOutcome::Continue
    }

    /// The reading is the result of the command last written, if one was:
    /// the drives' effort goes to the inertia estimate.
    fn observe_drives(&mut self, read_ok: bool) {
        if let Some(e) = self.inertia.as_mut().filter(|_| self.wrote && read_ok) {
            e.observe(&self.rig, &self.setpoint.pose, &self.cmd.force, &self.state);
        }
        self.wrote = false;
    }

    fn finish_tick(&mut self) {
        self.shared.ticks.fetch_add(1, Relaxed);
    }

    /// True while the plate must be held whatever the schedule says: a core
    /// thread died (permanent), or the driver reported a fault (until an
    /// operator's resume or `auto_resume_ticks` healthy reads).
    fn holds_for_fault(&mut self, read: Result<(), ReadError>) -> bool {
        let sh = &*self.shared;
        if sh.thread_died() {
            if self.mode != CoreState::Fault {
                self.stop_motion(CoreState::Fault);
            }
            return true;
        }
        if read == Err(ReadError::Fault) {
            self.enter_fault_hold(HealthCause::DriverReadFault);
            return true;
        }
        // A resume only ends a hold that exists when it arrives.
        let resume = sh.resume_requested.swap(false, Relaxed);
        if !self.fault_hold {
            return false;
        }
        self.healthy_reads += 1;
        let auto = self.policy.auto_resume_ticks;
        if !(resume || (auto > 0 && self.healthy_reads >= auto)) {
            return true;
        }
        self.fault_hold = false;
        sh.resumes.fetch_add(1, Relaxed);
        sh.set_driver_fault(None);
        // The next tick is a cycle boundary again and decides as usual.
        false
    }

    fn enter_fault_hold(&mut self, cause: HealthCause) {
        let sh = &*self.shared;
        sh.driver_faults.fetch_add(1, Relaxed);
        self.healthy_reads = 0;
        if !self.fault_hold {
            self.fault_hold = true;
            sh.fault_holds.fetch_add(1, Relaxed);
            sh.set_driver_fault(Some(cause));
            self.stop_motion(CoreState::Hold);
        }
    }

    /// Abandon the cycle being played: the plate is commanded home and the
    /// next motion starts at slot 0.
    fn stop_motion(&mut self, mode: CoreState) {
        if self.mode == CoreState::Running {
            self.shared.hold_events.fetch_add(1, Relaxed);
        }
        self.mode = mode;
        self.phase = 0;
        self.setpoint = PlateSample::default();
        if let Some(e) = &mut self.inertia {
            e.discard_cycle();
        }
        self.shared.set_state(mode);
        self.shared.set_pose(&Pose::HOME);
    }

    /// A tick that only holds the plate; a stop request ends the loop.
    fn hold_tick(&mut self) -> TickOutcome {
        self.driver.hold();
        self.driver.advance();
        if self.shared.stop.load(Relaxed) {
            self.shared.ticks.fetch_add(1, Relaxed);
            self.shared.motor_done.store(true, Relaxed);
            return TickOutcome::Stopped;
        }
        self.finish_tick();
        TickOutcome::Continue
    }

    fn at_boundary(&mut self, now_ns: u64) -> TickOutcome {
        let sh = &*self.shared;
        if sh.stop.load(Relaxed) {
            sh.set_pose(&Pose::HOME);
            sh.motor_done.store(true, Relaxed);
            return TickOutcome::Stopped;
        }
        // The cycle just played (none after a hold) updates the feed-forward.
        if let Some(e) = &mut self.inertia {
            let scale = e.end_cycle();
            self.rig.set_inertia_scale(scale);
            sh.set_inertia(scale, e.updates(), e.skipped());
        }
        if self.reader.take_newest() {
            sh.schedule_swaps.fetch_add(1, Relaxed);
            let frame = self.reader.current().frame_stamp_ns;
            self.frame_to_active_ns = if frame > 0 { now_ns.saturating_sub(frame).max(1) } else { 0 };
        }
        let playable = self.reader.current().motion.cycle_ticks() > 0;
        let next = if !playable || sh.operator_stop.load(Relaxed) {
            CoreState::Idle
        } else if sh.inputs_stale(now_ns, self.policy.parts_max_age_ns, self.policy.request_max_age_ns) {
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
            #[cfg(feature = "fault-injection")]
            self.inject.panic_if_due(ipc_types::HealthSource::MotorThread, woke);
            let outcome = self.tick(woke);
            let done = clock.now_ns();
            self.record(woke.saturating_sub(deadline), done.saturating_sub(woke));
            if outcome == TickOutcome::Stopped {
                return;
            }
            // A bus with its own clock (EtherCAT SYNC0) moves the phase.
            deadline = (deadline + period_ns).saturating_add_signed(self.driver.clock_correction_ns());
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
