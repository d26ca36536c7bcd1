//! `gyrocomp denoise` (to be written).

use super::CliError;

/// Arguments of `gyrocomp denoise`.
#[derive(Debug, clap::Args)]
pub struct DenoiseArgs {
    /// Input CSV file.
    pub input: std::path::PathBuf,
}

/// Runs `gyrocomp denoise`.
pub fn run(_args: &DenoiseArgs) -> Result<(), CliError> {
    Err("not written yet".into())
}
