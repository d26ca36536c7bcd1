//! `gyrocomp allan`: overlapping Allan deviation of one rate column and the IEEE Std 952-1997
//! (Annex C) noise-term fit, printed as a table, as JSON, or as the gyroscope keys of a Kalibr
//! `imu.yaml` ([`crate::diag::kalibr`]).

use std::io::Write;
use std::path::PathBuf;

use serde::Serialize;

use super::CliError;
use super::input::load_series;
use super::plot::allan::AllanFigure;
use super::plot::{file_name, save};
use crate::diag::allan::{AllanDeviation, Taus, oadev_with_max_m};
use crate::diag::fit_intervals::{DEFAULT_DRAWS, FitIntervals, fit_intervals};
use crate::diag::kalibr::KalibrGyro;
use crate::diag::noise_fit::{NoiseFit, Weighting, fit_allan};
use crate::diag::noise_model::{CustomaryNoise, NoiseModel};
use crate::io::detect_format;

/// Confidence level of the fitted terms' intervals (`fit_ci` of the JSON, the text table).
const CI_LEVEL: f64 = 0.95;
/// Seed of their bootstrap, fixed so that a file always gives the same intervals.
const CI_SEED: u64 = 952;
/// From this many samples on, the intervals' cost (one simulation and Allan deviation of the
/// input per replicate) is announced on stderr.
const CI_NOTICE_SAMPLES: usize = 1_000_000;

/// Above this many samples `--taus all` without `--max-m` logs a warning about its O(N²) cost.
const ALL_TAUS_WARN_SAMPLES: usize = 50_000;

/// The τ grid of `--taus`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum TauGrid {
    /// m = 1, 2, 4, 8, … samples (allantools "octave").
    Octave,
    /// Every m = 1, 2, 3, … (allantools "all"): about N²/4 operations for N samples.
    All,
}

/// Weights of the noise-term fit (`--fit-weights`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum FitWeights {
    /// n/m: independent terms per τ (default; long τ count less).
    Independent,
    /// n: overlapping terms per τ (nearly equal weights on an octave grid).
    Terms,
}

/// What `gyrocomp allan` prints (`--format`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum AllanFormat {
    /// A table of τ, σ(τ) and the fitted terms.
    Text,
    /// JSON (the same as `--json`).
    Json,
    /// Kalibr `imu.yaml` gyroscope keys: `update_rate`, `gyroscope_noise_density` (N) and
    /// `gyroscope_random_walk` (K), rad units.
    Kalibr,
}

/// Arguments of `gyrocomp allan`.
#[derive(Debug, clap::Args)]
pub struct AllanArgs {
    /// Input recording: CSV (header line, time column `t_s`, `t` or `time` in seconds, rates in
    /// deg/s or with --units rads; or EuRoC), or an MCAP bag (sensor_msgs/msg/Imu).
    pub input: PathBuf,
    /// Rate column to analyse, deg/s.
    #[arg(long, default_value = "gx_dps")]
    pub column: String,
    /// Sample rate in Hz (default: from the time column, (rows − 1)/(t_last − t_first)).
    #[arg(long)]
    pub rate: Option<f64>,
    /// Averaging times: octave (m = 1, 2, 4, … samples) or all (every m; O(N²): seconds for
    /// 10⁵ samples, about ten minutes for 10⁶; bound it with --max-m).
    #[arg(long, value_enum, default_value_t = TauGrid::Octave)]
    pub taus: TauGrid,
    /// Largest averaging factor m (samples) to evaluate.
    #[arg(long)]
    pub max_m: Option<usize>,
    /// Weights of the noise-term fit (always made on the octave points m = 2^k).
    #[arg(long, value_enum, default_value_t = FitWeights::Independent)]
    pub fit_weights: FitWeights,
    /// Print JSON: {"tau_s":[…],"adev":[…],"fit":{"q","n","b","k","r"},…} ("fit" is null when
    /// the Allan deviation is zero everywhere); "fit_ci" holds each term's 95 % interval.
    #[arg(long, conflicts_with = "format")]
    pub json: bool,
    /// Output format: text (default), json, or kalibr (the gyroscope keys of a Kalibr imu.yaml,
    /// from the fitted N and K in rad units; Kalibr takes one value for the three axes: run it
    /// per axis and keep the largest).
    #[arg(long, value_enum)]
    pub format: Option<AllanFormat>,
    /// Bootstrap replicates of the fitted terms' 95 % confidence intervals ("fit_ci" in the
    /// JSON, brackets in the table): recordings simulated from the fitted model and refitted;
    /// each costs about one Allan deviation of the input. 0: no intervals (`--format kalibr`
    /// prints none, so it never computes them).
    #[arg(long, default_value_t = DEFAULT_DRAWS)]
    pub ci_draws: usize,
    /// Also draw the Allan deviation into this file (.svg or .png, by its extension): the
    /// measured points with their 68 % χ² band, the fitted curve and each fitted term's line
    /// (slopes −1, −½, 0, +½, +1), log-log.
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,
    /// Input format options. `--topic` chooses the topic of an MCAP bag and is the `rostopic`
    /// key of `--format kalibr` (for a bag, the topic read by default; for CSV, only the key).
    #[command(flatten)]
    pub input_opts: super::input::InputArgs,
}

