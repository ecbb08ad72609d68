//! Latency histograms, owned by the io thread: the RT threads only push
//! samples into rings ([`super::samples`]). Written at exit in the HdrHistogram
//! percentile-distribution text format (`.hgrm`, values in µs).

use std::io::Write;
use std::path::Path;

use hdrhistogram::Histogram;
use ipc_types::{CoreLatencies, LatencyPercentiles};

use super::samples::{MotorSample, SolverSample};

/// 1 ns … 100 s at 3 significant digits: every sample fits, so recording
/// never resizes (auto-resize is off).
fn histogram() -> Histogram<u64> {
    // Bounds are constants that hdrhistogram accepts.
    #[allow(clippy::unwrap_used)]
    Histogram::new_with_bounds(1, 100_000_000_000, 3).unwrap()
}

#[derive(Debug, Clone)]
pub struct LatencyHistograms {
    pub motor_wakeup: Histogram<u64>,
    pub motor_tick: Histogram<u64>,
    pub solver: Histogram<u64>,
    pub ipc_vision_to_core: Histogram<u64>,
    /// Received by the core → validated on the solver thread.
    pub ipc_to_solver: Histogram<u64>,
    pub frame_to_schedule: Histogram<u64>,
}

impl Default for LatencyHistograms {
    fn default() -> Self {
        Self {
            motor_wakeup: histogram(),
            motor_tick: histogram(),
            solver: histogram(),
            ipc_vision_to_core: histogram(),
            ipc_to_solver: histogram(),
            frame_to_schedule: histogram(),
        }
    }
}

/// p50/p99/p99.9/max of one histogram, in ns.
pub fn percentiles(h: &Histogram<u64>) -> LatencyPercentiles {
    if h.is_empty() {
        return LatencyPercentiles::ZERO;
    }
    LatencyPercentiles {
        samples: h.len(),
        p50_ns: h.value_at_quantile(0.50),
        p99_ns: h.value_at_quantile(0.99),
        p999_ns: h.value_at_quantile(0.999),
        max_ns: h.max(),
    }
}

impl LatencyHistograms {
    pub fn record_motor(&mut self, s: &MotorSample) {
        // A 0 wake-up lateness is recorded as 1 ns (the histogram's floor).
        self.motor_wakeup.saturating_record(s.wakeup_ns.max(1));
        self.motor_tick.saturating_record(s.tick_ns.max(1));
        if s.frame_to_active_ns > 0 {
            self.frame_to_schedule.saturating_record(s.frame_to_active_ns);
        }
    }

    pub fn record_solver(&mut self, s: &SolverSample) {
        if s.solve_ns > 0 {
            self.solver.saturating_record(s.solve_ns);
        }
        if s.ipc_ns > 0 {
            self.ipc_vision_to_core.saturating_record(s.ipc_ns);
        }
        if s.pickup_ns > 0 {
            self.ipc_to_solver.saturating_record(s.pickup_ns);
        }
    }

    pub fn core_latencies(&self) -> CoreLatencies {
        CoreLatencies {
            motor_wakeup: percentiles(&self.motor_wakeup),
            solver: percentiles(&self.solver),
            ipc_vision_to_core: percentiles(&self.ipc_vision_to_core),
            frame_to_schedule: percentiles(&self.frame_to_schedule),
        }
    }

    /// Every histogram as `dir/<name>.hgrm`.
    pub fn write_hgrm_dir(&self, dir: &Path) -> std::io::Result<()> {
        std::fs::create_dir_all(dir)?;
        for (name, h) in [
            ("motor_wakeup", &self.motor_wakeup),
            ("motor_tick", &self.motor_tick),
            ("solver", &self.solver),
            ("ipc_vision_to_core", &self.ipc_vision_to_core),
            ("ipc_to_solver", &self.ipc_to_solver),
            ("frame_to_schedule", &self.frame_to_schedule),
        ] {
            let mut f = std::io::BufWriter::new(std::fs::File::create(dir.join(format!("{name}.hgrm")))?);
            write_hgrm(h, &mut f)?;
            f.flush()?;
        }
        Ok(())
    }
}

/// The percentile distribution as HdrHistogram's `outputPercentileDistribution`
/// prints it, values scaled from ns to µs.
pub fn write_hgrm(h: &Histogram<u64>, out: &mut impl Write) -> std::io::Result<()> {
    const SCALE: f64 = 1000.0;
    writeln!(out, "{:>12} {:>14} {:>10} {:>14}\n", "Value", "Percentile", "TotalCount", "1/(1-Percentile)")?;
    if !h.is_empty() {
        for v in h.iter_quantiles(5) {
            let q = v.quantile_iterated_to();
            let inv = if q < 1.0 { format!("{:>14.2}", 1.0 / (1.0 - q)) } else { format!("{:>14}", "") };
            writeln!(
                out,
                "{:>12.3} {:>2.12} {:>10} {inv}",
                v.value_iterated_to() as f64 / SCALE,
                q,
                v.count_since_last_iteration()
            )?;
        }
    }
    writeln!(out, "#[Mean    = {:>12.3}, StdDeviation   = {:>12.3}]", h.mean() / SCALE, h.stdev() / SCALE)?;
    writeln!(out, "#[Max     = {:>12.3}, Total count    = {:>12}]", h.max() as f64 / SCALE, h.len())?;
    writeln!(out, "#[Buckets = {:>12}, SubBuckets     = {:>12}]", h.buckets(), h.distinct_values())
}
