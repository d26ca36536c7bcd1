//! `gyrocomp cc`: the C-C method (Kim et al. 1999; paper Eq. 18–20, §4.2) on one column of a
//! recording. As in the paper, the series is wavelet-denoised first (db4, 3 levels, soft
//! threshold; `--no-denoise` skips it), then the first `--max-points` samples are analysed.

use std::time::Instant;

use serde::Serialize;

use super::CliError;
use super::input::load_series;
use crate::model::cc::{CcConfig, CcResult, TauRule, cc_method};
use crate::wavelet::{DenoiseConfig, denoise_batch};

/// Arguments of `gyrocomp cc`.
#[derive(Debug, clap::Args)]
pub struct CcArgs {
    /// Input recording: CSV (gyrocomp or EuRoC) or an MCAP bag (sensor_msgs/msg/Imu).
    pub input: std::path::PathBuf,
    /// Input format options (MCAP topic, CSV units).
    #[command(flatten)]
    pub input_opts: super::input::InputArgs,
    /// Rate column to analyse.
    #[arg(long, default_value = "gx_dps")]
    pub column: String,
    /// Print one JSON object instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Largest delay t examined (t = 1..=T); the analysed series needs at least 6·T samples.
    #[arg(long, default_value_t = 40)]
    pub t_max: usize,
    /// Analyse the first N samples only (the paper's first group has 5000); 0 = all. The cost
    /// grows as N².
    #[arg(long, default_value_t = 5000)]
    pub max_points: usize,
    /// Analyse the raw series instead of the wavelet-denoised one.
    #[arg(long)]
    pub no_denoise: bool,
}

/// The JSON printed by `gyrocomp cc --json`: the paper's quantities first, then context.
#[derive(Debug, Serialize)]
struct CcJson<'a> {
    tau: usize,
    tau_w: usize,
    m: usize,
    t: &'a [usize],
    s_mean: &'a [f64],
    delta_s_mean: &'a [f64],
    s_cor: &'a [f64],
    tau_rule: TauRule,
    points: usize,
    denoised: bool,
    column: &'a str,
    sigma: f64,
    rate_hz: f64,
}

/// Runs `gyrocomp cc`.
pub fn run(args: &CcArgs) -> Result<(), CliError> {
    let series = load_series(&args.input, &args.column, None, &args.input_opts.options())?;
    let started = Instant::now();
    let mut x = if args.no_denoise { series.values } else { denoise_batch(&series.values, &DenoiseConfig::paper()).0 };
    if args.max_points > 0 {
        x.truncate(args.max_points);
    }
    let config = CcConfig { t_max: args.t_max, threads: 0 };
    let result =
        cc_method(&x, &config).map_err(|e| format!("{}: column {}: {e}", args.input.display(), args.column))?;
    tracing::debug!("C-C method on {} points, t = 1..={}, in {:.2?}", x.len(), args.t_max, started.elapsed());
    if args.json {
        let out = CcJson {
            tau: result.tau,
            tau_w: result.tau_w,
            m: result.m,
            t: &result.t,
            s_mean: &result.s_mean,
            delta_s_mean: &result.delta_s_mean,
            s_cor: &result.s_cor,
            tau_rule: result.tau_rule,
            points: x.len(),
            denoised: !args.no_denoise,
            column: &args.column,
            sigma: result.sigma,
            rate_hz: series.rate_hz,
        };
        println!("{}", serde_json::to_string(&out)?);
    } else {
        print!("{}", table(args, &result, x.len(), series.rate_hz));
    }
    Ok(())
}

/// The human-readable report: one row per t, then the choices.
fn table(args: &CcArgs, r: &CcResult, points: usize, rate_hz: f64) -> String {
    let source = if args.no_denoise { "raw" } else { "wavelet-denoised (db4, 3 levels)" };
    let mut s = format!(
        "C-C method on {} column {}: {points} {source} samples, σ = {:.6}, radii jσ/2 for j = 1..4\n",
        args.input.display(),
        args.column,
        r.sigma
    );
    s.push_str(&format!("{:>4} {:>14} {:>14} {:>14}\n", "t", "S̄(t)", "ΔS̄(t)", "S_cor(t)"));
    for (i, &t) in r.t.iter().enumerate() {
        let mark = match (t == r.tau, t == r.tau_w) {
            (true, true) => "  ← τ, τw",
            (true, false) => "  ← τ",
            (false, true) => "  ← τw",
            (false, false) => "",
        };
        s.push_str(&format!(
            "{t:>4} {:>14.6e} {:>14.6e} {:>14.6e}{mark}\n",
            r.s_mean[i], r.delta_s_mean[i], r.s_cor[i]
        ));
    }
    let rule = match r.tau_rule {
        TauRule::FirstLocalMinimum => "first local minimum of ΔS̄",
        TauRule::FirstZeroCrossing => "first zero of S̄ (ΔS̄ has no local minimum)",
        TauRule::ArgminDeltaS => "smallest ΔS̄ (no local minimum, no zero of S̄)",
    };
    let secs = |samples: usize| samples as f64 / rate_hz;
    s.push_str(&format!("τ  = {} samples ({:.3} s), {rule}\n", r.tau, secs(r.tau)));
    s.push_str(&format!("τw = {} samples ({:.3} s), minimum of S_cor\n", r.tau_w, secs(r.tau_w)));
    s.push_str(&format!("m  = round(τw/τ) + 1 = {}\n", r.m));
    s
}
