//! `gyrocomp compensate`: the offline driver (docs/design.md "One pipeline, three drivers", driver 3).
//! The recording goes sample by sample through the daemon's pipeline and retrainer
//! ([`crate::drive::compensate_recording`], retraining deterministically) and every sample gets
//! one row in the output CSV ([`crate::io::compensated_csv`]). A one-line summary goes to stderr,
//! or with `--json` a JSON object to stdout.

use std::path::PathBuf;
use std::time::Instant;

use serde::Serialize;

use super::CliError;
use super::plot::compensate::{AxisTrace, CompensateFigure};
use super::plot::{PlotFormat, file_name, save};
use super::progress::Progress;
use crate::config::Config;
use crate::config::RateSetting;
use crate::drive::compensate_recording;
use crate::io::{CompensatedCsvWriter, Recording};
use crate::model::metrics::sample_std_dev;
use crate::stream::{STATUS_MOVING, STATUS_REJECTED};

/// Arguments of `gyrocomp compensate`.
#[derive(Debug, clap::Args)]
pub struct CompensateArgs {
    /// Input recording: CSV (header line, time column `t_s`; or EuRoC) or an MCAP bag
    /// (sensor_msgs/msg/Imu).
    pub input: PathBuf,
    /// Input format options (MCAP topic, CSV units).
    #[command(flatten)]
    pub input_opts: super::input::InputArgs,
    /// Configuration file (default: the built-in defaults of configs/default.toml). Offline runs
    /// always retrain deterministically (`retrain.mode = "deterministic"`).
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// Rate columns, deg/s: 1 to 3, axes x, y, z in this order (repeat or comma-separate).
    #[arg(long = "column", value_delimiter = ',', default_value = "gx_dps")]
    pub columns: Vec<String>,
    /// Column of 0/1 flags from the publisher: 1 = the platform is moving.
    #[arg(long)]
    pub moving_column: Option<String>,
    /// Output CSV (`-` for standard output).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Print the summary as JSON on standard output instead of a line on stderr.
    #[arg(long)]
    pub json: bool,
    /// Also draw the run into this file (.svg or .png, by its extension): per axis over time,
    /// the raw rate, the drift estimate with its ±1σ band, the compensated rate, and the
    /// samples flagged moving or rejected shaded (long runs drawn as min/max per pixel column).
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,
}

/// Static-sample figures of one axis.
#[derive(Debug, Serialize)]
struct AxisSummary {
    column: String,
    static_samples: usize,
    /// Standard deviation (n − 1) of the raw rate over samples that are neither moving nor
    /// rejected, deg/s.
    std_raw: Option<f64>,
    /// The same of the compensated rate.
    std_compensated: Option<f64>,
}

/// What a run did.
#[derive(Debug, Serialize)]
struct Summary {
    input: String,
    output: String,
    samples: u64,
    rejected: u64,
    moving: u64,
    gaps: u64,
    models_installed: u64,
    retrains_failed: u64,
    retrains_skipped: u64,
    model_version: u64,
    axes: Vec<AxisSummary>,
    seconds: f64,
}

