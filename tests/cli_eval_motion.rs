//! `gyrocomp eval --protocol motion` on simulated recordings with known truth: the truth scored
//! against itself is 0, a pure bias is removed by bias-hold, a ramp drift is tracked by the
//! one-step predictors but not by bias-hold, unguarded predictors eat the injected turns, and
//! the JSON has the shape of the specification.

use std::path::{Path, PathBuf};
use std::process::Command;

use gyrocomp::sim::{Generator, Preset};
use serde_json::Value;

mod common;

use common::ok as gyrocomp;

const NAMES: [&str; 12] = [
    "gyrocomp",
    "gyrocomp-flagged",
    "bias-hold",
    "last-static",
    "cpso-lssvm",
    "hybrid",
    "multiscale",
    "persistence",
    "ar",
    "highpass",
    "persistence-gated",
    "ar-gated",
];

/// A 10 Hz `gx_dps` recording: `bias + ramp·t`, plus the ADIS16405 preset's errors when `noisy`.
fn recording(dir: &Path, seconds: f64, bias: f64, ramp: f64, noisy: bool) -> PathBuf {
    let mut sim = Preset::Adis16405.config();
    sim.duration_s = seconds;
    let out = Generator::generate(&sim, 7).unwrap();
    let mut text = String::from("t_s,gx_dps\n");
    for (k, t) in out.t_s.iter().enumerate() {
        let errors = if noisy { out.axes[0].raw[k] } else { 0.0 };
        text.push_str(&format!("{t},{}\n", bias + ramp * t + errors));
    }
    let path = dir.join(format!("rec_{bias}_{ramp}_{noisy}.csv"));
    std::fs::write(&path, text).unwrap();
    path
}

/// Injects motion (`turns`, or none with `static_fraction` 1) and evaluates; returns the JSON.
fn evaluate(dir: &Path, rec: &Path, static_fraction: &str, models: Option<&str>) -> Value {
    let moved = dir.join("moved.csv");
    let (rec, moved_s) = (rec.to_str().unwrap(), moved.to_str().unwrap());
    gyrocomp(&[
        "motion",
        rec,
        "--profile",
        "turns",
        "--seed",
        "4",
        "--static-fraction",
        static_fraction,
        "-o",
        moved_s,
    ]);
    let config = dir.join("c.toml");
    // The recording is 10 Hz: the shipped 10 Hz settings (rate, gate thresholds) plus quick retrains.
    let ten_hz = include_str!("../configs/adis16405_10hz.toml");
    std::fs::write(&config, format!("{ten_hz}\n{}", common::QUICK_RETRAIN)).unwrap();
    let mut args = vec!["eval", moved_s, "--protocol", "motion", "--config", config.to_str().unwrap(), "--json"];
    if let Some(m) = models {
        args.extend(["--models", m]);
    }
    serde_json::from_slice(&gyrocomp(&args).stdout).unwrap()
}

fn model<'a>(report: &'a Value, name: &str) -> &'a Value {
    report["models"].as_array().unwrap().iter().find(|m| m["name"] == name).unwrap_or_else(|| panic!("no {name}"))
}

fn num(m: &Value, key: &str) -> f64 {
    m[key].as_f64().unwrap_or_else(|| panic!("{}: `{key}` is not a number: {m}", m["name"]))
}

#[test]
fn truth_scores_zero_and_a_pure_bias_is_removed_by_bias_hold() {
    let dir = tempfile::tempdir().unwrap();
    // No drift at all: raw = truth, and the start-up mean is exactly 0.
    let report = evaluate(dir.path(), &recording(dir.path(), 1200.0, 0.0, 0.0, false), "0.5", Some("bias-hold"));
    let b = model(&report, "bias-hold");
    assert!(report["data"]["segments"].as_u64().unwrap() >= 5, "{report}");
    for key in ["rate_rmse_dps", "angle_err_deg_median", "angle_err_deg_p95", "angle_err_deg_max", "angle_err_deg_run"]
    {
        assert_eq!(num(b, key), 0.0, "{key}");
    }
    // A constant bias: bias-hold removes it up to rounding.
    let report =
        evaluate(dir.path(), &recording(dir.path(), 1200.0, 0.37, 0.0, false), "0.5", Some("bias-hold,highpass"));
    let b = model(&report, "bias-hold");
    assert!(num(b, "angle_err_deg_max") < 1e-9 && num(b, "rate_rmse_dps") < 1e-12, "{b}");
    // The high-pass also removes a constant, but gives every turn back after it: the run error
    // is about the net injected angle.
    let h = model(&report, "highpass");
    assert!(num(h, "angle_err_deg_run") > 1.0, "{h}");
}

