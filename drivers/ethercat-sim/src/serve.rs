//! A simulated chain on a network interface: every EtherCAT frame that
//! arrives is answered by a [`Wire`] (the [`crate::SimulatedRig`], or a
//! bare [`crate::Chain`]) and sent back, as a chain on the other end of
//! the cable would. Used over a veth pair whose far end sits in its own
//! network namespace ([`crate::veth`]).

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering::Relaxed};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::Duration;

use upm_ethercat::{MAX_FRAME, RawSocket, Wire, WireError};

use crate::veth::VethPair;

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

/// A chain served from the far end of a veth pair on a thread of its own,
/// until dropped (which stops the thread, then deletes the pair).
#[derive(Debug)]
pub struct ChainServer<W: Wire + Send + 'static> {
    /// The chain behind the far end; the server holds the lock only while
    /// it answers one frame.
    pub wire: Arc<Mutex<W>>,
    /// While set, frames go unanswered (a pulled cable).
    pub mute: Arc<AtomicBool>,
    pub counters: Arc<ServeCounters>,
    stop: Arc<AtomicBool>,
    thread: Option<JoinHandle<Result<Result<(), String>, String>>>,
    pair: VethPair,
}

/// Where the server thread runs: SCHED_FIFO `priority` on `cpu` (refused:
/// the server does not start), or normal scheduling with `None`.
#[derive(Debug, Clone, Copy)]
pub struct ServerPlacement {
    pub realtime: Option<(u8, usize)>,
}

struct Muted<W> {
    wire: Arc<Mutex<W>>,
    mute: Arc<AtomicBool>,
}

impl<W: Wire> Wire for Muted<W> {
    fn round_trip(&mut self, frame: &mut [u8]) -> Result<(), WireError> {
        if self.mute.load(Relaxed) {
            return Err(WireError::Lost);
        }
        self.wire.lock().map_err(|_| WireError::Refused)?.round_trip(frame)
    }
}

impl<W: Wire + Send + 'static> ChainServer<W> {
    /// Serve `wire` on the far end of `pair`; returns once the far end's
    /// socket is open (or why it could not be).
    pub fn start(pair: VethPair, wire: W, placement: ServerPlacement) -> Result<Self, String> {
        let wire = Arc::new(Mutex::new(wire));
        let (mute, stop) = (Arc::new(AtomicBool::new(false)), Arc::new(AtomicBool::new(false)));
        let counters = Arc::new(ServeCounters::default());
        let far = pair.far.clone();
        let (ready_tx, ready) = std::sync::mpsc::channel();
        let thread = {
            let (wire, mute, stop, counters) = (wire.clone(), mute.clone(), stop.clone(), counters.clone());
            pair.in_namespace(move || {
                let placed = placement.realtime.map_or(Ok(()), |(priority, cpu)| {
                    let p = rt_core::rt_setup::make_current_thread_realtime_on(priority, cpu);
                    // The motor thread may wait on this thread's lock: it
                    // must be real-time too, or not run at all.
                    if p.fifo { Ok(()) } else { Err(format!("SCHED_FIFO {priority} on CPU {cpu} refused")) }
                });
                let socket = placed.and_then(|()| {
                    RawSocket::open(&far, Duration::from_millis(10)).map_err(|e| format!("{far}: {e}"))
                });
                let _ = ready_tx.send(socket.as_ref().map(|_| ()).map_err(Clone::clone));
                let socket = socket?;
                serve(&mut Muted { wire, mute }, &socket, &stop, &counters);
                Ok(())
            })
        };
        let mut server = Self { wire, mute, counters, stop, thread: Some(thread), pair };
        match ready.recv() {
            Ok(Ok(())) => Ok(server),
            Ok(Err(why)) => Err(why),
            // The thread ended before it could say (setns failed).
            Err(_) => Err(server.halt().err().unwrap_or_else(|| "the chain's server ended".into())),
        }
    }

    /// The MainDevice's end of the cable.
    pub fn near(&self) -> &str {
        &self.pair.near
    }

    /// Stop serving; the server's own error if it failed to start.
    pub fn stop(mut self) -> Result<(), String> {
        self.halt()
    }

    fn halt(&mut self) -> Result<(), String> {
        self.stop.store(true, Relaxed);
        match self.thread.take().map(JoinHandle::join) {
            None => Ok(()),
            Some(Ok(Ok(r))) => r,
            Some(Ok(Err(why))) => Err(why),
            Some(Err(_)) => Err("the chain's server thread panicked".into()),
        }
    }
}

impl<W: Wire + Send + 'static> Drop for ChainServer<W> {
    fn drop(&mut self) {
        let _ = self.halt();
    }
}
