//! One simulated SubDevice: the EtherCAT slave controller's memory (8 KiB:
//! registers below 0x1000, process RAM above) with the behaviour a
//! MainDevice relies on, and the CiA 402 drive behind it.
//!
//! - Read-only registers (type, features, DL status, AL status) ignore
//!   writes.
//! - AL control (0x0120) runs the state machine: INIT → PRE-OP needs both
//!   mailbox SyncManagers configured, PRE-OP → SAFE-OP needs the process
//!   data SyncManagers of the mapped size; a refused request sets the
//!   error bit (0x0130 bit 4) and a code (0x0134) until acknowledged.
//! - SII (0x0502): a read command copies 8 bytes of the EEPROM to 0x0508
//!   at once (never busy).
//! - Mailbox: a write that fills SM0's buffer to its last byte is a
//!   request; the reply lands in SM1's buffer with SM1's mailbox-full bit
//!   set, cleared when the MainDevice reads the buffer's last byte.
//! - Logical commands go through the enabled FMMUs; when outputs arrive the
//!   drive runs one cycle and refreshes the inputs.
//! - Distributed clocks (64-bit, enhanced sync): a local clock per device
//!   (the chain's time, the frame's arrival at this device, plus an epoch
//!   of its own); a write to port 0's receive time (0x0900) latches the
//!   receive times of ports 0 and 1 and of the processing unit (0x0918);
//!   system time (0x0910) reads local + offset (0x0920); a write to it
//!   (FRMW from the reference) is compared with the time plus the
//!   propagation delay (0x0928), the difference left in 0x092C and
//!   corrected by at most [`DC_STEP_NS`] per write, as an ESC's control
//!   loop converges. With SYNC0 active (0x0981, start 0x0990, cycle 0x09A0) the
//!   drive counts SYNC0 events and those that passed without fresh
//!   process data. Each clock may drift (`drift_ppb`).

use crate::cia402::{Drive, MAX_IMAGE, PowerState};
use crate::coe::{self, Identity};
use crate::logical_kind::LogicalKind;
use crate::sii;

const MEMORY: usize = 0x2000;

/// Registers.
mod reg {
    pub const TYPE: u16 = 0x0000;
    pub const FMMUS: u16 = 0x0004;
    pub const SYNC_MANAGERS: u16 = 0x0005;
    pub const RAM_KIB: u16 = 0x0006;
    pub const STATION: u16 = 0x0010;
    pub const DL_STATUS: u16 = 0x0110;
    pub const AL_CONTROL: u16 = 0x0120;
    pub const AL_STATUS: u16 = 0x0130;
    pub const AL_CODE: u16 = 0x0134;
    pub const SII_CONTROL: u16 = 0x0502;
    pub const SII_ADDRESS: u16 = 0x0504;
    pub const SII_DATA: u16 = 0x0508;
    pub const FMMU: u16 = 0x0600;
    pub const SM: u16 = 0x0800;
    pub const FEATURES: u16 = 0x0008;
    pub const DC_TIME_PORT0: u16 = 0x0900;
    pub const DC_TIME_PORT1: u16 = 0x0904;
    pub const DC_SYSTEM_TIME: u16 = 0x0910;
    pub const DC_RECEIVE_TIME: u16 = 0x0918;
    pub const DC_OFFSET: u16 = 0x0920;
    pub const DC_DELAY: u16 = 0x0928;
    pub const DC_DIFFERENCE: u16 = 0x092C;
    pub const DC_ACTIVATION: u16 = 0x0981;
    pub const DC_START: u16 = 0x0990;
    pub const DC_SYNC0_CYCLE: u16 = 0x09A0;
}

/// The most one distributed system-time write corrects a clock by.
pub const DC_STEP_NS: i64 = 100;

/// Features: DC supported (bit 2), 64-bit (bit 3), enhanced DC sync (bit 8).
const FEATURES_DC: u16 = 0x010C;

/// AL status codes (ETG.1000.6).
pub mod al_code {
    pub const INVALID_TRANSITION: u16 = 0x0011;
    pub const INVALID_MAILBOX: u16 = 0x0016;
    pub const INVALID_OUTPUTS: u16 = 0x001D;
    pub const INVALID_INPUTS: u16 = 0x001E;
}

