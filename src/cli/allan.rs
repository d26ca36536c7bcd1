//! `gyrocomp allan` (to be written).

use super::CliError;

/// Arguments of `gyrocomp allan`.
#[derive(Debug, clap::Args)]
pub struct AllanArgs {
    /// Input CSV file.
    pub input: std::path::PathBuf,
}

/// Runs `gyrocomp allan`.
pub fn run(_args: &AllanArgs) -> Result<(), CliError> {
    Err("not written yet".into())
}
