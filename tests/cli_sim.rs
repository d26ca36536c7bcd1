//! `gyrocomp sim` and `gyrocomp motion` end to end: columns, seeds, config errors, and the motion
//! injection (raw_out − truth = raw_in).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use serde_json::Value;

fn gyrocomp() -> Command {
    Command::new(env!("CARGO_BIN_EXE_gyrocomp"))
}

fn run_ok(cmd: &mut Command) -> Output {
    let out = cmd.output().unwrap();
    assert!(out.status.success(), "{cmd:?} failed: {}", String::from_utf8_lossy(&out.stderr));
    out
}

fn sim(dir: &Path, name: &str, args: &[&str]) -> PathBuf {
    let path = dir.join(name);
    run_ok(gyrocomp().arg("sim").args(args).arg("-o").arg(&path));
    path
}

fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<String> = lines.next().unwrap().split(',').map(str::to_owned).collect();
    let mut columns = vec![Vec::new(); header.len()];
    for line in lines {
        for (c, v) in columns.iter_mut().zip(line.split(',')) {
            c.push(v.parse::<f64>().unwrap());
        }
    }
    (header, columns)
}

const SIM_COLUMNS: [&str; 8] =
    ["t_s", "gx_dps", "gy_dps", "gz_dps", "temp_c", "gx_drift_dps", "gy_drift_dps", "gz_drift_dps"];

#[test]
fn sim_writes_the_columns_and_the_same_seed_gives_the_same_bytes() {
    let dir = tempfile::tempdir().unwrap();
    for preset in ["paper", "adis16405", "mpu6050"] {
        let args = ["--preset", preset, "--duration", "200", "--seed", "5"];
        let a = sim(dir.path(), &format!("{preset}_a.csv"), &args);
        let b = sim(dir.path(), &format!("{preset}_b.csv"), &args);
        let c = sim(dir.path(), &format!("{preset}_c.csv"), &["--preset", preset, "--duration", "200", "--seed", "6"]);
        let bytes_a = std::fs::read(&a).unwrap();
        assert_eq!(bytes_a, std::fs::read(&b).unwrap(), "{preset}: same seed, different file");
        assert_ne!(bytes_a, std::fs::read(&c).unwrap(), "{preset}: different seeds, same file");
        let (header, columns) = read_csv(&a);
        assert_eq!(header, SIM_COLUMNS, "{preset}");
        let rate = if preset == "mpu6050" { 100.0 } else { 10.0 };
        assert_eq!(columns[0].len(), (200.0 * rate) as usize, "{preset}: rows");
        assert_eq!(columns[0][1], 1.0 / rate);
        let (_, columns_c) = read_csv(&c);
        assert_ne!(columns[1], columns_c[1]);
    }
    // --rate replaces the preset's rate; the default preset is paper.
    let d = sim(dir.path(), "rate.csv", &["--duration", "10", "--rate", "50"]);
    assert_eq!(read_csv(&d).1[0].len(), 500);
}

