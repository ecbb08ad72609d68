//! ethercrab's PDU loop driven synchronously, on the thread that asks.
//!
//! ethercrab queues a frame and wakes its sender; here the sender's waker
//! *is* the wire: waking it takes the frame, carries it through the
//! [`Wire`] and hands the answer back before ethercrab first polls for it.
//! So a cyclic exchange completes in one poll, on the motor thread, with
//! no transport thread, no cross-thread wake-up and no timer (ethercrab's
//! std timer registers with a reactor: a syscall, and now and then an
//! allocation). A frame the wire loses is handed back as sent, as if no
//! device had touched it: its working counter is 0 and the driver counts
//! it lost, so no path ever waits on ethercrab's timeout.

use std::sync::atomic::{AtomicU64, Ordering::Relaxed};
use std::sync::{Arc, Mutex};
use std::task::{Wake, Waker};

use ethercrab::{PduRx, PduTx, ReceiveAction};

use crate::wire::{MAX_FRAME, Wire};

/// What crossed the wire.
#[derive(Debug, Default)]
pub struct WireCounters {
    pub frames: AtomicU64,
    /// Not answered (handed back with working counter 0).
    pub lost: AtomicU64,
    /// Answers ethercrab could not take (not ours, malformed, too late).
    pub bad: AtomicU64,
    /// A wake-up that found the pump busy (never expected: one thread).
    pub busy: AtomicU64,
}

struct Pump<W> {
    tx: PduTx<'static>,
    rx: PduRx<'static>,
    wire: W,
    frame: [u8; MAX_FRAME],
    /// The frame as sent, to hand back when the wire fails part way.
    sent: [u8; MAX_FRAME],
}

/// The sender's waker: carries every sendable frame through the wire.
pub(crate) struct FramePump<W> {
    pump: Mutex<Pump<W>>,
    pub(crate) counters: WireCounters,
}

impl<W> core::fmt::Debug for FramePump<W> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("FramePump").field("counters", &self.counters).finish_non_exhaustive()
    }
}

impl<W: Wire> FramePump<W> {
    /// Build the pump and register it as ethercrab's sender.
    pub(crate) fn start(tx: PduTx<'static>, rx: PduRx<'static>, wire: W) -> Arc<Self> {
        let pump = Arc::new(Self {
            pump: Mutex::new(Pump { tx, rx, wire, frame: [0; MAX_FRAME], sent: [0; MAX_FRAME] }),
            counters: WireCounters::default(),
        });
        if let Ok(p) = pump.pump.lock() {
            p.tx.replace_waker(&Waker::from(pump.clone()));
        }
        pump
    }

    /// Stop being ethercrab's sender: its PDU storage lives for the
    /// process and would keep the pump (and the wire) alive through the
    /// registered waker.
    pub(crate) fn release(&self) {
        if let Ok(p) = self.pump.lock() {
            p.tx.replace_waker(Waker::noop());
        }
    }

    /// Run `f` on the wire (never blocks: `None` if the pump is busy).
    pub(crate) fn with_wire<R>(&self, f: impl FnOnce(&mut W) -> R) -> Option<R> {
        self.pump.try_lock().ok().map(|mut p| f(&mut p.wire))
    }

    fn pump(self: &Arc<Self>) {
        let Ok(mut guard) = self.pump.try_lock() else {
            self.counters.busy.fetch_add(1, Relaxed);
            return;
        };
        let p = &mut *guard;
        // ethercrab takes the waker when it wakes us: register again
        // (an Arc clone, no allocation).
        p.tx.replace_waker(&Waker::from(self.clone()));
        while let Some(sendable) = p.tx.next_sendable_frame() {
            let mut len = 0;
            let copied = sendable.send_blocking(|bytes| {
                let n = bytes.len().min(MAX_FRAME);
                p.frame[..n].copy_from_slice(&bytes[..n]);
                p.sent[..n].copy_from_slice(&bytes[..n]);
                len = n;
                Ok(n)
            });
            if copied.is_err() {
                self.counters.bad.fetch_add(1, Relaxed);
                continue;
            }
            self.counters.frames.fetch_add(1, Relaxed);
            let frame = &mut p.frame[..len];
            if p.wire.round_trip(frame).is_err() {
                self.counters.lost.fetch_add(1, Relaxed);
                // Handed back as sent, whatever the wire left in it; with
                // a changed source address, as a chain's first device
                // would give it, so that ethercrab does not take it for
                // its own outgoing frame.
                frame.copy_from_slice(&p.sent[..len]);
                frame[6] |= 0x02;
            }
            match p.rx.receive_frame(frame) {
                Ok(ReceiveAction::Processed) => {}
                Ok(ReceiveAction::Ignored) | Err(_) => {
                    self.counters.bad.fetch_add(1, Relaxed);
                    // The answer is unusable: hand the frame back as sent
                    // (working counter 0), so the exchange still completes
                    // in this poll, as lost, and never reaches ethercrab's
                    // timer.
                    frame.copy_from_slice(&p.sent[..len]);
                    frame[6] |= 0x02;
                    let _ = p.rx.receive_frame(frame);
                }
            }
        }
    }
}

impl<W: Wire> Wake for FramePump<W> {
    fn wake(self: Arc<Self>) {
        self.pump();
    }

    fn wake_by_ref(self: &Arc<Self>) {
        self.pump();
    }
}
