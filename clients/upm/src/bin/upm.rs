use clap::Parser;
use rt_core::RtAllocCounter;

// Counts allocations on threads marked real-time (`upm bench` reports them).
#[global_allocator]
static ALLOC: RtAllocCounter = RtAllocCounter;

fn main() -> std::process::ExitCode {
    // Like other Unix tools: `upm … | head` ends quietly instead of
    // panicking on a closed pipe.
    // SAFETY: restoring the default disposition of one signal at start-up.
    unsafe { libc::signal(libc::SIGPIPE, libc::SIG_DFL) };
    let cli = upm_cli::cli::Cli::parse();
    match upm_cli::cli::run(cli) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            let (code, said) =
                e.downcast_ref::<upm_cli::cli::Exit>().map_or((1, false), |x| (x.code, x.message.is_empty()));
            if !said {
                // One line, naming the field: the contract scripts rely on.
                eprintln!("upm: error: {}", format!("{e:#}").replace('\n', " "));
            }
            std::process::ExitCode::from(code)
        }
    }
}
