//! `gyrocomp denoise`: wavelet-denoise one column of a recording, batch (the paper's offline step)
//! or causal (what the streaming pipeline does), and measure causal against batch.

use std::path::PathBuf;
use std::time::Instant;

use clap::ValueEnum;
use serde::Serialize;
use tracing::info;

use super::CliError;
use super::input::load_series;
use crate::config::Config;
use crate::io::CsvColumnsWriter;
use crate::model::metrics;
use crate::stream::{CausalConfig, denoise_causal};
use crate::wavelet::{DenoiseConfig, denoise_batch};

/// Batch or causal denoising.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Mode {
    /// Whole series at once (PyWavelets-equal; uses future samples).
    Batch,
    /// Sliding window: each output uses samples up to its own time plus the lag.
    Causal,
}

/// Arguments of `gyrocomp denoise`.
#[derive(Debug, clap::Args)]
pub struct DenoiseArgs {
    /// Input recording: CSV (header line, time column `t_s`; or EuRoC) or an MCAP bag
    /// (sensor_msgs/msg/Imu).
    pub input: PathBuf,
    /// Input format options (MCAP topic, CSV units).
    #[command(flatten)]
    pub input_opts: super::input::InputArgs,
    /// Rate column to denoise.
    #[arg(long, default_value = "gx_dps")]
    pub column: String,
    /// Batch (offline, the paper) or causal (streaming).
    #[arg(long, value_enum, default_value_t = Mode::Batch)]
    pub mode: Mode,
    /// Configuration file; its `[denoise]` keys are the defaults of the four options below
    /// (which take configs/default.toml's values when neither is given).
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// Mother wavelet (db1 … db10) [default: db4].
    #[arg(long)]
    pub wavelet: Option<String>,
    /// Decomposition levels [default: 3].
    #[arg(long)]
    pub level: Option<usize>,
    /// Causal mode: samples in the sliding window [default: 256].
    #[arg(long)]
    pub window: Option<usize>,
    /// Causal mode: the estimate of x[t−lag] is emitted at time t [default: 5].
    #[arg(long)]
    pub lag: Option<usize>,
    /// Output CSV `t_s,raw,denoised` (`-` for standard output).
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Print the summary as JSON on standard output.
    #[arg(long)]
    pub json: bool,
    /// Causal mode: instead of writing a file, tabulate RMSE against batch and cost per sample for
    /// windows 64…2048 and lags 0…32.
    #[arg(long)]
    pub sweep: bool,
}

/// Summary of one denoising run.
#[derive(Debug, Serialize)]
struct Summary {
    mode: Mode,
    samples: usize,
    wavelet: String,
    level: usize,
    #[serde(skip_serializing_if = "Option::is_none")]
    window: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    lag: Option<usize>,
    /// Batch noise σ and threshold (whole series).
    sigma: f64,
    threshold: f64,
    /// Causal only: RMSE of causal against batch over all samples, and after the first window.
    #[serde(skip_serializing_if = "Option::is_none")]
    rmse_vs_batch: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    rmse_vs_batch_steady: Option<f64>,
    std_raw: f64,
    std_denoised: f64,
    seconds: f64,
}

/// One row of the causal trade-off sweep.
#[derive(Debug, Serialize)]
struct SweepRow {
    window: usize,
    lag: usize,
    rmse_vs_batch_steady: f64,
    us_per_sample: f64,
}

