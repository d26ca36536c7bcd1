//! ROS 2 bags (MCAP, `sensor_msgs/msg/Imu`) as input, against bags written by the Python `mcap`
//! and `mcap-ros2-support` packages (tools/bags/imu_bag.py), an implementation independent of
//! ours; no ROS needed. Without those packages the bag tests are skipped with a SKIP line, and
//! under `CI=true` (where .ci/run installs them) they fail instead.
//!
//! Asserted:
//! - the CDR decoder reads the Python serializer's bytes (both byte orders; tests/goldens/
//!   imu_cdr.json from tools/goldens/imu_cdr_goldens.py) bit for bit, and every cut of them is
//!   an error naming a field, never a panic;
//! - a bag round-trips: `allan bag.mcap` (json and kalibr) gives the same numbers as the same
//!   samples in a rad/s CSV read with `--units rads`, `compensate bag.mcap` writes the same file
//!   as `compensate` on that CSV, and an uncompressed bag reads as the zstd one;
//! - header stamps (not log times) are the time, exact to the ns at epoch times;
//! - two Imu topics need `--topic`; a missing topic, a non-Imu topic and a bag without Imu are
//!   errors listing the topics; a cut message, a truncated or corrupt bag, lz4 chunks and a
//!   `.mcap` file that is not MCAP are errors naming the file (and the message and field).

mod common;

use common::{gyrocomp, ok};

#[allow(dead_code)] // its iceoryx2 probe is not used here
#[path = "common/python.rs"]
mod python;

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use gyrocomp::io::ros2_imu::decode_imu;
use gyrocomp::io::{InputOptions, Recording};
use gyrocomp::sim::{Generator, Preset};
use serde_json::Value;

/// Stamp of the first sample of the round-trip recording, ns: 1000 s, where an `f64` time in
/// seconds still resolves the ns (so the CSV's decimal times and the bag's stamps agree exactly).
const START_NS: u64 = 1_000_000_000_000;
/// Sample period, ns (100 Hz).
const PERIOD_NS: u64 = 10_000_000;

fn bags_or_skip(test: &str) -> bool {
    python::module_or_skip(test, "mcap_ros2.writer", "mcap + mcap-ros2-support", "pip install mcap mcap-ros2-support")
}

/// The error text of a failing `gyrocomp` run.
fn fails(args: &[&str]) -> String {
    let out = gyrocomp(args);
    assert!(!out.status.success(), "gyrocomp {args:?} should fail");
    String::from_utf8_lossy(&out.stderr).into_owned()
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Samples (`t_ns,wx,wy,wz`, rad/s) for tools/bags/imu_bag.py and the same samples as gyrocomp
/// CSV in rad/s (`t_s` the exact decimal of the stamp): `n` samples of the ADIS16405 preset
/// from `start_ns`.
fn write_samples(dir: &Path, n: usize, start_ns: u64) -> (PathBuf, PathBuf) {
    let mut sim = Preset::Adis16405.config();
    sim.rate_hz = 1e9 / PERIOD_NS as f64;
    sim.duration_s = n as f64 / sim.rate_hz;
    let out = Generator::generate(&sim, 5).unwrap();
    let (mut samples, mut csv) = (String::from("t_ns,wx,wy,wz\n"), String::from("t_s,gx_dps,gy_dps,gz_dps\n"));
    for k in 0..n.min(out.t_s.len()) {
        let rad = [0, 1, 2].map(|a| out.axes[a].raw[k].to_radians());
        let t_ns = start_ns + k as u64 * PERIOD_NS;
        writeln!(samples, "{t_ns},{:?},{:?},{:?}", rad[0], rad[1], rad[2]).unwrap();
        let t_s = format!("{}.{:09}", t_ns / 1_000_000_000, t_ns % 1_000_000_000);
        writeln!(csv, "{t_s},{:?},{:?},{:?}", rad[0], rad[1], rad[2]).unwrap();
    }
    let (a, b) = (dir.join("samples.csv"), dir.join("rads.csv"));
    std::fs::write(&a, samples).unwrap();
    std::fs::write(&b, csv).unwrap();
    (a, b)
}

/// Writes `out` with tools/bags/imu_bag.py from `samples` and `args`.
fn write_bag(out: &Path, samples: &Path, args: &[&str]) {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tools/bags/imu_bag.py");
    let run = Command::new("python3")
        .arg(script)
        .arg(out)
        .args(["--samples", s(samples)])
        .args(args)
        .output()
        .expect("run python3");
    assert!(run.status.success(), "imu_bag.py: {}", String::from_utf8_lossy(&run.stderr));
}

fn json(out: &Output) -> Value {
    serde_json::from_slice(&out.stdout).unwrap()
}

/// The `key: value` lines of a Kalibr YAML, comments and `rostopic` left out.
fn kalibr_values(out: &Output) -> Vec<String> {
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with("rostopic") && !l.trim().is_empty())
        .map(str::to_owned)
        .collect()
}

