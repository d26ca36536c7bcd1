//! Properties of the default drift path (issue 13): the Kalman bias tracker behind the
//! statistical detector, with the rate measured from the timestamps and no per-sensor key.
//! Seeded simulated recordings with injected motion; seeds 7–9 are used nowhere else (the
//! method's constants were chosen on seeds 100–105, its figures reported on the ADIS runs).

use gyrocomp::config::Config;
use gyrocomp::eval::{BaselineSettings, MotionModel, MotionRun, detection_scores, run_motion_model};
use gyrocomp::sim::{Generator, MotionKind, MotionPlan, Preset, SimConfig};
use gyrocomp::stream::{InputSample, OutputSample, Pipeline, STATUS_MOVING};

/// A recording of `preset` (`rate_hz`, `duration_s`, seed) with `kind` motion (same seed) added
/// to axis x: (inputs without flags, truth, moving flags).
fn recording(sim: &SimConfig, seed: u64, kind: MotionKind) -> (Vec<InputSample>, Vec<f64>, Vec<bool>, Vec<f64>) {
    let out = Generator::generate(sim, seed).unwrap();
    let t_rel: Vec<f64> = out.t_s.iter().map(|t| t - out.t_s[0]).collect();
    let plan = MotionPlan::plan(kind, seed, *t_rel.last().unwrap(), 0.5).unwrap();
    let (truth, moving) = plan.render(&t_rel);
    let inputs = (0..out.t_s.len())
        .map(|k| {
            let rate = [out.axes[0].raw[k] + truth[k], out.axes[1].raw[k], out.axes[2].raw[k]];
            InputSample::new(k as u64, (out.t_s[k] * 1e9).round() as u64, rate)
        })
        .collect();
    (inputs, truth, moving.iter().map(|&m| m > 0.5).collect(), out.t_s)
}

fn adis(rate_hz: f64, duration_s: f64) -> SimConfig {
    let mut sim = Preset::Adis16405.config();
    sim.rate_hz = rate_hz;
    sim.duration_s = duration_s;
    sim
}

struct Scored {
    median: f64,
    run: f64,
}

fn score(config: &Config, model: MotionModel, run: &MotionRun, inputs: &[InputSample], moving: &[bool]) -> Scored {
    let baselines = BaselineSettings { startup_s: 60.0, highpass_hz: 0.001 };
    let out = run_motion_model(model, config, run, inputs, moving, baselines, &mut |_| {}).unwrap();
    let s = run.score(&out.compensated).unwrap();
    Scored { median: s.angle_err_deg_median.unwrap(), run: s.angle_err_deg_run }
}

