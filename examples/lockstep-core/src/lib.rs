//! Nothing here: the example is `tests/lockstep.rs`.
