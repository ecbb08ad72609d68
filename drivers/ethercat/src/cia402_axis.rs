//! The MainDevice's side of a CiA 402 drive: read the statusword, choose
//! the controlword that walks the state machine towards *operation
//! enabled* (shutdown → switch on → enable operation), and pulse fault
//! reset (a rising edge of bit 7) while the drive is in fault.

/// Power states decoded from a statusword (0x6041).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PowerState {
    NotReadyToSwitchOn,
    SwitchOnDisabled,
    ReadyToSwitchOn,
    SwitchedOn,
    OperationEnabled,
    QuickStopActive,
    FaultReactionActive,
    Fault,
}

impl PowerState {
    /// The profile's decoding: bits 0–3, 5 and 6.
    pub const fn from_statusword(s: u16) -> Self {
        match (s & 0x004F, s & 0x006F) {
            (0x0000, _) => Self::NotReadyToSwitchOn,
            (0x0040, _) => Self::SwitchOnDisabled,
            (_, 0x0021) => Self::ReadyToSwitchOn,
            (_, 0x0023) => Self::SwitchedOn,
            (_, 0x0027) => Self::OperationEnabled,
            (_, 0x0007) => Self::QuickStopActive,
            (0x000F, _) => Self::FaultReactionActive,
            (0x0008, _) => Self::Fault,
            // Anything else is not a state of the profile: treat as fault.
            _ => Self::Fault,
        }
    }

    pub const fn is_fault(self) -> bool {
        matches!(self, Self::Fault | Self::FaultReactionActive)
    }
}

/// Controlword commands (0x6040).
pub mod controlword {
    pub const DISABLE_VOLTAGE: u16 = 0x0000;
    pub const SHUTDOWN: u16 = 0x0006;
    pub const SWITCH_ON: u16 = 0x0007;
    pub const ENABLE_OPERATION: u16 = 0x000F;
    pub const FAULT_RESET: u16 = 0x0080;
}

/// One axis's state-machine driver and its fault count.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Cia402Axis {
    /// Faults seen (entries into fault) since start.
    pub faults: u64,
    in_fault: bool,
    reset_high: bool,
}

impl Cia402Axis {
    /// Take in a statusword as it arrives (counts entries into fault).
    pub fn observe(&mut self, statusword: u16) {
        let fault = PowerState::from_statusword(statusword).is_fault();
        if fault && !self.in_fault {
            self.faults += 1;
        }
        self.in_fault = fault;
    }

    /// The controlword for this cycle given the drive's `statusword`.
    pub fn controlword(&mut self, statusword: u16) -> u16 {
        use controlword::*;
        let state = PowerState::from_statusword(statusword);
        if state != PowerState::Fault {
            self.reset_high = false;
        }
        match state {
            // A rising edge every other cycle until the drive leaves fault.
            PowerState::Fault => {
                self.reset_high = !self.reset_high;
                if self.reset_high { FAULT_RESET } else { DISABLE_VOLTAGE }
            }
            PowerState::NotReadyToSwitchOn
            | PowerState::FaultReactionActive
            | PowerState::QuickStopActive => DISABLE_VOLTAGE,
            PowerState::SwitchOnDisabled => SHUTDOWN,
            PowerState::ReadyToSwitchOn => SWITCH_ON,
            PowerState::SwitchedOn | PowerState::OperationEnabled => ENABLE_OPERATION,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn walks_to_operation_enabled_and_resets_faults_on_rising_edges() {
        let mut a = Cia402Axis::default();
        let step = |a: &mut Cia402Axis, s: u16| {
            a.observe(s);
            a.controlword(s)
        };
        assert_eq!(step(&mut a, 0x0240), controlword::SHUTDOWN);
        assert_eq!(step(&mut a, 0x0231), controlword::SWITCH_ON);
        assert_eq!(step(&mut a, 0x0233), controlword::ENABLE_OPERATION);
        assert_eq!(step(&mut a, 0x0237), controlword::ENABLE_OPERATION);
        assert_eq!(PowerState::from_statusword(0x0237), PowerState::OperationEnabled);
        let pulses: Vec<u16> = (0..4).map(|_| step(&mut a, 0x0208)).collect();
        assert_eq!(pulses, [0x0080, 0x0000, 0x0080, 0x0000]);
        assert_eq!(a.faults, 1, "one fault, however long it lasts");
        assert_eq!(step(&mut a, 0x0240), controlword::SHUTDOWN);
        step(&mut a, 0x0208);
        assert_eq!(a.faults, 2);
    }
}