#[test]
fn the_default_estimator_beats_bias_hold_and_the_ungated_predictor_on_unseen_seeds() {
    let config = Config::default();
    let tactical = SimConfig::from_toml(include_str!("../configs/sim/tactical.toml")).unwrap();
    // (recording, seed, bound on gyrocomp's per-turn median as a multiple of bias-hold's)
    for (sim, seed, per_turn_bound) in
        [(adis(10.0, 4000.0), 7, 1.0), (adis(100.0, 1500.0), 8, 1.5), (tactical, 9, 1.15)]
    {
        let (inputs, truth, moving, t_s) = recording(&sim, seed, MotionKind::Turns);
        let raw: Vec<f64> = inputs.iter().map(|s| s.rate_dps[0]).collect();
        let run = MotionRun::new(t_s, raw, truth, &moving).unwrap();
        let ours = score(&config, MotionModel::Gyrocomp, &run, &inputs, &moving);
        let hold = score(&config, MotionModel::BiasHold, &run, &inputs, &moving);
        let ungated = score(&config, MotionModel::Persistence, &run, &inputs, &moving);
        let floor = run.white_noise_floor(run.sensor_arw().unwrap());
        let floor = gyrocomp::model::metrics::quantile(&floor, 0.5).unwrap();
        let at = format!("{} Hz seed {seed}", sim.rate_hz);
        eprintln!(
            "{at}: median per turn gyrocomp {:.3}, bias-hold {:.3}, persistence {:.3}, floor {floor:.3}; run {:.2} / {:.2}",
            ours.median, hold.median, ungated.median, ours.run, hold.run
        );
        // Per turn the tracker beats bias-hold at 10 Hz; at 100 Hz it does not (docs/drift-estimation.md
        // "Where it loses": measured 1.2× on this seed and on the main job's), held to a regression bound;
        // the tactical preset on this short run measured 1.06× since the contiguous, winsorised
        // calibration (0.3–0.6× on the tuning seeds 100–103).
        assert!(ours.median < per_turn_bound * hold.median, "{at}: {} vs bias-hold {}", ours.median, hold.median);
        assert!(ours.median < 0.2 * ungated.median, "{at}: {} vs persistence {}", ours.median, ungated.median);
        if seed == 7 {
            // Over 4000 s the bias wanders away from the start-up mean; the tracker follows it.
            // (Over the 1500 s run at 100 Hz both stay within about a degree: 1.2 against 0.7.)
            assert!(ours.run < 0.2 * hold.run, "{at}: run {} vs bias-hold {}", ours.run, hold.run);
        }
        // Nothing removes the white noise integrated over a turn; the tracker stays near it.
        assert!(ours.median < 2.0 * floor && ours.median > 0.7 * floor, "{at}: {} vs floor {floor}", ours.median);
    }
}

fn process(config: &Config, inputs: &[InputSample]) -> (Pipeline, Vec<OutputSample>) {
    let mut p = Pipeline::new(config.pipeline().unwrap()).unwrap();
    let out = inputs.iter().map(|s| p.process(s)).collect();
    (p, out)
}

/// Bounds on the detector's scores on the 66 turns of seed 9 (4000 s at 10 Hz), about twice what
/// was measured when they were set: delay median 1.4 s and p95 4.9 s, 81 of 21,988 deg turned
/// passed on as static (0.4 %), no false alarm.
const DELAY_MEDIAN_S: f64 = 3.0;
const DELAY_P95_S: f64 = 10.0;
const LEAKED_SHARE: f64 = 0.01;
/// Two false alarms in the 1.1 h run fail.
const FALSE_ALARMS_PER_H: f64 = 1.5;

