//! Latency summary of one measured path, as published in telemetry.

#[cfg(feature = "iceoryx2")]
use iceoryx2::prelude::ZeroCopySend;

/// Percentiles of one latency since core start, all in **nanoseconds**
/// (`upm status` / metrics.json convert to µs). All zero before the first
/// sample.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "iceoryx2", derive(ZeroCopySend), type_name("upm::LatencyPercentiles.v6"))]
pub struct LatencyPercentiles {
    /// Number of samples recorded.
    pub samples: u64,
    pub p50_ns: u64,
    pub p99_ns: u64,
    pub p999_ns: u64,
    pub max_ns: u64,
}

const _: () = assert!(size_of::<LatencyPercentiles>() == 5 * 8);

impl LatencyPercentiles {
    pub const ZERO: Self = Self { samples: 0, p50_ns: 0, p99_ns: 0, p999_ns: 0, max_ns: 0 };

    /// True if p50 ≤ p99 ≤ p999 ≤ max, as any real distribution has.
    pub const fn is_ordered(&self) -> bool {
        self.p50_ns <= self.p99_ns && self.p99_ns <= self.p999_ns && self.p999_ns <= self.max_ns
    }
}
