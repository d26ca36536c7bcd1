//! `gyrocomp cc` end to end: JSON shape, agreement with the library, and a run on the real
//! ADIS16405 recording when ../shared/data is present.

mod common;

use std::io::Write;
use std::path::Path;
use std::process::Command;

use common::floats;
use gyrocomp::model::cc::{CcConfig, cc_method};
use gyrocomp::wavelet::{DenoiseConfig, denoise_batch};
use serde_json::Value;

const BIN: &str = env!("CARGO_BIN_EXE_gyrocomp");
const REAL: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/data/real/adis16405_run1_10hz.csv");

fn series(n: usize) -> Vec<f64> {
    let mut state = 0x2545_f491_4f6c_dd1d_u64;
    let mut ar = 0.0;
    (0..n)
        .map(|i| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let u = (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
            ar = 0.9 * ar + u;
            ar + (i as f64 * 0.2).sin()
        })
        .collect()
}

/// Writes `t_s,gx_dps,gy_dps` at 10 Hz; values in `{:?}` form read back exactly.
fn write_csv(x: &[f64]) -> tempfile::NamedTempFile {
    let mut f = tempfile::Builder::new().suffix(".csv").tempfile().unwrap();
    writeln!(f, "t_s,gx_dps,gy_dps").unwrap();
    for (i, v) in x.iter().enumerate() {
        writeln!(f, "{:?},{v:?},{:?}", i as f64 * 0.1, -v).unwrap();
    }
    f.flush().unwrap();
    f
}

fn run_json(path: &Path, extra: &[&str]) -> Value {
    let out = Command::new(BIN).arg("cc").arg(path).arg("--json").args(extra).output().expect("run gyrocomp");
    assert!(out.status.success(), "gyrocomp cc failed: {}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.starts_with(r#"{"tau":"#), "JSON starts with tau: {text}");
    serde_json::from_str(&text).expect("one JSON object")
}

fn assert_matches_library(json: &Value, x: &[f64], t_max: usize) {
    let keys: Vec<&str> = json.as_object().unwrap().keys().map(String::as_str).collect();
    for key in ["tau", "tau_w", "m", "t", "s_mean", "delta_s_mean", "s_cor", "tau_rule", "points", "denoised"] {
        assert!(keys.contains(&key), "missing key {key}: {keys:?}");
    }
    let lib = cc_method(x, &CcConfig { t_max, threads: 1 }).unwrap();
    assert_eq!(json["tau"].as_u64().unwrap() as usize, lib.tau);
    assert_eq!(json["tau_w"].as_u64().unwrap() as usize, lib.tau_w);
    assert_eq!(json["m"].as_u64().unwrap() as usize, lib.m);
    assert_eq!(json["points"].as_u64().unwrap() as usize, x.len());
    let t: Vec<usize> = json["t"].as_array().unwrap().iter().map(|v| v.as_u64().unwrap() as usize).collect();
    assert_eq!(t, lib.t);
    for (key, want) in [("s_mean", &lib.s_mean), ("delta_s_mean", &lib.delta_s_mean), ("s_cor", &lib.s_cor)] {
        let got = floats(&json[key]);
        assert_eq!(got.len(), want.len(), "{key}");
        for (a, b) in got.iter().zip(want.iter()) {
            assert!((a - b).abs() <= 1e-15 * b.abs().max(1.0), "{key}: {a} vs {b}");
        }
    }
}

#[test]
fn json_output_agrees_with_the_library() {
    let x = series(700);
    let file = write_csv(&x);
    // Raw series, first 600 points.
    let json = run_json(file.path(), &["--no-denoise", "--t-max", "12", "--max-points", "600"]);
    assert_eq!(json["denoised"], Value::Bool(false));
    assert_matches_library(&json, &x[..600], 12);
    // Default: the whole series is denoised, then truncated.
    let json = run_json(file.path(), &["--t-max", "10", "--max-points", "0"]);
    assert_eq!(json["denoised"], Value::Bool(true));
    assert_matches_library(&json, &denoise_batch(&x, &DenoiseConfig::paper()).0, 10);
    // Another column.
    let json = run_json(file.path(), &["--column", "gy_dps", "--no-denoise", "--t-max", "8"]);
    let negated: Vec<f64> = x.iter().map(|v| -v).collect();
    assert_matches_library(&json, &negated, 8);
}

#[test]
fn table_output_and_errors() {
    let x = series(300);
    let file = write_csv(&x);
    let out = Command::new(BIN).args(["cc", "--t-max", "6"]).arg(file.path()).output().unwrap();
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("τ  = ") && text.contains("τw = ") && text.contains("m  = "), "{text}");
    // 300 samples cannot support t_max = 60 (needs 360): a clean error, not a panic.
    let out = Command::new(BIN).args(["cc", "--t-max", "60"]).arg(file.path()).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("too short"));
    let out = Command::new(BIN).args(["cc", "--column", "nope"]).arg(file.path()).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn real_recording_with_defaults() {
    let path = Path::new(REAL);
    if !path.exists() {
        eprintln!("skipping real_recording_with_defaults: {REAL} not found (shared data absent)");
        return;
    }
    let json = run_json(path, &[]);
    assert_eq!(json["points"].as_u64(), Some(5000));
    assert_eq!(json["denoised"], Value::Bool(true));
    let tau = json["tau"].as_u64().unwrap();
    let tau_w = json["tau_w"].as_u64().unwrap();
    let m = json["m"].as_u64().unwrap();
    assert!((1..=40).contains(&tau) && (1..=40).contains(&tau_w), "τ = {tau}, τw = {tau_w}");
    assert!(m >= 2, "m = {m}");
    assert_eq!(floats(&json["s_cor"]).len(), 40);
}
