use clap::Parser;

fn main() -> std::process::ExitCode {
    let cli = upm_clients::cli::Cli::parse();
    match upm_clients::cli::run(cli) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            // One line, naming the field: the contract scripts rely on.
            eprintln!("upm: error: {e:#}");
            std::process::ExitCode::FAILURE
        }
    }
}
