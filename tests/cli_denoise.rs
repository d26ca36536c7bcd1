//! `gyrocomp denoise` end to end: CSV in, CSV out, equal to the PyWavelets golden; causal mode
//! never looks ahead; bad input gives a located error and exit code 2.

use std::io::Write;
use std::path::Path;
use std::process::Command;

use serde_json::Value;

fn gyrocomp() -> Command {
    Command::new(env!("CARGO_BIN_EXE_gyrocomp"))
}

fn golden_case(n: u64) -> (Vec<f64>, Vec<f64>) {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/goldens/wavelet.json");
    let g: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let case = g["cases"].as_array().unwrap().iter().find(|c| c["n"] == n).unwrap();
    let floats = |v: &Value| v.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect::<Vec<_>>();
    (floats(&case["x"]), floats(&case["denoised"]))
}

fn write_csv(dir: &Path, name: &str, x: &[f64]) -> std::path::PathBuf {
    let path = dir.join(name);
    let mut f = std::fs::File::create(&path).unwrap();
    writeln!(f, "t_s,gx_dps").unwrap();
    for (i, v) in x.iter().enumerate() {
        writeln!(f, "{},{v:?}", i as f64 * 0.1).unwrap();
    }
    path
}

fn read_output(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap().split(',').map(str::to_owned).collect();
    let rows = lines.map(|l| l.split(',').map(|v| v.parse().unwrap()).collect()).collect();
    (header, rows)
}

#[test]
fn batch_output_equals_pywavelets_for_odd_and_even_lengths() {
    let dir = tempfile::tempdir().unwrap();
    for n in [1000, 1001] {
        let (x, want) = golden_case(n);
        let input = write_csv(dir.path(), &format!("in{n}.csv"), &x);
        let output = dir.path().join(format!("out{n}.csv"));
        let status = gyrocomp()
            .args(["denoise", input.to_str().unwrap(), "--column", "gx_dps", "--mode", "batch", "-o"])
            .arg(&output)
            .status()
            .unwrap();
        assert!(status.success());
        let (header, rows) = read_output(&output);
        assert_eq!(header, ["t_s", "raw", "denoised"]);
        assert_eq!(rows.len(), x.len());
        for (i, row) in rows.iter().enumerate() {
            assert_eq!(row[1], x[i], "raw column round-trips exactly");
            assert!((row[2] - want[i]).abs() <= 1e-9, "n={n} row {i}: {} vs {}", row[2], want[i]);
        }
    }
}

#[test]
fn causal_mode_reports_its_distance_to_batch_and_never_looks_ahead() {
    let dir = tempfile::tempdir().unwrap();
    let (mut x, _) = golden_case(1000);
    let run = |x: &[f64], name: &str| {
        let input = write_csv(dir.path(), &format!("{name}.csv"), x);
        let output = dir.path().join(format!("{name}-out.csv"));
        let out = gyrocomp()
            .args([
                "denoise",
                input.to_str().unwrap(),
                "--mode",
                "causal",
                "--window",
                "128",
                "--lag",
                "4",
                "--json",
                "-o",
            ])
            .arg(&output)
            .output()
            .unwrap();
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let summary: Value = serde_json::from_slice(&out.stdout).unwrap();
        (summary, read_output(&output).1)
    };
    let (summary, base) = run(&x, "base");
    assert_eq!(summary["mode"], "causal");
    assert_eq!(summary["window"], 128);
    let rmse = summary["rmse_vs_batch_steady"].as_f64().unwrap();
    assert!(rmse > 0.0 && rmse.is_finite());
    x[700] += 5.0;
    let (_, changed) = run(&x, "changed");
    for t in 0..700 - 4 {
        assert_eq!(base[t][2], changed[t][2], "estimate of sample {t} moved when sample 700 changed");
    }
}

#[test]
fn bad_input_is_reported_with_file_line_and_field() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("bad.csv");
    std::fs::write(&input, "t_s,gx_dps\n0,1\n0.1,2\n0.2,x7\n").unwrap();
    let out = gyrocomp().args(["denoise", input.to_str().unwrap()]).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains(&format!("{}:4: field `gx_dps`: not a number: \"x7\"", input.display())), "{stderr}");

    let out = gyrocomp().args(["denoise", input.to_str().unwrap(), "--column", "gz_dps"]).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("column `gz_dps` not found"));

    let (x, _) = golden_case(1000);
    let input = write_csv(dir.path(), "ok.csv", &x);
    let out =
        gyrocomp().args(["denoise", input.to_str().unwrap(), "--mode", "causal", "--window", "40"]).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("shorter than the minimum 56"));
}
