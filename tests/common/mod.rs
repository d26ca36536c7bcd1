//! Helpers shared by the integration tests: golden files, float comparison and the real
//! recordings (which live outside the repository and may be absent).

#![allow(dead_code)] // every test binary uses its own subset

use std::path::PathBuf;
use std::process::{Command, Output};

use gyrocomp::eval::{PaperProtocol, Prepared};
use gyrocomp::io::{ReadOptions, read_table};
use serde_json::Value;

/// The paper's pipeline (CPSO-LSSVM forecaster behind the fixed-threshold gate) for tests of the
/// retraining and model machinery: TOML `[drift]` and `[motion]` sections.
pub const PAPER_PIPELINE: &str = "[drift]
estimator = \"cpso-lssvm\"
[motion]
detector = \"threshold\"
";

/// A `[retrain]` section that keeps CLI tests quick: a 600-sample window, a request every 1000
/// samples applied 50 samples later, and a small CPSO. Other `[retrain]` keys may follow it.
pub const QUICK_RETRAIN: &str = "[retrain]
window = 600
min_samples = 300
every_samples = 1000
apply_delay_samples = 50
cpso_candidates = 6
cpso_particles = 3
cpso_iterations = 2
";

/// Parses `tests/goldens/NAME`.
pub fn golden(name: &str) -> Value {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/goldens").join(name);
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// A JSON array of numbers.
pub fn floats(v: &Value) -> Vec<f64> {
    v.as_array().expect("array").iter().map(|x| x.as_f64().expect("number")).collect()
}

/// Equal lengths and every element within `tol` (absolute).
pub fn assert_close(got: &[f64], want: &[f64], tol: f64, what: &str) {
    assert_eq!(got.len(), want.len(), "{what}: length");
    let worst = got.iter().zip(want).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    assert!(worst <= tol, "{what}: max abs difference {worst:e} > {tol:e}");
}

/// `../shared/data/real/FILE` beside the repository, or `None` after printing (uncaptured) why
/// the calling test skips.
pub fn real_recording(file: &str) -> Option<PathBuf> {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/data/real").join(file);
    if path.exists() {
        Some(path)
    } else {
        // Straight to stderr, not through `eprintln!` (captured by the test harness): the skip
        // shows in a plain `cargo test`.
        use std::io::Write;
        let _ = writeln!(
            std::io::stderr(),
            "SKIP: {} not found (the real recordings live outside the repository)",
            path.display()
        );
        None
    }
}

/// The paper's first group (§4.3) on real data: `gx_dps` of run 1 at 10 Hz, first 5021 samples
/// (5000 PSR rows), denoised, scaled on the 4021 samples the first 4000 rows use; `None` (with a
/// skip message) when the recordings are absent.
pub fn paper_group() -> Option<Prepared> {
    let path = real_recording("adis16405_run1_10hz.csv")?;
    let table = read_table(&path, &["gx_dps"], ReadOptions::default()).expect("readable recording");
    let prepared = PaperProtocol { samples: 5021, ..PaperProtocol::default() }.prepare(&table.columns[0]).unwrap();
    assert_eq!(prepared.train_end, 4021);
    Some(prepared)
}

/// Runs the `gyrocomp` binary of this package with `args` and returns what it did.
pub fn gyrocomp(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_gyrocomp")).args(args).output().expect("run gyrocomp")
}

/// Runs `gyrocomp` with `args` and asserts that it succeeded (its stderr in the message).
pub fn ok(args: &[&str]) -> Output {
    let out = gyrocomp(args);
    assert!(out.status.success(), "gyrocomp {args:?}: {}", String::from_utf8_lossy(&out.stderr));
    out
}
