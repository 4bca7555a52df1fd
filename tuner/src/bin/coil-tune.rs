//! `coil-tune`: parses the command line and runs it (see `coil_tuner::cli`); errors go to
//! stderr with exit code 1 (clap's usage errors exit with 2).

use clap::Parser;

fn main() -> std::process::ExitCode {
    let cli = coil_tuner::cli::Cli::parse();
    match coil_tuner::cli::run(cli) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(error) => {
            // Every message already carries its causes (file, line, field, what was expected).
            eprintln!(
                "coil-tune: error: {}",
                coil_io::clean_message(&error.to_string())
            );
            std::process::ExitCode::FAILURE
        }
    }
}
