//! The whole core in one thread on a hand-stepped clock (copper-rs style):
//! the same [`MotorLoop`] and [`SolveStage`] as the real process, fed from
//! an in-memory inbox. With the same parameters, driver and inputs, two runs
//! are bit-identical.

use std::sync::Arc;

use ipc_types::{Rejection, Schedule, Telemetry};

use super::clock::{Clock, ManualClock};
use super::inbox::{InboxBuffers, QueueInbox};
use super::latency::LatencyHistograms;
use super::motor::MotorLoop;
use super::params::{CoreParams, CoreParamsError};
use super::process::fill_telemetry;
use super::samples::{MotorSample, StageOutputsRx};
use super::shared::CoreShared;
use super::solve_stage::SolveStage;
use super::stage_graph::StageGraph;
use upm_hardware::PlateDriver;

#[derive(Debug)]
pub struct Lockstep<D: PlateDriver> {
    clock: ManualClock,
    start_ns: u64,
    period_ns: u64,
    poll_ns: u64,
    next_poll_ns: u64,
    motor: MotorLoop<D>,
    stage: SolveStage,
    inbox: QueueInbox,
    buf: InboxBuffers,
    shared: Arc<CoreShared>,
    motor_rx: rtrb::Consumer<MotorSample>,
    outputs: StageOutputsRx,
    histograms: LatencyHistograms,
    published: Vec<Schedule>,
    rejections: Vec<Rejection>,
}

impl<D: PlateDriver> Lockstep<D> {
    /// A core at manual time `start_ns` (> 0, so stamps are never 0).
    pub fn new(params: &CoreParams, driver: D, start_ns: u64) -> Result<Self, CoreParamsError> {
        let graph = StageGraph::build(params, driver)?;
        Ok(Self {
            clock: ManualClock::new(start_ns),
            start_ns,
            period_ns: params.tick_ns(),
            poll_ns: params.rt.solver_poll_ns,
            next_poll_ns: start_ns,
            motor: graph.motor,
            stage: graph.stage,
            inbox: QueueInbox::default(),
            buf: InboxBuffers::default(),
            shared: graph.shared,
            motor_rx: graph.motor_samples,
            outputs: graph.outputs,
            histograms: LatencyHistograms::default(),
            published: Vec::new(),
            rejections: Vec::new(),
        })
    }

    /// Messages pushed here are handled at the next solver poll.
    pub fn inbox(&mut self) -> &mut QueueInbox {
        &mut self.inbox
    }

    pub fn now_ns(&self) -> u64 {
        self.clock.now_ns()
    }

    pub fn motor(&self) -> &MotorLoop<D> {
        &self.motor
    }

    /// The motor, e.g. to reach its driver in a test.
    pub fn motor_mut(&mut self) -> &mut MotorLoop<D> {
        &mut self.motor
    }

    pub fn shared(&self) -> &CoreShared {
        &self.shared
    }

    pub fn stage(&self) -> &SolveStage {
        &self.stage
    }

    /// Schedules the io thread would have published, in order.
    pub fn published(&self) -> &[Schedule] {
        &self.published
    }

    /// Rejections the io thread would have published, in order.
    pub fn rejections(&self) -> &[Rejection] {
        &self.rejections
    }

    /// Move the clock to `now_ns` (never back) and hand the inbox to the
    /// solve stage there, without motor ticks: how a replay puts each
    /// recorded message at the instant the recorded core handled it.
    pub fn handle_at(&mut self, now_ns: u64) -> usize {
        self.clock.sleep_until(now_ns);
        let handled = self.stage.drain(&mut self.inbox, &mut self.buf, &self.clock);
        self.collect();
        handled
    }

    pub fn histograms(&self) -> &LatencyHistograms {
        &self.histograms
    }

    /// Run `ticks` motor ticks; `each` sees the motor after every tick.
    pub fn run_ticks(&mut self, ticks: u64, mut each: impl FnMut(&MotorLoop<D>)) {
        for _ in 0..ticks {
            let now = self.clock.now_ns();
            if now >= self.next_poll_ns {
                self.stage.drain(&mut self.inbox, &mut self.buf, &self.clock);
                self.next_poll_ns = now + self.poll_ns;
            }
            self.motor.tick(now);
            // No wall-clock time passes in lock-step: latencies are 0.
            self.motor.record(0, 0);
            each(&self.motor);
            self.clock.advance(self.period_ns);
            self.collect();
        }
    }

    fn collect(&mut self) {
        while let Ok(s) = self.motor_rx.pop() {
            self.histograms.record_motor(&s);
        }
        while let Ok(s) = self.outputs.samples.pop() {
            self.histograms.record_solver(&s);
        }
        while let Ok(s) = self.outputs.schedules.pop() {
            self.published.push(s);
        }
        while let Ok(r) = self.outputs.rejections.pop() {
            self.rejections.push(r);
        }
    }

    /// Telemetry as the io thread would publish it now.
    pub fn telemetry(&self) -> Telemetry {
        let mut t = Telemetry::new();
        fill_telemetry(&mut t, &self.shared, &self.histograms, self.clock.now_ns(), self.start_ns);
        t
    }
}