#[test]
fn the_detector_finds_turns_at_once_and_keeps_false_alarms_rare() {
    let sim = adis(10.0, 4000.0);
    let (inputs, truth, moving, _) = recording(&sim, 9, MotionKind::Turns);
    let (p, out) = process(&Config::default(), &inputs);
    let flagged: Vec<bool> = out.iter().map(|o| o.status & STATUS_MOVING != 0).collect();
    // Leaks: samples turning faster than 2 deg/s (≈ 16σ of one sample) output as static — the
    // detection latency at a turn's onset (those samples are then discarded by the look-back, so
    // they never reach the estimate; their effect is in the angle errors above).
    let fast = truth.iter().filter(|t| t.abs() > 2.0).count();
    let leaked = truth.iter().zip(&flagged).filter(|(t, f)| t.abs() > 2.0 && !**f).count();
    // False alarms: static samples flagged moving, not within a motion or the 10 s after it
    // (settle_s = 5 s of hysteresis plus the tails of a sin² turn).
    let after = 100; // 10 s at 10 Hz
    let mut near = vec![false; moving.len()];
    for (i, &m) in moving.iter().enumerate() {
        if m {
            near[i..(i + after).min(moving.len())].iter_mut().for_each(|v| *v = true);
        }
    }
    let quiet = near.iter().filter(|n| !**n).count();
    let false_alarms = near.iter().zip(&flagged).filter(|(n, f)| !**n && **f).count();
    let stats = p.stats();
    eprintln!(
        "fast {fast}, leaked {leaked}; quiet {quiet}, false alarms {false_alarms}; onsets {}, committed {}, discarded {}",
        stats.detector.onsets, stats.committed, stats.discarded
    );
    assert!(fast > 1000 && quiet > 1000, "the profile has both ({fast}, {quiet})");
    assert!((leaked as f64) < 0.005 * fast as f64, "{leaked} of {fast} fast samples leaked");
    assert!((false_alarms as f64) < 0.05 * quiet as f64, "{false_alarms} of {quiet} quiet samples flagged");
    // Every motion of the profile starts an onset; spurious onsets stay few.
    let motions = gyrocomp::eval::motion::segments(&moving).len() as u64;
    assert!(stats.detector.onsets >= motions / 2 && stats.detector.onsets <= 3 * motions, "{stats:?} vs {motions}");
    // The same, as `gyrocomp eval --protocol motion` reports it (issue 13 item 3): every turn
    // (peak 1–90 deg/s) is found, within a few seconds of its first sample (the sin² onset stays
    // below the 0.5 s window's threshold for its first fraction of a second at the smallest peaks),
    // and the rotation passed on as static is a small share of the turned angle.
    let raw: Vec<f64> = inputs.iter().map(|s| s.rate_dps[0]).collect();
    let t_s: Vec<f64> = inputs.iter().map(|s| s.t_ns as f64 * 1e-9).collect();
    let run = MotionRun::new(t_s, raw, truth.clone(), &moving).unwrap();
    let d = detection_scores(&run, &flagged).unwrap();
    let turned: f64 = truth.iter().zip(run.dt()).map(|(t, dt)| t.abs() * dt).sum();
    eprintln!(
        "missed {}/{}, delay median {:?} p95 {:?} s, leaked {} samples, {:.1} of {turned:.0} deg; false alarms {} ({:.2}/h)",
        d.missed,
        d.motions,
        d.delay_s_median,
        d.delay_s_p95,
        d.leaked_samples,
        d.leaked_angle_deg_total,
        d.false_alarms,
        d.false_alarms_per_h
    );
    assert_eq!(d.missed, 0, "{d:?}");
    assert!(d.delay_s_median.unwrap() < DELAY_MEDIAN_S && d.delay_s_p95.unwrap() < DELAY_P95_S, "{d:?}");
    assert!(d.leaked_angle_deg_total < LEAKED_SHARE * turned, "{d:?}");
    assert!(d.false_alarms_per_h < FALSE_ALARMS_PER_H, "{d:?}");
}

#[test]
fn the_kalman_innovations_match_its_own_variances() {
    // White noise plus a rate random walk, no motion: the filter's model is right, so the
    // normalised innovation squared averages 1 (χ²(1)).
    let mut sim = SimConfig::from_toml(
        "rate_hz = 100.0\nduration_s = 2000.0\n[axis]\nbias_dps = 0.3\narw_deg_rt_h = 3.0\nrrw_deg_h_rt_h = 30.0\n",
    )
    .unwrap();
    sim.duration_s = 2000.0;
    let out = Generator::generate(&sim, 11).unwrap();
    let inputs: Vec<InputSample> = (0..out.t_s.len())
        .map(|k| {
            let rate = [out.axes[0].raw[k], out.axes[1].raw[k], out.axes[2].raw[k]];
            InputSample::new(k as u64, (out.t_s[k] * 1e9).round() as u64, rate)
        })
        .collect();
    // The filter alone: a threshold gate that never fires, so every sample is committed.
    let mut config = Config::default();
    config.motion.detector = gyrocomp::stream::DetectorKind::Threshold;
    config.motion.threshold.rate_dps = 1e9;
    config.motion.threshold.variance_dps2 = 1e9;
    let (p, _) = process(&config, &inputs);
    for axis in 0..3 {
        let k = p.estimator(axis).unwrap().kalman_counters().unwrap();
        let nis = k.mean_nis().unwrap();
        let n = p.noise(axis).unwrap();
        eprintln!(
            "axis {axis}: mean NIS {nis:.4} over {} commits, {} gated; m* {:?} R {:?}",
            k.nis_count,
            k.gated,
            n.optimal_block(),
            n.white_variance()
        );
        assert!(k.nis_count > 150_000, "{k:?}");
        // An R or Q off by 2× would give about 0.5 or 2.
        assert!((nis - 1.0).abs() < 0.1, "axis {axis}: mean NIS {nis}");
        assert!(k.gated < 20, "{k:?}");
    }
    assert_eq!(p.period_s(), Some(0.01), "rate measured from the timestamps");
}

