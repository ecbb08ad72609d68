//! What a driver knows about its own hardware beyond the plate: its kind,
//! the state of its bus, faults per actuator, lost and bad frames. The
//! motor copies it into the core's telemetry every tick, so `upm status`
//! shows a fieldbus rig's state without the io thread touching the driver.

use super::MAX_ACTUATORS;

/// Which kind of driver runs the plate.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DriverKind {
    /// The physics simulator or a mock.
    Simulated,
    /// CiA 402 drives over EtherCAT.
    Ethercat,
}

/// The bus state of a fieldbus driver, as EtherCAT names them (the lowest
/// state of any device on the bus); a simulator is always `Op`. Ordered
/// from worst to best.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum BusState {
    /// A device or the link reports a fault; the core holds.
    Fault,
    Init,
    PreOp,
    SafeOp,
    Op,
}

/// A driver's health snapshot (`Copy`, read by the motor every tick).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DriverHealth {
    pub kind: DriverKind,
    pub state: BusState,
    /// Faults entered per actuator since start.
    pub faults: [u64; MAX_ACTUATORS],
    /// Process-data frames that came back short of devices (working
    /// counter below what the bus should give) or not at all.
    pub lost_frames: u64,
    /// Frames from the wire that were not ours or not well formed.
    pub bad_frames: u64,
    /// With distributed clocks, how long after SYNC0 the last whole frame
    /// reached the reference drive (ns); `None` without.
    pub sync0_phase_ns: Option<u64>,
}

impl DriverHealth {
    /// A simulator: always operational, nothing lost.
    pub const SIMULATED: DriverHealth = DriverHealth {
        kind: DriverKind::Simulated,
        state: BusState::Op,
        faults: [0; MAX_ACTUATORS],
        lost_frames: 0,
        bad_frames: 0,
        sync0_phase_ns: None,
    };
}
