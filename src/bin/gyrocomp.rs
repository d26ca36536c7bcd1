//! `gyrocomp`: the offline command-line tool (denoise, cc, allan, …). See `gyrocomp --help`.

use std::process::ExitCode;

use clap::Parser;
use gyrocomp::cli::progress::stderr_clearing_bar;
use gyrocomp::cli::{Cli, run};
use gyrocomp::drive::error_chain;
use tracing_subscriber::EnvFilter;

fn main() -> ExitCode {
    let cli = Cli::parse();
    let filter = EnvFilter::try_new(&cli.log).unwrap_or_else(|_| EnvFilter::new("info"));
    tracing_subscriber::fmt().with_env_filter(filter).with_writer(stderr_clearing_bar).with_target(false).init();
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            eprintln!("error: {}", error_chain(err.as_ref()));
            ExitCode::from(2)
        }
    }
}
