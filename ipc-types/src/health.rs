//! The core's health as wire codes: which part of the core is unwell and
//! why ([`crate::Telemetry::health_source`] / `health_cause`). A thread
//! that stops is permanent (the core holds the plate and exits); a driver
//! fault holds the plate until resumed.

use core::fmt;

crate::wire_code::wire_code! {
    /// Which part of the core reports a problem.
    pub enum HealthSource {
        Ok = 0 => "ok",
        MotorThread = 1 => "motor_thread",
        SolverThread = 2 => "solver_thread",
        ReceiverThread = 3 => "receiver_thread",
        Driver = 4 => "driver",
    }
}

crate::wire_code::wire_code! {
    /// What happened to it.
    pub enum HealthCause {
        None = 0 => "none",
        /// The thread panicked (the detail names where).
        Panicked = 1 => "panicked",
        /// The thread ended while the core was not stopping.
        Exited = 2 => "exited",
        /// The driver's read reported a hardware fault.
        DriverReadFault = 3 => "driver_read_fault",
        /// The driver's write reported a hardware fault.
        DriverWriteFault = 4 => "driver_write_fault",
    }
}

/// Bytes of [`crate::Telemetry::health_detail`].
pub const HEALTH_DETAIL_BYTES: usize = 120;

/// A fixed buffer that `write!` fills without allocating; text beyond the
/// capacity is cut at a character boundary.
#[derive(Debug, Clone, Copy)]
pub struct DetailText {
    pub bytes: [u8; HEALTH_DETAIL_BYTES],
    pub len: usize,
}

impl DetailText {
    pub const fn new() -> Self {
        Self { bytes: [0; HEALTH_DETAIL_BYTES], len: 0 }
    }

    /// The text so far.
    pub fn as_str(&self) -> &str {
        detail_str(&self.bytes)
    }
}

impl Default for DetailText {
    fn default() -> Self {
        Self::new()
    }
}

impl fmt::Write for DetailText {
    fn write_str(&mut self, s: &str) -> fmt::Result {
        for c in s.chars() {
            let mut utf8 = [0u8; 4];
            let c = c.encode_utf8(&mut utf8).as_bytes();
            let Some(dst) = self.bytes.get_mut(self.len..self.len + c.len()) else { break };
            dst.copy_from_slice(c);
            self.len += c.len();
        }
        Ok(())
    }
}

/// The text of a NUL-padded detail field: up to the first NUL, and up to
/// the last whole UTF-8 character (a hostile peer can write any bytes).
pub fn detail_str(bytes: &[u8]) -> &str {
    let end = bytes.iter().position(|&b| b == 0).unwrap_or(bytes.len());
    match core::str::from_utf8(&bytes[..end]) {
        Ok(s) => s,
        Err(e) => core::str::from_utf8(&bytes[..e.valid_up_to()]).unwrap_or_default(),
    }
}

#[cfg(test)]
mod tests {
    use core::fmt::Write;

    use super::*;

    #[test]
    fn codes_round_trip() {
        for code in 0..8 {
            if let Some(s) = HealthSource::from_code(code) {
                assert_eq!(s as u32, code);
            }
            if let Some(c) = HealthCause::from_code(code) {
                assert_eq!(c as u32, code);
            }
        }
        assert_eq!(HealthSource::from_code(5), None);
        assert_eq!(HealthCause::from_code(5), None);
    }

    #[test]
    fn detail_text_is_cut_at_a_character_boundary() {
        let mut d = DetailText::new();
        for _ in 0..100 {
            let _ = write!(d, "é");
        }
        assert_eq!(d.len, HEALTH_DETAIL_BYTES);
        assert_eq!(d.as_str().chars().count(), HEALTH_DETAIL_BYTES / 2);
        let mut bytes = [b'a'; 8];
        bytes[3] = 0xff;
        assert_eq!(detail_str(&bytes), "aaa");
    }
}