/// Runs `gyrocomp denoise`.
pub fn run(args: &DenoiseArgs) -> Result<(), CliError> {
    let mut settings = Config::load(args.config.as_deref())?;
    let section = &mut settings.denoise;
    section.wavelet = args.wavelet.clone().unwrap_or(std::mem::take(&mut section.wavelet));
    section.level = args.level.unwrap_or(section.level);
    section.window = args.window.unwrap_or(section.window);
    section.lag = args.lag.unwrap_or(section.lag);
    let config = settings.denoise()?;
    let series = load_series(&args.input, &args.column, None, &args.input_opts.options())?;
    let x = &series.values;
    let started = Instant::now();
    let (batch, report) = denoise_batch(x, &config);
    if args.sweep {
        return sweep(x, &batch, &config, args.json);
    }
    let causal = match args.mode {
        Mode::Batch => None,
        Mode::Causal => Some(denoise_causal(x, &settings.causal_denoise()?)?),
    };
    let denoised = causal.as_deref().unwrap_or(&batch);
    let (window, lag) = match args.mode {
        Mode::Batch => (None, None),
        Mode::Causal => (Some(settings.denoise.window), Some(settings.denoise.lag)),
    };
    let seconds = started.elapsed().as_secs_f64();
    let summary = Summary {
        mode: args.mode,
        samples: x.len(),
        wavelet: config.wavelet.name().to_owned(),
        level: config.level,
        window,
        lag,
        sigma: report.sigma,
        threshold: report.threshold,
        rmse_vs_batch: window.map(|_| rmse(denoised, &batch)),
        rmse_vs_batch_steady: window.map(|w| rmse(&denoised[w.min(x.len())..], &batch[w.min(x.len())..])),
        std_raw: metrics::sample_std_dev(x).unwrap_or(0.0),
        std_denoised: metrics::sample_std_dev(denoised).unwrap_or(0.0),
        seconds,
    };
    if let Some(path) = &args.output {
        CsvColumnsWriter::create(path)
            .and_then(|w| w.write(&["t_s", "raw", "denoised"], &[&series.t_s, x, denoised]))
            .map_err(|e| format!("{}: cannot write: {e}", path.display()))?;
    }
    if args.json {
        println!("{}", serde_json::to_string(&summary)?);
    } else {
        info!(
            mode = ?summary.mode,
            samples = summary.samples,
            sigma = summary.sigma,
            threshold = summary.threshold,
            rmse_vs_batch = ?summary.rmse_vs_batch,
            rmse_vs_batch_steady = ?summary.rmse_vs_batch_steady,
            std_raw = summary.std_raw,
            std_denoised = summary.std_denoised,
            seconds = summary.seconds,
            "denoised"
        );
        if let Some(r) = summary.rmse_vs_batch_steady {
            eprintln!("causal vs batch RMSE (after the first window): {r:.6e}");
        }
    }
    Ok(())
}

fn sweep(x: &[f64], batch: &[f64], config: &DenoiseConfig, json: bool) -> Result<(), CliError> {
    let mut rows = Vec::new();
    for window in [64, 128, 256, 512, 1024, 2048] {
        for lag in [0, 2, 5, 10, 20, 32] {
            let causal = CausalConfig { denoise: config.clone(), window, lag };
            if causal.validate().is_err() || window >= x.len() {
                continue;
            }
            let started = Instant::now();
            let out = denoise_causal(x, &causal)?;
            let us_per_sample = started.elapsed().as_secs_f64() * 1e6 / x.len() as f64;
            let steady = rmse(&out[window..], &batch[window..]);
            rows.push(SweepRow { window, lag, rmse_vs_batch_steady: steady, us_per_sample });
        }
    }
    let raw = rmse(x, batch);
    let shift = shift_variance(x, batch, config);
    if json {
        println!(
            "{}",
            serde_json::json!({ "rmse_raw_vs_batch": raw, "rmse_batch_shifted_vs_batch": shift, "rows": rows })
        );
    } else {
        println!("RMSE of the raw series against batch (no denoising at all): {raw:.3e} deg/s");
        let mean = shift.iter().sum::<f64>() / shift.len().max(1) as f64;
        let max = shift.iter().copied().fold(0.0, f64::max);
        println!(
            "RMSE of batch started 1…{} samples later against batch (shift variance of the decimated DWT): mean {mean:.3e}, max {max:.3e} deg/s\n",
            shift.len()
        );
        println!("| window | lag | RMSE causal vs batch (deg/s) | µs/sample |");
        println!("|---:|---:|---:|---:|");
        for r in &rows {
            println!("| {} | {} | {:.3e} | {:.1} |", r.window, r.lag, r.rmse_vs_batch_steady, r.us_per_sample);
        }
    }
    Ok(())
}

/// How much the batch result itself moves when the series starts `k` samples later, for
/// k = 1 … 2^level − 1 (the decimated DWT is not shift-invariant); RMSE over the samples away from
/// either end. This is the floor any causal (sliding-window) denoiser can reach against batch.
fn shift_variance(x: &[f64], batch: &[f64], config: &DenoiseConfig) -> Vec<f64> {
    let margin = 1000.min(x.len() / 4);
    (1..1usize << config.level)
        .filter(|&k| x.len() > k + 2 * margin)
        .map(|k| {
            let (shifted, _) = denoise_batch(&x[k..], config);
            let end = shifted.len() - margin;
            rmse(&shifted[margin..end], &batch[k + margin..k + end])
        })
        .collect()
}

fn rmse(a: &[f64], b: &[f64]) -> f64 {
    metrics::rmse(a, b).unwrap_or(0.0)
}
