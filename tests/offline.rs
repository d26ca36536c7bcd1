//! The shared offline foundation: `Recording` (columns → axes, flags, line-exact errors, the one
//! t_s → t_ns conversion), the output CSV writer (bit-exact round trip) and the offline driver
//! (the daemon's pipeline construction, deterministic retraining, reproducible runs), on
//! simulated data.

use std::io::Write;
use std::path::{Path, PathBuf};

use gyrocomp::config::Config;
use gyrocomp::drive::{compensate_recording, run_pipeline};
use gyrocomp::io::{CompensatedCsvWriter, ReadOptions, Recording, RecordingError, read_table};
use gyrocomp::sim::{Generator, Preset};
use gyrocomp::stream::{FLAG_MOVING, OutputSample, Pipeline, RetrainMode, STATUS_NO_MODEL, STATUS_REJECTED, Trainer};

fn write_file(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::File::create(&path).unwrap().write_all(text.as_bytes()).unwrap();
    path
}

/// A simulated three-axis paper-preset recording (10 Hz) of `n` samples, written as CSV.
fn simulated(dir: &Path, n: usize, seed: u64) -> PathBuf {
    let mut sim = Preset::Paper.config();
    sim.duration_s = n as f64 / sim.rate_hz;
    let out = Generator::generate(&sim, seed).unwrap();
    let mut text = String::from("t_s,gx_dps,gy_dps,gz_dps,temp_c\n");
    for k in 0..n {
        let a = &out.axes;
        text.push_str(&format!("{},{},{},{},{}\n", out.t_s[k], a[0].raw[k], a[1].raw[k], a[2].raw[k], out.temp_c[k]));
    }
    write_file(dir, "sim.csv", &text)
}

/// A quick configuration: short windows, a small CPSO, retraining every 1000 samples.
fn config(mode: RetrainMode) -> Config {
    let mut c = Config::paper();
    c.input.rate_hz = gyrocomp::config::RateSetting::Hz(10.0);
    c.retrain.schedule.mode = mode;
    c.retrain.schedule.window = 600;
    c.retrain.schedule.min_samples = 300;
    c.retrain.schedule.every_samples = 1000;
    c.retrain.schedule.apply_delay_samples = 50;
    c.retrain.fit.cpso.candidates = 6;
    c.retrain.fit.cpso.particles = 3;
    c.retrain.fit.cpso.iterations = 2;
    c
}

fn run(config: &Config, rec: &Recording) -> Vec<OutputSample> {
    let mut out = Vec::with_capacity(rec.len());
    compensate_recording(config, rec, |i, o| {
        assert_eq!(i, out.len());
        out.push(*o);
    })
    .unwrap();
    out
}

#[test]
fn columns_become_axes_with_temperature_and_moving_flags() {
    let dir = tempfile::tempdir().unwrap();
    let path = write_file(
        dir.path(),
        "r.csv",
        "t_s,gx_dps,gy_dps,temp_c,moving\n0.0,1.5,-2.5,20.5,0\n\n0.1,NaN,3.0,,1\n0.25,0.5,inf,21,0\n",
    );
    let rec = Recording::load(&path, &["gy_dps", "gx_dps"], Some("moving")).unwrap();
    assert_eq!(rec.len(), 3);
    assert_eq!(rec.columns(), ["gy_dps", "gx_dps"]);
    let a = rec.input(0);
    assert_eq!((a.seq, a.t_ns, a.rate_dps, a.temp_c, a.flags), (0, 0, [-2.5, 1.5, 0.0], 20.5, 0));
    let b = rec.input(1);
    assert_eq!((b.seq, b.t_ns, b.flags), (1, 100_000_000, FLAG_MOVING));
    assert!(b.rate_dps[1].is_nan() && b.temp_c.is_nan());
    assert_eq!(rec.input(2).t_ns, 250_000_000);
    assert_eq!(rec.input(2).rate_dps[0], f64::INFINITY);
    assert_eq!(rec.moving(), Some(&[false, true, false][..]));

    // Without temperature and moving columns: NaN and no flags; a single column is axis x.
    let plain = write_file(dir.path(), "p.csv", "time,gz\n1.0,0.25\n2.0,0.5\n");
    let mut rec = Recording::load(&plain, &["gz"], None).unwrap();
    let s = rec.input(1);
    assert_eq!((s.t_ns, s.rate_dps, s.flags), (2_000_000_000, [0.5, 0.0, 0.0], 0));
    assert!(s.temp_c.is_nan());
    assert_eq!(rec.take_moving(), None);
    assert_eq!(rec.sample_rate_hz(), Some(1.0));
}