/// EtherCAT states as AL status has them.
pub mod al_state {
    pub const INIT: u8 = 1;
    pub const PRE_OP: u8 = 2;
    pub const SAFE_OP: u8 = 4;
    pub const OP: u8 = 8;
}

#[derive(Debug, Clone)]
pub struct SubDevice {
    mem: Vec<u8>,
    eeprom: Vec<u8>,
    pub identity: Identity,
    pub drive: Drive,
    /// Process-data cycles run (outputs received).
    pub cycles: u64,
    /// Where this device's local clock starts (ns): every device's differs.
    pub clock_epoch_ns: u64,
    /// How fast the local clock runs against the chain's time (parts per
    /// billion; a crystal is typically within ±50 000).
    pub drift_ppb: i64,
    /// The chain's time as the current frame reaches this device, and how
    /// long it takes to come back through port 1 from the devices after.
    arrival_ns: u64,
    return_ns: u64,
    /// What the drift control has added to the local clock so far.
    correction_ns: i64,
    /// SYNC0 events seen at process-data cycles; those that passed without
    /// fresh outputs (a frame late or lost); the last event's index.
    pub sync0_events: u64,
    pub sync0_missed: u64,
    last_sync0: Option<u64>,
}

impl SubDevice {
    /// A CiA 402 servo drive with UPM's simulated identity.
    pub fn servo_drive() -> Self {
        Self::with_identity(Identity { vendor: 0x0055_504D, product: 0x0000_0402, revision: 1, serial: 0 })
    }

    pub fn with_identity(identity: Identity) -> Self {
        let mut d = Self {
            mem: vec![0; MEMORY],
            eeprom: sii::image(&identity),
            identity,
            drive: Drive::default(),
            cycles: 0,
            clock_epoch_ns: 0,
            drift_ppb: 0,
            arrival_ns: 0,
            return_ns: 0,
            correction_ns: 0,
            sync0_events: 0,
            sync0_missed: 0,
            last_sync0: None,
        };
        d.mem[usize::from(reg::TYPE)] = 0x11;
        d.mem[usize::from(reg::FMMUS)] = 16;
        d.mem[usize::from(reg::SYNC_MANAGERS)] = 16;
        d.mem[usize::from(reg::RAM_KIB)] = ((MEMORY - 0x1000) / 1024) as u8;
        d.set_u16(reg::FEATURES, FEATURES_DC);
        d.set_u16(reg::SII_CONTROL, 0x0040);
        d.set_u16(reg::AL_STATUS, u16::from(al_state::INIT));
        d.set_links(false);
        d
    }

    /// DL status: port 0 open, and port 1 when another SubDevice follows.
    pub fn set_links(&mut self, successor: bool) {
        self.set_u16(reg::DL_STATUS, if successor { 0x0030 } else { 0x0010 });
    }

    /// The chain's time when the frame now passing reaches this device, and
    /// how much later it passes again on its way back (port 1).
    pub fn set_arrival(&mut self, arrival_ns: u64, return_ns: u64) {
        self.arrival_ns = arrival_ns;
        self.return_ns = return_ns;
    }

    fn local_time(&self) -> u64 {
        let drift = (i128::from(self.arrival_ns) * i128::from(self.drift_ppb) / 1_000_000_000) as i64;
        self.arrival_ns
            .wrapping_add(self.clock_epoch_ns)
            .wrapping_add_signed(drift)
            .wrapping_add_signed(self.correction_ns)
    }

    /// DC system time: local clock + offset.
    pub fn system_time(&self) -> u64 {
        let offset = i64::from_le_bytes(self.bytes(reg::DC_OFFSET));
        self.local_time().wrapping_add_signed(offset)
    }

    /// The difference a FRMW of the reference's time left (0x092C), as
    /// received minus own (ns): positive when this clock is behind.
    pub fn system_time_difference(&self) -> i64 {
        let d = u32::from_le_bytes(self.bytes(reg::DC_DIFFERENCE));
        let magnitude = i64::from(d & 0x7FFF_FFFF);
        if d & 0x8000_0000 != 0 { magnitude } else { -magnitude }
    }

    fn bytes<const N: usize>(&self, at: u16) -> [u8; N] {
        let a = usize::from(at);
        let mut b = [0u8; N];
        b.copy_from_slice(&self.mem[a..a + N]);
        b
    }

