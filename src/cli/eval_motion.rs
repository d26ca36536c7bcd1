//! `gyrocomp eval IN --protocol motion`: the motion-injected protocol ([`crate::eval::motion`]) on
//! a file made by `gyrocomp motion` — the rate column (recording + profile), `truth_dps` (the
//! profile) and `moving` (1 inside a motion). Every model ([`crate::eval::motion_models`]) runs on
//! the same stream; the table or JSON gives the compensated-rate RMSE and the angle errors.
//!
//! The gyrocomp pipeline gets the rate column only: its motion gate works from thresholds, as in
//! the daemon. The `moving` column defines the scored segments, and is given to the pipeline
//! only in the clearly named `gyrocomp-flagged` row (an oracle). `input.rate_hz` of the
//! configuration is set to the recording's rate (it only decides which steps are flagged as gaps).

use std::time::Instant;

use serde::Serialize;

use super::CliError;
use super::eval_args::{EvalArgs, parse_models};
use super::plot::motion::{ModelErrors, MotionFigure};
use super::plot::{PlotFormat, file_name, save};
use super::progress::Progress;
use crate::config::Config;
use crate::eval::motion::MotionScores;
use crate::eval::{BaselineSettings, MotionModel, MotionRun, run_motion_model};
use crate::eval::{DetectionScores, detection_scores};
use crate::io::{ReadOptions, Recording, read_columns};
use crate::model::metrics::quantile;

/// Column of the injected truth written by `gyrocomp motion`.
pub const TRUTH_COLUMN: &str = "truth_dps";
/// Column of the moving flags written by `gyrocomp motion`.
pub const MOVING_COLUMN: &str = "moving";

/// What the evaluation ran on.
#[derive(Debug, Serialize)]
struct DataInfo {
    input: String,
    column: String,
    samples: usize,
    rate_hz: f64,
    segments: usize,
    moving_samples: usize,
    startup_s: f64,
    highpass_hz: f64,
    /// Angle random walk of the sensor series (raw − truth), deg/√s, from its Allan fit.
    arw_n_deg_rt_s: Option<f64>,
    /// Median over the motion segments of the white-noise floor 0.674·N·√T, deg.
    white_floor_deg_median: Option<f64>,
    /// Each segment's length, s.
    segment_s: Vec<f64>,
    /// Each segment's white-noise floor, deg.
    white_floor_deg_segments: Vec<f64>,
}

/// One row of the JSON output.
#[derive(Debug, Serialize)]
struct ModelRow {
    name: MotionModel,
    #[serde(flatten)]
    scores: MotionScores,
    detail: String,
    seconds: f64,
    /// How the pipeline's motion judgement did against the truth ([`crate::eval::detection`]);
    /// `null` for the baselines that run no pipeline.
    detection: Option<DetectionScores>,
}