#[test]
fn a_bias_learnt_from_a_rotation_at_power_on_is_relearnt() {
    // The platform already turns at power-on, at a steady 1 deg/s for 100 s, then stays still
    // for 20 min. Nothing tells the start-up that the first samples move (no onset, no change
    // of variance), so the tracker learns bias + 1 deg/s, and every later sample looks moving
    // against it: a deadlock. After relearn_s (600 s) of an unchanging residual the estimate is
    // relearnt from the still platform.
    let sim = adis(10.0, 1500.0);
    let out = Generator::generate(&sim, 7).unwrap();
    let inputs: Vec<InputSample> = (0..out.t_s.len())
        .map(|k| {
            let turn = if out.t_s[k] - out.t_s[0] < 100.0 { 1.0 } else { 0.0 };
            InputSample::new(
                k as u64,
                (out.t_s[k] * 1e9).round() as u64,
                [out.axes[0].raw[k] + turn, out.axes[1].raw[k], out.axes[2].raw[k]],
            )
        })
        .collect();
    let tail = inputs.len() - 3000;
    let still_mean = inputs[tail..].iter().map(|s| s.rate_dps[0]).sum::<f64>() / 3000.0;
    let (p, outputs) = process(&Config::default(), &inputs);
    // Over the last 5 min the output is static and its drift, on average, within 0.015 deg/s
    // of the still platform's mean rate (the tracker wanders by its own noise, ≈ 0.01; worst
    // 0.04) — against 1 deg/s off in the deadlock.
    let moving = outputs[tail..].iter().filter(|o| o.status & STATUS_MOVING != 0).count();
    let errors: Vec<f64> = outputs[tail..].iter().map(|o| (o.drift_dps[0] - still_mean).abs()).collect();
    let mean_err = errors.iter().sum::<f64>() / errors.len() as f64;
    let worst = errors.iter().copied().fold(0.0, f64::max);
    eprintln!(
        "relearns {}, moving in the last 5 min {moving}, drift error mean {mean_err:.4} worst {worst:.4}",
        p.stats().detector.relearns
    );
    assert_eq!(p.stats().detector.relearns, 1);
    assert!(moving < 150, "{moving} of 3000 samples moving in the last 5 min");
    assert!(mean_err < 0.015 && worst < 0.04, "drift off by {mean_err} on average, {worst} at worst");
    // With relearn_s = 0 (never) the deadlock stays: moving to the end, the drift 1 deg/s off.
    let mut never = Config::default();
    never.motion.statistical.relearn_s = 0.0;
    let (q, stuck) = process(&never, &inputs);
    let off = (stuck.last().unwrap().drift_dps[0] - still_mean).abs();
    assert!(off > 0.5 && stuck.last().unwrap().status & STATUS_MOVING != 0, "without relearning: drift {off} off");
    assert_eq!(q.stats().detector.relearns, 0);
}

