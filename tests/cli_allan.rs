//! Tests of the `gyrocomp allan` command line: JSON shape, agreement with the library, errors,
//! and (when the shared recordings are present) the published Allan deviation of a real gyro.

mod common;

use common::gyrocomp;

use std::io::Write;
use std::path::Path;

use common::floats;
use gyrocomp::diag::allan::{Taus, oadev};
use gyrocomp::diag::noise_fit::{Weighting, fit_allan};
use serde_json::Value;

/// A deterministic rate series: a slow sinusoidal drift plus an LCG-driven noise, deg/s.
fn series(len: usize) -> Vec<f64> {
    let mut state = 0x2545_F491_4F6C_DD1Du64;
    (0..len)
        .map(|k| {
            state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
            let u = (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
            0.3 + 0.02 * (k as f64 * 0.01).sin() + 0.1 * u
        })
        .collect()
}

fn write_csv(x: &[f64], fs: f64) -> tempfile::NamedTempFile {
    let mut file = tempfile::Builder::new().suffix(".csv").tempfile().expect("tempfile");
    writeln!(file, "t_s,gx_dps,gz_dps").unwrap();
    for (k, v) in x.iter().enumerate() {
        // `{:?}` prints the shortest decimal that round-trips, so the CLI reads exactly `x`.
        writeln!(file, "{:?},{:?},{:?}", k as f64 / fs, -v, v).unwrap();
    }
    file.flush().unwrap();
    file
}

fn close(a: f64, b: f64, rel: f64) -> bool {
    (a - b).abs() <= rel * a.abs().max(b.abs())
}

#[test]
fn json_has_the_documented_keys_and_matches_the_library() {
    let x = series(3000);
    let csv = write_csv(&x, 10.0);
    let path = csv.path().to_str().unwrap();
    let out = gyrocomp(&["allan", path, "--column", "gz_dps", "--rate", "10", "--json"]);
    assert!(out.status.success(), "stderr: {}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8(out.stdout).unwrap();
    // The stable interface: these keys first, in this order.
    assert!(text.starts_with(r#"{"tau_s":["#), "{text}");
    let (i_adev, i_fit) = (text.find(r#""adev":["#).unwrap(), text.find(r#""fit":{"q":"#).unwrap());
    assert!(i_adev < i_fit);
    let json: Value = serde_json::from_str(&text).unwrap();
    let fit = &json["fit"];
    for key in ["q", "n", "b", "k", "r"] {
        assert!(fit[key].as_f64().is_some_and(|v| v >= 0.0), "fit.{key} = {}", fit[key]);
    }

    let lib = oadev(&x, 10.0, &Taus::Octave).unwrap();
    let (tau, adev) = (floats(&json["tau_s"]), floats(&json["adev"]));
    assert_eq!(tau.len(), lib.len());
    for i in 0..lib.len() {
        // JSON carries the shortest round-trip decimal; allow for a 1-ulp parse difference.
        assert!(close(tau[i], lib.tau_s[i], 1e-15) && close(adev[i], lib.adev[i], 1e-15), "point {i}");
    }
    let n_terms: Vec<usize> =
        json["n_terms"].as_array().unwrap().iter().map(|v| v.as_u64().unwrap() as usize).collect();
    assert_eq!(n_terms, lib.n);
    let lib_fit = fit_allan(&lib.octave_points(), Weighting::default()).unwrap().model;
    for (key, v) in [("q", lib_fit.q), ("n", lib_fit.n), ("b", lib_fit.b), ("k", lib_fit.k), ("r", lib_fit.r)] {
        assert!(close(fit[key].as_f64().unwrap(), v, 1e-12), "fit.{key}: {} vs {v}", fit[key]);
    }
}

#[test]
fn default_column_rate_from_time_and_all_taus() {
    let x = series(200);
    let csv = write_csv(&x, 50.0);
    let out = gyrocomp(&["allan", csv.path().to_str().unwrap(), "--taus", "all", "--json"]);
    assert!(out.status.success(), "stderr: {}", String::from_utf8_lossy(&out.stderr));
    let json: Value = serde_json::from_slice(&out.stdout).unwrap();
    let rate = json["rate_hz"].as_f64().unwrap();
    assert!(close(rate, 50.0, 1e-9), "rate from the time column: {rate}");
    // Default column gx_dps holds −x: same Allan deviation as x.
    let lib = oadev(&x, rate, &Taus::All).unwrap();
    assert_eq!(lib.len(), 99);
    let adev = floats(&json["adev"]);
    assert!(adev.iter().zip(&lib.adev).all(|(a, b)| close(*a, *b, 1e-12)));
}

/// A dropout (a stretch of the time column with no samples) neither lowers the sample rate nor
/// passes unremarked: the rate is the stamps' own, and a warning names the file, the sample
/// before the gap, its time and the samples missing.
#[test]
fn a_dropout_keeps_the_rate_and_is_named_in_a_warning() {
    let x = series(3000);
    let mut file = tempfile::Builder::new().suffix(".csv").tempfile().expect("tempfile");
    writeln!(file, "t_s,gx_dps").unwrap();
    // 20 Hz; samples 1,000..1,250 (12.5 s) missing.
    for (k, v) in x.iter().enumerate().filter(|(k, _)| !(1_000..1_250).contains(k)) {
        writeln!(file, "{:?},{:?}", k as f64 / 20.0, v).unwrap();
    }
    file.flush().unwrap();
    let path = file.path().to_str().unwrap();
    let out = gyrocomp(&["allan", path, "--json"]);
    assert!(out.status.success(), "stderr: {}", String::from_utf8_lossy(&out.stderr));
    let json: Value = serde_json::from_slice(&out.stdout).unwrap();
    let rate = json["rate_hz"].as_f64().unwrap();
    // From the first and last stamps alone it would be 2,749 / 149.95 s = 18.3 Hz.
    assert!(close(rate, 20.0, 1e-9), "rate {rate}");
    assert_eq!(json["samples"].as_u64(), Some(2_750));
    let stderr = String::from_utf8_lossy(&out.stderr);
    let warning = format!(
        "{path}: 1 dropout(s), 250 samples missing in all: after sample 999 (t = 49.950 s, 12.550 s to the next)"
    );
    assert!(stderr.contains("WARN") && stderr.contains(&warning), "stderr: {stderr}");
}

#[test]
fn table_output_names_the_terms_in_both_units() {
    let csv = write_csv(&series(1000), 10.0);
    let out = gyrocomp(&["allan", csv.path().to_str().unwrap()]);
    assert!(out.status.success(), "stderr: {}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8(out.stdout).unwrap();
    for needle in ["tau_s", "adev_dps", "angle random walk", "deg/√h", "deg/h/√h", "deg/h²", "IEEE Std 952"] {
        assert!(text.contains(needle), "missing {needle:?} in:\n{text}");
    }
}

#[test]
fn bad_input_gives_a_clear_error() {
    let csv = write_csv(&series(2), 10.0);
    let path = csv.path().to_str().unwrap();
    let out = gyrocomp(&["allan", path, "--json"]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("too few samples"), "{err}");

    let csv = write_csv(&series(100), 10.0);
    let out = gyrocomp(&["allan", csv.path().to_str().unwrap(), "--column", "nope"]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("`nope`"));
}

#[test]
fn constant_series_has_zero_adev_and_null_fit() {
    let csv = write_csv(&[0.5; 64], 10.0);
    let out = gyrocomp(&["allan", csv.path().to_str().unwrap(), "--json"]);
    assert!(out.status.success(), "stderr: {}", String::from_utf8_lossy(&out.stderr));
    let json: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert!(floats(&json["adev"]).iter().all(|&d| d == 0.0));
    assert!(json["fit"].is_null());
}

/// Real ADIS16405 recording (shared data, not in the repository): the values of gx, run 1, in
/// configs/sim/README.md ("Presets beside the real ADIS16405 run 1").
#[test]
fn real_adis16405_matches_published_allan_deviation() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/data/real/adis16405_run1_10hz.csv");
    if !path.exists() {
        eprintln!("SKIP real_adis16405_matches_published_allan_deviation: {} not found", path.display());
        return;
    }
    let out = gyrocomp(&["allan", path.to_str().unwrap(), "--json"]);
    assert!(out.status.success(), "stderr: {}", String::from_utf8_lossy(&out.stderr));
    let json: Value = serde_json::from_slice(&out.stdout).unwrap();
    let (tau, adev) = (floats(&json["tau_s"]), floats(&json["adev"]));
    assert!(close(tau[0], 0.1, 1e-9), "first tau {}", tau[0]);
    assert!(close(adev[0], 0.125, 0.10), "adev(0.1 s) = {}", adev[0]);
    // The bias-instability floor: the first local minimum of the curve. (The last, few-sample
    // octave points at ≥ 800 s dip lower again; they are not the floor configs/sim/README.md shows.)
    let i = (1..adev.len() - 1).find(|&i| adev[i] <= adev[i - 1] && adev[i] < adev[i + 1]).expect("a local minimum");
    assert!((50.0..=200.0).contains(&tau[i]), "floor at tau {} s", tau[i]);
    assert!(close(adev[i], 0.0072, 0.10), "floor adev {} at {} s", adev[i], tau[i]);
}

/// The value of `key: value` in a YAML text written by `--format kalibr`.
fn yaml_value(yaml: &str, key: &str) -> f64 {
    let line =
        yaml.lines().find(|l| l.starts_with(&format!("{key}:"))).unwrap_or_else(|| panic!("no {key} in\n{yaml}"));
    line[key.len() + 1..].trim().parse().unwrap_or_else(|e| panic!("{key}: {e} in {line:?}"))
}

#[test]
fn kalibr_yaml_matches_an_independent_allantools_fit_and_the_true_terms() {
    // tests/goldens/kalibr.json (tools/goldens/kalibr_goldens.py): the generator's parameters, and
    // N and K from allantools.oadev plus a two-term least-squares fit, in rad units.
    let golden: Value = serde_json::from_str(include_str!("goldens/kalibr.json")).unwrap();
    let g = &golden["generator"];
    let (mut state, samples) = (g["seed"].as_u64().unwrap(), g["samples"].as_u64().unwrap() as usize);
    let (white, step, bias, fs) = (
        g["white"].as_f64().unwrap(),
        g["step"].as_f64().unwrap(),
        g["bias"].as_f64().unwrap(),
        g["rate_hz"].as_f64().unwrap(),
    );
    let mut draw = || {
        state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let mut walk = 0.0;
    let x: Vec<f64> = (0..samples)
        .map(|_| {
            let w = white * draw();
            walk += step * draw();
            bias + w + walk
        })
        .collect();
    let csv = write_csv(&x, fs);
    let path = csv.path().to_str().unwrap();
    let out = gyrocomp(&["allan", path, "--column", "gz_dps", "--format", "kalibr", "--topic", "/imu0"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let yaml = String::from_utf8(out.stdout).unwrap();
    assert!(yaml.contains("\nrostopic: /imu0\n"), "{yaml}");
    assert_eq!(yaml_value(&yaml, "update_rate"), fs);
    for key in ["gyroscope_noise_density", "gyroscope_random_walk"] {
        let ours = yaml_value(&yaml, key);
        let reference = golden[key].as_f64().unwrap();
        let truth = golden[format!("true_{key}")].as_f64().unwrap();
        eprintln!("{key}: gyrocomp {ours:.4e}, allantools fit {reference:.4e}, true {truth:.4e}");
        assert!((ours / reference - 1.0).abs() < 0.05, "{key}: {ours} vs the allantools fit {reference}");
        assert!((ours / truth - 1.0).abs() < 0.10, "{key}: {ours} vs the true {truth}");
    }
    assert!(!yaml.contains("bound through the Allan minimum"), "{yaml}");
    // The JSON report carries the same values; --json and --format json are one thing.
    let json: Value =
        serde_json::from_slice(&gyrocomp(&["allan", path, "--column", "gz_dps", "--format", "json"]).stdout).unwrap();
    assert_eq!(
        json["kalibr"]["gyroscope_noise_density"].as_f64().unwrap(),
        yaml_value(&yaml, "gyroscope_noise_density")
    );
    let legacy: Value =
        serde_json::from_slice(&gyrocomp(&["allan", path, "--column", "gz_dps", "--json"]).stdout).unwrap();
    assert_eq!(json, legacy);
    assert!(
        !gyrocomp(&["allan", path, "--json", "--format", "text"]).status.success(),
        "--json conflicts with --format"
    );
}

#[test]
fn kalibr_update_rate_of_a_100_hz_file_is_100() {
    // The rate from the time column, (rows − 1)/(t_last − t_first), is 99.99999999999997 here:
    // the YAML carries it rounded to 6 significant digits, and the JSON's `kalibr` the same.
    let csv = write_csv(&series(4000), 100.0);
    let path = csv.path().to_str().unwrap();
    let out = gyrocomp(&["allan", path, "--format", "kalibr"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let yaml = String::from_utf8(out.stdout).unwrap();
    assert!(yaml.contains("\nupdate_rate: 100\n"), "{yaml}");
    let json: Value = serde_json::from_slice(&gyrocomp(&["allan", path, "--format", "json"]).stdout).unwrap();
    assert_eq!(json["kalibr"]["update_rate"].as_f64(), Some(100.0));
}
