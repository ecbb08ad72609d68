//! A counting global allocator: counts heap allocations made by threads
//! marked real-time, so `rt_thread_allocations` in telemetry is a
//! measurement, not a promise. Binaries and tests opt in with
//! `#[global_allocator] static A: RtAllocCounter = RtAllocCounter;`.

use core::alloc::{GlobalAlloc, Layout};
use core::cell::Cell;
use core::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::alloc::System;

static RT_ALLOCATIONS: AtomicU64 = AtomicU64::new(0);
static ABORT_ON_RT_ALLOCATION: AtomicBool = AtomicBool::new(false);

thread_local! {
    // const-initialised Cell<bool>: no destructor, no lazy init, so it is
    // safe to read from inside the allocator.
    static IS_RT: Cell<bool> = const { Cell::new(false) };
    // This thread's share of the count, so a measurement on one thread is
    // not disturbed by another marked thread running at the same time.
    static THREAD_RT_ALLOCATIONS: Cell<u64> = const { Cell::new(0) };
}

/// System allocator plus a count of allocations on RT-marked threads.
#[derive(Debug, Clone, Copy, Default)]
pub struct RtAllocCounter;

#[inline]
fn count() {
    if IS_RT.with(Cell::get) {
        RT_ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        THREAD_RT_ALLOCATIONS.with(|c| c.set(c.get() + 1));
        if ABORT_ON_RT_ALLOCATION.load(Ordering::Relaxed) {
            std::process::abort();
        }
    }
}

// SAFETY: every call forwards to `System` unchanged; counting has no effect
// on the returned memory.
unsafe impl GlobalAlloc for RtAllocCounter {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count();
        // SAFETY: forwarded with the caller's layout.
        unsafe { System.alloc(layout) }
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        count();
        // SAFETY: forwarded with the caller's layout.
        unsafe { System.alloc_zeroed(layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count();
        // SAFETY: forwarded unchanged.
        unsafe { System.realloc(ptr, layout, new_size) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: forwarded unchanged.
        unsafe { System.dealloc(ptr, layout) }
    }
}

/// Start (true) or stop (false) counting this thread's allocations.
pub fn mark_rt_thread(on: bool) {
    IS_RT.with(|c| c.set(on));
}

/// Allocations made by RT-marked threads since process start.
pub fn rt_allocations() -> u64 {
    RT_ALLOCATIONS.load(Ordering::Relaxed)
}

/// Run `f` with this thread marked real-time; returns its result and the
/// allocations this thread made meanwhile (other threads never count in).
pub fn allocations_in<R>(f: impl FnOnce() -> R) -> (R, u64) {
    let was = IS_RT.with(Cell::get);
    mark_rt_thread(true);
    let before = THREAD_RT_ALLOCATIONS.with(Cell::get);
    let r = f();
    let after = THREAD_RT_ALLOCATIONS.with(Cell::get);
    mark_rt_thread(was);
    (r, after - before)
}

/// True if [`RtAllocCounter`] is the global allocator (checked by
/// allocating once on a marked thread); if false, the count means nothing.
/// The probe is taken back out of the process-wide count.
pub fn counter_installed() -> bool {
    let trap = ABORT_ON_RT_ALLOCATION.swap(false, Ordering::Relaxed);
    let (probe, counted) = allocations_in(|| std::hint::black_box(Box::new(0u64)));
    drop(probe);
    ABORT_ON_RT_ALLOCATION.store(trap, Ordering::Relaxed);
    RT_ALLOCATIONS.fetch_sub(counted, Ordering::Relaxed);
    counted > 0
}

/// Debugging aid: abort the process at the first allocation on an RT-marked
/// thread, so a debugger shows where it came from.
pub fn abort_on_rt_allocation(on: bool) {
    ABORT_ON_RT_ALLOCATION.store(on, Ordering::Relaxed);
}
