//! `gyrocomp cc` (to be written).

use super::CliError;

/// Arguments of `gyrocomp cc`.
#[derive(Debug, clap::Args)]
pub struct CcArgs {
    /// Input CSV file.
    pub input: std::path::PathBuf,
}

/// Runs `gyrocomp cc`.
pub fn run(_args: &CcArgs) -> Result<(), CliError> {
    Err("not written yet".into())
}
