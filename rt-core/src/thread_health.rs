//! No silent thread death. Each core thread runs inside a [`CoreThread`]
//! guard. If it panics, a process-wide panic hook records the thread and
//! where it panicked in the core's [`CoreShared`] and parks the thread for
//! good instead of unwinding: unwinding allocates (the exception object),
//! parking does not, and a half-unwound RT thread has nothing left to do.
//! If the thread body returns while the core is not stopping, the guard
//! records that. The motor holds the plate when it sees either; the io
//! thread reports it and ends the process with an error.
//!
//! Cost on the panic path: the hook itself allocates nothing, but std
//! formats a panic *message with arguments* (an index out of bounds, say)
//! into a `String` before any hook runs; a literal message costs nothing.

use core::cell::Cell;
use core::sync::atomic::Ordering::Relaxed;
use std::sync::{Arc, Once};
use std::time::Duration;

use ipc_types::{HealthCause, HealthSource};

use super::shared::CoreShared;

thread_local! {
    // const-initialised, no destructor: readable from inside a panic hook.
    static CORE_THREAD: Cell<Option<(HealthSource, *const CoreShared)>> = const { Cell::new(None) };
}

/// Marks the current thread as one of the core's for as long as it lives.
#[derive(Debug)]
pub struct CoreThread {
    source: HealthSource,
    shared: Arc<CoreShared>,
}

impl CoreThread {
    /// Enter on the thread that runs `source`'s body (start-up: may allocate
    /// once, to install the hook).
    pub fn enter(source: HealthSource, shared: Arc<CoreShared>) -> Self {
        install_panic_hook();
        CORE_THREAD.set(Some((source, Arc::as_ptr(&shared))));
        Self { source, shared }
    }
}

impl Drop for CoreThread {
    fn drop(&mut self) {
        CORE_THREAD.set(None);
        if !self.shared.stop.load(Relaxed) {
            self.shared.record_thread_death(
                self.source,
                HealthCause::Exited,
                format_args!("{} ended while the core was running", self.source),
            );
        }
    }
}

fn install_panic_hook() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            let Some((source, shared)) = CORE_THREAD.get() else {
                previous(info);
                return;
            };
            // SAFETY: the pointer is set only while this thread's CoreThread
            // guard holds an Arc to it, and the guard is not dropped: this
            // thread is inside its body and never leaves the hook.
            let shared = unsafe { &*shared };
            let payload = info.payload();
            let message = payload
                .downcast_ref::<&str>()
                .copied()
                .or_else(|| payload.downcast_ref::<String>().map(String::as_str))
                .unwrap_or("(non-text payload)");
            match info.location() {
                Some(l) => shared.record_thread_death(
                    source,
                    HealthCause::Panicked,
                    format_args!("panicked at {}:{}: {message}", l.file(), l.line()),
                ),
                None => shared.record_thread_death(
                    source,
                    HealthCause::Panicked,
                    format_args!("panicked: {message}"),
                ),
            }
            loop {
                std::thread::sleep(Duration::from_secs(3600));
            }
        }));
    });
}
