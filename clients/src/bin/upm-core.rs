//! The RT kernel process; all logic lives in `upm_clients::core_process`.

use clap::Parser;
use rt_core::runtime::RtAllocCounter;

// Counts heap allocations on the motor and solver threads (telemetry's
// `rt_thread_allocations`).
#[global_allocator]
static ALLOC: RtAllocCounter = RtAllocCounter;

fn main() {
    let args = upm_clients::core_process::CoreArgs::parse();
    match upm_clients::core_process::run(args) {
        Ok(report) => {
            let t = &report.telemetry;
            eprintln!(
                "upm-core: stopped cleanly, plate home; {} ticks, {} cycles, {} overruns, {} hold events, {} rt allocations",
                t.counters.ticks,
                t.cycle,
                t.counters.overruns,
                t.counters.hold_events,
                t.counters.rt_thread_allocations
            );
        }
        Err(e) => {
            eprintln!("upm-core: error: {}", format!("{e:#}").replace('\n', " "));
            std::process::exit(1);
        }
    }
}
