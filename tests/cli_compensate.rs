//! `gyrocomp compensate` on simulated recordings (`gyrocomp sim`, `gyrocomp motion`): the output
//! columns, one row per input row, status bits, the deterministic retrain schedule, byte-identical
//! runs, and errors that name the file, line and field or the configuration key.

use std::path::Path;

use serde_json::Value;

const ONE_AXIS_HEADER: &str = "t_s,raw_dps,drift_dps,compensated_dps,status,model_version";

mod common;

use common::{gyrocomp, ok};

/// A quick configuration at 10 Hz with `retrain.mode = "live"` on purpose: compensate must still
/// retrain deterministically.
fn config_text() -> String {
    format!("{}[input]\nrate_hz = 10.0\n{}mode = \"live\"\n", common::PAPER_PIPELINE, common::QUICK_RETRAIN)
}

/// A 300 s paper-preset recording (3000 samples at 10 Hz) and the configuration file.
fn setup(dir: &Path) -> (String, String) {
    let csv = dir.join("sim.csv").to_str().unwrap().to_owned();
    ok(&["sim", "--preset", "paper", "--seed", "2", "--duration", "300", "-o", &csv]);
    let config = dir.join("c.toml");
    std::fs::write(&config, config_text()).unwrap();
    (csv, config.to_str().unwrap().to_owned())
}

/// Data rows of a CSV file, split into fields.
fn rows(path: &str) -> (String, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap().to_owned();
    (header, lines.map(|l| l.split(',').map(str::to_owned).collect()).collect())
}

fn column(header: &str, name: &str) -> usize {
    header.split(',').position(|h| h == name).unwrap_or_else(|| panic!("no column {name} in {header}"))
}

#[test]
fn one_row_per_sample_with_the_retrain_schedule_and_identical_runs() {
    let dir = tempfile::tempdir().unwrap();
    let (csv, config) = setup(dir.path());
    let out_csv = dir.path().join("out.csv").to_str().unwrap().to_owned();
    let out = ok(&["compensate", &csv, "--config", &config, "-o", &out_csv, "--json"]);
    let summary: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(summary["samples"], 3000);
    assert_eq!((summary["rejected"].as_u64(), summary["models_installed"].as_u64()), (Some(0), Some(2)));
    assert_eq!(summary["model_version"], 2);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("deterministic"), "the forced retrain mode is logged: {stderr}");
    assert!(!stderr.contains('\r'), "no progress bar when stderr is not a terminal");
    let axis = &summary["axes"][0];
    assert_eq!(axis["column"], "gx_dps");
    assert!(axis["std_compensated"].as_f64().unwrap() > 0.0 && axis["std_raw"].as_f64().unwrap() > 0.0);

    let (header, data) = rows(&out_csv);
    assert_eq!(header, ONE_AXIS_HEADER);
    let (in_header, input) = rows(&csv);
    assert_eq!(data.len(), input.len());
    let gx = column(&in_header, "gx_dps");
    for (i, (row, inp)) in data.iter().zip(&input).enumerate() {
        assert_eq!(row.len(), 6);
        // Time and raw values are the recording's, as written.
        assert_eq!((&row[0], &row[1]), (&inp[0], &inp[gx]), "row {i}");
        let f = |k: usize| row[k].parse::<f64>().unwrap();
        let (raw, drift, comp) = (f(1), f(2), f(3));
        assert_eq!(comp.to_bits(), (raw - drift).to_bits(), "row {i}: compensated = raw − drift");
        let (status, version): (u32, u64) = (row[4].parse().unwrap(), row[5].parse().unwrap());
        let want = if i < 1050 {
            0
        } else if i < 2050 {
            1
        } else {
            2
        };
        assert_eq!(version, want, "row {i}");
        assert_eq!(status & 1 != 0, i < 1050, "row {i}: status bit 0 (no model) until the first model");
        assert_eq!(status & 0b1100, 0, "row {i}: no reject, no gap");
    }

    // Byte-identical on a second run, and the same bytes on standard output.
    let again = dir.path().join("again.csv").to_str().unwrap().to_owned();
    let out = ok(&["compensate", &csv, "--config", &config, "-o", &again]);
    assert_eq!(std::fs::read(&out_csv).unwrap(), std::fs::read(&again).unwrap());
    let line = String::from_utf8_lossy(&out.stderr);
    assert!(line.contains("compensate: 3000 samples") && line.contains("2 models installed"), "{line}");
    let stdout = ok(&["compensate", &csv, "--config", &config, "-o", "-"]).stdout;
    assert_eq!(stdout, std::fs::read(&out_csv).unwrap());
}

