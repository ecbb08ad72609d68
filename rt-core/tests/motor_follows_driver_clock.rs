//! The motor loop shifts its next deadline by what the driver asks
//! (`PlateDriver::clock_correction_ns`: a fieldbus with its own clock), on
//! a hand-set clock that records every deadline the loop sleeps to.

use std::sync::atomic::{AtomicU64, Ordering::Relaxed};
use std::sync::{Arc, Mutex};

use rt_core::{Clock, CoreShared, MotorLoop, MotorPolicy, StagedMotion, motion_handoff};
use upm_hardware::{ActuatorCommand, ActuatorLimits, PlateDriver, PlateState, ReadError, WriteError};
use upm_motion::{MotionParams, PlateMotion, Rig, RigParams};

/// A driver on a bus that asks for +700 ns every third tick.
struct BusDriver {
    limits: ActuatorLimits,
    ticks: u64,
}

impl PlateDriver for BusDriver {
    fn limits(&self) -> ActuatorLimits {
        self.limits
    }
    fn tick_period(&self) -> f64 {
        1e-4
    }
    fn read(&mut self, _: &mut PlateState) -> Result<(), ReadError> {
        Ok(())
    }
    fn write(&mut self, _: &ActuatorCommand) -> Result<(), WriteError> {
        Ok(())
    }
    fn hold(&mut self) {}
    fn advance(&mut self) {
        self.ticks += 1;
    }
    fn clock_correction_ns(&mut self) -> i64 {
        if self.ticks.is_multiple_of(3) { 700 } else { 0 }
    }
}

/// Manual time that remembers the deadlines and stops the loop after 30.
struct Recorder {
    now: AtomicU64,
    deadlines: Mutex<Vec<u64>>,
    shared: Arc<CoreShared>,
}

impl Clock for Recorder {
    fn now_ns(&self) -> u64 {
        self.now.load(Relaxed)
    }
    fn sleep_until(&self, deadline_ns: u64) {
        self.now.fetch_max(deadline_ns, Relaxed);
        if let Ok(mut d) = self.deadlines.lock() {
            d.push(deadline_ns);
            if d.len() == 30 {
                self.shared.stop.store(true, Relaxed);
            }
        }
    }
}

#[test]
fn the_next_deadline_moves_by_the_drivers_correction() {
    let rig = Rig::new(RigParams::default()).expect("rig");
    let driver = BusDriver { limits: ActuatorLimits::from_rig(&rig), ticks: 0 };
    let empty = PlateMotion::new(MotionParams::default()).expect("motion");
    let (_writer, reader) =
        motion_handoff(&StagedMotion { motion: empty, request_seq: 0, frame_stamp_ns: 0 });
    let shared = Arc::new(CoreShared::new());
    let (samples, _rx) = rtrb::RingBuffer::new(64);
    let policy = MotorPolicy {
        parts_max_age_ns: u64::MAX,
        request_max_age_ns: u64::MAX,
        auto_resume_ticks: 0,
        inertia_adaptation: None,
    };
    let mut motor = MotorLoop::new(driver, rig, reader, shared.clone(), samples, policy);
    let clock = Recorder { now: AtomicU64::new(1_000_000), deadlines: Mutex::new(Vec::new()), shared };
    let period = 100_000;
    motor.run(&clock, period);
    let d = clock.deadlines.lock().expect("deadlines").clone();
    assert!(d.len() >= 30, "{} deadlines", d.len());
    for (k, w) in d.windows(2).enumerate().take(28) {
        // The tick that slept to d[k] was tick k + 1 of the driver.
        let expected = period + if (k as u64 + 1).is_multiple_of(3) { 700 } else { 0 };
        assert_eq!(w[1] - w[0], expected, "deadline {k}");
    }
}