/// Offset of the (compressed) records of the first Chunk record of an MCAP file whose Header
/// record is followed by a chunk (MCAP specification: magic, then opcode u8 + length u64 +
/// content per record; a Chunk's content is start, end, uncompressed size (u64 each),
/// uncompressed CRC (u32), compression (u32-prefixed string), records length (u64), records).
fn first_chunk_records(bytes: &[u8]) -> usize {
    let u64_at = |i: usize| u64::from_le_bytes(bytes[i..i + 8].try_into().unwrap()) as usize;
    let u32_at = |i: usize| u32::from_le_bytes(bytes[i..i + 4].try_into().unwrap()) as usize;
    let header = 8;
    assert_eq!(bytes[header], 0x01, "Header record");
    let chunk = header + 9 + u64_at(header + 1);
    assert_eq!(bytes[chunk], 0x06, "a Chunk record follows the Header");
    let compression = chunk + 9 + 8 + 8 + 8 + 4;
    compression + 4 + u32_at(compression) + 8
}

#[test]
fn the_cdr_decoder_reads_the_python_serializers_bytes() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/goldens/imu_cdr.json");
    let golden: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let messages = golden["messages"].as_array().unwrap();
    assert!(messages.iter().any(|m| m["byte_order"] == "be") && messages.iter().any(|m| m["byte_order"] == "le"));
    let bits =
        |v: &Value| -> Vec<u64> { v.as_array().unwrap().iter().map(|x| x.as_f64().unwrap().to_bits()).collect() };
    for m in messages {
        let hex = m["hex"].as_str().unwrap();
        let data: Vec<u8> =
            (0..hex.len()).step_by(2).map(|i| u8::from_str_radix(&hex[i..i + 2], 16).unwrap()).collect();
        let what = format!("{} {}", m["byte_order"], m["frame_id"]);
        let msg = decode_imu(&data).unwrap_or_else(|e| panic!("{what}: {e}"));
        assert_eq!(i64::from(msg.stamp_sec), m["sec"].as_i64().unwrap(), "{what}");
        assert_eq!(u64::from(msg.stamp_nanosec), m["nanosec"].as_u64().unwrap(), "{what}");
        assert_eq!(msg.frame_id, m["frame_id"].as_str().unwrap(), "{what}");
        let got = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(got(&msg.orientation), bits(&m["orientation"]), "{what}: orientation");
        assert_eq!(got(&msg.angular_velocity), bits(&m["angular_velocity"]), "{what}: angular_velocity");
        assert_eq!(got(&msg.linear_acceleration), bits(&m["linear_acceleration"]), "{what}: linear_acceleration");
        assert_eq!(msg.stamp_ns(), Some(m["sec"].as_u64().unwrap() * 1_000_000_000 + m["nanosec"].as_u64().unwrap()));
        for cut in 0..data.len() {
            let e = decode_imu(&data[..cut]).expect_err("a cut message is an error");
            assert!(!e.field.is_empty() && e.offset <= cut, "{what} cut at {cut}: {e}");
        }
    }
}

