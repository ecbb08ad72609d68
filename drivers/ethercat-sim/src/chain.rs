//! A chain of SubDevices answering EtherCAT frames in place, as the frame
//! would come back from the last port of a real chain: each datagram passes
//! every SubDevice in order; each acts on it by command and address, adds
//! to the working counter, and (auto-increment and broadcast commands)
//! counts the address on.
//!
//! Frame layout: Ethernet header (14 bytes, EtherType 0x88A4), EtherCAT
//! header (u16: length of the datagrams in bits 0–10, type 1 in bits
//! 12–15), then datagrams of `cmd u8, index u8, address u32, flags u16
//! (length bits 0–10, more-follows bit 15), irq u16, data, wkc u16`.

use core::fmt;

use crate::logical_kind::LogicalKind;
use crate::subdevice::SubDevice;

/// EtherType of EtherCAT frames.
pub const ETHERTYPE: u16 = 0x88A4;
const ETH_HEADER: usize = 14;
const DATAGRAM_HEADER: usize = 10;

/// Why a frame was not answered (it is left as it was).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FrameError {
    /// Shorter than an Ethernet and an EtherCAT header.
    TooShort,
    /// Another EtherType.
    NotEtherCat,
    /// EtherCAT header type is not 1 (datagrams), or its length is 0.
    BadHeader,
    /// A datagram runs past the end of the frame.
    Overrun,
    /// Lost on the wire, as injected by [`Chain::lose_frames`].
    Lost,
}

impl fmt::Display for FrameError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::TooShort => "frame shorter than its headers",
            Self::NotEtherCat => "not an EtherCAT frame (EtherType)",
            Self::BadHeader => "EtherCAT header: not a datagram frame, or empty",
            Self::Overrun => "a datagram runs past the end of the frame",
            Self::Lost => "lost on the wire (injected)",
        })
    }
}

impl core::error::Error for FrameError {}

/// EtherCAT commands.
mod cmd {
    pub const NOP: u8 = 0;
    pub const APRD: u8 = 1;
    pub const APWR: u8 = 2;
    pub const APRW: u8 = 3;
    pub const FPRD: u8 = 4;
    pub const FPWR: u8 = 5;
    pub const FPRW: u8 = 6;
    pub const BRD: u8 = 7;
    pub const BWR: u8 = 8;
    pub const BRW: u8 = 9;
    pub const LRD: u8 = 10;
    pub const LWR: u8 = 11;
    pub const LRW: u8 = 12;
    pub const ARMW: u8 = 13;
    pub const FRMW: u8 = 14;
}

/// The simulated chain, first SubDevice first.
#[derive(Debug)]
pub struct Chain {
    pub devices: Vec<SubDevice>,
    /// Frames answered, and refused (with why, the last one).
    pub answered: u64,
    pub refused: u64,
    pub last_refusal: Option<FrameError>,
    /// SubDevices a frame reaches: fewer than all when the cable is cut
    /// after one ([`Chain::cut_after`]).
    reachable: usize,
    /// Frames still to be lost ([`Chain::lose_frames`]).
    to_lose: u32,
    /// Answers still to be garbled ([`Chain::garble_frames`]).
    to_garble: u32,
    /// The time (ns) a frame enters the chain ([`Chain::set_time`]).
    time_ns: u64,
}

/// A frame's passage from one device to the next (cable and forwarding).
pub const HOP_NS: u64 = 700;

impl Chain {
    /// The chain in this order; each SubDevice's links say whether
    /// another follows it.
    pub fn new(mut devices: Vec<SubDevice>) -> Self {
        let n = devices.len();
        for (i, d) in devices.iter_mut().enumerate() {
            d.set_links(i + 1 < n);
        }
        for (i, d) in devices.iter_mut().enumerate() {
            // Clocks that started at different moments, as after power-up.
            d.clock_epoch_ns = (i as u64 + 1) * 1_234_567_891;
        }
        Self {
            devices,
            answered: 0,
            refused: 0,
            last_refusal: None,
            reachable: n,
            to_lose: 0,
            to_garble: 0,
            time_ns: 0,
        }
    }

    /// The time the next frame enters the chain (ns, the plant's clock).
    pub fn set_time(&mut self, ns: u64) {
        self.time_ns = ns;
    }

    /// Cut the chain after its first `n` SubDevices (the rest disappear
    /// from the wire, as with a pulled cable); `n` ≥ the length mends it.
    pub fn cut_after(&mut self, n: usize) {
        self.reachable = n.min(self.devices.len());
    }

    /// Lose the next `n` frames (no answer at all).
    pub fn lose_frames(&mut self, n: u32) {
        self.to_lose = n;
    }