/// Runs `gyrocomp compensate`.
pub fn run(args: &CompensateArgs) -> Result<(), CliError> {
    if args.json && args.output.as_os_str() == "-" {
        return Err("--json prints the summary on standard output, where `-o -` writes the CSV: choose one".into());
    }
    if let Some(path) = &args.plot {
        PlotFormat::of(path)?; // before the run, not after it
    }
    let config = Config::load(args.config.as_deref())?;
    let columns: Vec<&str> = args.columns.iter().map(String::as_str).collect();
    let rec = Recording::load_with(&args.input, &columns, args.moving_column.as_deref(), &args.input_opts.options())?;
    if let RateSetting::Hz(hz) = config.input.rate_hz {
        warn_on_rate_mismatch(&rec, hz, config.input.check.gap_factor);
    }
    let write_err = |e: std::io::Error| format!("{}: cannot write: {e}", args.output.display());
    let mut writer = CompensatedCsvWriter::create(&args.output, &rec).map_err(write_err)?;
    let axes = rec.columns().len();
    let mut static_raw = vec![Vec::new(); axes];
    let mut static_comp = vec![Vec::new(); axes];
    let mut failed = None;
    let plotting = args.plot.is_some();
    let mut traces: Vec<AxisTrace> =
        rec.columns().iter().map(|c| AxisTrace { column: c.clone(), ..AxisTrace::default() }).collect();
    let (mut moving, mut rejected) = (Vec::new(), Vec::new());
    let mut progress = Progress::new("compensate", rec.len() as u64);
    let started = Instant::now();
    let run = compensate_recording(&config, &rec, |i, out| {
        progress.set(i as u64 + 1);
        if failed.is_none()
            && let Err(e) = writer.write(i, out)
        {
            failed = Some(e);
        }
        if plotting {
            moving.push(out.status & STATUS_MOVING != 0);
            rejected.push(out.status & STATUS_REJECTED != 0);
            for (axis, trace) in traces.iter_mut().enumerate() {
                trace.raw.push(rec.rate(axis).map_or(f64::NAN, |r| r[i]));
                trace.drift.push(out.drift_dps[axis]);
                trace.drift_std.push(out.drift_std_dps[axis]);
                trace.compensated.push(out.rate_dps[axis]);
            }
        }
        if out.status & (STATUS_MOVING | STATUS_REJECTED) == 0 {
            for axis in 0..axes {
                static_raw[axis].push(rec.rate(axis).map_or(f64::NAN, |r| r[i]));
                static_comp[axis].push(out.rate_dps[axis]);
            }
        }
    })?;
    progress.finish();
    if let Some(e) = failed {
        return Err(write_err(e).into());
    }
    writer.finish().map_err(write_err)?;
    if let Some(path) = &args.plot {
        let figure = CompensateFigure {
            title: format!("gyrocomp compensate: {}", file_name(&args.input)),
            t_s: rec.t_s(),
            moving: &moving,
            rejected: &rejected,
            axes: &traces,
        };
        save(&figure, path)?;
    }
    let stats = run.stats;
    let summary = Summary {
        input: args.input.display().to_string(),
        output: args.output.display().to_string(),
        samples: stats.samples,
        rejected: stats.rejected,
        moving: stats.moving,
        gaps: stats.gaps,
        models_installed: stats.models_installed,
        retrains_failed: stats.retrain_failed,
        retrains_skipped: stats.retrain_skipped + stats.retrain_starved,
        model_version: run.model_version,
        axes: (0..axes)
            .map(|a| AxisSummary {
                column: rec.columns()[a].clone(),
                static_samples: static_raw[a].len(),
                std_raw: sample_std_dev(&static_raw[a]),
                std_compensated: sample_std_dev(&static_comp[a]),
            })
            .collect(),
        seconds: started.elapsed().as_secs_f64(),
    };
    if args.json {
        println!("{}", serde_json::to_string(&summary)?);
    } else {
        eprintln!("{}", summary_line(&summary));
    }
    Ok(())
}

/// Warns when the recording's rate is not the configured `input.rate_hz`: steps longer than
/// `gap_factor` nominal periods are all flagged as gaps (status bit 3), and the windows in
/// samples of the configuration span another length of time.
fn warn_on_rate_mismatch(rec: &Recording, rate_hz: f64, gap_factor: f64) {
    let Some(actual) = rec.sample_rate_hz() else { return };
    if (actual / rate_hz - 1.0).abs() > 0.1 {
        tracing::warn!(
            recording_hz = actual,
            input_rate_hz = rate_hz,
            every_step_is_a_gap = rate_hz / actual > gap_factor,
            "the recording's sample rate is not [input] rate_hz of the configuration; set it to the recording's rate"
        );
    }
}

fn summary_line(s: &Summary) -> String {
    let fmt = |v: Option<f64>| v.map_or_else(|| "n/a".to_owned(), |v| format!("{v:.4e}"));
    let axes: Vec<String> =
        s.axes.iter().map(|a| format!("{} {} → {}", a.column, fmt(a.std_raw), fmt(a.std_compensated))).collect();
    format!(
        "compensate: {} samples ({} rejected, {} moving, {} gaps) → {}; {} models installed (last version {}, {} failed, {} skipped); std over static samples, raw → compensated (deg/s): {}; {:.1} s",
        s.samples,
        s.rejected,
        s.moving,
        s.gaps,
        s.output,
        s.models_installed,
        s.model_version,
        s.retrains_failed,
        s.retrains_skipped,
        axes.join(", "),
        s.seconds
    )
}
