//! The motor's update step, one implementation for the real-time motor loop
//! and for playback without a clock (`upm validate`, the driver
//! conformance suite).

use multiversion::multiversion;

use super::plan::PlateMotion;
use super::pose::PlateSample;
use super::rig::Rig;
use crate::ActuatorCommand;

/// The command for the end of motion tick `tick`, given the setpoint at its
/// start (`now`, which becomes the new one). The feed-forward acceleration
/// is the tick average, which is what a zero-order-held force produces.
/// No allocation, no panic; an AVX2 clone where the CPU has it (nothing is
/// fused, so both clones give the same bits).
#[multiversion(targets("x86_64+avx2"))]
pub fn next_command(
    rig: &Rig,
    motion: &PlateMotion,
    tick_s: f64,
    tick: u64,
    now: &mut PlateSample,
    cmd: &mut ActuatorCommand,
) {
    let mut next = motion.sample_tick(tick + 1);
    next.acceleration.x = (next.velocity.x - now.velocity.x) / tick_s;
    next.acceleration.y = (next.velocity.y - now.velocity.y) / tick_s;
    next.acceleration.theta = (next.velocity.theta - now.velocity.theta) / tick_s;
    rig.command(&next, cmd);
    *now = next;
}
