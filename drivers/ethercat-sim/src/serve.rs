//! A simulated chain on a network interface: every EtherCAT frame that
//! arrives is answered by a [`Wire`] (the [`crate::SimulatedRig`], or a
//! bare [`crate::Chain`]) and sent back, as a chain on the other end of
//! the cable would. Used over a veth pair whose far end sits in its own
//! network namespace ([`crate::veth`]).

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering::Relaxed};

use upm_ethercat::{MAX_FRAME, RawSocket, Wire, WireError};

/// What the server saw.
#[derive(Debug, Default)]
pub struct ServeCounters {
    pub answered: AtomicU64,
    /// Frames the chain lost or refused (no answer sent).
    pub dropped: AtomicU64,
    /// Sends or receives the OS failed.
    pub io_errors: AtomicU64,
}

/// Answer frames on `socket` until `stop` (checked at least every receive
/// timeout of the socket).
pub fn serve<W: Wire>(wire: &mut W, socket: &RawSocket, stop: &AtomicBool, counters: &ServeCounters) {
    let mut buf = [0u8; MAX_FRAME];
    while !stop.load(Relaxed) {
        let n = match socket.recv(&mut buf, true) {
            Ok(n) => n.min(MAX_FRAME),
            Err(WireError::Lost) => continue,
            Err(_) => {
                counters.io_errors.fetch_add(1, Relaxed);
                continue;
            }
        };
        let frame = &mut buf[..n];
        if wire.round_trip(frame).is_err() {
            counters.dropped.fetch_add(1, Relaxed);
            continue;
        }
        // The first device marks the source address as it forwards, so the
        // MainDevice does not take the answer for its own frame.
        frame[6] |= 0x02;
        match socket.send(frame) {
            Ok(()) => counters.answered.fetch_add(1, Relaxed),
            Err(_) => counters.io_errors.fetch_add(1, Relaxed),
        };
    }
}

impl Wire for crate::Chain {
    fn round_trip(&mut self, frame: &mut [u8]) -> Result<(), WireError> {
        match self.answer(frame) {
            Ok(()) => Ok(()),
            Err(crate::FrameError::Lost) => Err(WireError::Lost),
            Err(_) => Err(WireError::Refused),
        }
    }
}