#[test]
fn bad_files_and_bad_column_lists_are_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let err = |text: &str, moving: Option<&str>| {
        let path = write_file(dir.path(), "bad.csv", text);
        let e = Recording::load(&path, &["gx_dps"], moving).unwrap_err();
        assert!(matches!(e, RecordingError::Csv(_)), "{e}");
        e.to_string()
    };
    let e = err("t_s,gx_dps\n-0.5,1.0\n", None);
    assert!(e.contains("bad.csv:2: field `t_s`") && e.contains("≥ 0"), "{e}");
    let e = err("t_s,gx_dps,moving\n0.0,1.0,0\n0.1,1.0,2\n", Some("moving"));
    assert!(e.contains("bad.csv:3: field `moving`") && e.contains("0 or 1"), "{e}");
    let e = err("t_s,gx_dps,moving\n0.0,1.0,NaN\n", Some("moving"));
    assert!(e.contains("bad.csv:2: field `moving`"), "{e}");
    let e = err("t_s,gx_dps\n0.0,1.0\n\n0.1,x\n", None);
    assert!(e.contains("bad.csv:4: field `gx_dps`: not a number"), "{e}");
    let e = err("t_s,gy_dps\n0.0,1.0\n", None);
    assert!(e.contains("bad.csv:1") && e.contains("`gx_dps` not found"), "{e}");
    let e = err("t_s,gx_dps\n0.2,1.0\n0.1,1.0\n", None);
    assert!(e.contains("bad.csv:3: field `t_s`: time does not increase"), "{e}");
    let e = err("t_s,gx_dps\n", None);
    assert!(e.contains("no data rows"), "{e}");

    let path = write_file(dir.path(), "ok.csv", "t_s,a,b,c,d\n0,1,2,3,4\n");
    for columns in [&[][..], &["a", "b", "c", "d"], &["a", "a"]] {
        let e = Recording::load(&path, columns, None).unwrap_err();
        assert!(matches!(e, RecordingError::Columns(_)), "{columns:?}: {e}");
    }
    assert!(matches!(Recording::load(&path, &["a"], Some("a")), Err(RecordingError::Columns(_))));
}

#[test]
fn offline_runs_are_the_daemons_pipeline_retrained_deterministically() {
    let dir = tempfile::tempdir().unwrap();
    let rec = Recording::load(&simulated(dir.path(), 2600, 4), &["gx_dps", "gy_dps", "gz_dps"], None).unwrap();
    // A live-mode file is run deterministically offline.
    let first = run(&config(RetrainMode::Live), &rec);
    let second = run(&config(RetrainMode::Deterministic), &rec);
    assert_eq!(first, second, "two offline runs differ");

    // The same as building the pipeline by hand from the configuration, as the daemon did.
    let c = config(RetrainMode::Deterministic);
    let mut pipeline = Pipeline::new(c.pipeline().unwrap()).unwrap();
    pipeline.attach_trainer(Trainer::spawn(c.cpso_lssvm().unwrap()).unwrap());
    let mut by_hand = Vec::new();
    let summary = run_pipeline(&mut pipeline, rec.inputs(), |_, o| by_hand.push(*o));
    assert_eq!(by_hand, first);
    assert_eq!(summary.stats.samples, 2600);

    // Requests after samples 1000 and 2000, each installed 50 samples later.
    for (i, o) in first.iter().enumerate() {
        assert_eq!(o.seq, i as u64);
        let want = if i < 1050 {
            0
        } else if i < 2050 {
            1
        } else {
            2
        };
        assert_eq!(o.model_version, want, "sample {i}");
    }
    assert!(first[1049].status & STATUS_NO_MODEL != 0 && first[1050].status & STATUS_NO_MODEL == 0);
    assert_eq!(summary.model_version, 2);
}

