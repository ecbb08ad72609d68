//! The project's one counting allocator (`rt_core::alloc_count`),
//! installed for this test binary: it counts allocations made by threads
//! marked real-time, here the test thread while `count` runs.

use rt_core::alloc_count::RtAllocCounter;
pub use rt_core::alloc_count::allocations_in as count;

#[global_allocator]
static ALLOCATOR: RtAllocCounter = RtAllocCounter;
