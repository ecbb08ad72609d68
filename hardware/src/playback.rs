//! Playback of one motion on a driver without a clock, schedule hand-over
//! or safety holds: read → update (`upm_motion::next_command`, the
//! motor loop's own update step) → write → advance, one iteration per tick.
//! For `upm validate`, the driver conformance suite and driver benchmarks;
//! the real-time loop is `rt_core::MotorLoop`.

use crate::{ActuatorCommand, PlateDriver, PlateState, WriteError};
use upm_motion::{InertiaEstimate, PlateMotion, Rig, next_command};

/// Play `ticks` ticks of `motion` from motion tick `start` (where the
/// driver is assumed to sit). Returns
/// the number of rejected writes (always 0 for finite motions) or stops at
/// the first read error.
pub fn play<D: PlateDriver>(
    driver: &mut D,
    rig: &Rig,
    motion: &PlateMotion,
    start: u64,
    ticks: u64,
    state: &mut PlateState,
) -> Result<u64, crate::ReadError> {
    play_estimating(driver, rig, motion, start, ticks, state, None)
}

/// [`play`], feeding each tick's drive forces to `estimate` as the motor
/// loop does (the caller ends its cycles and scales the rig).
pub fn play_estimating<D: PlateDriver>(
    driver: &mut D,
    rig: &Rig,
    motion: &PlateMotion,
    start: u64,
    ticks: u64,
    state: &mut PlateState,
    mut estimate: Option<&mut InertiaEstimate>,
) -> Result<u64, crate::ReadError> {
    let mut cmd = ActuatorCommand::HOME;
    let mut rejected = 0;
    let h = driver.tick_period();
    let mut now = motion.sample_tick(start);
    for t in start..start + ticks {
        driver.read(state)?;
        if let Some(e) = estimate.as_deref_mut().filter(|_| t > start) {
            e.observe(rig, &now.pose, &cmd.force, state);
        }
        let from = now;
        next_command(rig, motion, h, t, &mut now, &mut cmd);
        if let Some(e) = estimate.as_deref_mut() {
            e.predict(&from, &now, h);
        }
        if let Err(WriteError::NonFinite { .. } | WriteError::Fault) = driver.write(&cmd) {
            rejected += 1;
        }
        driver.advance();
    }
    driver.read(state)?;
    if let Some(e) = estimate.filter(|_| ticks > 0) {
        e.observe(rig, &now.pose, &cmd.force, state);
    }
    Ok(rejected)
}

/// The commands `play` would write for ticks `0..ticks` (tick period `h`).
pub fn record_commands(rig: &Rig, motion: &PlateMotion, h: f64, ticks: u64) -> Vec<ActuatorCommand> {
    let mut now = motion.sample_tick(0);
    (0..ticks)
        .map(|t| {
            let mut cmd = ActuatorCommand::HOME;
            next_command(rig, motion, h, t, &mut now, &mut cmd);
            cmd
        })
        .collect()
}

/// Drive `driver` for `ticks` ticks with pre-recorded commands, cycling
/// through them: the driver's own cost, without the motion sampling.
/// Returns the number of rejected writes.
pub fn replay<D: PlateDriver>(
    driver: &mut D,
    commands: &[ActuatorCommand],
    ticks: u64,
    state: &mut PlateState,
) -> Result<u64, crate::ReadError> {
    let mut rejected = 0;
    for cmd in commands.iter().cycle().take(ticks as usize) {
        driver.read(state)?;
        if driver.write(cmd).is_err() {
            rejected += 1;
        }
        driver.advance();
    }
    driver.read(state)?;
    Ok(rejected)
}
