//! The drive behind each simulated SubDevice: the CiA 402 state machine
//! (controlword 0x6040 → statusword 0x6041) and cyclic synchronous
//! position mode (0x6060 = 8): in *operation enabled* the actual position
//! (0x6064) follows the target (0x607A). A drive can be put into fault
//! (statusword bit 3); a rising fault-reset bit (controlword bit 7) clears
//! it back to *switch on disabled*.
//!
//! The process image is what the PDO mapping (0x1600 / 0x1A00,
//! [`PdoMap`]) lays out, little-endian and packed; by default outputs (SM2)
//! `controlword u16, target i32, velocity offset i32, torque offset i16,
//! mode i8` and inputs (SM3) `statusword u16, actual i32, torque actual
//! i16, mode display i8`. Torques are per mille of the rated torque
//! (0x6076), as the profile has them.

use crate::pdo_map::PdoMap;

/// The default PDO mapping: RxPDO 0x1600 (outputs) and TxPDO 0x1A00
/// (inputs), entries `index << 16 | subindex << 8 | bits`.
pub const RX_PDO: [u32; 5] = [0x6040_0010, 0x607A_0020, 0x60B1_0020, 0x60B2_0010, 0x6060_0008];
pub const TX_PDO: [u32; 4] = [0x6041_0010, 0x6064_0020, 0x6077_0010, 0x6061_0008];

/// Bytes of the default output and input images.
pub const OUTPUT_BYTES: usize = 13;
pub const INPUT_BYTES: usize = 9;
/// Bytes of an image at most (8 entries of 32 bits).
pub const MAX_IMAGE: usize = 32;

/// Modes of operation (0x6060): cyclic synchronous position.
pub const MODE_CSP: i8 = 8;

/// CiA 402 power states.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PowerState {
    SwitchOnDisabled,
    ReadyToSwitchOn,
    SwitchedOn,
    OperationEnabled,
    QuickStopActive,
    Fault,
}

impl PowerState {
    /// The statusword bits of the state (bit 4 voltage enabled, bit 5
    /// quick stop *not* active, as the profile has them).
    pub const fn statusword(self) -> u16 {
        match self {
            Self::SwitchOnDisabled => 0x0040,
            Self::ReadyToSwitchOn => 0x0031,
            Self::SwitchedOn => 0x0033,
            Self::OperationEnabled => 0x0037,
            Self::QuickStopActive => 0x0017,
            Self::Fault => 0x0008,
        }
    }
}

/// Who moves the drive's position.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Servo {
    /// The actual position is the target at once (protocol tests).
    Instant,
    /// A plant outside the drive sets `actual` and `torque_actual` each
    /// cycle (the physics simulator, in `rig`); the drive only checks the
    /// following error.
    External,
}

/// One drive.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Drive {
    pub state: PowerState,
    pub controlword: u16,
    pub mode: i8,
    pub target: i32,
    /// Velocity feed-forward (counts/s, 0x60B1).
    pub velocity_offset: i32,
    /// Torque feed-forward (per mille of rated, 0x60B2).
    pub torque_offset: i16,
    pub actual: i32,
    /// Per mille of rated (0x6077).
    pub torque_actual: i16,
    /// Rated torque (0x6076; mN·m, or mN for a linear motor).
    pub rated_torque: u32,
    pub servo: Servo,
    /// Largest |target − actual| before a following-error fault (counts).
    pub following_error_window: u32,
    /// Faults entered (injected or following error).
    pub faults: u64,
    /// PDO mappings: outputs (RxPDO) and inputs (TxPDO).
    pub rx: PdoMap,
    pub tx: PdoMap,
}

impl Default for Drive {
    fn default() -> Self {
        Self {
            state: PowerState::SwitchOnDisabled,
            controlword: 0,
            mode: 0,
            target: 0,
            velocity_offset: 0,
            torque_offset: 0,
            actual: 0,
            torque_actual: 0,
            rated_torque: 1000,
            servo: Servo::Instant,
            following_error_window: u32::MAX,
            faults: 0,
            rx: PdoMap::new(0x1600, &RX_PDO, &RX_PDO),
            tx: PdoMap::new(0x1A00, &TX_PDO, &TX_PDO),
        }
    }
}

impl Drive {
    /// The statusword: the state's bits, remote (bit 9), following error
    /// (bit 13) while in fault from it.
    pub fn statusword(&self) -> u16 {
        self.state.statusword() | 0x0200
    }

    /// A new controlword: the state machine's transition, if any.
    pub fn command(&mut self, controlword: u16) {
        let rising_reset = controlword & 0x80 != 0 && self.controlword & 0x80 == 0;
        self.controlword = controlword;
        use PowerState::*;
        let low = controlword & 0x000F;
        self.state = match self.state {
            Fault if rising_reset => SwitchOnDisabled,
            Fault => Fault,
            _ if controlword & 0x0002 == 0 => SwitchOnDisabled, // disable voltage
            OperationEnabled if controlword & 0x0004 == 0 => QuickStopActive,
            QuickStopActive => SwitchOnDisabled,
            _ if controlword & 0x0004 == 0 => SwitchOnDisabled, // quick stop
            _ if low & 0x0007 == 0x0006 => ReadyToSwitchOn,     // shutdown
            ReadyToSwitchOn | SwitchedOn | OperationEnabled if low == 0x000F => OperationEnabled,
            ReadyToSwitchOn | SwitchedOn | OperationEnabled if low == 0x0007 => SwitchedOn,
            s => s,
        };
    }