    fn set_bytes(&mut self, at: u16, b: &[u8]) {
        let a = usize::from(at);
        self.mem[a..a + b.len()].copy_from_slice(b);
    }

    pub fn station_address(&self) -> u16 {
        self.u16_at(reg::STATION)
    }

    /// The EtherCAT state (AL status bits 0–3) and whether its error bit is set.
    pub fn al_state(&self) -> (u8, bool) {
        let s = self.u16_at(reg::AL_STATUS);
        ((s & 0x0F) as u8, s & 0x10 != 0)
    }

    fn u16_at(&self, at: u16) -> u16 {
        let a = usize::from(at);
        u16::from_le_bytes([self.mem[a], self.mem[a + 1]])
    }

    fn set_u16(&mut self, at: u16, v: u16) {
        let a = usize::from(at);
        self.mem[a..a + 2].copy_from_slice(&v.to_le_bytes());
    }

    /// SyncManager `n`: start, length, enabled.
    fn sync_manager(&self, n: u16) -> (u16, u16, bool) {
        let base = reg::SM + 8 * n;
        (self.u16_at(base), self.u16_at(base + 2), self.mem[usize::from(base + 6)] & 1 != 0)
    }

    fn read_only(at: usize) -> bool {
        let at = at as u16;
        at < 0x0010
            || (reg::DL_STATUS..reg::DL_STATUS + 2).contains(&at)
            || (reg::AL_STATUS..reg::AL_CODE + 2).contains(&at)
            || (reg::DC_TIME_PORT0..reg::DC_OFFSET).contains(&at)
            || (reg::DC_DIFFERENCE..reg::DC_DIFFERENCE + 4).contains(&at)
    }

    fn overlaps(span: &core::ops::Range<usize>, at: u16, len: usize) -> bool {
        span.start < usize::from(at) + len && usize::from(at) < span.end
    }

    /// Registers whose value is the moment's: system time.
    fn before_read(&mut self, span: &core::ops::Range<usize>) {
        if Self::overlaps(span, reg::DC_SYSTEM_TIME, 8) {
            let t = self.system_time();
            self.set_bytes(reg::DC_SYSTEM_TIME, &t.to_le_bytes());
        }
    }

    /// Bytes `[ado, ado + len)` that exist, as a range of the memory.
    fn span(ado: u16, len: usize) -> core::ops::Range<usize> {
        let start = usize::from(ado).min(MEMORY);
        start..(start + len).min(MEMORY)
    }

    /// FPRD / APRD: copy registers into `data`; returns the WKC added.
    pub fn read(&mut self, ado: u16, data: &mut [u8]) -> u16 {
        let span = Self::span(ado, data.len());
        self.before_read(&span);
        data.fill(0);
        data[..span.len()].copy_from_slice(&self.mem[span.clone()]);
        self.after_read(span);
        1
    }

    /// BRD: OR registers into `data`.
    pub fn read_or(&mut self, ado: u16, data: &mut [u8]) -> u16 {
        let span = Self::span(ado, data.len());
        self.before_read(&span);
        for (d, m) in data.iter_mut().zip(&self.mem[span.clone()]) {
            *d |= *m;
        }
        self.after_read(span);
        1
    }

    /// FPWR / APWR / BWR: write `data` into the registers that take it.
    pub fn write(&mut self, ado: u16, data: &[u8]) -> u16 {
        let span = Self::span(ado, data.len());
        if !span.is_empty() && span.start == usize::from(reg::DC_SYSTEM_TIME) {
            self.compare_system_time(data);
        }
        for (k, a) in span.clone().enumerate() {
            if !Self::read_only(a) {
                self.mem[a] = data[k];
            }
        }
        self.after_write(span);
        1
    }

    /// FPRW / APRW: the old contents come back, `data` is written.
    pub fn read_write(&mut self, ado: u16, data: &mut [u8]) -> u16 {
        let mut old = [0u8; 2048];
        let n = data.len().min(old.len());
        self.read(ado, &mut old[..n]);
        self.write(ado, data);
        data[..n].copy_from_slice(&old[..n]);
        3
    }

    /// BRW: ORed old contents come back, `data` is written.
    pub fn read_or_write(&mut self, ado: u16, data: &mut [u8]) -> u16 {
        let mut written = [0u8; 2048];
        let n = data.len().min(written.len());
        written[..n].copy_from_slice(&data[..n]);
        self.read_or(ado, data);
        self.write(ado, &written[..n]);
        3
    }

