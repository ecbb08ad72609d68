//! The plate driver's own state inside [`crate::Telemetry`]: which driver,
//! its bus state, faults per axis, frames lost and bad frames.

#[cfg(feature = "iceoryx2")]
use iceoryx2::prelude::ZeroCopySend;

/// Axes a driver reports faults for (the rig's actuator limit).
pub const DRIVER_AXES: usize = 8;

/// Driver kind codes.
pub mod driver_kind {
    /// The physics simulator or a mock.
    pub const SIMULATED: u32 = 0;
    /// CiA 402 drives over EtherCAT.
    pub const ETHERCAT: u32 = 1;
}

/// Bus state codes (EtherCAT's AL states; a simulator is always OP).
pub mod bus_state {
    pub const INIT: u32 = 1;
    pub const PRE_OP: u32 = 2;
    pub const SAFE_OP: u32 = 4;
    pub const OP: u32 = 8;
    /// A device or the link reports a fault (the core holds).
    pub const FAULT: u32 = 0x10;
}

#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "iceoryx2", derive(ZeroCopySend), type_name("upm::DriverTelemetry.v6"))]
pub struct DriverTelemetry {
    /// [`driver_kind`] code.
    pub kind: u32,
    /// [`bus_state`] code.
    pub state: u32,
    /// Faults entered per axis since start.
    pub faults: [u64; DRIVER_AXES],
    /// Process-data frames lost (not answered, or short of devices).
    pub lost_frames: u64,
    /// Frames from the wire that were not ours or not well formed.
    pub bad_frames: u64,
    /// With distributed clocks: how long after SYNC0 the last whole frame
    /// reached the reference drive (ns); [`NO_SYNC0`] when the drives run
    /// free or there is no bus.
    pub sync0_phase_ns: i64,
}

/// `sync0_phase_ns` when there are no distributed clocks.
pub const NO_SYNC0: i64 = -1;

const _: () = assert!(size_of::<DriverTelemetry>() == 8 + DRIVER_AXES * 8 + 24);

impl DriverTelemetry {
    /// A simulator: operational, nothing lost.
    pub const SIMULATED: Self = Self {
        kind: driver_kind::SIMULATED,
        state: bus_state::OP,
        faults: [0; DRIVER_AXES],
        lost_frames: 0,
        bad_frames: 0,
        sync0_phase_ns: NO_SYNC0,
    };

    /// The kind's name, `None` for an unknown code.
    pub const fn kind_str(&self) -> Option<&'static str> {
        match self.kind {
            driver_kind::SIMULATED => Some("simulated"),
            driver_kind::ETHERCAT => Some("ethercat"),
            _ => None,
        }
    }

    /// The state's name, `None` for an unknown code.
    pub const fn state_str(&self) -> Option<&'static str> {
        match self.state {
            bus_state::INIT => Some("init"),
            bus_state::PRE_OP => Some("pre-op"),
            bus_state::SAFE_OP => Some("safe-op"),
            bus_state::OP => Some("op"),
            bus_state::FAULT => Some("fault"),
            _ => None,
        }
    }
}
