//! The project's one counting allocator (`rt_core::runtime::alloc_count`),
//! installed for this test binary: it counts allocations made by threads
//! marked real-time, here the test thread while `count` runs.

use rt_core::runtime::alloc_count::{RtAllocCounter, mark_rt_thread, rt_allocations};

#[global_allocator]
static ALLOCATOR: RtAllocCounter = RtAllocCounter;

/// Allocations made by this thread while running `f`.
pub fn count<R>(f: impl FnOnce() -> R) -> (R, u64) {
    mark_rt_thread(true);
    let before = rt_allocations();
    let r = f();
    let after = rt_allocations();
    mark_rt_thread(false);
    (r, after - before)
}
