//! See README.md: the crate is its integration test, `tests/hostile.rs`.
