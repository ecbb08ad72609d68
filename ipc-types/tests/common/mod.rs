//! Helpers shared by the allocation tests.

pub mod counting_allocator;
