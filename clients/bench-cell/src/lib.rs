//! `upm bench line` and `upm bench hmi`: figures of a production cell's
//! outside world, each from real `upm run feed` rigs started as a user
//! would, beside a run without it in the same invocation.

pub mod bench_hmi;
pub mod bench_line;
