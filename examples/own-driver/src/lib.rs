//! Your own plate driver: a plate on stepper actuators that count whole
//! steps. Everything a real driver does is here in small: the rig's
//! kinematics and limits from `upm-motion`, the one limit policy
//! (`CommandGate`), the hardware's own units (steps), hold, and a tick
//! that lets time pass. `tests/conformance.rs` runs the suite every driver
//! passes.

use upm_hardware::{
    ActuatorCommand, ActuatorLimits, CommandGate, MAX_ACTUATORS, PlateDriver, PlateState, ReadError,
    WriteError,
};
use upm_motion::{Rig, RigError, RigParams};

/// Steps per metre of stroke (1 µm steps).
pub const STEPS_PER_M: f64 = 1e6;

/// A plate whose actuators move to the nearest whole step of each command
/// within the tick. Hardware would write the step targets to its
/// controller in `write` and read the counters back in `read`.
#[derive(Debug, Clone)]
pub struct StepperPlate {
    rig: Rig,
    limits: ActuatorLimits,
    tick_s: f64,
    tick: u64,
    /// The command, through the one limit policy; clamps and refusals
    /// counted.
    gate: CommandGate,
    /// Each actuator's step counter.
    steps: [i64; MAX_ACTUATORS],
}

impl StepperPlate {
    pub fn new(rig: RigParams, tick_hz: f64) -> Result<Self, RigError> {
        let rig = Rig::new(rig)?;
        Ok(Self {
            limits: ActuatorLimits::from_rig(&rig),
            rig,
            tick_s: 1.0 / tick_hz,
            tick: 0,
            gate: CommandGate::default(),
            steps: [0; MAX_ACTUATORS],
        })
    }
}

impl PlateDriver for StepperPlate {
    fn limits(&self) -> ActuatorLimits {
        self.limits
    }

    fn tick_period(&self) -> f64 {
        self.tick_s
    }

    fn read(&mut self, state: &mut PlateState) -> Result<(), ReadError> {
        for (p, &s) in state.actuator_position.iter_mut().zip(&self.steps) {
            *p = s as f64 / STEPS_PER_M;
        }
        state.tick = self.tick;
        state.time = self.tick as f64 * self.tick_s;
        state.pose = self.rig.pose_from_actuators(&state.actuator_position);
        state.velocity = self.rig.twist_from_actuators(&state.pose, &self.gate.command.velocity);
        // Steppers have no force sensor: report the feed-forward.
        state.actuator_force = self.gate.command.force;
        self.gate.report(state);
        Ok(())
    }

    fn write(&mut self, command: &ActuatorCommand) -> Result<(), WriteError> {
        self.gate.write(&self.limits, command)
    }

    fn hold(&mut self) {
        self.gate.hold();
    }

    fn advance(&mut self) {
        for (s, &p) in self.steps.iter_mut().zip(&self.gate.command.position) {
            *s = (p * STEPS_PER_M).round() as i64;
        }
        self.tick += 1;
    }
}