    /// Enter fault (a drive error, or injected by a test).
    pub fn fault(&mut self) {
        if self.state != PowerState::Fault {
            self.state = PowerState::Fault;
            self.faults += 1;
        }
    }

    /// One cycle of process data: take the mapped outputs, move, report
    /// the mapped inputs into `inputs` (its first [`PdoMap::bytes`]).
    pub fn cycle(&mut self, outputs: &[u8], inputs: &mut [u8]) {
        let field = |index: u16| -> Option<u32> {
            let (at, n) = self.rx.find(index)?;
            let b = outputs.get(at..at + n)?;
            let mut v = [0u8; 4];
            v[..n.min(4)].copy_from_slice(&b[..n.min(4)]);
            Some(u32::from_le_bytes(v))
        };
        let (controlword, target) = (field(0x6040), field(0x607A));
        let (velocity, torque, mode) = (field(0x60B1), field(0x60B2), field(0x6060));
        if let Some(c) = controlword {
            self.command(c as u16);
        }
        self.target = target.map_or(self.target, |t| t as i32);
        self.velocity_offset = velocity.map_or(self.velocity_offset, |v| v as i32);
        self.torque_offset = torque.map_or(self.torque_offset, |t| t as u16 as i16);
        self.mode = mode.map_or(self.mode, |m| m as u8 as i8);
        if self.is_following() {
            if self.target.abs_diff(self.actual) > self.following_error_window {
                self.fault();
            } else if self.servo == Servo::Instant {
                self.actual = self.target;
            }
        }
        self.inputs(inputs);
    }

    /// Operation enabled in cyclic synchronous position: the target moves
    /// the drive.
    pub fn is_following(&self) -> bool {
        self.state == PowerState::OperationEnabled && self.mode == MODE_CSP
    }

    /// The mapped inputs as they stand, into `inputs`.
    pub fn inputs(&self, inputs: &mut [u8]) {
        let mut at = 0;
        for e in self.tx.active() {
            let n = (e & 0xFF) as usize / 8;
            let value: u32 = match (e >> 16) as u16 {
                0x6041 => u32::from(self.statusword()),
                0x6064 => self.actual as u32,
                0x6077 => u32::from(self.torque_actual as u16),
                0x6061 => u32::from(self.mode as u8),
                _ => 0,
            };
            if let Some(dst) = inputs.get_mut(at..at + n) {
                dst.copy_from_slice(&value.to_le_bytes()[..n.min(4)]);
            }
            at += n;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn out(controlword: u16, target: i32) -> [u8; OUTPUT_BYTES] {
        let mut o = [0u8; OUTPUT_BYTES];
        o[..2].copy_from_slice(&controlword.to_le_bytes());
        o[2..6].copy_from_slice(&target.to_le_bytes());
        o[12] = MODE_CSP as u8;
        o
    }

    #[test]
    fn shutdown_switch_on_enable_then_follow() {
        let mut d = Drive::default();
        assert_eq!(d.statusword() & 0x006F, 0x0040);
        d.cycle(&out(0x0006, 0), &mut [0; INPUT_BYTES]);
        assert_eq!(d.state, PowerState::ReadyToSwitchOn);
        d.cycle(&out(0x0007, 0), &mut [0; INPUT_BYTES]);
        assert_eq!(d.state, PowerState::SwitchedOn);
        d.cycle(&out(0x000F, 0), &mut [0; INPUT_BYTES]);
        assert_eq!(d.state, PowerState::OperationEnabled);
        let mut inputs = [0u8; INPUT_BYTES];
        d.cycle(&out(0x000F, 1234), &mut inputs);
        assert_eq!(i32::from_le_bytes([inputs[2], inputs[3], inputs[4], inputs[5]]), 1234);
        assert_eq!(u16::from_le_bytes([inputs[0], inputs[1]]) & 0x006F, 0x0027);
    }

    #[test]
    fn a_fault_holds_until_a_rising_fault_reset() {
        let mut d = Drive { following_error_window: 100, ..Drive::default() };
        for cw in [0x0006, 0x0007, 0x000F] {
            d.cycle(&out(cw, 0), &mut [0; INPUT_BYTES]);
        }
        d.cycle(&out(0x000F, 500), &mut [0; INPUT_BYTES]);
        assert_eq!((d.state, d.actual, d.faults), (PowerState::Fault, 0, 1), "following error");
        d.cycle(&out(0x000F, 0), &mut [0; INPUT_BYTES]);
        assert_eq!(d.state, PowerState::Fault, "enable does not clear a fault");
        d.cycle(&out(0x0080, 0), &mut [0; INPUT_BYTES]);
        assert_eq!(d.state, PowerState::SwitchOnDisabled);
        d.cycle(&out(0x0080, 0), &mut [0; INPUT_BYTES]);
        assert_eq!(d.state, PowerState::SwitchOnDisabled, "a held reset bit is not a new reset");
    }
}
