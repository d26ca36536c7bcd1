//! Tests of `gyrocomp simgap`: the JSON interface on a simulated recording with a known effect,
//! determinism, the HTML report, bad input, and (when the shared recordings are present) a real
//! ADIS16405 run.

mod common;

use common::gyrocomp;

use std::io::Write;
use std::process::Output;

use gyrocomp::diag::simgap::EffectKind;
use gyrocomp::diag::simgap::selftest::{Injected, RATE_HZ, case_seed, synthesize};
use serde_json::Value;

/// A self-test recording written as CSV (`t_s,gx_dps,temp_c`), `{:?}` so it reads back exactly.
fn recording(injected: Injected, duration_s: f64, seed: u64) -> (tempfile::NamedTempFile, String) {
    let (rate, temp, magnitudes) = synthesize(injected, duration_s, 1.0, case_seed(seed, injected, 0)).unwrap();
    let mut file = tempfile::Builder::new().suffix(".csv").tempfile().unwrap();
    writeln!(file, "t_s,gx_dps,temp_c").unwrap();
    for (k, (r, t)) in rate.iter().zip(&temp).enumerate() {
        writeln!(file, "{:?},{:?},{:?}", k as f64 / RATE_HZ, r, t).unwrap();
    }
    file.flush().unwrap();
    (file, magnitudes)
}

fn json(out: &Output) -> Value {
    assert!(out.status.success(), "stderr: {}", String::from_utf8_lossy(&out.stderr));
    serde_json::from_slice(&out.stdout).expect("JSON on stdout")
}

#[test]
fn names_an_injected_sinusoid_with_the_documented_json() {
    let (csv, magnitudes) = recording(Injected::Effect(EffectKind::Sinusoid), 3000.0, 3);
    let path = csv.path().to_str().unwrap();
    let out = gyrocomp(&["simgap", "--real", path, "--ensemble", "16", "--json"]);
    let text = String::from_utf8(out.stdout.clone()).unwrap();
    // The stable interface: these keys first, in this order.
    let order = ["\"gap_before\":", "\"gap_after\":", "\"where\":", "\"effects\":", "\"chosen\":"];
    let at: Vec<usize> = order.iter().map(|k| text.find(k).unwrap_or_else(|| panic!("{k} missing"))).collect();
    assert!(at.windows(2).all(|w| w[0] < w[1]), "key order: {at:?}");
    let doc = json(&out);
    assert_eq!(doc["chosen"], serde_json::json!(["sinusoid"]), "{magnitudes}: {doc}");
    assert_eq!(doc["verdict"], "explained");
    let (before, after) = (doc["gap_before"].as_f64().unwrap(), doc["gap_after"].as_f64().unwrap());
    assert!(after < 0.5 * before, "hold-out gap {before} → {after}");
    // `where`: outside the band, largest |z| first, with the band's edges.
    let entries = doc["where"].as_array().unwrap();
    assert!(!entries.is_empty());
    let mut last = f64::INFINITY;
    for e in entries {
        let (real, lo, hi) =
            (e["real"].as_f64().unwrap(), e["sim_lo"].as_f64().unwrap(), e["sim_hi"].as_f64().unwrap());
        assert!(real < lo || real > hi, "{e}");
        assert!(e["statistic"].is_string() && e["band"].is_string());
        let z = e["z"].as_f64().unwrap().abs();
        assert!(z <= last);
        last = z;
    }
    // Furthest out: one of the two line statistics (the Welch PSD's, the whole part's periodogram's).
    assert!(["spectral_line", "fast_line"].contains(&entries[0]["statistic"].as_str().unwrap()), "{}", entries[0]);
    // `effects`: all eight, best first by `log_score` (the ranking: the mean of the two parts'
    // Dawid–Sebastiani scores; only an unbounded warm-up may be moved to right behind the ramp),
    // not applicable ones last.
    let effects = doc["effects"].as_array().unwrap();
    assert_eq!(effects.len(), 8);
    assert_eq!(effects[0]["name"], "sinusoid");
    let score = |e: &Value| e["log_score"].as_f64().unwrap_or(f64::INFINITY);
    let moved = |i: usize| i > 0 && effects[i]["name"] == "warmup" && effects[i - 1]["name"] == "ramp";
    let ranked: Vec<&Value> = (0..effects.len()).filter(|&i| !moved(i)).map(|i| &effects[i]).collect();
    assert!(ranked.windows(2).all(|w| score(w[0]) <= score(w[1])), "{effects:?}");
    // The fitted frequency is the injected one ("… at F Hz").
    let injected: f64 = magnitudes.rsplit(" at ").next().unwrap().trim_end_matches(" Hz").parse().unwrap();
    let fitted = effects[0]["params"]["frequency_hz"].as_f64().unwrap();
    assert!((fitted / injected - 1.0).abs() < 0.01, "{fitted} vs {injected}");
    // The gap tests' thresholds: the p quantile of a Gumbel law with the mean and standard
    // deviation of the members' T — for the baseline p = 1 − 0.01/2 on each part (one false alarm
    // in 100 over the two), for the final model p = 0.99.
    let gumbel = |part: &Value, p: f64| {
        let (mean, sd) = (part["t_members"]["mean"].as_f64().unwrap(), part["t_members"]["sd"].as_f64().unwrap());
        let beta = sd * 6f64.sqrt() / std::f64::consts::PI;
        mean - 0.577_215_664_901_532_9 * beta - beta * (-p.ln()).ln()
    };
    for part in ["train", "holdout"] {
        for (model, p) in [("before", 0.995), ("after", 0.99)] {
            let comparison = &doc[model][part];
            let threshold = comparison["t_threshold"].as_f64().unwrap();
            assert!((threshold - gumbel(comparison, p)).abs() < 1e-9, "{model} {part}: {comparison}");
            let t = comparison["t"].as_f64().unwrap();
            assert_eq!(comparison["significant"].as_bool().unwrap(), t > threshold, "{model} {part}");
        }
    }
}