    fn after_read(&mut self, span: core::ops::Range<usize>) {
        let (start, len, on) = self.sync_manager(1);
        let last = usize::from(start) + usize::from(len);
        if on && len > 0 && span.contains(&(last - 1)) {
            self.mem[usize::from(reg::SM + 8 + 5)] &= !0x08;
        }
    }

    /// The reference's system time arrives (FRMW): it was sent the
    /// propagation delay ago; keep the difference and correct towards it.
    fn compare_system_time(&mut self, data: &[u8]) {
        let mut b = [0u8; 8];
        let n = data.len().min(8);
        b[..n].copy_from_slice(&data[..n]);
        let delay = u64::from(u32::from_le_bytes(self.bytes(reg::DC_DELAY)));
        let own = if n == 8 { self.system_time() } else { self.system_time() & 0xFFFF_FFFF };
        let diff = u64::from_le_bytes(b).wrapping_add(delay).wrapping_sub(own) as i64;
        self.correction_ns += diff.clamp(-DC_STEP_NS, DC_STEP_NS);
        let magnitude = diff.unsigned_abs().min(0x7FFF_FFFF) as u32;
        // Bit 31: this clock is behind the time received (the ESC's sense).
        let sign = if diff > 0 { 0x8000_0000 } else { 0 };
        self.set_bytes(reg::DC_DIFFERENCE, &(magnitude | sign).to_le_bytes());
    }

    /// A write to port 0's receive time latches every receive time.
    fn latch_receive_times(&mut self) {
        let here = self.local_time();
        let back = if self.return_ns > 0 { here.wrapping_add(self.return_ns) } else { 0 };
        self.set_bytes(reg::DC_TIME_PORT0, &(here as u32).to_le_bytes());
        self.set_bytes(reg::DC_TIME_PORT1, &(back as u32).to_le_bytes());
        self.set_bytes(reg::DC_RECEIVE_TIME, &here.to_le_bytes());
    }

    /// SYNC0 events since the last process-data cycle.
    fn count_sync0(&mut self) {
        let active = self.mem[usize::from(reg::DC_ACTIVATION)] & 0x03 == 0x03;
        let start = u64::from_le_bytes(self.bytes(reg::DC_START));
        let cycle = u64::from(u32::from_le_bytes(self.bytes(reg::DC_SYNC0_CYCLE)));
        let now = self.system_time();
        if !active || cycle == 0 || now < start {
            self.last_sync0 = None;
            return;
        }
        let k = (now - start) / cycle;
        if let Some(last) = self.last_sync0 {
            let events = k.saturating_sub(last);
            self.sync0_events += events;
            self.sync0_missed += events.saturating_sub(1);
        }
        self.last_sync0 = Some(k);
    }

    fn after_write(&mut self, span: core::ops::Range<usize>) {
        let touches = |at: u16, len: usize| span.start < usize::from(at) + len && usize::from(at) < span.end;
        if touches(reg::DC_TIME_PORT0, 4) {
            self.latch_receive_times();
        }
        if touches(reg::AL_CONTROL, 2) {
            self.al_control();
        }
        if touches(reg::SII_CONTROL, 2) {
            self.sii_command();
        }
        let (start, len, on) = self.sync_manager(0);
        let last = usize::from(start) + usize::from(len);
        if on && len > 0 && last <= MEMORY && span.contains(&(last - 1)) {
            self.mailbox(usize::from(start)..last);
        }
    }

