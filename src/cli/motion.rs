//! `gyrocomp motion`: add a known motion profile to the rate columns of a static recording, for the
//! motion-injected evaluation (docs/design.md). Every column of the input is kept, in order; the chosen
//! rate columns get the profile added; `truth_dps` (the profile) and `moving` (1 inside a motion,
//! else 0) are appended. The same profile goes into each chosen column, so each is a separate test
//! case with the same truth.

use std::path::PathBuf;

use clap::ValueEnum;
use serde::Serialize;
use tracing::info;

use super::CliError;
use crate::io::csv_read::TIME_COLUMN_NAMES;
use crate::io::{CsvColumnsWriter, ReadOptions, SampleReader, read_table};
use crate::sim::{MotionKind, MotionPlan};

/// Motion profiles (see `gyrocomp::sim::motion`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ProfileArg {
    /// Smooth turns, 1–90 deg/s, 2–60 s each.
    Turns,
    /// Slow rotations, 0.05–1 deg/s, 20–300 s each.
    Slow,
    /// Turns and slow rotations.
    Mixed,
}

impl From<ProfileArg> for MotionKind {
    fn from(p: ProfileArg) -> Self {
        match p {
            ProfileArg::Turns => MotionKind::Turns,
            ProfileArg::Slow => MotionKind::Slow,
            ProfileArg::Mixed => MotionKind::Mixed,
        }
    }
}

/// Arguments of `gyrocomp motion`.
#[derive(Debug, clap::Args)]
pub struct MotionArgs {
    /// Static recording (CSV with a time column).
    pub input: PathBuf,
    /// Motion profile.
    #[arg(long, value_enum, default_value_t = ProfileArg::Mixed)]
    pub profile: ProfileArg,
    /// Seed of the profile.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Least fraction of the run that stays static (0–1).
    #[arg(long, default_value_t = 0.5)]
    pub static_fraction: f64,
    /// Rate columns to add the profile to (default: those of gx_dps, gy_dps, gz_dps present).
    #[arg(long, value_delimiter = ',')]
    pub columns: Vec<String>,
    /// Output CSV (`-` for standard output).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Print the summary as JSON on standard output.
    #[arg(long)]
    pub json: bool,
}

/// Summary of one injection.
#[derive(Debug, Serialize)]
struct Summary {
    profile: ProfileArg,
    seed: u64,
    samples: usize,
    columns: Vec<String>,
    motions: usize,
    static_fraction: f64,
    max_abs_rate_dps: f64,
    total_abs_angle_deg: f64,
}

/// Runs `gyrocomp motion`.
pub fn run(args: &MotionArgs) -> Result<(), CliError> {
    let options = ReadOptions { allow_non_finite: true, require_increasing_time: true };
    let header = SampleReader::open(&args.input, &[], options)?.header().to_vec();
    let time_name = TIME_COLUMN_NAMES.iter().find(|n| header.iter().any(|h| h == *n)).copied();
    let others: Vec<&str> = header.iter().map(String::as_str).filter(|h| Some(*h) != time_name).collect();
    for reserved in ["truth_dps", "moving"] {
        if others.contains(&reserved) {
            return Err(format!(
                "{}: already has a `{reserved}` column (motion injected twice?)",
                args.input.display()
            )
            .into());
        }
    }
    let targets: Vec<String> = if args.columns.is_empty() {
        ["gx_dps", "gy_dps", "gz_dps"].into_iter().filter(|c| others.contains(c)).map(str::to_owned).collect()
    } else {
        args.columns.clone()
    };
    if targets.is_empty() {
        return Err(format!(
            "{}: no gx_dps/gy_dps/gz_dps column; name the rate columns with --columns",
            args.input.display()
        )
        .into());
    }
    if let Some(missing) = targets.iter().find(|t| !others.contains(&t.as_str())) {
        return Err(format!("{}: no column `{missing}` (columns: {})", args.input.display(), header.join(", ")).into());
    }
    let mut table = read_table(&args.input, &others, options)?;
    let t0 = table.t_s[0];
    let duration = table.t_s[table.len() - 1] - t0;
    let t_rel: Vec<f64> = table.t_s.iter().map(|t| t - t0).collect();
    let plan = MotionPlan::plan(args.profile.into(), args.seed, duration, args.static_fraction)?;
    let (truth, moving) = plan.render(&t_rel);
    for (name, column) in table.names.iter().zip(table.columns.iter_mut()) {
        if targets.contains(name) {
            for (v, &m) in column.iter_mut().zip(&truth) {
                *v += m;
            }
        }
    }
    let mut out_header: Vec<&str> = vec!["t_s"];
    out_header.extend(table.names.iter().map(String::as_str));
    out_header.extend(["truth_dps", "moving"]);
    let mut columns: Vec<&[f64]> = vec![&table.t_s];
    columns.extend(table.columns.iter().map(Vec::as_slice));
    columns.push(&truth);
    columns.push(&moving);
    CsvColumnsWriter::create(&args.output)
        .and_then(|w| w.write(&out_header, &columns))
        .map_err(|e| format!("{}: cannot write: {e}", args.output.display()))?;
    let summary = Summary {
        profile: args.profile,
        seed: args.seed,
        samples: table.len(),
        columns: targets,
        motions: plan.segments.len(),
        static_fraction: plan.static_fraction(),
        max_abs_rate_dps: truth.iter().fold(0.0, |m, v| v.abs().max(m)),
        total_abs_angle_deg: plan.segments.iter().map(|s| s.angle_deg().abs()).sum(),
    };
    if args.json {
        println!("{}", serde_json::to_string(&summary)?);
    } else {
        info!(
            profile = ?summary.profile,
            motions = summary.motions,
            static_fraction = summary.static_fraction,
            max_abs_rate_dps = summary.max_abs_rate_dps,
            total_abs_angle_deg = summary.total_abs_angle_deg,
            "motion injected"
        );
    }
    Ok(())
}
