//! A trivial driver: the plate is exactly where the last command put it.
//! Used as the mock for the conformance suite and for kinematic tests.

use crate::{ActuatorCommand, ActuatorLimits, PlateDriver, PlateState, ReadError, WriteError, apply_limits};
use upm_motion::{Rig, RigError, RigParams};

#[derive(Debug, Clone)]
pub struct IdealDriver {
    rig: Rig,
    limits: ActuatorLimits,
    h: f64,
    command: ActuatorCommand,
    tick: u64,
    clamped: u64,
    rejected: u64,
    holding: bool,
}

impl IdealDriver {
    pub fn new(rig: RigParams, tick_hz: f64) -> Result<Self, RigError> {
        let rig = Rig::new(rig)?;
        let h = if tick_hz.is_finite() && tick_hz > 0.0 { 1.0 / tick_hz } else { 1e-4 };
        Ok(Self {
            limits: ActuatorLimits::from_rig(&rig),
            rig,
            h,
            command: ActuatorCommand::HOME,
            tick: 0,
            clamped: 0,
            rejected: 0,
            holding: false,
        })
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
        state.pose = self.rig.pose_from_actuators(&self.command.position);
        state.velocity = self.rig.twist_from_actuators(&state.pose, &self.command.velocity);
        state.actuator_position = self.command.position;
        state.actuator_force = self.command.force;
        state.clamped = self.clamped;
        state.rejected = self.rejected;
        state.holding = self.holding;
        Ok(())
    }

    fn write(&mut self, command: &ActuatorCommand) -> Result<(), WriteError> {
        match apply_limits(&self.limits, command, &mut self.command) {
            Ok(c) => {
                self.clamped += c as u64;
                self.holding = false;
                Ok(())
            }
            Err(e) => {
                self.rejected += 1;
                Err(e)
            }
        }
    }

    fn hold(&mut self) {
        self.command = ActuatorCommand::HOME;
        self.holding = true;
    }

    fn advance(&mut self) {
        self.tick += 1;
    }
}
