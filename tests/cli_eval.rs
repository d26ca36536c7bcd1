//! `gyrocomp eval` on a simulated paper-like recording: every model beside the baselines, on the
//! same split, with the JSON fields of the specification.

mod common;

use common::ok as gyrocomp;

use std::process::Command;

use serde_json::Value;

#[test]
fn paper_protocol_scores_every_model_on_the_same_split() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("paper.csv");
    let csv = csv.to_str().unwrap();
    gyrocomp(&["sim", "--preset", "paper", "--seed", "3", "-o", csv]);
    let out = gyrocomp(&[
        "eval",
        csv,
        "--column",
        "gx_dps",
        "--models",
        "cpso-lssvm,lssvm,bp-ann,persistence,ar,mean,bias-hold,linear-psr",
        "--gam",
        "10",
        "--sig2",
        "50",
        "--json",
    ]);
    let report: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(report["data"]["samples"], 5000);
    assert_eq!(report["data"]["train_samples"], 3983 + 21);
    let models = report["models"].as_array().unwrap();
    let names: Vec<&str> = models.iter().map(|m| m["name"].as_str().unwrap()).collect();
    assert_eq!(names, ["cpso-lssvm", "lssvm", "bp-ann", "persistence", "ar", "mean", "bias-hold", "linear-psr"]);
    let field = |m: &Value, k: &str| m[k].as_f64().unwrap_or_else(|| panic!("{} has no number `{k}`", m["name"]));
    for m in models {
        for key in [
            "mae_norm",
            "rmse_norm",
            "mae_dps",
            "rmse_dps",
            "std_raw_before",
            "std_raw_after",
            "std_drift_before",
            "std_drift_after",
            "train_s",
        ] {
            assert!(field(m, key).is_finite() && field(m, key) >= 0.0, "{} {key}", m["name"]);
        }
        // Every model is scored on the same test part.
        assert_eq!(field(m, "std_raw_before"), field(&models[0], "std_raw_before"));
        assert_eq!(field(m, "std_drift_before"), field(&models[0], "std_drift_before"));
        assert!(m.get("are").is_some() && m.get("gam").is_some() && m.get("sig2").is_some());
    }
    let by_name = |n: &str| models.iter().find(|m| m["name"] == n).unwrap();
    // A constant prediction cannot change the standard deviation of what it is subtracted from.
    for constant in ["mean", "bias-hold"] {
        let m = by_name(constant);
        assert!((field(m, "std_drift_after") - field(m, "std_drift_before")).abs() < 1e-15);
    }
    // The denoised drift is smooth: one-step persistence beats the training mean by far.
    assert!(field(by_name("persistence"), "rmse_norm") < 0.5 * field(by_name("mean"), "rmse_norm"));
    // The fixed LSSVM reports the parameters it was given; CPSO reports the ones it chose.
    assert_eq!((field(by_name("lssvm"), "gam"), field(by_name("lssvm"), "sig2")), (10.0, 50.0));
    assert!(field(by_name("cpso-lssvm"), "gam") > 0.0 && field(by_name("cpso-lssvm"), "sig2") > 0.0);
    // Errors in deg/s are the normalised ones times the scaler's half range.
    let half =
        0.5 * (report["data"]["scale_max_dps"].as_f64().unwrap() - report["data"]["scale_min_dps"].as_f64().unwrap());
    let p = by_name("persistence");
    assert!((field(p, "rmse_dps") - half * field(p, "rmse_norm")).abs() < 1e-15);
}

#[test]
fn unknown_models_are_refused_by_name() {
    let out =
        Command::new(env!("CARGO_BIN_EXE_gyrocomp")).args(["eval", "x.csv", "--models", "lstm"]).output().unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("lstm"));
}
