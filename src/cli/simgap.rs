//! `gyrocomp simgap`: the sim-to-real gap diagnosis of one rate column (where the simulation
//! differs, which unmodelled effect explains it, how far the gap shrinks on the held-out part), as
//! text, JSON or an HTML report; `--selftest` runs the diagnosis on simulated recordings with a
//! known effect and prints the confusion table.
//!
//! Split by concern: [`super::simgap_args`] (arguments), [`super::simgap_json`] (`--json`),
//! [`super::simgap_text`] (text report), [`super::simgap_report`] (HTML),
//! [`super::simgap_selftest`] (`--selftest`).

use std::io::Write;
use std::time::Instant;

use super::CliError;
use super::input::load_series;
use super::simgap_args::SimgapArgs;
use super::simgap_json::json_report;
use super::simgap_report::write_report;
use super::simgap_selftest::run_selftest_cli;
use super::simgap_text::write_text;
use crate::diag::simgap::{Baseline, Recording, diagnose};
use crate::sim::SimConfig;

/// Runs `gyrocomp simgap`.
pub fn run(args: &SimgapArgs) -> Result<(), CliError> {
    if args.selftest {
        return run_selftest_cli(args);
    }
    let path = args.real.as_ref().ok_or("--real FILE is required (or --selftest)")?;
    let series = load_series(path, &args.column, args.rate, &args.input_opts.options())?;
    let temp_c = match series.temp_c {
        Some(t) if t.iter().all(|v| v.is_finite()) => Some(t),
        Some(_) => {
            tracing::warn!(
                "{}: the temperature column has empty or non-finite rows; the temperature effect is skipped",
                path.display()
            );
            None
        }
        None => None,
    };
    let baseline = match &args.sim {
        Some(file) => {
            let text = std::fs::read_to_string(file).map_err(|e| format!("{}: cannot read: {e}", file.display()))?;
            let config = SimConfig::from_toml(&text).map_err(|e| format!("{}: {e}", file.display()))?;
            if (config.rate_hz - series.rate_hz).abs() > 1e-6 * series.rate_hz {
                tracing::warn!(
                    "{}: rate_hz {} differs from the recording's {} Hz; the recording's rate is simulated",
                    file.display(),
                    config.rate_hz,
                    series.rate_hz
                );
            }
            Baseline::Given(Box::new(config.axis_model(axis_of_column(&args.column))))
        }
        None => Baseline::Fitted,
    };
    let recording = Recording { rate: &series.values, rate_hz: series.rate_hz, temp_c: temp_c.as_deref() };
    let started = Instant::now();
    let diagnosis = diagnose(&recording, &baseline, &args.settings())
        .map_err(|e| format!("{}: column `{}`: {e}", path.display(), args.column))?;
    let seconds = started.elapsed().as_secs_f64();
    tracing::info!("diagnosis took {seconds:.1} s ({} ensembles of {})", diagnosis.ensembles_run, args.ensemble);
    let mut out = std::io::stdout().lock();
    if args.json {
        serde_json::to_writer(&mut out, &json_report(args, &diagnosis))?;
        writeln!(out)?;
    } else {
        write_text(&mut out, args, &diagnosis, seconds)?;
    }
    if let Some(dir) = &args.report {
        let file = write_report(dir, args, &diagnosis)?;
        if !args.json {
            writeln!(out, "\nReport: {}", file.display())?;
        }
    }
    out.flush()?;
    Ok(())
}

/// The simulator axis of a column name: `g?x…`/`…x_dps` → x, y, z (x when unclear).
fn axis_of_column(column: &str) -> usize {
    let name = column.to_ascii_lowercase();
    ["x", "y", "z"]
        .iter()
        .position(|a| name.starts_with(&format!("g{a}")) || name.contains(&format!("{a}_")))
        .unwrap_or(0)
}