#[test]
fn a_bag_gives_the_same_allan_fit_and_compensation_as_the_same_samples_in_csv() {
    if !bags_or_skip("a_bag_gives_the_same_allan_fit_and_compensation_as_the_same_samples_in_csv") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (samples, rads) = write_samples(dir.path(), 36_000, START_NS);
    let bag = dir.path().join("imu.mcap");
    write_bag(&bag, &samples, &[]);
    let plain = dir.path().join("plain.mcap");
    write_bag(&plain, &samples, &["--compression", "none", "--chunk-size", "65536"]);
    for column in ["gx_dps", "gz_dps"] {
        let a = json(&ok(&["allan", s(&bag), "--column", column, "--format", "json"]));
        let b = json(&ok(&["allan", s(&rads), "--units", "rads", "--column", column, "--format", "json"]));
        assert_eq!(a["adev"], b["adev"], "{column}: the same samples in both files");
        assert_eq!(a["fit"], b["fit"], "{column}");
        assert_eq!(a["rate_hz"], b["rate_hz"], "{column}");
        assert!(a["fit"]["n"].as_f64().unwrap() > 0.0, "{column}: a fit was made");
        let c = json(&ok(&["allan", s(&plain), "--column", column, "--format", "json"]));
        assert_eq!(a["adev"], c["adev"], "{column}: an uncompressed bag reads the same");
    }
    let ka = ok(&["allan", s(&bag), "--column", "gy_dps", "--format", "kalibr"]);
    let kb = ok(&["allan", s(&rads), "--units", "rads", "--column", "gy_dps", "--format", "kalibr"]);
    assert_eq!(kalibr_values(&ka), kalibr_values(&kb));
    assert_eq!(kalibr_values(&ka).len(), 3, "update_rate, noise density, random walk");
    assert!(String::from_utf8_lossy(&ka.stdout).contains("rostopic: /imu\n"), "the bag's topic is the rostopic");
    // Our CSV in deg/s is the rad/s one times 180/π: --units is applied, not ignored.
    let dps = json(&ok(&["allan", s(&rads), "--column", "gx_dps", "--format", "json"]));
    let a = json(&ok(&["allan", s(&bag), "--column", "gx_dps", "--format", "json"]));
    let ratio = a["adev"][0].as_f64().unwrap() / dps["adev"][0].as_f64().unwrap();
    assert!((ratio - 180.0 / std::f64::consts::PI).abs() < 1e-9, "{ratio}");

    let (oa, ob) = (dir.path().join("a.csv"), dir.path().join("b.csv"));
    ok(&["compensate", s(&bag), "--column", "gx_dps,gy_dps,gz_dps", "-o", s(&oa)]);
    ok(&["compensate", s(&rads), "--units", "rads", "--column", "gx_dps,gy_dps,gz_dps", "-o", s(&ob)]);
    let (a, b) = (std::fs::read_to_string(&oa).unwrap(), std::fs::read_to_string(&ob).unwrap());
    assert_eq!(a.lines().count(), 36_001);
    assert!(a == b, "compensate on the bag and on the CSV differ");
    // The time is the header stamp (the bag's log times are 1 µs later).
    let first = a.lines().nth(1).unwrap();
    assert!(first.starts_with("1000,"), "{first}");
    // A bag named .csv is still read as a bag (the magic decides).
    let renamed = dir.path().join("imu_bag.csv");
    std::fs::copy(&bag, &renamed).unwrap();
    let r = json(&ok(&["allan", s(&renamed), "--column", "gx_dps", "--format", "json"]));
    assert_eq!(r["adev"], json(&ok(&["allan", s(&bag), "--column", "gx_dps", "--format", "json"]))["adev"]);
}

#[test]
fn epoch_stamps_are_kept_to_the_ns() {
    if !bags_or_skip("epoch_stamps_are_kept_to_the_ns") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let start = 1_700_000_000_123_456_789;
    let (samples, _) = write_samples(dir.path(), 500, start);
    let bag = dir.path().join("epoch.mcap");
    write_bag(&bag, &samples, &["--topic", "/imu/data_raw"]);
    let rec = Recording::load_with(&bag, &["gz_dps", "angular_velocity.x"], None, &InputOptions::default()).unwrap();
    assert_eq!(rec.len(), 500);
    for (k, input) in rec.inputs().enumerate() {
        assert_eq!(input.t_ns, start + k as u64 * PERIOD_NS, "sample {k}");
        assert!(input.temp_c.is_nan(), "a bag has no temperature");
    }
    let e = Recording::load_with(&bag, &["gx_dps"], Some("moving"), &InputOptions::default()).unwrap_err().to_string();
    assert!(e.contains("column `moving`") && e.contains(s(&bag)), "{e}");
}

