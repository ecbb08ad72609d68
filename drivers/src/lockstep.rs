//! The motor loop without wall-clock time: read → update (sample the motion,
//! kinematics) → write → advance, one iteration per tick.

use multiversion::multiversion;
use rt_core::driver::{ActuatorCommand, PlateDriver, PlateState, WriteError};
use rt_core::motion::{PlateMotion, PlateSample, Rig};

/// Play `ticks` ticks (the driver is assumed to sit at motion tick `start`) of `motion` starting at motion tick `start`. Returns
/// the number of rejected writes (always 0 for finite motions) or stops at
/// the first read error.
pub fn play<D: PlateDriver>(
    driver: &mut D,
    rig: &Rig,
    motion: &PlateMotion,
    start: u64,
    ticks: u64,
    state: &mut PlateState,
) -> Result<u64, rt_core::driver::ReadError> {
    let mut cmd = ActuatorCommand::HOME;
    let mut rejected = 0;
    let h = driver.tick_period();
    let mut now = motion.sample_tick(start);
    for t in start..start + ticks {
        driver.read(state)?;
        next_command(rig, motion, h, t, &mut now, &mut cmd);
        if let Err(WriteError::NonFinite { .. } | WriteError::Fault) = driver.write(&cmd) {
            rejected += 1;
        }
        driver.advance();
    }
    driver.read(state)?;
    Ok(rejected)
}

/// The update step: the command for the end of tick `t`, given the sample at
/// its start (`now`, advanced to the end). AVX2 clone where the CPU has it
/// (nothing is fused, so both clones give the same bits).
#[multiversion(targets("x86_64+avx2"))]
fn next_command(
    rig: &Rig,
    motion: &PlateMotion,
    h: f64,
    t: u64,
    now: &mut PlateSample,
    cmd: &mut ActuatorCommand,
) {
    // Setpoint for the end of this tick; the feed-forward acceleration is
    // the tick average, which is what a zero-order-held force gives.
    let mut next = motion.sample_tick(t + 1);
    let end_velocity = next.velocity;
    next.acceleration.x = (end_velocity.x - now.velocity.x) / h;
    next.acceleration.y = (end_velocity.y - now.velocity.y) / h;
    next.acceleration.theta = (end_velocity.theta - now.velocity.theta) / h;
    rig.command(&next, cmd);
    *now = next;
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
) -> Result<u64, rt_core::driver::ReadError> {
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