/// Runs the motion-injected protocol.
pub fn run(args: &EvalArgs) -> Result<(), CliError> {
    let kinds = parse_models::<MotionModel>(args.models.as_deref())?.unwrap_or_else(|| MotionModel::ALL.to_vec());
    if let Some(path) = &args.plot {
        PlotFormat::of(path)?; // before the models run, not after
    }
    let config = Config::load(args.config.as_deref())?;
    // Finite rates and truth, with line-exact errors; the flags checked to be 0/1 the same way.
    let input = args.input_opts.options();
    let mut table = read_columns(&args.input, &[&args.column, TRUTH_COLUMN], ReadOptions::default(), &input)?;
    let mut rec = Recording::load_with(&args.input, &[&args.column], Some(MOVING_COLUMN), &input)?;
    let moving = rec.take_moving().unwrap_or_default();
    let truth = table.columns.pop().unwrap_or_default();
    let raw = table.columns.pop().unwrap_or_default();
    let run = MotionRun::new(table.t_s, raw, truth, &moving)?;
    let inputs: Vec<_> = rec.inputs().collect();
    let baselines = BaselineSettings { startup_s: args.startup_s, highpass_hz: args.highpass_hz };

    let mut rows = Vec::with_capacity(kinds.len());
    for kind in kinds {
        let started = Instant::now();
        let mut bar = Progress::new(kind.name(), if kind.uses_pipeline() { run.len() as u64 } else { 0 });
        let out = run_motion_model(kind, &config, &run, &inputs, &moving, baselines, &mut |i| bar.set(i as u64))
            .map_err(|e| format!("model `{kind}`: {e}"))?;
        bar.finish();
        let scores = run.score(&out.compensated)?;
        let detection = out.judged_moving.as_deref().map(|judged| detection_scores(&run, judged)).transpose()?;
        rows.push(ModelRow {
            name: kind,
            scores,
            detail: out.detail,
            seconds: started.elapsed().as_secs_f64(),
            detection,
        });
    }
    let arw = run.sensor_arw();
    let floor = arw.map(|n| run.white_noise_floor(n)).unwrap_or_default();
    let info = DataInfo {
        arw_n_deg_rt_s: arw,
        white_floor_deg_median: quantile(&floor, 0.5),
        segment_s: run.segment_durations(),
        white_floor_deg_segments: floor,
        input: args.input.display().to_string(),
        column: args.column.clone(),
        samples: run.len(),
        rate_hz: run.rate_hz(),
        segments: run.segments().len(),
        moving_samples: run.moving_samples(),
        startup_s: args.startup_s,
        highpass_hz: args.highpass_hz,
    };
    if let Some(path) = &args.plot {
        let models: Vec<ModelErrors> = rows
            .iter()
            .map(|r| ModelErrors {
                name: r.name.name().to_owned(),
                angle_err_deg: r.scores.angle_err_deg_segments.clone(),
                median_deg: r.scores.angle_err_deg_median,
            })
            .collect();
        let figure = MotionFigure {
            title: format!("Angle error per motion: {} of {}", info.column, file_name(&args.input)),
            models: &models,
            floor_deg: &info.white_floor_deg_segments,
            segment_s: &info.segment_s,
        };
        save(&figure, path)?;
    }
    if args.json {
        println!("{}", serde_json::json!({ "protocol": "motion", "data": info, "models": rows }));
    } else {
        print_table(&info, &rows);
    }
    Ok(())
}

fn print_table(info: &DataInfo, rows: &[ModelRow]) {
    println!(
        "Motion-injected protocol: {} samples of `{}` at {:.4} Hz, {} motion segments ({} moving samples)",
        info.samples, info.column, info.rate_hz, info.segments, info.moving_samples
    );
    println!("Angle error = |∫(compensated − truth)dt| per motion segment (median, p95, max) and over the run.");
    if let (Some(n), Some(f)) = (info.arw_n_deg_rt_s, info.white_floor_deg_median) {
        println!(
            "White-noise floor per motion, 0.674·N·√T: median {f:.4} deg (N = {n:.4e} deg/√s from the Allan fit of raw − truth)."
        );
    }
    println!();
    println!(
        "{:<18} {:>13} {:>12} {:>12} {:>12} {:>12} {:>8}  detail",
        "model", "RMSE dps", "median deg", "p95 deg", "max deg", "run deg", "s"
    );
    let opt = |v: Option<f64>| v.map_or_else(|| "—".to_owned(), |v| format!("{v:.4}"));
    for r in rows {
        let s = &r.scores;
        println!(
            "{:<18} {:>13.4e} {:>12} {:>12} {:>12} {:>12.4} {:>8.1}  {}",
            r.name.name(),
            s.rate_rmse_dps,
            opt(s.angle_err_deg_median),
            opt(s.angle_err_deg_p95),
            opt(s.angle_err_deg_max),
            s.angle_err_deg_run,
            r.seconds,
            r.detail
        );
    }
    if rows.iter().any(|r| r.detection.is_some()) {
        println!();
        println!("Motion judgement of the pipeline models against the truth (leaked: moving samples judged static;");
        println!("false alarm: a moving judgement that overlaps no motion; held: static samples judged moving).");
        println!(
            "{:<18} {:>9} {:>11} {:>11} {:>15} {:>13} {:>13} {:>13}",
            "model",
            "missed",
            "delay med s",
            "delay p95 s",
            "leaked samples",
            "leaked deg",
            "false alarms",
            "held static"
        );
        for r in rows {
            let Some(d) = &r.detection else { continue };
            println!(
                "{:<18} {:>9} {:>11} {:>11} {:>15} {:>13.2} {:>13} {:>13}",
                r.name.name(),
                format!("{}/{}", d.missed, d.motions),
                opt(d.delay_s_median),
                opt(d.delay_s_p95),
                format!("{}/{}", d.leaked_samples, d.moving_samples),
                d.leaked_angle_deg_total,
                format!("{} ({:.2}/h)", d.false_alarms, d.false_alarms_per_h),
                format!("{}/{}", d.static_held_moving, d.static_samples),
            );
        }
    }
}
