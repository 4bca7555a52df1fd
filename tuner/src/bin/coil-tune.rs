//! `coil-tune`: parses the command line and runs it (see `coil_tuner::cli`); errors go to
//! stderr with exit code 1 (clap's usage errors exit with 2).

use clap::Parser;

fn main() -> std::process::ExitCode {
    let cli = coil_tuner::cli::Cli::parse();
    match coil_tuner::cli::run(cli) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("coil-tune: error: {error}");
            let mut source = std::error::Error::source(&error);
            while let Some(cause) = source {
                eprintln!("  caused by: {cause}");
                source = cause.source();
            }
            std::process::ExitCode::FAILURE
        }
    }
}