    fn al_control(&mut self) {
        use al_state::*;
        let control = self.u16_at(reg::AL_CONTROL);
        let (want, ack) = ((control & 0x0F) as u8, control & 0x10 != 0);
        let (now, error) = self.al_state();
        if error && !ack {
            return;
        }
        let outcome = match (now, want) {
            (_, INIT) => Ok(()),
            (INIT | PRE_OP, PRE_OP) => self.mailbox_configured(),
            (SAFE_OP | OP, PRE_OP) => Ok(()),
            (PRE_OP | SAFE_OP | OP, SAFE_OP) => self.process_data_configured(),
            (SAFE_OP | OP, OP) => Ok(()),
            _ => Err(al_code::INVALID_TRANSITION),
        };
        match outcome {
            Ok(()) => {
                self.set_u16(reg::AL_STATUS, u16::from(want));
                self.set_u16(reg::AL_CODE, 0);
                if want == SAFE_OP || want == OP {
                    // Inputs are valid from SAFE-OP on.
                    let inp = usize::from(sii::INPUTS_AT);
                    let n = self.drive.tx.bytes().min(MAX_IMAGE);
                    self.drive.inputs(&mut self.mem[inp..inp + n]);
                }
                if want != OP && self.drive.state == PowerState::OperationEnabled {
                    // Leaving OP stops the drive, as a real one does.
                    self.drive.command(0);
                }
            }
            Err(code) => {
                self.set_u16(reg::AL_STATUS, u16::from(now) | 0x10);
                self.set_u16(reg::AL_CODE, code);
            }
        }
    }

    fn mailbox_configured(&self) -> Result<(), u16> {
        let ok = |n, at| {
            let (start, len, on) = self.sync_manager(n);
            on && start == at && len == sii::MAILBOX_BYTES
        };
        if ok(0, sii::MAILBOX_OUT) && ok(1, sii::MAILBOX_IN) { Ok(()) } else { Err(al_code::INVALID_MAILBOX) }
    }

    fn process_data_configured(&self) -> Result<(), u16> {
        let ok = |n, at, bytes: usize| {
            let (start, len, on) = self.sync_manager(n);
            on && start == at && usize::from(len) == bytes
        };
        if !ok(2, sii::OUTPUTS_AT, self.drive.rx.bytes()) {
            return Err(al_code::INVALID_OUTPUTS);
        }
        if !ok(3, sii::INPUTS_AT, self.drive.tx.bytes()) {
            return Err(al_code::INVALID_INPUTS);
        }
        Ok(())
    }

    fn sii_command(&mut self) {
        let control = self.u16_at(reg::SII_CONTROL);
        if control & 0x0100 != 0 {
            let a = usize::from(reg::SII_ADDRESS);
            let word = u32::from_le_bytes([self.mem[a], self.mem[a + 1], self.mem[a + 2], self.mem[a + 3]]);
            let at = (word as usize).saturating_mul(2);
            let data = usize::from(reg::SII_DATA);
            for k in 0..8 {
                self.mem[data + k] = self.eeprom.get(at + k).copied().unwrap_or(0);
            }
        }
        // Done at once: not busy, no error, 8-byte reads.
        self.set_u16(reg::SII_CONTROL, 0x0040);
    }

    fn mailbox(&mut self, request: core::ops::Range<usize>) {
        let mut req = [0u8; sii::MAILBOX_BYTES as usize];
        let n = request.len().min(req.len());
        req[..n].copy_from_slice(&self.mem[request.start..request.start + n]);
        let mut reply = [0u8; coe::SDO_BYTES];
        let Some(len) = coe::answer(&req[..n], &mut reply, &mut self.drive, &self.identity) else { return };
        let (start, size, on) = self.sync_manager(1);
        let at = usize::from(start);
        if !on || usize::from(size) < len || at + len > MEMORY {
            return;
        }
        self.mem[at..at + usize::from(size).min(MEMORY - at)].fill(0);
        self.mem[at..at + len].copy_from_slice(&reply[..len]);
        self.mem[usize::from(reg::SM + 8 + 5)] |= 0x08;
    }