#[test]
fn several_axes_and_publisher_moving_flags() {
    let dir = tempfile::tempdir().unwrap();
    let (csv, config) = setup(dir.path());
    let moved = dir.path().join("moved.csv").to_str().unwrap().to_owned();
    ok(&["motion", &csv, "--profile", "turns", "--seed", "3", "-o", &moved]);
    let out_csv = dir.path().join("out.csv").to_str().unwrap().to_owned();
    let args = ["compensate", &moved, "--config", &config, "--column", "gx_dps,gy_dps", "--column", "gz_dps"];
    let out = ok(&[&args[..], &["--moving-column", "moving", "-o", &out_csv, "--json"]].concat());
    let (header, data) = rows(&out_csv);
    let mut want = vec!["t_s".to_owned()];
    for a in ["gx", "gy", "gz"] {
        want.extend(["raw_dps", "drift_dps", "compensated_dps"].map(|q| format!("{q}_{a}")));
    }
    want.extend(["status".to_owned(), "model_version".to_owned()]);
    assert_eq!(header, want.join(","));

    let (in_header, input) = rows(&moved);
    let flag = column(&in_header, "moving");
    let status = column(&header, "status");
    let mut flagged = 0;
    for (row, inp) in data.iter().zip(&input) {
        assert_eq!(row[column(&header, "raw_dps_gz")], inp[column(&in_header, "gz_dps")]);
        if inp[flag] == "1" {
            flagged += 1;
            assert!(row[status].parse::<u32>().unwrap() & 2 != 0, "a flagged sample is moving (status bit 1)");
        }
    }
    assert!(flagged > 100, "the profile moves: {flagged} samples");
    let summary: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert!(summary["moving"].as_u64().unwrap() >= flagged);
    assert_eq!(summary["axes"].as_array().unwrap().len(), 3);
    assert!(summary["axes"][2]["static_samples"].as_u64().unwrap() <= 3000 - flagged);
}

#[test]
fn bad_files_and_bad_configurations_are_named() {
    let dir = tempfile::tempdir().unwrap();
    let (_, config) = setup(dir.path());
    let bad = dir.path().join("bad.csv");
    std::fs::write(&bad, "t_s,gx_dps\n0.0,0.1\n0.1,0.2\n0.2,abc\n").unwrap();
    let out_csv = dir.path().join("out.csv").to_str().unwrap().to_owned();
    let fail = |args: &[&str]| {
        let out = gyrocomp(args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        String::from_utf8_lossy(&out.stderr).into_owned()
    };
    let err = fail(&["compensate", bad.to_str().unwrap(), "--config", &config, "-o", &out_csv]);
    assert!(err.contains("bad.csv:4: field `gx_dps`: not a number"), "{err}");

    let flags = dir.path().join("flags.csv");
    std::fs::write(&flags, "t_s,gx_dps,moving\n0.0,0.1,0\n0.1,0.2,0.5\n").unwrap();
    let err = fail(&["compensate", flags.to_str().unwrap(), "--moving-column", "moving", "-o", &out_csv]);
    assert!(err.contains("flags.csv:3: field `moving`"), "{err}");

    let bad_config = dir.path().join("bad.toml");
    std::fs::write(&bad_config, "[retrain]\nwindw = 600\n").unwrap();
    let good = dir.path().join("good.csv");
    std::fs::write(&good, "t_s,gx_dps\n0.0,0.1\n").unwrap();
    let good = good.to_str().unwrap();
    let err = fail(&["compensate", good, "--config", bad_config.to_str().unwrap(), "-o", &out_csv]);
    assert!(err.contains("bad.toml") && err.contains("windw"), "{err}");
    std::fs::write(&bad_config, "[motion]\nrate_dps = -2.0\n").unwrap();
    let err = fail(&["compensate", good, "--config", bad_config.to_str().unwrap(), "-o", &out_csv]);
    assert!(err.contains("motion.rate_dps"), "{err}");

    let err = fail(&["compensate", good, "--column", "gx_dps,gy_dps,gz_dps,gw_dps", "-o", &out_csv]);
    assert!(err.contains("1 to 3 rate columns"), "{err}");
    let err = fail(&["compensate", good, "-o", "-", "--json"]);
    assert!(err.contains("--json"), "{err}");
}