    /// Garble the next `n` answers (the EtherCAT header claims more than
    /// the frame holds), as a faulty link might.
    pub fn garble_frames(&mut self, n: u32) {
        self.to_garble = n;
    }

    /// Answer `frame` in place. A refused frame is counted and left as it
    /// was (a real chain would drop it; the MainDevice times out).
    pub fn answer(&mut self, frame: &mut [u8]) -> Result<(), FrameError> {
        let result = self.process(frame);
        if result.is_ok() && self.to_garble > 0 {
            self.to_garble -= 1;
            frame[14..16].copy_from_slice(&0x17FFu16.to_le_bytes());
        }
        match result {
            Ok(()) => self.answered += 1,
            Err(e) => {
                self.refused += 1;
                self.last_refusal = Some(e);
            }
        }
        result
    }

    fn process(&mut self, frame: &mut [u8]) -> Result<(), FrameError> {
        if self.to_lose > 0 {
            self.to_lose -= 1;
            return Err(FrameError::Lost);
        }
        if frame.len() < ETH_HEADER + 2 {
            return Err(FrameError::TooShort);
        }
        if u16::from_be_bytes([frame[12], frame[13]]) != ETHERTYPE {
            return Err(FrameError::NotEtherCat);
        }
        let header = u16::from_le_bytes([frame[14], frame[15]]);
        let length = usize::from(header & 0x07FF);
        if header >> 12 != 1 || length == 0 {
            return Err(FrameError::BadHeader);
        }
        let body = frame.get(ETH_HEADER + 2..ETH_HEADER + 2 + length).ok_or(FrameError::Overrun)?;
        // Check every datagram fits before touching any device.
        let mut spans = [(0usize, 0usize); 256];
        let mut count = 0;
        let mut at = 0;
        loop {
            let h = body.get(at..at + DATAGRAM_HEADER).ok_or(FrameError::Overrun)?;
            let flags = u16::from_le_bytes([h[6], h[7]]);
            let len = usize::from(flags & 0x07FF);
            let end = at + DATAGRAM_HEADER + len + 2;
            if end > body.len() || count == spans.len() {
                return Err(FrameError::Overrun);
            }
            spans[count] = (at, len);
            count += 1;
            at = end;
            if flags & 0x8000 == 0 {
                break;
            }
        }
        // The reply's source MAC marks it as having passed a SubDevice
        // (a MainDevice ignores its own frames coming back untouched).
        frame[6] |= 0x02;
        let last = self.reachable.saturating_sub(1) as u64;
        for (i, d) in self.devices[..self.reachable].iter_mut().enumerate() {
            let i = i as u64;
            d.set_arrival(self.time_ns + i * HOP_NS, 2 * (last - i) * HOP_NS);
        }
        let body = &mut frame[ETH_HEADER + 2..ETH_HEADER + 2 + length];
        for &(at, len) in &spans[..count] {
            let (head, rest) = body[at..].split_at_mut(DATAGRAM_HEADER);
            let (data, tail) = rest.split_at_mut(len);
            let mut wkc = u16::from_le_bytes([tail[0], tail[1]]);
            self.datagram(head, data, &mut wkc);
            tail[..2].copy_from_slice(&wkc.to_le_bytes());
        }
        Ok(())
    }

    /// One datagram through every SubDevice.
    fn datagram(&mut self, head: &mut [u8], data: &mut [u8], wkc: &mut u16) {
        let command = head[0];
        let mut adp = u16::from_le_bytes([head[2], head[3]]);
        let ado = u16::from_le_bytes([head[4], head[5]]);
        let logical = u32::from_le_bytes([head[2], head[3], head[4], head[5]]);
        for d in &mut self.devices[..self.reachable] {
            let here = adp == 0;
            let fixed = adp == d.station_address();
            let add = match command {
                cmd::APRD if here => d.read(ado, data),
                cmd::APWR if here => d.write(ado, data),
                cmd::APRW if here => d.read_write(ado, data),
                cmd::FPRD if fixed => d.read(ado, data),
                cmd::FPWR if fixed => d.write(ado, data),
                cmd::FPRW if fixed => d.read_write(ado, data),
                cmd::BRD => d.read_or(ado, data),
                cmd::BWR => d.write(ado, data),
                cmd::BRW => d.read_or_write(ado, data),
                cmd::LRD | cmd::LWR | cmd::LRW => d.logical(command_kind(command), logical, data),
                cmd::ARMW if here => d.read(ado, data),
                cmd::ARMW => d.write(ado, data),
                cmd::FRMW if fixed => d.read(ado, data),
                cmd::FRMW => d.write(ado, data),
                _ => 0,
            };
            *wkc = wkc.wrapping_add(add);
            if matches!(
                command,
                cmd::APRD | cmd::APWR | cmd::APRW | cmd::BRD | cmd::BWR | cmd::BRW | cmd::ARMW
            ) {
                adp = adp.wrapping_add(1);
            }
        }
        if command != cmd::NOP && !matches!(command, cmd::LRD | cmd::LWR | cmd::LRW) {
            head[2..4].copy_from_slice(&adp.to_le_bytes());
        }
    }
}

