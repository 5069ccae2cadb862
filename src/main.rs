//! The `kecsim` binary: parses the command line and runs the command (see [`cli`]).

mod cli;

use std::process::ExitCode;

use clap::Parser;

fn main() -> ExitCode {
    match cli::run(cli::Cli::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("kecsim: error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