#[test]
fn topics_are_chosen_by_name_and_wrong_choices_list_the_topics() {
    if !bags_or_skip("topics_are_chosen_by_name_and_wrong_choices_list_the_topics") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (samples, rads) = write_samples(dir.path(), 2000, START_NS);
    let two = dir.path().join("two.mcap");
    write_bag(&two, &samples, &["--topic", "/imu", "--topic", "/imu2", "--string-topic", "/note"]);
    let e = fails(&["allan", s(&two), "--format", "json"]);
    assert!(e.contains(s(&two)) && e.contains("--topic"), "{e}");
    assert!(e.contains("/imu (sensor_msgs/msg/Imu)") && e.contains("/imu2 (sensor_msgs/msg/Imu)"), "{e}");
    assert!(e.contains("/note (std_msgs/msg/String)"), "{e}");
    let a = json(&ok(&["allan", s(&two), "--topic", "/imu2", "--format", "json"]));
    let b = json(&ok(&["allan", s(&rads), "--units", "rads", "--format", "json"]));
    assert_eq!(a["adev"], b["adev"]);
    let e = fails(&["cc", s(&two), "--topic", "/nope"]);
    assert!(e.contains("topic `/nope` not found") && e.contains("/imu2 (sensor_msgs/msg/Imu)"), "{e}");
    let e = fails(&["denoise", s(&two), "--topic", "/note"]);
    assert!(e.contains("std_msgs/msg/String, not sensor_msgs/msg/Imu"), "{e}");

    let none = dir.path().join("none.mcap");
    write_bag(&none, &samples, &["--string-topic", "/note"]);
    let e = fails(&["compensate", s(&none), "-o", s(&dir.path().join("x.csv"))]);
    assert!(e.contains(s(&none)) && e.contains("no sensor_msgs/msg/Imu topic") && e.contains("/note"), "{e}");
    // Options that do not fit the file.
    let e = fails(&["allan", s(&two), "--topic", "/imu", "--units", "dps"]);
    assert!(e.contains("--units dps"), "{e}");
    let e = fails(&["compensate", s(&rads), "--topic", "/imu", "-o", s(&dir.path().join("y.csv"))]);
    assert!(e.contains("--topic") && e.contains("CSV"), "{e}");
}

#[test]
fn damaged_bags_are_errors_naming_the_file_and_the_message() {
    if !bags_or_skip("damaged_bags_are_errors_naming_the_file_and_the_message") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (samples, _) = write_samples(dir.path(), 3000, START_NS);
    // One message cut short: its number, log time and field are named.
    let cut = dir.path().join("cut.mcap");
    write_bag(&cut, &samples, &["--cut-message", "5"]);
    let e = fails(&["allan", s(&cut)]);
    let log_time = START_NS + 4 * PERIOD_NS + 1000;
    assert!(e.contains(s(&cut)) && e.contains("/imu message 5"), "{e}");
    assert!(e.contains(&format!("log time {log_time} ns")) && e.contains("field `"), "{e}");

    // Truncated: everything after the first half is lost.
    for compression in ["zstd", "none"] {
        let bag = dir.path().join(format!("{compression}.mcap"));
        write_bag(&bag, &samples, &["--compression", compression, "--chunk-size", "32768"]);
        let bytes = std::fs::read(&bag).unwrap();
        let truncated = dir.path().join(format!("truncated_{compression}.mcap"));
        std::fs::write(&truncated, &bytes[..bytes.len() / 2]).unwrap();
        let e = fails(&["compensate", s(&truncated), "-o", s(&dir.path().join("o.csv"))]);
        assert!(e.contains(s(&truncated)) && e.contains("truncated or corrupt"), "{compression}: {e}");
        // Corrupt: 64 bytes inside the records of the first chunk overwritten (its CRC or its
        // decompression fails).
        let mut corrupt = bytes.clone();
        let at = first_chunk_records(&bytes) + 2000;
        for b in &mut corrupt[at..at + 64] {
            *b ^= 0x5A;
        }
        let path = dir.path().join(format!("corrupt_{compression}.mcap"));
        std::fs::write(&path, &corrupt).unwrap();
        let e = fails(&["allan", s(&path)]);
        assert!(e.contains(s(&path)), "{compression}: {e}");
    }
    let lz4 = dir.path().join("lz4.mcap");
    write_bag(&lz4, &samples, &["--compression", "lz4"]);
    let e = fails(&["allan", s(&lz4)]);
    assert!(e.contains(s(&lz4)) && e.contains("compressed with `lz4`"), "{e}");
    let text = dir.path().join("text.mcap");
    std::fs::write(&text, "t_s,gx_dps\n0,1\n").unwrap();
    let e = fails(&["allan", s(&text)]);
    assert!(e.contains(s(&text)) && e.to_lowercase().contains("magic"), "{e}");
}
