//! Bad inputs of the new kinds (issue 15, items 4 and 6) through the default pipeline (Kalman
//! tracker with its temperature term, statistical detector): a stuck sensor, saturation at the
//! range, ±∞ and implausible temperatures, huge time steps. Each bad sample is flagged and
//! counted, leaves the estimator state as it was, and nothing panics.

use gyrocomp::config::{Config, RateSetting};
use gyrocomp::stream::input_check::{InputCheck, InputConfig};
use gyrocomp::stream::sample::STATUS_SENSOR_FAULT;
use gyrocomp::stream::{InputSample, OutputSample, Pipeline, STATUS_GAP, STATUS_REJECTED};

const PERIOD_NS: u64 = 10_000_000;

fn pipeline(rate: RateSetting) -> Pipeline {
    let mut c = Config::default();
    c.input.rate_hz = rate;
    Pipeline::new(c.pipeline().unwrap()).unwrap()
}

/// Deterministic noise of σ ≈ 0.1 deg/s (uniform) on a bias of 0.2, 0.1, −0.1 deg/s, 100 Hz, 25 °C + a ramp.
fn sample(k: u64) -> InputSample {
    // SplitMix64 of (k, axis): independent uniform noise.
    let noise = |a: u64| {
        let mut z = (k * 3 + a).wrapping_add(1).wrapping_mul(0x9E37_79B9_7F4A_7C15);
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        ((z >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 0.35
    };
    let mut s = InputSample::new(k, k * PERIOD_NS, [0.2 + noise(0), 0.1 + noise(1), -0.1 + noise(2)]);
    s.temp_c = 25.0 + k as f64 * 1e-4;
    s
}

fn finite(o: &OutputSample) -> bool {
    o.rate_dps.iter().chain(&o.drift_dps).all(|v| v.is_finite())
}

/// Static samples 0..7000 (70 s: past the 62 s commit delay, so the tracker has committed).
fn warmed() -> Pipeline {
    let mut p = pipeline(RateSetting::Hz(100.0));
    for k in 0..7000 {
        assert_eq!(p.process(&sample(k)).status & STATUS_REJECTED, 0, "sample {k}");
    }
    assert!(p.stats().committed > 500, "{:?}", p.stats());
    p
}

#[test]
fn a_stuck_axis_is_flagged_after_stuck_s_and_none_of_its_run_is_ever_committed() {
    let mut p = warmed();
    let start = 7000;
    let stuck = 0.2345;
    let mut flagged = Vec::new();
    for k in start..start + 500 {
        let mut s = sample(k);
        s.rate_dps[0] = stuck;
        let before = p.warm_state();
        let o = p.process(&s);
        assert!(finite(&o));
        if o.status & STATUS_SENSOR_FAULT != 0 {
            assert!(o.status & STATUS_REJECTED != 0);
            // A flagged sample changes no estimator state.
            assert_eq!(p.warm_state(), before, "sample {k}");
            // Nothing of the run is pending, so nothing of it can be committed later.
            assert!(p.stream_state().pending.samples.iter().all(|(i, ..)| *i < start), "sample {k}");
            flagged.push(k);
        }
    }
    // Flagged from 2 s (200 samples) into the run until it ends.
    assert_eq!(flagged, (start + 200..start + 500).collect::<Vec<_>>());
    assert_eq!(p.stats().input.stuck, 300);
    // The value moves again: accepted from the first sample on (the spike estimates, which the
    // run's first 2 s narrowed, started afresh).
    let after: Vec<u32> = (start + 500..start + 600).map(|k| p.process(&sample(k)).status).collect();
    assert!(after.iter().all(|s| s & STATUS_REJECTED == 0), "{after:?}");
}

#[test]
fn an_axis_constant_from_the_start_is_absent_not_stuck() {
    let mut p = pipeline(RateSetting::Hz(100.0));
    for k in 0..1000 {
        let mut s = sample(k);
        s.rate_dps[2] = 0.0;
        assert_eq!(p.process(&s).status & STATUS_SENSOR_FAULT, 0, "sample {k}");
    }
    assert_eq!(p.stats().input.stuck, 0);
}

#[test]
fn saturation_at_the_range_is_flagged_counted_and_learnt_from_never() {
    let mut p = warmed();
    let range = p.config().input.range_dps;
    for (j, x) in [range, -range, range * 0.9995, range].into_iter().enumerate() {
        let mut s = sample(7000 + j as u64);
        s.rate_dps[1] = x;
        let before = p.warm_state();
        let o = p.process(&s);
        assert_eq!(o.status & (STATUS_SENSOR_FAULT | STATUS_REJECTED), STATUS_SENSOR_FAULT | STATUS_REJECTED, "{x}");
        assert!(finite(&o));
        assert_eq!(p.warm_state(), before);
    }
    assert_eq!(p.stats().input.saturated, 4);
    // Just below the tolerance is a rate like any other (here: a motion, not a fault).
    let mut s = sample(7010);
    s.rate_dps[1] = range * 0.99;
    assert_eq!(p.process(&s).status & STATUS_SENSOR_FAULT, 0);
}

#[test]
fn infinite_or_implausible_temperatures_never_reach_the_temperature_term() {
    // Two pipelines: one sees ±∞ and absurd temperatures, the other NaN (none) on the same
    // samples. Bit-identical outputs and states: the bad values went nowhere.
    let mut bad = pipeline(RateSetting::Hz(100.0));
    let mut none = pipeline(RateSetting::Hz(100.0));
    let mut counted = 0;
    for k in 0..9000 {
        let mut s = sample(k);
        let mut t = s;
        if k % 50 == 7 {
            s.temp_c = [f64::INFINITY, f64::NEG_INFINITY, 1e300, -500.0][(k / 50 % 4) as usize];
            t.temp_c = f64::NAN;
            counted += 1;
        }
        let (a, b) = (bad.process(&s), none.process(&t));
        assert!(finite(&a));
        assert_eq!(a, b, "sample {k}");
    }
    assert_eq!(bad.stats().input.bad_temperature, counted);
    assert_eq!(none.stats().input.bad_temperature, 0);
    assert_eq!(bad.warm_state(), none.warm_state());
    assert!(bad.warm_state().iter().all(|w| w.temperature.is_some_and(|t| t.values().iter().all(|v| v.is_finite()))));
}

#[test]
fn huge_time_steps_are_gaps_and_time_at_the_end_of_u64_does_not_panic() {
    // "auto" rate: one huge step among the first ones does not set the period (a median).
    let mut p = pipeline(RateSetting::Auto);
    let mut t = 0u64;
    for k in 0..3000u64 {
        t += if k == 5 { 1_000_000_000_000_000_000 } else { PERIOD_NS };
        let mut s = sample(k);
        s.t_ns = t;
        let o = p.process(&s);
        assert!(finite(&o));
    }
    assert_eq!(p.period_s(), Some(PERIOD_NS as f64 * 1e-9));
    let mut p = warmed();
    let mut s = sample(7000);
    s.t_ns = u64::MAX - 1;
    let o = p.process(&s);
    assert!(o.status & STATUS_GAP != 0 && o.status & STATUS_REJECTED == 0 && finite(&o), "{o:?}");
    assert_eq!(p.stats().gaps, 1);
    // The gap sample is good data: it waits in the pending queue like any static sample (the
    // buffers are kept across a gap), it is not committed at once.
    assert_eq!(p.stream_state().pending.samples.last().map(|s| s.0), Some(7000));
    // The clock cannot go further: the next samples go back in time and are rejected, counted.
    for k in 7001..7005 {
        let o = p.process(&sample(k));
        assert!(o.status & STATUS_REJECTED != 0 && finite(&o));
    }
    assert_eq!(p.stats().input.time_backwards, 4);
}

/// The stuck test on real recordings: no run of identical values reaches the default 2 s.
#[test]
fn real_recordings_are_never_stuck_at_the_default_threshold() {
    let dir = std::path::Path::new("../shared/data/real");
    let Ok(entries) = std::fs::read_dir(dir) else {
        eprintln!("SKIP real_recordings_are_never_stuck_at_the_default_threshold: {} absent", dir.display());
        return;
    };
    let defaults = Config::default().pipeline().unwrap().input;
    let mut files = 0;
    for path in entries.flatten().map(|e| e.path()).filter(|p| p.extension().is_some_and(|e| e == "csv")) {
        let text = std::fs::read_to_string(&path).unwrap();
        let mut check = InputCheck::new(InputConfig { spike_z: 0.0, ..defaults });
        let mut longest = [0usize; 3];
        let (mut run, mut prev) = ([0usize; 3], [f64::NAN; 3]);
        for (k, line) in text.lines().skip(1).enumerate() {
            let v: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
            let rate = [v[1], v[2], v[3]];
            let verdict = check.check(k as u64, k as u64, (v[0] * 1e9).round() as u64, &rate, false);
            assert_eq!(verdict.status & STATUS_SENSOR_FAULT, 0, "{} row {k}", path.display());
            for a in 0..3 {
                run[a] = if rate[a] == prev[a] { run[a] + 1 } else { 1 };
                longest[a] = longest[a].max(run[a]);
            }
            prev = rate;
        }
        eprintln!("{}: longest runs of identical values per axis {longest:?}", path.display());
        assert_eq!(check.counters().stuck, 0);
        files += 1;
    }
    assert!(files > 0);
}