fn command_kind(command: u8) -> LogicalKind {
    LogicalKind { read: command != cmd::LWR, write: command != cmd::LRD }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(datagrams: &[(u8, u32, &[u8])]) -> Vec<u8> {
        let mut f = vec![0xFF; 6];
        f.extend_from_slice(&[0x10; 6]);
        f.extend_from_slice(&ETHERTYPE.to_be_bytes());
        let body: usize = datagrams.iter().map(|d| DATAGRAM_HEADER + d.2.len() + 2).sum();
        f.extend_from_slice(&(body as u16 | 0x1000).to_le_bytes());
        for (i, (c, addr, data)) in datagrams.iter().enumerate() {
            let more = if i + 1 < datagrams.len() { 0x8000 } else { 0 };
            f.push(*c);
            f.push(i as u8);
            f.extend_from_slice(&addr.to_le_bytes());
            f.extend_from_slice(&(data.len() as u16 | more).to_le_bytes());
            f.extend_from_slice(&[0, 0]);
            f.extend_from_slice(data);
            f.extend_from_slice(&[0, 0]);
        }
        f
    }

    fn wkc(f: &[u8], nth: usize) -> u16 {
        let mut at = ETH_HEADER + 2;
        for _ in 0..nth {
            let len = usize::from(u16::from_le_bytes([f[at + 6], f[at + 7]]) & 0x7FF);
            at += DATAGRAM_HEADER + len + 2;
        }
        let len = usize::from(u16::from_le_bytes([f[at + 6], f[at + 7]]) & 0x7FF);
        u16::from_le_bytes([f[at + DATAGRAM_HEADER + len], f[at + DATAGRAM_HEADER + len + 1]])
    }

    #[test]
    fn count_then_address_then_read_back() {
        let mut chain = Chain::new((0..3).map(|_| SubDevice::servo_drive()).collect());
        let mut f = frame(&[(cmd::BRD, 0, &[0])]);
        chain.answer(&mut f).expect("answered");
        assert_eq!(wkc(&f, 0), 3, "every SubDevice counts");
        for i in 0..3u16 {
            let adp = 0u16.wrapping_sub(i) as u32;
            let mut f = frame(&[(cmd::APWR, adp | (0x0010 << 16), &(0x1000 + i).to_le_bytes())]);
            chain.answer(&mut f).expect("answered");
            assert_eq!(wkc(&f, 0), 1);
        }
        let mut f = frame(&[
            (cmd::FPRD, 0x1002 | (0x0010 << 16), &[0, 0]),
            (cmd::FPRD, 0x1007 | (0x0010 << 16), &[0, 0]),
        ]);
        chain.answer(&mut f).expect("answered");
        assert_eq!((wkc(&f, 0), wkc(&f, 1)), (1, 0), "only station 0x1002 exists");
        assert_eq!(f[6], 0x12, "the reply is marked");
    }

    #[test]
    fn malformed_frames_are_refused_untouched() {
        let mut chain = Chain::new(vec![SubDevice::servo_drive()]);
        let good = frame(&[(cmd::BRD, 0, &[0, 0])]);
        let mut short = good[..good.len() - 3].to_vec();
        let before = short.clone();
        assert_eq!(chain.answer(&mut short), Err(FrameError::Overrun));
        assert_eq!(short, before);
        let mut other = good.clone();
        other[12] = 0x08;
        assert_eq!(chain.answer(&mut other), Err(FrameError::NotEtherCat));
        assert_eq!(chain.answer(&mut [0u8; 5]), Err(FrameError::TooShort));
        let mut typed = good.clone();
        typed[15] = 0x40;
        assert_eq!(chain.answer(&mut typed), Err(FrameError::BadHeader));
        assert_eq!(chain.refused, 4);
        // Any bytes at all: answered or refused, never a panic.
        let mut x = 12345u64;
        for _ in 0..2000 {
            let mut f = good.clone();
            for b in f.iter_mut().skip(14) {
                x ^= x << 13;
                x ^= x >> 7;
                x ^= x << 17;
                *b = x as u8;
            }
            let _ = chain.answer(&mut f);
        }
    }
}
