//! Driver faults in lock-step: the core holds in the very tick the driver
//! reports a fault, counts it, and stays in hold until a resume command or
//! `auto_resume` worth of healthy reads; the plate is commanded home while
//! it holds.

mod common;

use common::{PAPER_PARTS, part_states, request};
use drivers::{SimConfig, Simulator};
use ipc_types::{CoreCommand, CoreState, HealthCause, HealthSource};
use rt_core::CoreParams;
use rt_core::lockstep::Lockstep;
use upm_hardware::{ActuatorCommand, ActuatorLimits, PlateDriver, PlateState, ReadError, WriteError};

const START_NS: u64 = 1_000_000_000;

/// The simulator, with read (or write) faults switched on from outside.
#[derive(Debug)]
struct Faulty {
    sim: Simulator,
    read_fault: bool,
    write_fault: bool,
}

impl PlateDriver for Faulty {
    fn limits(&self) -> ActuatorLimits {
        self.sim.limits()
    }
    fn tick_period(&self) -> f64 {
        self.sim.tick_period()
    }
    fn read(&mut self, state: &mut PlateState) -> Result<(), ReadError> {
        let r = self.sim.read(state);
        if self.read_fault { Err(ReadError::Fault) } else { r }
    }
    fn write(&mut self, command: &ActuatorCommand) -> Result<(), WriteError> {
        let r = self.sim.write(command);
        if self.write_fault { Err(WriteError::Fault) } else { r }
    }
    fn hold(&mut self) {
        self.sim.hold();
    }
    fn advance(&mut self) {
        self.sim.advance();
    }
}

fn core(auto_resume_ns: u64) -> Lockstep<Faulty> {
    let sim = Simulator::new(SimConfig::default(), &[]).expect("sim");
    let mut params = CoreParams::default();
    params.safety.auto_resume_ns = auto_resume_ns;
    Lockstep::new(&params, Faulty { sim, read_fault: false, write_fault: false }, START_NS).expect("core")
}

/// Fresh inputs every 10 ticks for `ticks` ticks.
fn run_fed(c: &mut Lockstep<Faulty>, ticks: u64, seq: &mut u64) {
    for t in 0..ticks {
        if t % 10 == 0 {
            *seq += 1;
            let now = c.now_ns();
            c.inbox().push_parts(&part_states(*seq, now, &PAPER_PARTS));
            c.inbox().push_request(&request(*seq, now, &PAPER_PARTS, 1.0));
        }
        c.run_ticks(1, |_| {});
    }
}

/// Run until the core plays mid-cycle (not at a boundary).
fn until_running(c: &mut Lockstep<Faulty>, seq: &mut u64) {
    run_fed(c, 2_000, seq);
    assert_eq!(c.motor().mode(), CoreState::Running);
    run_fed(c, 7, seq);
}

fn assert_fault_hold(c: &Lockstep<Faulty>, cause: HealthCause) {
    assert_eq!(c.motor().mode(), CoreState::Hold, "not held in the faulting tick");
    let h = c.shared().health();
    assert_eq!((h.source, h.cause), (HealthSource::Driver, cause));
    assert_eq!(c.shared().pose(), [0.0; 3], "the plate is not commanded home");
    assert_eq!(c.telemetry().counters.fault_holds, 1);
}

#[test]
fn a_read_fault_holds_in_its_own_tick_until_resumed() {
    let mut c = core(0);
    let mut seq = 0;
    until_running(&mut c, &mut seq);
    c.motor_mut().driver_mut().read_fault = true;
    c.run_ticks(1, |_| {});
    assert_fault_hold(&c, HealthCause::DriverReadFault);
    run_fed(&mut c, 100, &mut seq);
    assert_eq!(c.telemetry().counters.driver_faults, 101);
    c.motor_mut().driver_mut().read_fault = false;
    // Healthy reads and fresh input do not end the hold by themselves.
    run_fed(&mut c, 5_000, &mut seq);
    assert_eq!(c.motor().mode(), CoreState::Hold);
    assert!(c.motor().driver().sim.plate_pose().x.abs() < 1e-6, "the plate did not go home");
    // A resume before a fault would not count; this one ends the hold.
    let now = c.now_ns();
    c.inbox().push_command(&CoreCommand::new(CoreCommand::RESUME, 1, now));
    run_fed(&mut c, 2_000, &mut seq);
    assert_eq!(c.motor().mode(), CoreState::Running);
    let t = c.telemetry();
    assert_eq!((t.counters.resumes, t.health_source, t.counters.fault_holds), (1, 0, 1));
}

#[test]
fn a_write_fault_holds_at_once_and_auto_resume_ends_it() {
    let auto_ns = 50_000_000;
    let mut c = core(auto_ns);
    let mut seq = 0;
    until_running(&mut c, &mut seq);
    c.motor_mut().driver_mut().write_fault = true;
    c.run_ticks(1, |_| {});
    assert_fault_hold(&c, HealthCause::DriverWriteFault);
    c.motor_mut().driver_mut().write_fault = false;
    // 50 ms = 500 healthy ticks: still holding one tick before.
    run_fed(&mut c, 499, &mut seq);
    assert_eq!(c.motor().mode(), CoreState::Hold);
    run_fed(&mut c, 2_000, &mut seq);
    assert_eq!(c.motor().mode(), CoreState::Running);
    assert_eq!(c.telemetry().counters.resumes, 1);
}

#[test]
fn an_operator_stop_idles_the_plate_at_home_until_start() {
    let mut c = core(0);
    let mut seq = 0;
    until_running(&mut c, &mut seq);
    let holds = c.telemetry().counters.hold_events;
    let now = c.now_ns();
    c.inbox().push_command(&CoreCommand::new(CoreCommand::STOP, 1, now));
    // Fresh input keeps arriving: the stop, not staleness, idles the plate.
    run_fed(&mut c, 5_000, &mut seq);
    assert_eq!(c.motor().mode(), CoreState::Idle);
    assert_eq!(c.shared().pose(), [0.0; 3], "the plate is not home");
    assert!(c.motor().driver().sim.plate_pose().x.abs() < 1e-6, "the plate moved while stopped");
    assert_eq!(c.telemetry().counters.hold_events, holds, "a stop is no hold");
    let now = c.now_ns();
    c.inbox().push_command(&CoreCommand::new(CoreCommand::START, 2, now));
    run_fed(&mut c, 2_000, &mut seq);
    assert_eq!(c.motor().mode(), CoreState::Running);
}
