//! The core's stages and the wires between them, built in one place for
//! the real process and for lock-step: a solve stage that hands motions to
//! the motor loop through the wait-free hand-over, the rings they leave
//! samples and outputs in for the io side, and the state both report into.
//! Who runs the stages (threads, or one loop on a manual clock) is the
//! caller's business.

use std::sync::Arc;

use upm_hardware::PlateDriver;
use upm_motion::PlateMotion;

use super::handoff::{StagedMotion, motion_handoff};
use super::motor::{MotorLoop, MotorPolicy};
use super::params::{CoreParams, CoreParamsError, playable_k_bounds};
use super::samples::{MOTOR_RING, MotorSample, StageOutputs, StageOutputsRx};
use super::shared::CoreShared;
use super::solve_stage::SolveStage;

/// Every stage of one core, built (allocating) and not yet running.
#[derive(Debug)]
pub struct StageGraph<D: PlateDriver> {
    pub motor: MotorLoop<D>,
    pub stage: SolveStage,
    pub shared: Arc<CoreShared>,
    /// What the motor leaves for the io side each tick.
    pub motor_samples: rtrb::Consumer<MotorSample>,
    /// Schedules, rejections and solver samples from the solve stage.
    pub outputs: StageOutputsRx,
    /// Each center's bound on |k| the stage solves under (announced in
    /// `RigInfo`).
    pub k_bounds: Vec<f64>,
}

impl<D: PlateDriver> StageGraph<D> {
    /// Validate `params` and build every stage around `driver`.
    pub fn build(params: &CoreParams, driver: D) -> Result<Self, CoreParamsError> {
        params.validate()?;
        let rig = params.plate_rig()?;
        let empty = PlateMotion::new(params.motion).map_err(CoreParamsError::Motion)?;
        let (writer, reader) =
            motion_handoff(&StagedMotion { motion: empty, request_seq: 0, frame_stamp_ns: 0 });
        let shared = Arc::new(CoreShared::new());
        let (motor_tx, motor_samples) = rtrb::RingBuffer::new(MOTOR_RING);
        let (out, outputs) = StageOutputs::rings();
        let k_bounds = playable_k_bounds(params, &rig)?;
        let stage = SolveStage::new(params, rig.clone(), k_bounds.clone(), writer, shared.clone(), out)?;
        let policy = MotorPolicy::from_params(params);
        let motor = MotorLoop::new(driver, rig, reader, shared.clone(), motor_tx, policy);
        Ok(Self { motor, stage, shared, motor_samples, outputs, k_bounds })
    }
}
