//! The arguments of `gyrocomp eval`, shared by its two protocols ([`super::eval`] and
//! [`super::eval_motion`]).

use std::path::PathBuf;
use std::str::FromStr;

use clap::ValueEnum;

use super::CliError;

/// Evaluation protocols.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Protocol {
    /// The paper's: first N samples, denoise, PSR, scale, 80/20 split, one-step prediction.
    Paper,
    /// Motion-injected (a file made by `gyrocomp motion`): compensated rate and angle against the
    /// injected truth, for gyrocomp and the baselines.
    Motion,
}

/// Arguments of `gyrocomp eval`.
#[derive(Debug, clap::Args)]
pub struct EvalArgs {
    /// Input recording: CSV (header line, time column `t_s`; or EuRoC) or an MCAP bag
    /// (sensor_msgs/msg/Imu).
    pub input: PathBuf,
    /// Input format options (MCAP topic, CSV units).
    #[command(flatten)]
    pub input_opts: super::input::InputArgs,
    /// Rate column, deg/s.
    #[arg(long, default_value = "gx_dps")]
    pub column: String,
    /// Comma-separated models to run (default: all). Paper protocol: cpso-lssvm, lssvm, bp-ann,
    /// persistence, ar, mean, bias-hold, linear-psr. Motion protocol: gyrocomp, gyrocomp-flagged,
    /// bias-hold, persistence, ar, highpass, persistence-gated, ar-gated.
    #[arg(long, value_delimiter = ',')]
    pub models: Option<Vec<String>>,
    /// Protocol.
    #[arg(long, value_enum, default_value_t = Protocol::Paper)]
    pub protocol: Protocol,
    /// Paper protocol: samples taken from the start of the recording.
    #[arg(long, default_value_t = 5000)]
    pub samples: usize,
    /// γ of the fixed-parameter `lssvm` model (default: the paper's 29.358).
    #[arg(long, default_value_t = 29.358)]
    pub gam: f64,
    /// σ² of the fixed-parameter `lssvm` model (default: the paper's 83.162).
    #[arg(long, default_value_t = 83.162)]
    pub sig2: f64,
    /// Seed of the stochastic models (BP-ANN initialisation, CPSO).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Configuration file (paper protocol: its `[denoise]` and `[embedding]` keys; motion
    /// protocol: the whole pipeline configuration, `input.rate_hz` taken from the recording).
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// Motion protocol: start-up window of the bias-hold baseline, s (it also ends at the first
    /// motion).
    #[arg(long, default_value_t = 60.0)]
    pub startup_s: f64,
    /// Motion protocol: cutoff of the first-order high-pass baseline, Hz (1 mHz: time constant
    /// 159 s, 2.6 times the longest turn of `gyrocomp motion`).
    #[arg(long, default_value_t = 0.001)]
    pub highpass_hz: f64,
    /// Print JSON instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Motion protocol: also draw each model's angle error per motion segment against the
    /// white-noise floor into this file (.svg or .png, by its extension).
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,
}

/// Parses the `--models` names for one protocol; `None` without `--models`.
pub fn parse_models<T: FromStr<Err = String>>(names: Option<&[String]>) -> Result<Option<Vec<T>>, CliError> {
    names.map(|names| names.iter().map(|n| n.parse::<T>().map_err(CliError::from)).collect()).transpose()
}