#[test]
fn sim_config_files_and_their_errors() {
    let dir = tempfile::tempdir().unwrap();
    // --print-config writes a TOML that reproduces the preset's output byte for byte.
    let printed = run_ok(gyrocomp().args(["sim", "--preset", "mpu6050", "--duration", "30", "--print-config"]));
    let config = dir.path().join("mpu.toml");
    std::fs::write(&config, &printed.stdout).unwrap();
    let from_preset = sim(dir.path(), "p.csv", &["--preset", "mpu6050", "--duration", "30", "--seed", "1"]);
    let from_file = sim(dir.path(), "f.csv", &["--config", config.to_str().unwrap(), "--seed", "1"]);
    assert_eq!(std::fs::read(from_preset).unwrap(), std::fs::read(from_file).unwrap());
    // A config's own seed is used unless --seed is given.
    let seeded = dir.path().join("seeded.toml");
    std::fs::write(&seeded, "rate_hz = 10.0\nduration_s = 20.0\nseed = 4\n[axis]\narw_deg_rt_h = 1.0\n").unwrap();
    let s4 = sim(dir.path(), "s4.csv", &["--config", seeded.to_str().unwrap()]);
    let s4b = sim(dir.path(), "s4b.csv", &["--config", seeded.to_str().unwrap(), "--seed", "4"]);
    assert_eq!(std::fs::read(&s4).unwrap(), std::fs::read(&s4b).unwrap());
    // Unknown keys are rejected with a message that names the key and the file.
    let bad = dir.path().join("bad.toml");
    std::fs::write(&bad, "rate_hz = 10.0\nduration_s = 20.0\n[axis]\narw_deg_rt_h = 1.0\nbias_instabilty_b = 3.0\n")
        .unwrap();
    let out = gyrocomp()
        .args(["sim", "--config", bad.to_str().unwrap(), "-o"])
        .arg(dir.path().join("x.csv"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("`bias_instabilty_b`") && stderr.contains("bad.toml"), "{stderr}");
    // An out-of-range value names its key.
    std::fs::write(&bad, "rate_hz = 10.0\nduration_s = 20.0\n[z.quantization]\nstep_dps = -1.0\n").unwrap();
    let out = gyrocomp()
        .args(["sim", "--config", bad.to_str().unwrap(), "-o"])
        .arg(dir.path().join("x.csv"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("z.quantization.step_dps"));
    // --preset and --config together are refused.
    let out = gyrocomp().args(["sim", "--preset", "paper", "--config", "x.toml", "-o", "-"]).output().unwrap();
    assert!(!out.status.success());
}

#[test]
fn gyrocomp_allan_recovers_the_simulated_arw() {
    // 2^17 samples of white noise alone at 100 Hz: the fit's N rests on ~10^5 independent
    // differences at m = 1 (relative error ≈ 0.3 %); 10 % is the bound.
    let dir = tempfile::tempdir().unwrap();
    let config = dir.path().join("white.toml");
    std::fs::write(&config, "rate_hz = 100.0\nduration_s = 1310.72\n[axis]\narw_deg_rt_h = 1.5\n").unwrap();
    let csv = sim(dir.path(), "white.csv", &["--config", config.to_str().unwrap(), "--seed", "3"]);
    for column in ["gx_dps", "gy_dps", "gz_dps"] {
        let out = run_ok(gyrocomp().arg("allan").arg(&csv).args(["--column", column, "--json"]));
        let v: Value = serde_json::from_slice(&out.stdout).unwrap();
        let n = v["fit"]["n"].as_f64().unwrap();
        assert!((n / (1.5 / 60.0) - 1.0).abs() < 0.10, "{column}: N = {n}");
    }
}

#[test]
fn motion_adds_a_known_profile_and_keeps_everything_else() {
    let dir = tempfile::tempdir().unwrap();
    let input = sim(dir.path(), "static.csv", &["--preset", "paper", "--seed", "2"]);
    let (in_header, in_cols) = read_csv(&input);
    let mut outputs = Vec::new();
    for (profile, seed) in [("turns", "1"), ("slow", "1"), ("mixed", "1"), ("mixed", "1"), ("mixed", "2")] {
        let output = dir.path().join(format!("motion_{profile}_{seed}_{}.csv", outputs.len()));
        let summary = run_ok(
            gyrocomp()
                .arg("motion")
                .arg(&input)
                .args(["--profile", profile, "--seed", seed, "--static-fraction", "0.4", "--json", "-o"])
                .arg(&output),
        );
        let summary: Value = serde_json::from_slice(&summary.stdout).unwrap();
        assert!(summary["static_fraction"].as_f64().unwrap() >= 0.4);
        assert!(summary["motions"].as_u64().unwrap() >= 1);
        let (header, cols) = read_csv(&output);
        let mut want_header = in_header.clone();
        want_header.extend(["truth_dps".to_owned(), "moving".to_owned()]);
        assert_eq!(header, want_header);
        let truth = &cols[header.len() - 2];
        let moving = &cols[header.len() - 1];
        assert!(moving.iter().all(|m| *m == 0.0 || *m == 1.0));
        assert!(truth.iter().zip(moving).all(|(r, m)| *m == 1.0 || *r == 0.0), "truth only while moving");
        assert!(truth.iter().any(|r| *r != 0.0));
        let max = truth.iter().fold(0.0f64, |a, r| a.max(r.abs()));
        match profile {
            "turns" => assert!(max <= 90.0 && max > 0.9, "turns peak {max}"),
            "slow" => assert!(max <= 1.0, "slow peak {max}"),
            _ => {}
        }
        for (i, name) in in_header.iter().enumerate() {
            for (k, (&out_v, &in_v)) in cols[i].iter().zip(&in_cols[i]).enumerate() {
                if matches!(name.as_str(), "gx_dps" | "gy_dps" | "gz_dps") {
                    assert!((out_v - truth[k] - in_v).abs() <= 1e-12 * (1.0 + truth[k].abs()), "{name} row {k}");
                } else {
                    assert_eq!(out_v, in_v, "{name} row {k} is passed through");
                }
            }
        }
        outputs.push(std::fs::read(&output).unwrap());
    }
    assert_eq!(outputs[2], outputs[3], "same seed, same file");
    assert_ne!(outputs[3], outputs[4], "different seeds, different files");
    // --columns restricts the injection; a missing column is named.
    let output = dir.path().join("gz_only.csv");
    run_ok(gyrocomp().arg("motion").arg(&input).args(["--profile", "turns", "--columns", "gz_dps", "-o"]).arg(&output));
    let (_, cols) = read_csv(&output);
    assert_eq!(cols[1], in_cols[1], "gx untouched");
    assert_ne!(cols[3], in_cols[3], "gz moved");
    let out = gyrocomp().arg("motion").arg(&input).args(["--columns", "wx", "-o"]).arg(&output).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("`wx`"));
    // Injecting twice is refused.
    let out = gyrocomp().arg("motion").arg(dir.path().join("gz_only.csv")).args(["-o", "-"]).output().unwrap();
    assert!(!out.status.success());
}

#[test]
fn motion_on_the_real_static_recording() {
    let real = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/data/real/adis16405_run1_10hz.csv"));
    if !real.exists() {
        eprintln!("skipping: {} is absent (shared data lives beside the checkout)", real.display());
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let output = dir.path().join("adis_motion.csv");
    run_ok(gyrocomp().arg("motion").arg(real).args(["--profile", "mixed", "--seed", "9", "-o"]).arg(&output));
    let (header, cols) = read_csv(&output);
    assert_eq!(header, ["t_s", "gx_dps", "gy_dps", "gz_dps", "truth_dps", "moving"]);
    assert_eq!(cols[0].len(), 100_000);
    let static_fraction = 1.0 - cols[5].iter().sum::<f64>() / cols[5].len() as f64;
    assert!(static_fraction >= 0.5 - 1e-3, "default static fraction 0.5: {static_fraction}");
}