    /// LRD / LWR / LRW through the enabled FMMUs; returns the WKC added
    /// (1 for inputs read, 2 for outputs written).
    pub fn logical(&mut self, kind: LogicalKind, address: u32, data: &mut [u8]) -> u16 {
        let (mut read, mut wrote) = (false, false);
        let end = u64::from(address) + data.len() as u64;
        for f in 0..16u16 {
            let b = usize::from(reg::FMMU + 16 * f);
            let m = &self.mem;
            if m[b + 12] & 1 == 0 {
                continue;
            }
            let start = u32::from_le_bytes([m[b], m[b + 1], m[b + 2], m[b + 3]]);
            let len = u16::from_le_bytes([m[b + 4], m[b + 5]]);
            let phys = usize::from(u16::from_le_bytes([m[b + 8], m[b + 9]]));
            let direction = m[b + 11];
            let lo = u64::from(start).max(u64::from(address));
            let hi = (u64::from(start) + u64::from(len)).min(end);
            if lo >= hi {
                continue;
            }
            let (in_frame, in_mem) =
                ((lo - u64::from(address)) as usize, phys + (lo - u64::from(start)) as usize);
            if in_mem >= MEMORY {
                // Mapped beyond this device's memory: nothing there.
                continue;
            }
            let n = ((hi - lo) as usize).min(MEMORY - in_mem);
            if direction & 1 != 0 && kind.read {
                data[in_frame..in_frame + n].copy_from_slice(&self.mem[in_mem..in_mem + n]);
                read = true;
            }
            if direction & 2 != 0 && kind.write {
                self.mem[in_mem..in_mem + n].copy_from_slice(&data[in_frame..in_frame + n]);
                wrote = true;
            }
        }
        if wrote {
            self.process_data_cycle();
        }
        u16::from(read) + 2 * u16::from(wrote)
    }

    /// The drive reads its outputs (in OP only; a real drive ignores them
    /// below) and refreshes its inputs.
    fn process_data_cycle(&mut self) {
        let (state, _) = self.al_state();
        let out = usize::from(sii::OUTPUTS_AT);
        let inp = usize::from(sii::INPUTS_AT);
        let mut inputs = [0u8; MAX_IMAGE];
        if state == al_state::OP {
            let mut outputs = [0u8; MAX_IMAGE];
            let n = self.drive.rx.bytes().min(MAX_IMAGE);
            outputs[..n].copy_from_slice(&self.mem[out..out + n]);
            self.cycles += 1;
            self.count_sync0();
            self.drive.cycle(&outputs[..n], &mut inputs);
        } else {
            self.drive.inputs(&mut inputs);
        }
        let n = self.drive.tx.bytes().min(MAX_IMAGE);
        self.mem[inp..inp + n].copy_from_slice(&inputs[..n]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn request(d: &mut SubDevice, state: u16) {
        d.write(reg::AL_CONTROL, &state.to_le_bytes());
    }

    #[test]
    fn refused_transitions_set_the_error_and_its_code_until_acknowledged() {
        let mut d = SubDevice::servo_drive();
        request(&mut d, u16::from(al_state::OP));
        assert_eq!(d.al_state(), (al_state::INIT, true));
        assert_eq!(d.u16_at(reg::AL_CODE), al_code::INVALID_TRANSITION);
        // Mailboxes not configured: PRE-OP is refused too, but only after
        // the error is acknowledged; until then requests are ignored.
        request(&mut d, u16::from(al_state::PRE_OP));
        assert_eq!(d.u16_at(reg::AL_CODE), al_code::INVALID_TRANSITION);
        request(&mut d, 0x10 | u16::from(al_state::PRE_OP));
        assert_eq!(
            (d.al_state(), d.u16_at(reg::AL_CODE)),
            ((al_state::INIT, true), al_code::INVALID_MAILBOX)
        );
        request(&mut d, 0x11);
        assert_eq!((d.al_state(), d.u16_at(reg::AL_CODE)), ((al_state::INIT, false), 0));
        // Read-only registers stay.
        d.write(reg::AL_STATUS, &[8, 0]);
        assert_eq!(d.al_state(), (al_state::INIT, false));
    }

    #[test]
    fn sii_reads_return_eight_bytes_of_the_eeprom() {
        let mut d = SubDevice::servo_drive();
        // Read command at word 0x0008 (vendor id).
        d.write(reg::SII_CONTROL, &[0x00, 0x01, 0x08, 0x00, 0x00, 0x00]);
        let mut data = [0u8; 8];
        d.read(reg::SII_DATA, &mut data);
        assert_eq!(u32::from_le_bytes([data[0], data[1], data[2], data[3]]), 0x0055_504D);
        let mut status = [0u8; 2];
        d.read(reg::SII_CONTROL, &mut status);
        assert_eq!(u16::from_le_bytes(status), 0x0040, "idle, 8-byte reads");
        // Past the end: zeros, no panic.
        d.write(reg::SII_CONTROL, &[0x00, 0x01, 0xFF, 0xFF, 0xFF, 0xFF]);
        d.read(reg::SII_DATA, &mut data);
        assert_eq!(data, [0; 8]);
    }
}