#[test]
fn a_single_column_gets_models_and_zero_elsewhere() {
    let dir = tempfile::tempdir().unwrap();
    let rec = Recording::load(&simulated(dir.path(), 1200, 5), &["gy_dps"], None).unwrap();
    let out = run(&config(RetrainMode::Deterministic), &rec);
    let last = out.last().unwrap();
    assert_eq!(last.model_version, 1, "the missing axes must not stop retraining");
    assert_eq!(last.status & STATUS_NO_MODEL, 0);
    for o in &out {
        assert_eq!((o.rate_dps[1], o.rate_dps[2], o.drift_dps[1], o.drift_dps[2]), (0.0, 0.0, 0.0, 0.0));
    }
}

#[test]
fn the_output_csv_reads_back_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let mut text = std::fs::read_to_string(simulated(dir.path(), 1100, 6)).unwrap();
    // One rejected sample: its raw value is written as NaN.
    let line: Vec<&str> = text.lines().collect();
    let mut fields: Vec<String> = line[500].split(',').map(str::to_owned).collect();
    fields[2] = "NaN".into();
    text = text.replace(line[500], &fields.join(","));
    let path = write_file(dir.path(), "with_nan.csv", &text);
    let rec = Recording::load(&path, &["gx_dps", "gy_dps"], None).unwrap();
    let out = run(&config(RetrainMode::Deterministic), &rec);
    assert!(out[499].status & STATUS_REJECTED != 0);

    let csv = dir.path().join("out.csv");
    let mut writer = CompensatedCsvWriter::create(&csv, &rec).unwrap();
    for (i, o) in out.iter().enumerate() {
        writer.write(i, o).unwrap();
    }
    assert!(writer.write(out.len(), &out[0]).is_err(), "a row past the end is refused");
    writer.finish().unwrap();

    let names = [
        "raw_dps_gx",
        "drift_dps_gx",
        "compensated_dps_gx",
        "raw_dps_gy",
        "drift_dps_gy",
        "compensated_dps_gy",
        "status",
        "model_version",
    ];
    let header = std::fs::read_to_string(&csv).unwrap().lines().next().unwrap().to_owned();
    assert_eq!(header, format!("t_s,{}", names.join(",")));
    let options = ReadOptions { allow_non_finite: true, require_increasing_time: true };
    let back = read_table(&csv, &names, options).unwrap();
    assert_eq!(back.len(), rec.len());
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&back.t_s), bits(rec.t_s()));
    for axis in 0..2 {
        assert_eq!(bits(&back.columns[3 * axis]), bits(rec.rate(axis).unwrap()));
        let drift: Vec<f64> = out.iter().map(|o| o.drift_dps[axis]).collect();
        let comp: Vec<f64> = out.iter().map(|o| o.rate_dps[axis]).collect();
        assert_eq!(bits(&back.columns[3 * axis + 1]), bits(&drift));
        assert_eq!(bits(&back.columns[3 * axis + 2]), bits(&comp));
    }
    let status: Vec<f64> = out.iter().map(|o| o.status as f64).collect();
    let version: Vec<f64> = out.iter().map(|o| o.model_version as f64).collect();
    assert_eq!((&back.columns[6], &back.columns[7]), (&status, &version));
}