/// A temperature column named as another logger names it (`temperature`) still makes the
/// temperature response a candidate: fitted, scored and named on an injected one.
#[test]
fn a_temperature_column_under_another_name_is_a_candidate() {
    let (csv, magnitudes) = recording(Injected::Effect(EffectKind::Temperature), 3000.0, 1);
    let text = std::fs::read_to_string(csv.path()).unwrap().replacen("t_s,gx_dps,temp_c", "t_s,gx_dps,temperature", 1);
    let mut renamed = tempfile::Builder::new().suffix(".csv").tempfile().unwrap();
    renamed.write_all(text.as_bytes()).unwrap();
    let path = renamed.path().to_str().unwrap();
    let doc = json(&gyrocomp(&["simgap", "--real", path, "--ensemble", "16", "--json"]));
    let effects = doc["effects"].as_array().unwrap();
    let temperature = effects.iter().find(|e| e["name"] == "temperature").expect("a temperature entry");
    assert!(temperature["note"].is_null() && temperature["log_score"].is_f64(), "{magnitudes}: {temperature}");
    assert_eq!(doc["chosen"][0], "temperature", "{magnitudes}: {doc}");
}

#[test]
fn same_seed_same_answer_whatever_the_threads() {
    let (csv, _) = recording(Injected::Effect(EffectKind::Spikes), 1500.0, 4);
    let path = csv.path().to_str().unwrap();
    let run = |threads: &str, seed: &str| {
        let out =
            gyrocomp(&["simgap", "--real", path, "--ensemble", "8", "--json", "--threads", threads, "--seed", seed]);
        json(&out);
        out.stdout
    };
    let one = run("1", "5");
    assert_eq!(one, run("2", "5"));
    assert_ne!(one, run("1", "6"));
}

