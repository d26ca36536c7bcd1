//! Criterion benchmark of the reader layer (issue 17): 1,000,000 three-axis gyro samples read
//! from a ROS 2 bag (MCAP, `sensor_msgs/msg/Imu`, CDR) against the same samples in gyrocomp's CSV
//! (the baseline, measured in the same run). Target: the bag within 2× the CSV.
//!
//! - `read_1m/csv`: `read_columns` of `t_s,gx_dps,gy_dps,gz_dps` (the `{}` text of each f64).
//! - `read_1m/mcap_zstd`: the same samples as Imu messages in zstd chunks of 1 MiB, as
//!   rosbag2's MCAP plugin and the Python writer write them by default.
//! - `read_1m/mcap_plain`: uncompressed chunks.
//!
//! The bags are written here with the `mcap` crate's writer and a little-endian CDR encoding of
//! `sensor_msgs/msg/Imu` (tests/mcap.rs checks the reader against the Python writer). The files
//! go to a temporary directory under the target directory (about 60 MB of CSV, 330 MB of
//! uncompressed bag) and are removed.
//!
//! Run: `cargo bench --bench input`. Compare ratios, not absolute times: this machine is noisy.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::hint::black_box;
use std::io::{BufWriter, Write};
use std::path::Path;

use criterion::{Criterion, criterion_group, criterion_main};
use gyrocomp::io::{InputOptions, ReadOptions, read_columns};
use mcap::records::MessageHeader;

/// Samples in each file.
const SAMPLES: usize = 1_000_000;
/// First stamp, ns (an epoch time, as real bags have).
const START_NS: u64 = 1_700_000_000_000_000_000;
/// Sample period, ns (200 Hz).
const PERIOD_NS: u64 = 5_000_000;
const COLUMNS: [&str; 3] = ["gx_dps", "gy_dps", "gz_dps"];

/// Deterministic rates, rad/s: white noise on a slow walk, per axis.
fn rates(n: usize) -> Vec<[f64; 3]> {
    let mut state = 0x9e37_79b9_7f4a_7c15_u64;
    let mut walk = [0.0; 3];
    (0..n)
        .map(|_| {
            let mut w = [0.0; 3];
            for (a, v) in w.iter_mut().enumerate() {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                let u = (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
                walk[a] += 1e-6 * u;
                *v = walk[a] + 1e-3 * u;
            }
            w
        })
        .collect()
}

/// One `sensor_msgs/msg/Imu` in CDR_LE (src/io/ros2_imu.rs gives the field order).
fn imu_cdr(buf: &mut Vec<u8>, t_ns: u64, w: [f64; 3]) {
    buf.clear();
    buf.extend([0x00, 0x01, 0x00, 0x00]);
    buf.extend(((t_ns / 1_000_000_000) as i32).to_le_bytes());
    buf.extend(((t_ns % 1_000_000_000) as u32).to_le_bytes());
    buf.extend(4u32.to_le_bytes());
    buf.extend(b"imu\0"); // ends at offset 20: 16 after the header, aligned for f64
    let f = |buf: &mut Vec<u8>, v: f64| buf.extend(v.to_le_bytes());
    for v in [0.0, 0.0, 0.0, 1.0] {
        f(buf, v);
    }
    let zeros = [0.0; 9];
    zeros.iter().for_each(|&v| f(buf, v));
    w.iter().for_each(|&v| f(buf, v));
    zeros.iter().for_each(|&v| f(buf, v));
    [0.1, -0.2, 9.81].iter().for_each(|&v| f(buf, v));
    zeros.iter().for_each(|&v| f(buf, v));
}

fn write_bag(path: &Path, samples: &[[f64; 3]], compression: Option<mcap::Compression>) {
    let file = BufWriter::new(std::fs::File::create(path).unwrap());
    let mut w = mcap::WriteOptions::new().compression(compression).profile("ros2").create(file).unwrap();
    let schema = w.add_schema("sensor_msgs/msg/Imu", "ros2msg", b"(definition omitted)").unwrap();
    let channel = w.add_channel(schema, "/imu", "cdr", &BTreeMap::new()).unwrap();
    let mut buf = Vec::with_capacity(320);
    for (k, &rate) in samples.iter().enumerate() {
        let t_ns = START_NS + k as u64 * PERIOD_NS;
        imu_cdr(&mut buf, t_ns, rate);
        let header = MessageHeader { channel_id: channel, sequence: k as u32, log_time: t_ns, publish_time: t_ns };
        w.write_to_known_channel(&header, &buf).unwrap();
    }
    w.finish().unwrap();
}

fn write_csv(path: &Path, samples: &[[f64; 3]]) {
    let mut out = BufWriter::new(std::fs::File::create(path).unwrap());
    writeln!(out, "t_s,gx_dps,gy_dps,gz_dps").unwrap();
    let mut line = String::new();
    for (k, w) in samples.iter().enumerate() {
        line.clear();
        let t_s = (START_NS + k as u64 * PERIOD_NS) as f64 * 1e-9;
        let d = w.map(f64::to_degrees);
        writeln!(line, "{t_s},{},{},{}", d[0], d[1], d[2]).unwrap();
        out.write_all(line.as_bytes()).unwrap();
    }
    out.flush().unwrap();
}

fn read(path: &Path) -> usize {
    let t = read_columns(path, &COLUMNS, ReadOptions::default(), &InputOptions::default()).unwrap();
    t.len()
}

fn bench(c: &mut Criterion) {
    // In the target directory (cargo's CARGO_TARGET_TMPDIR), not /tmp: the files are large.
    let dir = tempfile::tempdir_in(env!("CARGO_TARGET_TMPDIR")).unwrap();
    let samples = rates(SAMPLES);
    let (csv, zstd, plain) = (dir.path().join("imu.csv"), dir.path().join("zstd.mcap"), dir.path().join("plain.mcap"));
    write_csv(&csv, &samples);
    write_bag(&zstd, &samples, Some(mcap::Compression::Zstd));
    write_bag(&plain, &samples, None);
    drop(samples);
    for p in [&csv, &zstd, &plain] {
        let size = std::fs::metadata(p).unwrap().len();
        eprintln!("{}: {:.1} MB", p.file_name().unwrap().to_string_lossy(), size as f64 / 1e6);
        assert_eq!(read(p), SAMPLES);
    }
    let mut group = c.benchmark_group("read_1m");
    group.sample_size(10);
    group.bench_function("csv", |b| b.iter(|| black_box(read(&csv))));
    group.bench_function("mcap_zstd", |b| b.iter(|| black_box(read(&zstd))));
    group.bench_function("mcap_plain", |b| b.iter(|| black_box(read(&plain))));
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