impl AllanArgs {
    /// The format asked for (`--json` is `--format json`).
    fn output_format(&self) -> AllanFormat {
        match (self.format, self.json) {
            (Some(f), _) => f,
            (None, true) => AllanFormat::Json,
            (None, false) => AllanFormat::Text,
        }
    }
}

/// Runs `gyrocomp allan`.
pub fn run(args: &AllanArgs) -> Result<(), CliError> {
    let mut input = args.input_opts.options();
    if detect_format(&args.input)?.name() != "mcap" {
        input.topic = None; // for CSV, --topic is only Kalibr's `rostopic` key
    }
    let series = load_series(&args.input, &args.column, args.rate, &input)?;
    let samples = series.values.len();
    let taus = match args.taus {
        TauGrid::Octave => Taus::Octave,
        TauGrid::All => Taus::All,
    };
    if args.taus == TauGrid::All && args.max_m.is_none() && samples > ALL_TAUS_WARN_SAMPLES {
        tracing::warn!(
            "--taus all on {samples} samples costs about N²/4 = {:.1e} operations; bound it with --max-m",
            (samples as f64).powi(2) / 4.0
        );
    }
    let allan = oadev_with_max_m(&series.values, series.rate_hz, &taus, args.max_m.unwrap_or(usize::MAX))
        .map_err(|e| format!("{}: column `{}`: {e}", args.input.display(), args.column))?;
    let weighting = match args.fit_weights {
        FitWeights::Independent => Weighting::IndependentTerms,
        FitWeights::Terms => Weighting::Terms,
    };
    let octave = allan.octave_points();
    let fit = match fit_allan(&octave, weighting) {
        Ok(fit) => Some(fit),
        Err(e) => {
            tracing::warn!("{}: column `{}`: no noise-term fit: {e}", args.input.display(), args.column);
            None
        }
    };
    // The Kalibr YAML has no intervals: the bootstrap runs only for the formats that print them.
    let draws = if args.output_format() == AllanFormat::Kalibr { 0 } else { args.ci_draws };
    if fit.is_some() && draws > 0 && samples >= CI_NOTICE_SAMPLES {
        tracing::info!(
            "confidence intervals: simulating and fitting {} recordings of {samples} samples, each about the cost of this Allan deviation (--ci-draws 0 skips them)",
            draws
        );
    }
    let ci = match (&fit, draws) {
        (Some(f), draws) if draws > 0 => match fit_intervals(&octave, weighting, f, CI_LEVEL, draws, CI_SEED) {
            Ok(ci) => Some(ci),
            Err(e) => {
                tracing::warn!("{}: column `{}`: no confidence intervals: {e}", args.input.display(), args.column);
                None
            }
        },
        _ => None,
    };
    if let Some(path) = &args.plot {
        let figure = AllanFigure {
            title: format!("Allan deviation of {} in {}", args.column, file_name(&args.input)),
            allan: &allan,
            fit: fit.as_ref(),
        };
        save(&figure, path)?;
    }
    let mut out = std::io::stdout().lock();
    match args.output_format() {
        AllanFormat::Json => {
            let report = JsonReport::new(args, &allan, fit.as_ref(), ci);
            serde_json::to_writer(&mut out, &report)?;
            writeln!(out)?;
        }
        AllanFormat::Text => write_table(&mut out, args, &allan, fit.as_ref(), ci.as_ref())?,
        AllanFormat::Kalibr => {
            let fit = fit.ok_or_else(|| {
                format!(
                    "{}: column `{}`: no noise-term fit, so no Kalibr parameters",
                    args.input.display(),
                    args.column
                )
            })?;
            let source = format!("{} column {}", args.input.display(), args.column);
            let topic = args.input_opts.topic.as_deref().or(series.topic.as_deref());
            out.write_all(KalibrGyro::from_fit(&fit.model, &allan).to_yaml(&source, topic).as_bytes())?;
        }
    }
    out.flush()?;
    Ok(())
}

/// The JSON document of `--json`; the first three keys are the stable interface.
#[derive(Serialize)]
struct JsonReport<'a> {
    tau_s: &'a [f64],
    adev: &'a [f64],
    fit: Option<NoiseModel>,
    n_terms: &'a [usize],
    m: &'a [usize],
    adev_err: &'a [f64],
    fit_customary: Option<CustomaryNoise>,
    fit_info: Option<FitInfo>,
    fit_ci: Option<FitIntervals>,
    kalibr: Option<KalibrGyro>,
    column: &'a str,
    rate_hz: f64,
    samples: usize,
    units: Units,
}

#[derive(Serialize)]
struct FitInfo {
    model: &'static str,
    taus: &'static str,
    weights: &'static str,
    points: usize,
    rms_relative_residual: f64,
}

