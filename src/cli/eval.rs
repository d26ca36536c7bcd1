//! `gyrocomp eval`: the paper's evaluation protocol (docs/design.md) for the paper's models beside the
//! honest baselines, as a table shaped like the paper's Tables 1–2 or as JSON; with
//! `--protocol motion`, the motion-injected protocol ([`super::eval_motion`]).

use serde::Serialize;

use super::CliError;
use super::eval_args::{EvalArgs, Protocol, parse_models};
use super::input::load_series;
use crate::config::Config;
use crate::eval::models::{ModelKind, ModelOptions, ModelRun, run_model};
use crate::eval::paper::{PaperProtocol, PaperScores, Prepared, score};

/// One row of the JSON output (field names as in the specification).
#[derive(Debug, Serialize)]
struct ModelRow {
    name: ModelKind,
    #[serde(flatten)]
    scores: PaperScores,
    train_s: f64,
    gam: Option<f64>,
    sig2: Option<f64>,
    detail: String,
}

/// What the evaluation ran on.
#[derive(Debug, Serialize)]
struct DataInfo {
    samples: usize,
    train_samples: usize,
    test_targets: usize,
    rate_hz: f64,
    scale_min_dps: f64,
    scale_max_dps: f64,
}

/// Runs `gyrocomp eval`.
pub fn run(args: &EvalArgs) -> Result<(), CliError> {
    if args.protocol == Protocol::Motion {
        return super::eval_motion::run(args);
    }
    if args.plot.is_some() {
        return Err("--plot draws the motion protocol's angle errors: use it with --protocol motion".into());
    }
    let kinds = parse_models::<ModelKind>(args.models.as_deref())?.unwrap_or_else(|| ModelKind::ALL.to_vec());
    let settings = Config::load(args.config.as_deref())?;
    let series = load_series(&args.input, &args.column, None, &args.input_opts.options())?;
    let protocol = PaperProtocol {
        samples: args.samples,
        embedding: settings.embedding(),
        denoise: settings.denoise()?,
        ..PaperProtocol::default()
    };
    let data = protocol.prepare(&series.values)?;
    let options = ModelOptions {
        embedding: protocol.embedding,
        seed: args.seed,
        bias_hold_samples: (60.0 * series.rate_hz).round().max(1.0) as usize,
        gamma: args.gam,
        sigma2: args.sig2,
    };
    let mut rows = Vec::with_capacity(kinds.len());
    for kind in kinds {
        let run = run_model(kind, &data, &options).map_err(|e| format!("model `{kind}`: {e}"))?;
        rows.push(row(&data, run));
    }
    let info = DataInfo {
        samples: data.raw.len(),
        train_samples: data.train_end,
        test_targets: data.test_len(),
        rate_hz: series.rate_hz,
        scale_min_dps: data.scaler.min,
        scale_max_dps: data.scaler.max,
    };
    if args.json {
        println!("{}", serde_json::json!({ "protocol": "paper", "data": info, "models": rows }));
    } else {
        print_table(&info, &rows);
    }
    Ok(())
}

fn row(data: &Prepared, run: ModelRun) -> ModelRow {
    ModelRow {
        name: run.kind,
        scores: score(data, &run.predictions),
        train_s: run.train_s,
        gam: run.gam,
        sig2: run.sig2,
        detail: run.detail,
    }
}

fn print_table(info: &DataInfo, rows: &[ModelRow]) {
    println!(
        "Paper protocol: first {} samples at {} Hz, train {} samples, test {} one-step targets; scaled on [{:.5}, {:.5}] deg/s",
        info.samples, info.rate_hz, info.train_samples, info.test_targets, info.scale_min_dps, info.scale_max_dps
    );
    println!();
    println!("Prediction of the denoised drift (paper Table 1; normalised units and deg/s):");
    println!(
        "{:<12} {:>10} {:>10} {:>9} {:>11} {:>11} {:>9}  detail",
        "model", "MAE", "RMSE", "ARE", "MAE dps", "RMSE dps", "train s"
    );
    for r in rows {
        let s = &r.scores;
        println!(
            "{:<12} {:>10.5} {:>10.5} {:>8.2}% {:>11.3e} {:>11.3e} {:>9.3}  {}",
            r.name.name(),
            s.mae_norm,
            s.rmse_norm,
            100.0 * s.are,
            s.mae_dps,
            s.rmse_dps,
            r.train_s,
            r.detail
        );
    }
    println!();
    println!("Standard deviation before and after compensation, deg/s (paper Table 2 is the drift pair):");
    println!("{:<12} {:>12} {:>12} {:>12} {:>12}", "model", "drift before", "drift after", "raw before", "raw after");
    for r in rows {
        let s = &r.scores;
        println!(
            "{:<12} {:>12.3e} {:>12.3e} {:>12.3e} {:>12.3e}",
            r.name.name(),
            s.std_drift_before,
            s.std_drift_after,
            s.std_raw_before,
            s.std_raw_after
        );
    }
}