#[test]
fn writes_an_html_report_with_svg_plots() {
    let (csv, _) = recording(Injected::Nothing, 1500.0, 5);
    let dir = tempfile::tempdir().unwrap();
    let out = gyrocomp(&[
        "simgap",
        "--real",
        csv.path().to_str().unwrap(),
        "--ensemble",
        "8",
        "--report",
        dir.path().to_str().unwrap(),
    ]);
    assert!(out.status.success(), "stderr: {}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("Where (hold-out part") && text.contains("Which (candidate effects"), "{text}");
    let html = std::fs::read_to_string(dir.path().join("index.html")).unwrap();
    assert!(html.starts_with("<!DOCTYPE html>") && html.ends_with("</html>\n"));
    // Allan, PSD and trajectory for two parts, and the ranking.
    assert_eq!(html.matches("<svg").count(), 7);
    assert!(html.contains("Allan deviation, hold-out") && html.contains("PSD bands, training"));
    assert!(!html.contains("NaN"), "no NaN coordinates in the plots");
}

#[test]
fn bad_input_is_a_clear_error() {
    let (csv, _) = recording(Injected::Nothing, 600.0, 6);
    let path = csv.path().to_str().unwrap();
    let out = gyrocomp(&["simgap", "--real", path, "--column", "gy_dps"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains(path) && err.contains("gy_dps"), "{err}");

    let out = gyrocomp(&["simgap", "--real", path, "--holdout", "1.5"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("holdout 1.5"));

    let mut short = tempfile::Builder::new().suffix(".csv").tempfile().unwrap();
    writeln!(short, "t_s,gx_dps").unwrap();
    for k in 0..100 {
        writeln!(short, "{},{}", k as f64 * 0.1, 0.3 + 0.01 * (k % 7) as f64).unwrap();
    }
    short.flush().unwrap();
    let out = gyrocomp(&["simgap", "--real", short.path().to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("at least 512"), "{}", String::from_utf8_lossy(&out.stderr));

    let mut bad = tempfile::Builder::new().suffix(".csv").tempfile().unwrap();
    writeln!(bad, "t_s,gx_dps\n0,0.1\n0.1,abc").unwrap();
    bad.flush().unwrap();
    let out = gyrocomp(&["simgap", "--real", bad.path().to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains(":3:") && err.contains("gx_dps"), "{err}");
}

/// The 10 Hz ADIS16405 files are 10-sample means of 0.05 deg/s samples: their values sit on a
/// 0.005 deg/s grid, which the IEEE noise terms cannot describe; the diagnosis must see the grid
/// and put the grid coherence outside the band on the hold-out part.
#[test]
fn real_adis16405_run1_sits_on_a_grid() {
    let Some(path) = common::real_recording("adis16405_run1_10hz.csv") else { return };
    let out = gyrocomp(&["simgap", "--real", path.to_str().unwrap(), "--ensemble", "8", "--threads", "2", "--json"]);
    let doc = json(&out);
    assert!((doc["grid_step_dps"].as_f64().unwrap() - 0.005).abs() < 1e-9, "{}", doc["grid_step_dps"]);
    assert_eq!(doc["samples"], 100_000);
    let entries = doc["where"].as_array().unwrap();
    let grid = entries.iter().find(|e| e["statistic"] == "quantisation").expect("grid coherence outside the band");
    assert!((grid["real"].as_f64().unwrap() - 1.0).abs() < 1e-9 && grid["sim_hi"].as_f64().unwrap() < 0.1);
    let quantization = doc["effects"].as_array().unwrap().iter().find(|e| e["name"] == "quantization").unwrap();
    assert!((quantization["params"]["step_dps"].as_f64().unwrap() - 0.005).abs() < 1e-9);
}

/// `gyrocomp sim --config` of the `adis16405` preset for 3000 s, with `extra` TOML appended.
fn simulated(extra: &str, seed: u64) -> tempfile::NamedTempFile {
    let preset = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("configs/sim/adis16405.toml");
    let mut config = tempfile::Builder::new().suffix(".toml").tempfile().unwrap();
    write!(config, "{}\n{extra}", std::fs::read_to_string(&preset).unwrap()).unwrap();
    config.flush().unwrap();
    let csv = tempfile::Builder::new().suffix(".csv").tempfile().unwrap();
    let seed = seed.to_string();
    let out = gyrocomp(&[
        "sim",
        "--config",
        config.path().to_str().unwrap(),
        "--duration",
        "3000",
        "--seed",
        &seed,
        "-o",
        csv.path().to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    csv
}

/// With `--sim` the given model is the baseline: a recording made by that very model shows no
/// significant gap (and its own fitted white noise, reported beside the simulator's, is the
/// simulator's), and one made by it plus a sinusoid it lacks gets the sinusoid named.
#[test]
fn a_given_sim_config_is_the_baseline() {
    let preset = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("configs/sim/adis16405.toml");
    let preset = preset.to_str().unwrap();
    let diagnose = |csv: &tempfile::NamedTempFile| {
        json(&gyrocomp(&[
            "simgap",
            "--real",
            csv.path().to_str().unwrap(),
            "--sim",
            preset,
            "--ensemble",
            "16",
            "--threads",
            "2",
            "--json",
        ]))
    };
    let same = diagnose(&simulated("", 11));
    assert_eq!(same["verdict"], "no_significant_gap", "{same}");
    assert_eq!(same["chosen"], serde_json::json!([]));
    assert!(same["baseline_terms"].is_null(), "a given model is not refitted: {}", same["baseline_terms"]);
    // The recording's own terms, set beside the simulator's: the preset's N (2.4 deg/√h on x).
    let n = same["recording_terms"]["n"].as_f64().unwrap() * 60.0;
    assert!((n / 2.4 - 1.0).abs() < 0.05, "recording N {n} deg/√h against the preset's 2.4");
    let line = "[[x.sinusoids]]\namplitude_dps = 0.02\nfrequency_hz = 0.05\nphase_deg = 30.0\n";
    let with_line = diagnose(&simulated(line, 12));
    assert_eq!(with_line["chosen"], serde_json::json!(["sinusoid"]), "{with_line}");
    let sinusoid = with_line["effects"].as_array().unwrap().iter().find(|e| e["name"] == "sinusoid").unwrap();
    let f = sinusoid["params"]["frequency_hz"].as_f64().unwrap();
    assert!((f - 0.05).abs() < 1e-3, "fitted frequency {f}");
}
