//! The drive behind each simulated SubDevice: the CiA 402 state machine
//! (controlword 0x6040 → statusword 0x6041) and cyclic synchronous
//! position mode (0x6060 = 8): in *operation enabled* the actual position
//! (0x6064) follows the target (0x607A). A drive can be put into fault
//! (statusword bit 3); a rising fault-reset bit (controlword bit 7) clears
//! it back to *switch on disabled*.
//!
//! Process image, as the default PDO mapping (0x1600 / 0x1A00) lays it out
//! (little-endian, packed):
//! outputs (SM2) `controlword u16, target i32, velocity offset i32,
//! torque offset i16, mode i8`; inputs (SM3) `statusword u16, actual i32,
//! torque actual i16, mode display i8`. Torques are per mille of the rated
//! torque (0x6076), as the profile has them.

/// Bytes of the output and of the input image.
pub const OUTPUT_BYTES: usize = 13;
pub const INPUT_BYTES: usize = 9;

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

    /// One cycle of process data: read the outputs, move, report.
    pub fn cycle(&mut self, outputs: &[u8; OUTPUT_BYTES]) -> [u8; INPUT_BYTES] {
        self.command(u16::from_le_bytes([outputs[0], outputs[1]]));
        self.target = i32::from_le_bytes([outputs[2], outputs[3], outputs[4], outputs[5]]);
        self.velocity_offset = i32::from_le_bytes([outputs[6], outputs[7], outputs[8], outputs[9]]);
        self.torque_offset = i16::from_le_bytes([outputs[10], outputs[11]]);
        self.mode = outputs[12] as i8;
        if self.is_following() {
            if self.target.abs_diff(self.actual) > self.following_error_window {
                self.fault();
            } else if self.servo == Servo::Instant {
                self.actual = self.target;
            }
        }
        self.inputs()
    }

    /// Operation enabled in cyclic synchronous position: the target moves
    /// the drive.
    pub fn is_following(&self) -> bool {
        self.state == PowerState::OperationEnabled && self.mode == MODE_CSP
    }

    /// The input image as it stands.
    pub fn inputs(&self) -> [u8; INPUT_BYTES] {
        let mut i = [0u8; INPUT_BYTES];
        i[..2].copy_from_slice(&self.statusword().to_le_bytes());
        i[2..6].copy_from_slice(&self.actual.to_le_bytes());
        i[6..8].copy_from_slice(&self.torque_actual.to_le_bytes());
        i[8] = self.mode as u8;
        i
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
        d.cycle(&out(0x0006, 0));
        assert_eq!(d.state, PowerState::ReadyToSwitchOn);
        d.cycle(&out(0x0007, 0));
        assert_eq!(d.state, PowerState::SwitchedOn);
        d.cycle(&out(0x000F, 0));
        assert_eq!(d.state, PowerState::OperationEnabled);
        let inputs = d.cycle(&out(0x000F, 1234));
        assert_eq!(i32::from_le_bytes([inputs[2], inputs[3], inputs[4], inputs[5]]), 1234);
        assert_eq!(u16::from_le_bytes([inputs[0], inputs[1]]) & 0x006F, 0x0027);
    }

    #[test]
    fn a_fault_holds_until_a_rising_fault_reset() {
        let mut d = Drive { following_error_window: 100, ..Drive::default() };
        for cw in [0x0006, 0x0007, 0x000F] {
            d.cycle(&out(cw, 0));
        }
        d.cycle(&out(0x000F, 500));
        assert_eq!((d.state, d.actual, d.faults), (PowerState::Fault, 0, 1), "following error");
        d.cycle(&out(0x000F, 0));
        assert_eq!(d.state, PowerState::Fault, "enable does not clear a fault");
        d.cycle(&out(0x0080, 0));
        assert_eq!(d.state, PowerState::SwitchOnDisabled);
        d.cycle(&out(0x0080, 0));
        assert_eq!(d.state, PowerState::SwitchOnDisabled, "a held reset bit is not a new reset");
    }
}
