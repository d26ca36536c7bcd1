//! `gyrocomp sim`: simulate a gyro triad from a preset or a TOML config and write it as CSV:
//! `t_s,gx_dps,gy_dps,gz_dps,temp_c,gx_drift_dps,gy_drift_dps,gz_drift_dps` (the drift columns are
//! the truth: every error term except white noise and quantisation).

use std::path::PathBuf;
use std::time::Instant;

use clap::ValueEnum;
use serde::Serialize;
use tracing::info;

use super::CliError;
use crate::io::write_sim_csv;
use crate::model::metrics::population_std_dev;
use crate::sim::{Generator, Preset, SimConfig};

/// The built-in presets (documented in `gyrocomp::sim::presets`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum PresetArg {
    /// The seed paper's data: 10 Hz, 1500 s, drift std ≈ 0.0035 deg/s.
    Paper,
    /// Fitted to the static ADIS16405 recording (run 1, 10 Hz, 10,000 s).
    Adis16405,
    /// MPU-6050 datasheet-typical, with warm-up and temperature: 100 Hz, 1800 s.
    Mpu6050,
}

impl From<PresetArg> for Preset {
    fn from(p: PresetArg) -> Self {
        match p {
            PresetArg::Paper => Preset::Paper,
            PresetArg::Adis16405 => Preset::Adis16405,
            PresetArg::Mpu6050 => Preset::Mpu6050,
        }
    }
}

/// Arguments of `gyrocomp sim`.
#[derive(Debug, clap::Args)]
pub struct SimArgs {
    /// Built-in error model (default `paper` when no --config is given).
    #[arg(long, value_enum, conflicts_with = "config")]
    pub preset: Option<PresetArg>,
    /// TOML error model (see configs/sim/); unknown keys are errors.
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// Seed of the random streams (replaces the config's `seed`; default 0).
    #[arg(long)]
    pub seed: Option<u64>,
    /// Length of the run, s (replaces `duration_s`).
    #[arg(long)]
    pub duration: Option<f64>,
    /// Sample rate, Hz (replaces `rate_hz`; noise densities are kept, so the Allan curve is too).
    #[arg(long)]
    pub rate: Option<f64>,
    /// Output CSV (`-` for standard output).
    #[arg(short, long, required_unless_present = "print_config")]
    pub output: Option<PathBuf>,
    /// Print the effective configuration as TOML on standard output and exit.
    #[arg(long)]
    pub print_config: bool,
    /// Print the summary as JSON on standard output.
    #[arg(long)]
    pub json: bool,
}

/// Summary of one simulation.
#[derive(Debug, Serialize)]
struct Summary {
    samples: usize,
    rate_hz: f64,
    duration_s: f64,
    seed: u64,
    /// Standard deviation of the raw output per axis, deg/s.
    std_raw_dps: [f64; 3],
    /// Standard deviation of the truth drift per axis, deg/s.
    std_drift_dps: [f64; 3],
    seconds: f64,
}

/// The configuration the arguments ask for (preset or file, then the overrides).
pub fn effective_config(args: &SimArgs) -> Result<SimConfig, CliError> {
    let mut config = match (&args.config, args.preset) {
        (Some(path), _) => {
            let text = std::fs::read_to_string(path).map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
            SimConfig::from_toml(&text).map_err(|e| format!("{}: {e}", path.display()))?
        }
        (None, preset) => Preset::from(preset.unwrap_or(PresetArg::Paper)).config(),
    };
    if let Some(d) = args.duration {
        config.duration_s = d;
    }
    if let Some(r) = args.rate {
        config.rate_hz = r;
    }
    if let Some(s) = args.seed {
        config.seed = Some(s);
    }
    config.validate()?;
    Ok(config)
}

/// Runs `gyrocomp sim`.
pub fn run(args: &SimArgs) -> Result<(), CliError> {
    let config = effective_config(args)?;
    if args.print_config {
        print!("{}", config.to_toml());
        return Ok(());
    }
    let seed = config.seed.unwrap_or(0);
    let started = Instant::now();
    let out = Generator::generate(&config, seed)?;
    let path = args.output.as_ref().expect("clap requires --output without --print-config");
    write_sim_csv(path, &out)?;
    let summary = Summary {
        samples: out.len(),
        rate_hz: config.rate_hz,
        duration_s: config.duration_s,
        seed,
        std_raw_dps: out.axes.each_ref().map(|a| population_std_dev(&a.raw).unwrap_or(0.0)),
        std_drift_dps: out.axes.each_ref().map(|a| population_std_dev(&a.drift).unwrap_or(0.0)),
        seconds: started.elapsed().as_secs_f64(),
    };
    if args.json {
        println!("{}", serde_json::to_string(&summary)?);
    } else {
        info!(
            samples = summary.samples,
            seed = summary.seed,
            std_raw_dps = ?summary.std_raw_dps,
            std_drift_dps = ?summary.std_drift_dps,
            seconds = summary.seconds,
            "simulated"
        );
    }
    Ok(())
}
