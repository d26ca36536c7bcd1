//! `gyrocompd`: the gyro drift compensation daemon (iceoryx2 in and out, background retraining).
//! See `gyrocompd --help` and docs/usage.md, section "gyrocompd"; the work is in `gyrocomp::daemon`.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;
use gyrocomp::config::Config;
use gyrocomp::daemon::{Daemon, DaemonError, Signals, logging};
use gyrocomp::drive::error_chain;

/// Exit code when another gyrocompd already serves the service prefix or state directory.
const ALREADY_RUNNING: u8 = 3;

/// gyrocompd: compensates MEMS gyro drift for an INS over iceoryx2 shared memory.
/// SIGTERM/SIGINT: answer the samples already received, publish a final status, exit 0.
/// SIGHUP: reload the config file (motion/input thresholds and retrain schedule apply at once).
/// Exit codes: 0 stopped by a signal, 2 could not start, 3 another gyrocompd already serves this
/// service prefix or state directory.
#[derive(Debug, Parser)]
#[command(name = "gyrocompd", version, about)]
struct Args {
    /// Configuration file (TOML, keys as in configs/default.toml); built-in defaults without it.
    #[arg(long)]
    config: Option<PathBuf>,
}

fn main() -> ExitCode {
    let args = Args::parse();
    let config = match Config::load(args.config.as_deref()).map_err(DaemonError::from) {
        Ok(c) => c,
        Err(e) => return fail(&e),
    };
    if let Err(e) = logging::init(&config) {
        return fail(&e);
    }
    let signals = match Signals::install() {
        Ok(s) => s,
        Err(e) => return fail(&e),
    };
    match Daemon::new(config, args.config, signals).run() {
        Ok(_) => ExitCode::SUCCESS,
        Err(e) => {
            tracing::error!(error = %e, "gyrocompd could not start");
            let code = fail(&e);
            // A distinct code for "another instance runs", so that a supervisor or script can
            // tell it from a broken configuration (docs/usage.md "Exit codes").
            if matches!(e, DaemonError::AlreadyRunning { .. }) { ExitCode::from(ALREADY_RUNNING) } else { code }
        }
    }
}

/// Prints `error` and its causes on stderr (logging may not be set up yet) and returns 2.
fn fail(error: &dyn std::error::Error) -> ExitCode {
    eprintln!("gyrocompd: error: {}", error_chain(error));
    ExitCode::from(2)
}