#[test]
fn a_turn_that_begins_a_second_after_power_on_does_not_become_the_reference() {
    // One second still, then a 40 s turn (sin², 20 deg/s peak, as the motion profiles' turns),
    // then still. The turn is found within the look-back's reach of the start, so the
    // look-back would discard every pending sample; the oldest is kept as the reference (the
    // pipeline's settle_pending). Without it the estimate fell back to the mean of the samples
    // that followed, moving ones the detector could not test without a reference, and locked
    // onto the turn: on an independently generated floor whose turns kept coming, for the rest
    // of the run (no relearn, which needs minutes of an unchanging residual).
    // A quiet gyro (white noise 0.18 deg/√h, 0.01 deg/s per sample at 10 Hz, and a rate random
    // walk), on which the turn's start is found at once.
    let sim = SimConfig::from_toml(
        "rate_hz = 10.0\nduration_s = 1500.0\n[axis]\nbias_dps = 0.5\narw_deg_rt_h = 0.18\nrrw_deg_h_rt_h = 2.0\n",
    )
    .unwrap();
    let out = Generator::generate(&sim, 8).unwrap();
    let turn = |t: f64| {
        if (1.0..41.0).contains(&t) { 20.0 * (std::f64::consts::PI * (t - 1.0) / 40.0).sin().powi(2) } else { 0.0 }
    };
    let inputs: Vec<InputSample> = (0..out.t_s.len())
        .map(|k| {
            let t = out.t_s[k] - out.t_s[0];
            InputSample::new(
                k as u64,
                (out.t_s[k] * 1e9).round() as u64,
                [out.axes[0].raw[k] + turn(t), out.axes[1].raw[k], out.axes[2].raw[k]],
            )
        })
        .collect();
    let (p, outputs) = process(&Config::default(), &inputs);
    // From 100 s after the turn on: static, the drift within 0.002 deg/s of the true one on
    // average and 0.01 at worst (measured 0.0003 and 0.0023) — against 2.7 and 20 deg/s, and a
    // relearn, when the turn became the reference.
    let from = 1410;
    let moving = outputs[from..].iter().filter(|o| o.status & STATUS_MOVING != 0).count();
    let errors: Vec<f64> =
        (from..outputs.len()).map(|k| (outputs[k].drift_dps[0] - out.axes[0].drift[k]).abs()).collect();
    let mean_err = errors.iter().sum::<f64>() / errors.len() as f64;
    let worst = errors.iter().copied().fold(0.0, f64::max);
    eprintln!(
        "relearns {}, moving after the turn {moving} of {}, drift error mean {mean_err:.4} worst {worst:.4}",
        p.stats().detector.relearns,
        errors.len()
    );
    assert_eq!(p.stats().detector.relearns, 0);
    assert!(mean_err < 0.002 && worst < 0.01, "drift off by {mean_err} on average, {worst} at worst after the turn");
    assert!(moving < (outputs.len() - from) / 20, "{moving} samples moving after the turn");
}

#[test]
fn the_temperature_term_follows_a_bias_that_moves_with_temperature_while_moving() {
    // An ADIS-like white noise with a temperature coefficient of 0.01 deg/s/°C: the temperature
    // rises 6 °C and falls back while static (so c can be learnt), then rises 4 °C during a
    // 600 s motion the publisher flags. The bias moves 0.04 deg/s during the motion; the
    // temperature term predicts it, the scalar tracker holds the bias of the motion's start.
    let sim = SimConfig::from_toml(
        "rate_hz = 10.0\nduration_s = 3700.0\n\
         [temperature]\nstart_c = 20.0\nramps = [{ start_s = 200.0, duration_s = 1000.0, delta_c = 6.0 }, \
         { start_s = 1800.0, duration_s = 1000.0, delta_c = -6.0 }, { start_s = 3000.0, duration_s = 600.0, delta_c = 4.0 }]\n\
         [axis]\nbias_dps = 0.3\narw_deg_rt_h = 2.4\ntemperature_coefficient = { dps_per_c = 0.01, reference_c = 20.0 }\n",
    )
    .unwrap();
    let out = Generator::generate(&sim, 21).unwrap();
    let inputs: Vec<InputSample> = (0..out.t_s.len())
        .map(|k| {
            let mut s = InputSample::new(k as u64, (out.t_s[k] * 1e9).round() as u64, [out.axes[0].raw[k], 0.0, 0.0]);
            s.temp_c = out.temp_c[k];
            if (3000.0..3600.0).contains(&out.t_s[k]) {
                s.flags = gyrocomp::stream::FLAG_MOVING;
            }
            s
        })
        .collect();
    let end = out.t_s.iter().position(|&t| t >= 3599.0).unwrap();
    let error_at_end = |config: &Config| {
        let (_, outputs) = process(config, &inputs);
        assert!(outputs[end].status & STATUS_MOVING != 0);
        (outputs[end].drift_dps[0] - out.axes[0].drift[end]).abs()
    };
    let with = error_at_end(&Config::default());
    let mut scalar = Config::default();
    scalar.drift.temperature = false;
    let without = error_at_end(&scalar);
    eprintln!("drift error at the end of the motion: with the temperature term {with:.4}, without {without:.4} deg/s");
    assert!(with < 0.01, "with the temperature term: {with}");
    assert!(without > 0.03, "without: {without} (the bias moved 0.04 deg/s)");
}

