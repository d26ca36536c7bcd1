//! EuRoC MAV / TUM-VI CSV (`#timestamp [ns],w_RS_S_x [rad s^-1],…`) is read by every command as
//! it is: the same samples written in gyrocomp's layout (seconds, deg/s) and in EuRoC's (ns,
//! rad/s) give the same Allan fit and the same compensated output.

mod common;

use common::ok;

use std::fmt::Write as _;
use std::path::Path;
use std::process::Command;

use gyrocomp::sim::{Generator, Preset};
use serde_json::Value;

/// 600 s of the ADIS16405 preset at 100 Hz, three axes, written both ways. EuRoC's stamps start
/// at a real dataset's first timestamp (MH_01_easy), where an f64 resolves 256 ns.
fn write_both(dir: &Path) -> (String, String) {
    let mut sim = Preset::Adis16405.config();
    sim.rate_hz = 100.0;
    sim.duration_s = 600.0;
    let out = Generator::generate(&sim, 3).unwrap();
    let (mut ours, mut euroc) = (String::from("t_s,gx_dps,gy_dps,gz_dps\n"), String::new());
    euroc.push_str("#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1],a_RS_S_x [m s^-2],a_RS_S_y [m s^-2],a_RS_S_z [m s^-2]\n");
    let start_ns = 1_403_636_579_758_555_392u64;
    for k in 0..out.t_s.len() {
        let deg = [out.axes[0].raw[k], out.axes[1].raw[k], out.axes[2].raw[k]];
        let rad = deg.map(f64::to_radians);
        // The deg/s file holds exactly what the EuRoC reader makes of the rad/s values.
        let back = rad.map(|r| r * (180.0 / std::f64::consts::PI));
        let t_ns = start_ns + k as u64 * 10_000_000;
        writeln!(ours, "{:?},{:?},{:?},{:?}", t_ns as f64 * 1e-9, back[0], back[1], back[2]).unwrap();
        writeln!(euroc, "{t_ns},{:?},{:?},{:?},0.1,-0.2,9.81", rad[0], rad[1], rad[2]).unwrap();
    }
    let (a, b) = (dir.join("ours.csv"), dir.join("euroc.csv"));
    std::fs::write(&a, ours).unwrap();
    std::fs::write(&b, euroc).unwrap();
    (a.to_str().unwrap().to_owned(), b.to_str().unwrap().to_owned())
}

#[test]
fn a_euroc_file_gives_the_same_allan_fit_and_compensation_as_the_same_samples_in_deg_per_s() {
    let dir = tempfile::tempdir().unwrap();
    let (ours, euroc) = write_both(dir.path());
    for column in ["gx_dps", "gz_dps"] {
        let a: Value =
            serde_json::from_slice(&ok(&["allan", &ours, "--column", column, "--format", "json"]).stdout).unwrap();
        let b: Value =
            serde_json::from_slice(&ok(&["allan", &euroc, "--column", column, "--format", "json"]).stdout).unwrap();
        assert_eq!(a["adev"], b["adev"], "{column}: the same values in both files");
        assert_eq!(a["fit"], b["fit"], "{column}");
        assert_eq!(a["rate_hz"], b["rate_hz"]);
    }
    // By the EuRoC name too.
    let c: Value =
        serde_json::from_slice(&ok(&["allan", &euroc, "--column", "w_RS_S_z", "--format", "json"]).stdout).unwrap();
    let a: Value =
        serde_json::from_slice(&ok(&["allan", &ours, "--column", "gz_dps", "--format", "json"]).stdout).unwrap();
    assert_eq!(a["adev"], c["adev"]);
    let (oa, ob) = (dir.path().join("a.csv"), dir.path().join("b.csv"));
    ok(&["compensate", &ours, "--column", "gx_dps,gy_dps,gz_dps", "-o", oa.to_str().unwrap()]);
    ok(&["compensate", &euroc, "--column", "gx_dps,gy_dps,gz_dps", "-o", ob.to_str().unwrap()]);
    assert_eq!(
        std::fs::read_to_string(&oa).unwrap(),
        std::fs::read_to_string(&ob).unwrap(),
        "compensate: byte-identical"
    );
}

#[test]
fn a_euroc_file_without_the_wanted_column_names_the_file_and_what_it_has() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("e.csv");
    std::fs::write(&path, "#timestamp [ns],w_RS_S_x [rad s^-1]\n1000,0.1\n2000,0.2\n").unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_gyrocomp"))
        .args(["allan", path.to_str().unwrap(), "--column", "gy_dps"])
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("e.csv") && err.contains("gy_dps") && err.contains("w_RS_S_x [rad s^-1]"), "{err}");
}