#[derive(Serialize)]
struct Units {
    tau_s: &'static str,
    adev: &'static str,
    fit: [&'static str; 5],
    fit_customary: [&'static str; 5],
}

impl<'a> JsonReport<'a> {
    fn new(args: &'a AllanArgs, allan: &'a AllanDeviation, fit: Option<&NoiseFit>, ci: Option<FitIntervals>) -> Self {
        Self {
            tau_s: &allan.tau_s,
            adev: &allan.adev,
            fit: fit.map(|f| f.model),
            n_terms: &allan.n,
            m: &allan.m,
            adev_err: &allan.adev_err,
            fit_customary: fit.map(|f| f.model.customary()),
            fit_info: fit.map(|f| FitInfo {
                model: "IEEE Std 952-1997 Annex C: avar = 3q^2/tau^2 + n^2/tau + (2 ln2/pi) b^2 + k^2 tau/3 + r^2 tau^2/2",
                taus: "octave points (m = 2^k)",
                weights: weights_label(args.fit_weights),
                points: f.points,
                rms_relative_residual: f.rms_relative_residual,
            }),
            fit_ci: ci,
            kalibr: fit.map(|f| KalibrGyro::from_fit(&f.model, allan)),
            column: &args.column,
            rate_hz: allan.rate_hz,
            samples: allan.samples,
            units: Units {
                tau_s: "s",
                adev: "deg/s",
                fit: ["q: deg", "n: deg/sqrt(s)", "b: deg/s", "k: deg/s/sqrt(s)", "r: deg/s^2"],
                fit_customary: ["q_deg: deg", "n: deg/sqrt(h)", "b: deg/h", "k: deg/h/sqrt(h)", "r: deg/h^2"],
            },
        }
    }
}

fn weights_label(w: FitWeights) -> &'static str {
    match w {
        FitWeights::Independent => "relative residual of avar, weight n/m (independent terms)",
        FitWeights::Terms => "relative residual of avar, weight n (overlapping terms)",
    }
}

fn write_table(
    out: &mut impl Write,
    args: &AllanArgs,
    allan: &AllanDeviation,
    fit: Option<&NoiseFit>,
    ci: Option<&FitIntervals>,
) -> std::io::Result<()> {
    writeln!(
        out,
        "Overlapping Allan deviation of `{}` in {}: {} samples at {} Hz",
        args.column,
        args.input.display(),
        allan.samples,
        allan.rate_hz
    )?;
    writeln!(out)?;
    writeln!(
        out,
        "{:>14} {:>10} {:>14} {:>12} {:>10} {:>14}",
        "tau_s", "m", "adev_dps", "adev_err", "n", "fit_adev_dps"
    )?;
    for i in 0..allan.len() {
        let model = fit.map_or(String::from("-"), |f| format!("{:.6e}", f.model.allan_deviation(allan.tau_s[i])));
        writeln!(
            out,
            "{:>14.6} {:>10} {:>14.6e} {:>12.3e} {:>10} {:>14}",
            allan.tau_s[i], allan.m[i], allan.adev[i], allan.adev_err[i], allan.n[i], model
        )?;
    }
    writeln!(out)?;
    let Some(fit) = fit else {
        return writeln!(out, "No noise-term fit: the Allan deviation is zero or unusable at every tau.");
    };
    let (m, c) = (fit.model, fit.model.customary());
    writeln!(out, "IEEE Std 952-1997 Annex C noise-term fit")?;
    writeln!(out, "  avar(tau) = 3Q²/tau² + N²/tau + (2 ln2/π)B² + K²tau/3 + R²tau²/2")?;
    writeln!(
        out,
        "  on {} octave points, {}; weighted RMS relative misfit {:.3}",
        fit.points,
        weights_label(args.fit_weights),
        fit.rms_relative_residual
    )?;
    let range = |pick: fn(&FitIntervals) -> [f64; 2]| {
        ci.map_or_else(String::new, |ci| {
            let [lo, hi] = pick(ci);
            format!("   [{lo:.3e}, {hi:.3e}]")
        })
    };
    writeln!(out, "  Q  quantisation      {:>12.4e} deg{}", m.q, range(|c| c.q))?;
    writeln!(
        out,
        "  N  angle random walk {:>12.4e} deg/√s      = {:>12.4e} deg/√h{}",
        m.n,
        c.n_deg_per_sqrt_h,
        range(|c| c.n)
    )?;
    writeln!(
        out,
        "  B  bias instability  {:>12.4e} deg/s       = {:>12.4e} deg/h{}",
        m.b,
        c.b_deg_per_h,
        range(|c| c.b)
    )?;
    writeln!(
        out,
        "  K  rate random walk  {:>12.4e} deg/s/√s    = {:>12.4e} deg/h/√h{}",
        m.k,
        c.k_deg_per_h_sqrt_h,
        range(|c| c.k)
    )?;
    writeln!(
        out,
        "  R  rate ramp         {:>12.4e} deg/s²      = {:>12.4e} deg/h²{}",
        m.r,
        c.r_deg_per_h2,
        range(|c| c.r)
    )?;
    if let Some(ci) = ci {
        writeln!(
            out,
            "  [..]: {:.0} % intervals in the first unit; parametric bootstrap, {} recordings simulated from the fit (seed {})",
            100.0 * ci.level,
            ci.fits,
            ci.seed
        )?;
    }
    Ok(())
}
