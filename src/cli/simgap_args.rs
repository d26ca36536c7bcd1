//! The arguments of `gyrocomp simgap` and the diagnosis settings they make.

use std::path::PathBuf;

use crate::diag::simgap::Settings;

/// Arguments of `gyrocomp simgap`.
#[derive(Debug, clap::Args)]
pub struct SimgapArgs {
    /// The real recording: CSV with a header, time column `t_s` (or `t`, `time`), rates in deg/s,
    /// optionally a temperature in °C, `temp_c` (or `temperature_c`, `temperature`, `temp`; then
    /// `temperature` is a candidate effect).
    /// An MCAP bag (sensor_msgs/msg/Imu) or a EuRoC CSV is read as well.
    #[arg(long, required_unless_present = "selftest")]
    pub real: Option<PathBuf>,
    /// Input format options (MCAP topic, CSV units).
    #[command(flatten)]
    pub input_opts: super::input::InputArgs,
    /// Rate column to diagnose, deg/s.
    #[arg(long, default_value = "gx_dps")]
    pub column: String,
    /// Simulator config (TOML, as `gyrocomp sim --config`) to diagnose instead of the IEEE Std 952
    /// terms fitted to the recording; the axis matching the column (gx → x, gy → y, gz → z) is used.
    #[arg(long)]
    pub sim: Option<PathBuf>,
    /// Share of the recording held out at its end; effects are fitted on the rest.
    #[arg(long, default_value_t = 0.3)]
    pub holdout: f64,
    /// Seed of the simulated ensemble (and of the self-test).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Members of each simulated ensemble (≥ 8).
    #[arg(long, default_value_t = 32)]
    pub ensemble: usize,
    /// Share of the excess gap² an added effect must remove on every part with a significant gap
    /// (whether the result explains the gap is decided on the hold-out part).
    #[arg(long, default_value_t = 0.25)]
    pub min_share: f64,
    /// Most effects combined.
    #[arg(long, default_value_t = 3)]
    pub max_effects: usize,
    /// Worker threads for the ensembles (results do not depend on it).
    #[arg(long, default_value_t = 1)]
    pub threads: usize,
    /// Sample rate in Hz (default: from the time column).
    #[arg(long)]
    pub rate: Option<f64>,
    /// Print JSON: {"gap_before","gap_after","where":[…],"effects":[…],"chosen":[…],…}.
    #[arg(long)]
    pub json: bool,
    /// Write an HTML report with SVG plots into this folder (index.html).
    #[arg(long)]
    pub report: Option<PathBuf>,
    /// Run the self-test instead: simulated recordings with a known injected effect.
    #[arg(long)]
    pub selftest: bool,
    /// Self-test: seeded cases per effect and per control.
    #[arg(long, default_value_t = 10)]
    pub cases: usize,
    /// Self-test: length of each simulated recording, s (at 10 Hz).
    #[arg(long, default_value_t = 10000.0)]
    pub duration: f64,
    /// Self-test: only these kinds of case (effect names, `none`, `chirp`; default all).
    #[arg(long, value_delimiter = ',')]
    pub only: Option<Vec<String>>,
    /// Self-test: factor on every injected magnitude (1 = the documented ranges; smaller values
    /// measure how small an effect is still found).
    #[arg(long, default_value_t = 1.0)]
    pub magnitude: f64,
}

impl SimgapArgs {
    /// The diagnosis settings of these arguments.
    pub fn settings(&self) -> Settings {
        Settings {
            holdout: self.holdout,
            ensemble: self.ensemble,
            seed: self.seed,
            min_share: self.min_share,
            max_effects: self.max_effects,
            threads: self.threads.max(1),
        }
    }
}
