//! The driver's health as the motor last read it, for the io thread's
//! telemetry: atomics only (the motor stores, the io thread loads).

use core::sync::atomic::{AtomicI64, AtomicU32, AtomicU64, Ordering::Relaxed};

use ipc_types::{DRIVER_AXES, DriverTelemetry, NO_SYNC0};

use upm_hardware::{BusState, DriverHealth, DriverKind, MAX_ACTUATORS};

const _: () = assert!(DRIVER_AXES == MAX_ACTUATORS);

#[derive(Debug)]
pub struct DriverCell {
    kind: AtomicU32,
    state: AtomicU32,
    faults: [AtomicU64; DRIVER_AXES],
    lost_frames: AtomicU64,
    bad_frames: AtomicU64,
    sync0_phase_ns: AtomicI64,
}

impl Default for DriverCell {
    fn default() -> Self {
        let s = DriverTelemetry::SIMULATED;
        Self {
            kind: AtomicU32::new(s.kind),
            state: AtomicU32::new(s.state),
            faults: Default::default(),
            lost_frames: AtomicU64::new(0),
            bad_frames: AtomicU64::new(0),
            sync0_phase_ns: AtomicI64::new(s.sync0_phase_ns),
        }
    }
}

impl DriverCell {
    /// Motor thread: a few relaxed stores.
    pub fn store(&self, h: &DriverHealth) {
        self.kind.store(kind_code(h.kind), Relaxed);
        self.state.store(state_code(h.state), Relaxed);
        for (cell, n) in self.faults.iter().zip(h.faults) {
            cell.store(n, Relaxed);
        }
        self.lost_frames.store(h.lost_frames, Relaxed);
        self.bad_frames.store(h.bad_frames, Relaxed);
        let phase = h.sync0_phase_ns.map_or(NO_SYNC0, |p| i64::try_from(p).unwrap_or(i64::MAX));
        self.sync0_phase_ns.store(phase, Relaxed);
    }

    pub fn load(&self) -> DriverTelemetry {
        DriverTelemetry {
            kind: self.kind.load(Relaxed),
            state: self.state.load(Relaxed),
            faults: core::array::from_fn(|i| self.faults[i].load(Relaxed)),
            lost_frames: self.lost_frames.load(Relaxed),
            bad_frames: self.bad_frames.load(Relaxed),
            sync0_phase_ns: self.sync0_phase_ns.load(Relaxed),
        }
    }
}

const fn kind_code(k: DriverKind) -> u32 {
    match k {
        DriverKind::Simulated => ipc_types::driver_kind::SIMULATED,
        DriverKind::Ethercat => ipc_types::driver_kind::ETHERCAT,
    }
}

const fn state_code(s: BusState) -> u32 {
    use ipc_types::bus_state as b;
    match s {
        BusState::Init => b::INIT,
        BusState::PreOp => b::PRE_OP,
        BusState::SafeOp => b::SAFE_OP,
        BusState::Op => b::OP,
        BusState::Fault => b::FAULT,
    }
}
