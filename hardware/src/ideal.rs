//! A trivial driver: the plate is exactly where the last command put it.
//! Used as the mock for the conformance suite and for kinematic tests.

use crate::{ActuatorCommand, ActuatorLimits, CommandGate, PlateDriver, PlateState, ReadError, WriteError};
use upm_motion::{Rig, RigError, RigParams};

#[derive(Debug, Clone)]
pub struct IdealDriver {
    rig: Rig,
    limits: ActuatorLimits,
    h: f64,
    gate: CommandGate,
    tick: u64,
}

impl IdealDriver {
    pub fn new(rig: RigParams, tick_hz: f64) -> Result<Self, RigError> {
        let rig = Rig::new(rig)?;
        let h = if tick_hz.is_finite() && tick_hz > 0.0 { 1.0 / tick_hz } else { 1e-4 };
        Ok(Self { limits: ActuatorLimits::from_rig(&rig), rig, h, gate: CommandGate::default(), tick: 0 })
    }
}

impl PlateDriver for IdealDriver {
    fn limits(&self) -> ActuatorLimits {
        self.limits
    }

    fn tick_period(&self) -> f64 {
        self.h
    }

    fn read(&mut self, state: &mut PlateState) -> Result<(), ReadError> {
        state.tick = self.tick;
        state.time = self.tick as f64 * self.h;
        let command = &self.gate.command;
        state.pose = self.rig.pose_from_actuators(&command.position);
        state.velocity = self.rig.twist_from_actuators(&state.pose, &command.velocity);
        state.actuator_position = command.position;
        state.actuator_force = command.force;
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
        self.tick += 1;
    }
}