#[test]
fn the_hybrid_estimator_follows_a_periodic_bias_through_a_motion_where_the_tracker_holds() {
    // White noise (ADIS-like ARW, 10 Hz) on a bias that swings ±0.05 deg/s with a 1200 s
    // period (a thermal cycle), then a 300 s turn at 5 deg/s, from a zero crossing of the bias to
    // its trough, that the detector finds at once.
    // The hybrid estimator's model of the 10 s block means has seen four periods; it forecasts
    // the swing through the motion, while the Kalman tracker holds the bias of the motion's
    // start. (Where the bias wanders at random, as on the ADIS recordings, the forecast does not
    // help: docs/drift-estimation.md.)
    let sim = SimConfig::from_toml("rate_hz = 10.0\nduration_s = 6000.0\n[axis]\nbias_dps = 0.0\narw_deg_rt_h = 2.4\n")
        .unwrap();
    let out = Generator::generate(&sim, 31).unwrap();
    let bias = |t: f64| 0.05 * (2.0 * std::f64::consts::PI * t / 1200.0).sin();
    let motion = 5400.0..5700.0;
    let inputs: Vec<InputSample> = (0..out.t_s.len())
        .map(|k| {
            let t = out.t_s[k] - out.t_s[0];
            let turn = if motion.contains(&t) { 5.0 } else { 0.0 };
            InputSample::new(
                k as u64,
                (out.t_s[k] * 1e9).round() as u64,
                [out.axes[0].raw[k] + bias(t) + turn, 0.0, 0.0],
            )
        })
        .collect();
    let drift_error_over_motion = |estimator: &str| {
        let mut config = Config::from_toml(&format!(
            "[drift]\nestimator = \"{estimator}\"\n[retrain]\nmode = \"deterministic\"\nmin_samples = 100\nevery_samples = 50000\n"
        ), "test")
        .unwrap();
        config.retrain.fit.cpso.iterations = 6;
        let mut p = gyrocomp::drive::build_pipeline(&config).unwrap();
        let outputs: Vec<OutputSample> = inputs.iter().map(|s| p.process(s)).collect();
        let (mut sum, mut n, mut moving) = (0.0, 0, 0);
        for (k, o) in outputs.iter().enumerate() {
            let t = out.t_s[k] - out.t_s[0];
            if motion.contains(&t) {
                sum += (o.drift_dps[0] - bias(t)).abs();
                n += 1;
                moving += usize::from(o.status & STATUS_MOVING != 0);
            }
        }
        assert!(moving as f64 > 0.99 * n as f64, "{estimator}: the turn is found ({moving} of {n} moving)");
        (sum / n as f64, p.model_version())
    };
    let (hybrid, version) = drift_error_over_motion("hybrid");
    let (kalman, _) = drift_error_over_motion("kalman");
    eprintln!(
        "mean drift error over the motion: hybrid {hybrid:.4}, kalman {kalman:.4} deg/s (model version {version})"
    );
    assert!(version >= 1, "a model of the block means was installed");
    assert!(hybrid < 0.5 * kalman, "hybrid {hybrid} vs kalman {kalman}");
}
