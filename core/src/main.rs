//! The RT kernel process; all logic lives in `upm_core::core_process`.

use clap::Parser;
use rt_core::RtAllocCounter;

// Counts heap allocations on the motor and solver threads (telemetry's
// `rt_thread_allocations`).
#[global_allocator]
static ALLOC: RtAllocCounter = RtAllocCounter;

fn main() {
    let args = upm_core::core_process::CoreArgs::parse();
    let result = upm_core::core_process::run(args).and_then(|r| upm_core::core_process::report(&r));
    if let Err(e) = result {
        eprintln!("upm-core: error: {}", format!("{e:#}").replace('\n', " "));
        std::process::exit(1);
    }
}