#[test]
fn a_ramp_drift_is_tracked_by_the_predictors_and_not_by_bias_hold() {
    let dir = tempfile::tempdir().unwrap();
    let rec = recording(dir.path(), 1500.0, -0.4, 2e-4, true);
    // Static only: every model sees the drift and nothing else.
    let report = evaluate(dir.path(), &rec, "1", Some("gyrocomp,bias-hold,persistence,ar"));
    assert_eq!(report["data"]["segments"], 0);
    let bias = model(&report, "bias-hold");
    assert!(bias["angle_err_deg_median"].is_null(), "no segment, no median");
    for name in ["gyrocomp", "persistence", "ar"] {
        let m = model(&report, name);
        assert!(num(m, "rate_rmse_dps") < num(bias, "rate_rmse_dps"), "{name}: {m} against {bias}");
        assert!(num(m, "angle_err_deg_run") < 0.2 * num(bias, "angle_err_deg_run"), "{name}: {m} against {bias}");
    }

    // With turns: the unguarded predictors take the rotation for drift.
    let report = evaluate(dir.path(), &rec, "0.5", None);
    let names: Vec<&str> = report["models"].as_array().unwrap().iter().map(|m| m["name"].as_str().unwrap()).collect();
    assert_eq!(names, NAMES);
    for m in report["models"].as_array().unwrap() {
        let (median, p95, max) =
            (num(m, "angle_err_deg_median"), num(m, "angle_err_deg_p95"), num(m, "angle_err_deg_max"));
        assert!(0.0 <= median && median <= p95 && p95 <= max, "{m}");
        assert!(num(m, "rate_rmse_dps") > 0.0 && num(m, "angle_err_deg_run") >= 0.0, "{m}");
    }
    let bias = model(&report, "bias-hold");
    let flagged = model(&report, "gyrocomp-flagged");
    assert!(num(flagged, "angle_err_deg_median") < 0.5 * num(bias, "angle_err_deg_median"), "{flagged} {bias}");
    for name in ["persistence", "ar"] {
        let m = model(&report, name);
        let gated = model(&report, &format!("{name}-gated"));
        assert!(num(m, "angle_err_deg_median") > 5.0 * num(gated, "angle_err_deg_median"), "{m} {gated}");
    }
    // The motion judgement is scored for the pipeline models only; the ungated predictors judge
    // nothing moving, so every motion is missed and all its rotation leaks; with the publisher's
    // flags nothing leaks and every motion is found at once.
    let motions = report["data"]["segments"].as_f64().unwrap();
    for m in report["models"].as_array().unwrap() {
        let d = &m["detection"];
        match m["name"].as_str().unwrap() {
            "bias-hold" | "last-static" | "highpass" => assert!(d.is_null(), "{m}"),
            name => assert_eq!(num(d, "motions"), motions, "{name}: {d}"),
        }
    }
    let ungated = &model(&report, "persistence")["detection"];
    assert_eq!((num(ungated, "missed"), num(ungated, "false_alarms")), (motions, 0.0), "{ungated}");
    assert_eq!(num(ungated, "leaked_samples"), num(ungated, "moving_samples"), "{ungated}");
    let oracle = &flagged["detection"];
    assert_eq!(
        (num(oracle, "missed"), num(oracle, "leaked_samples"), num(oracle, "delay_s_p95")),
        (0.0, 0.0, 0.0),
        "{oracle}"
    );
}

#[test]
fn unknown_models_and_files_without_truth_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let rec = recording(dir.path(), 60.0, 0.0, 0.0, true);
    let run = |args: &[&str]| Command::new(env!("CARGO_BIN_EXE_gyrocomp")).args(args).output().unwrap();
    let out = run(&["eval", rec.to_str().unwrap(), "--protocol", "motion", "--models", "lstm"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("lstm"));
    let out = run(&["eval", rec.to_str().unwrap(), "--protocol", "motion"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("rec_") && err.contains("truth_dps"), "{err}");
}
