//! The IMU error simulator as a library: config files and presets, determinism, truth columns,
//! each term against its theory, motion profiles.

use gyrocomp::model::metrics::population_std_dev;
use gyrocomp::sim::terms::{FLICKER_FLOOR, flicker_poles};
use gyrocomp::sim::theory::{axis_adev, gauss_markov_avar_continuous};
use gyrocomp::sim::{
    AxisConfig, BiasInstability, Generator, Jumps, MotionKind, MotionPlan, Preset, Quantization, QuantizationMode,
    SimConfig, Sinusoid, Spikes, TemperatureCoefficient, TemperatureConfig, TemperatureRamp, Warmup,
};

/// A config with one model on all axes.
fn config(rate_hz: f64, duration_s: f64, axis: AxisConfig) -> SimConfig {
    SimConfig::with_axis(rate_hz, duration_s, axis)
}

/// Overlapping Allan variance of rate samples `x` averaged over `m` samples.
fn oavar(x: &[f64], m: usize) -> f64 {
    let mut s = Vec::with_capacity(x.len() + 1);
    s.push(0.0);
    let mut acc = 0.0;
    for v in x {
        acc += v;
        s.push(acc);
    }
    let n = x.len();
    assert!(n > 2 * m);
    let terms = n + 1 - 2 * m;
    let mut sum = 0.0;
    for k in 0..terms {
        let d = s[k + 2 * m] - 2.0 * s[k + m] + s[k];
        sum += d * d;
    }
    sum / (2.0 * (m * m) as f64 * terms as f64)
}

#[test]
fn presets_equal_their_config_files_and_round_trip_through_toml() {
    for preset in Preset::ALL {
        let path = format!("{}/configs/sim/{}.toml", env!("CARGO_MANIFEST_DIR"), preset.name());
        let text = std::fs::read_to_string(&path).unwrap();
        let from_file = SimConfig::from_toml(&text).unwrap_or_else(|e| panic!("{path}: {e}"));
        assert_eq!(from_file, preset.config(), "{path} differs from the preset");
        assert_eq!(SimConfig::from_toml(&preset.config().to_toml()).unwrap(), preset.config());
        assert_eq!(Preset::from_name(preset.name()), Some(preset));
    }
    let all = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/configs/sim/all-terms.toml")).unwrap();
    let all = SimConfig::from_toml(&all).unwrap();
    assert_eq!(all.axis_model(2).bias_dps, Some(-0.2));
    assert_eq!(all.axis_model(0).bias_dps, Some(0.1));
    assert!(all.axis_model(2).spikes.is_some(), "[z] keeps the [axis] keys it does not set");
    let out = Generator::generate(&SimConfig { duration_s: 60.0, ..all }, 1).unwrap();
    assert_eq!(out.len(), 6000);
    assert!(out.axes.iter().all(|a| a.raw.iter().all(|v| v.is_finite())));
}

#[test]
fn unknown_keys_and_bad_values_are_rejected_by_name() {
    for (text, key) in [
        ("rate_hz = 10\nduration_s = 1\nrate = 5\n", "rate"),
        ("rate_hz = 10\nduration_s = 1\n[axis]\narw = 1.0\n", "arw"),
        (
            "rate_hz = 10\nduration_s = 1\n[y.bias_instability]\nmodel = \"flicker\"\nb_deg_h = 1\nfloor_from_s = 1\nfloor_to_s = 10\ntau = 3\n",
            "tau",
        ),
        ("rate_hz = 10\nduration_s = 1\n[x.quantization]\nstep_dps = 0.1\nmode = \"angel\"\n", "angel"),
        ("rate_hz = 10\nduration_s = 1\n[temperature]\nstart = 20\n", "start"),
    ] {
        let err = SimConfig::from_toml(text).unwrap_err().to_string();
        assert!(err.contains(&format!("`{key}`")), "error for `{key}` does not name it: {err}");
    }
    let err =
        SimConfig::from_toml("rate_hz = 10\nduration_s = 1\n[x.warmup]\namplitude_dps = 1\ntime_constant_s = 0\n")
            .unwrap_err()
            .to_string();
    assert!(err.contains("x.warmup.time_constant_s"), "{err}");
    let err = SimConfig::from_toml("rate_hz = -1\nduration_s = 1\n").unwrap_err().to_string();
    assert!(err.contains("rate_hz"), "{err}");
}

#[test]
fn same_seed_same_numbers_different_seed_different_any_block_cut() {
    let cfg = SimConfig { duration_s: 1000.0, ..Preset::Mpu6050.config() };
    let a = Generator::generate(&cfg, 42).unwrap();
    let b = Generator::generate(&cfg, 42).unwrap();
    assert_eq!(a, b);
    let c = Generator::generate(&cfg, 43).unwrap();
    for (i, (ax, cx)) in a.axes.iter().zip(&c.axes).enumerate() {
        let same = ax.raw.iter().zip(&cx.raw).filter(|(p, q)| p == q).count();
        assert!(same < ax.raw.len() / 10, "axis {i}: seeds 42 and 43 agree on {same} samples");
    }
    // The same run cut into blocks of other lengths (some crossing the internal chunk size).
    let mut generator = Generator::new(&cfg, 42).unwrap();
    let mut pieces = gyrocomp::sim::SimOutput::default();
    let mut joined = gyrocomp::sim::SimOutput::default();
    for len in [1, 4095, 4097, 10_000, 81_807] {
        generator.fill(len, &mut pieces);
        joined.t_s.extend_from_slice(&pieces.t_s);
        joined.temp_c.extend_from_slice(&pieces.temp_c);
        for (j, p) in joined.axes.iter_mut().zip(&pieces.axes) {
            j.raw.extend_from_slice(&p.raw);
            j.drift.extend_from_slice(&p.drift);
            j.white.extend_from_slice(&p.white);
        }
    }
    assert_eq!(joined, a);
    // Axes sharing one model still draw different noise.
    assert_ne!(a.axes[0].white, a.axes[1].white);
}

/// One axis generated alone ([`Generator::into_axis`]) is that axis of the whole run, to the bit,
/// however the run is cut into blocks and from whatever position the generator was reduced at.
#[test]
fn one_axis_alone_is_that_axis_of_the_whole_run() {
    let cfg = SimConfig { duration_s: 1000.0, ..Preset::Mpu6050.config() };
    let all = Generator::generate(&cfg, 42).unwrap();
    for (axis, series) in all.axes.iter().enumerate() {
        let mut one = Generator::new(&cfg, 42).unwrap().into_axis(axis);
        let (mut piece, mut joined) = (Vec::new(), Vec::new());
        for len in [1, 4095, 4097, 10_000, 81_807] {
            one.fill(len, &mut piece);
            joined.extend_from_slice(&piece);
        }
        assert_eq!(joined, series.raw, "axis {axis}");
    }
    let mut generator = Generator::new(&cfg, 42).unwrap();
    generator.fill(5_000, &mut gyrocomp::sim::SimOutput::default());
    let mut rest = Vec::new();
    generator.into_axis(2).fill(1_000, &mut rest);
    assert_eq!(rest, all.axes[2].raw[5_000..6_000]);
}

#[test]
fn truth_columns_add_up_and_terms_keep_their_streams() {
    let full = AxisConfig {
        bias_dps: Some(0.3),
        arw_deg_rt_h: Some(3.0),
        bias_instability: Some(BiasInstability::Flicker { b_deg_h: 20.0, floor_from_s: 1.0, floor_to_s: 100.0 }),
        rrw_deg_h_rt_h: Some(30.0),
        ramp_deg_h2: Some(50.0),
        warmup: Some(Warmup { amplitude_dps: 0.2, time_constant_s: 30.0 }),
        sinusoids: Some(vec![Sinusoid { amplitude_dps: 0.01, frequency_hz: 0.3, phase_deg: 10.0 }]),
        jumps: Some(Jumps { rate_per_h: 20.0, size_dps: 0.05 }),
        spikes: Some(Spikes { rate_per_h: 60.0, size_dps: 2.0 }),
        ..AxisConfig::default()
    };
    for mode in [QuantizationMode::Angle, QuantizationMode::Rate] {
        let step = 0.05;
        let axis = AxisConfig { quantization: Some(Quantization { step_dps: step, mode }), ..full.clone() };
        let out = Generator::generate(&config(100.0, 600.0, axis), 9).unwrap();
        let bound = if mode == QuantizationMode::Angle { step } else { step / 2.0 };
        for a in &out.axes {
            let mut sum_err = 0.0;
            for ((&raw, &drift), &white) in a.raw.iter().zip(&a.drift).zip(&a.white) {
                let err = raw - (drift + white);
                assert!(err.abs() <= bound * (1.0 + 1e-9), "{mode:?}: quantisation error {err}");
                assert!(((raw / step).round() - raw / step).abs() < 1e-6, "raw {raw} is on the {step} grid");
                sum_err += err;
            }
            if mode == QuantizationMode::Angle {
                // The carried error telescopes: the integrated error stays within one LSB.
                assert!(sum_err.abs() <= step, "angle-mode error sum {sum_err}");
            }
        }
    }
    // Without a quantiser raw = drift + white exactly, and the white stream is the same as that of
    // a white-only run with the same seed; the drift is the same as that of a run without white.
    let with_all = Generator::generate(&config(100.0, 600.0, full.clone()), 9).unwrap();
    let white_only = Generator::generate(
        &config(100.0, 600.0, AxisConfig { arw_deg_rt_h: full.arw_deg_rt_h, ..AxisConfig::default() }),
        9,
    )
    .unwrap();
    let no_white = Generator::generate(&config(100.0, 600.0, AxisConfig { arw_deg_rt_h: None, ..full }), 9).unwrap();
    for i in 0..3 {
        let a = &with_all.axes[i];
        assert!(a.raw.iter().zip(&a.drift).zip(&a.white).all(|((r, d), w)| *r == d + w));
        assert_eq!(a.white, white_only.axes[i].white);
        assert_eq!(white_only.axes[i].raw, white_only.axes[i].white);
        assert!(white_only.axes[i].drift.iter().all(|&d| d == 0.0));
        assert_eq!(a.drift, no_white.axes[i].drift);
    }
}

#[test]
fn deterministic_terms_follow_their_formulas() {
    let axis = AxisConfig {
        bias_dps: Some(0.25),
        ramp_deg_h2: Some(36.0),
        warmup: Some(Warmup { amplitude_dps: 0.5, time_constant_s: 20.0 }),
        sinusoids: Some(vec![Sinusoid { amplitude_dps: 0.1, frequency_hz: 0.5, phase_deg: 30.0 }]),
        ..AxisConfig::default()
    };
    let out = Generator::generate(&config(10.0, 100.0, axis), 0).unwrap();
    for (k, (&t, &d)) in out.t_s.iter().zip(&out.axes[1].drift).enumerate() {
        assert_eq!(t, k as f64 / 10.0);
        let want = 0.25
            + 36.0 / 3600.0 / 3600.0 * t
            + 0.5 * (-t / 20.0).exp()
            + 0.1 * (2.0 * std::f64::consts::PI * 0.5 * t + 30f64.to_radians()).sin();
        assert!((d - want).abs() < 1e-12, "t={t}: {d} vs {want}");
        assert_eq!(out.axes[1].raw[k], d, "no white, no quantiser");
    }
}

#[test]
fn temperature_trajectory_and_hysteresis() {
    let mut cfg = config(
        1.0,
        4000.0,
        AxisConfig {
            temperature_coefficient: Some(TemperatureCoefficient {
                dps_per_c: 0.02,
                reference_c: 25.0,
                hysteresis_c: 1.0,
            }),
            ..AxisConfig::default()
        },
    );
    cfg.temperature = TemperatureConfig {
        start_c: 20.0,
        warmup_rise_c: 5.0,
        warmup_time_constant_s: 100.0,
        ramps: vec![
            TemperatureRamp { start_s: 1000.0, duration_s: 1000.0, delta_c: 10.0 },
            TemperatureRamp { start_s: 2500.0, duration_s: 1000.0, delta_c: -10.0 },
        ],
        noise_c: 0.0,
    };
    let out = Generator::generate(&cfg, 0).unwrap();
    let temp = |t: usize| out.temp_c[t];
    assert_eq!(temp(0), 20.0);
    assert!((temp(999) - 25.0).abs() < 1e-3, "warm-up settles at 25: {}", temp(999));
    assert!((temp(1500) - 30.0).abs() < 1e-3, "half-way up the ramp: {}", temp(1500));
    assert!((temp(2200) - 35.0).abs() < 1e-3);
    assert!((temp(3000) - 30.0).abs() < 1e-3, "half-way down: {}", temp(3000));
    // At 30 °C on the way up the effective temperature lags by 0.5 °C, on the way down it leads.
    let drift = &out.axes[0].drift;
    assert!((drift[1500] - 0.02 * (29.5 - 25.0)).abs() < 1e-3, "warming: {}", drift[1500]);
    assert!((drift[3000] - 0.02 * (30.5 - 25.0)).abs() < 1e-3, "cooling: {}", drift[3000]);
    assert!((drift[3000] - drift[1500] - 0.02 * 1.0).abs() < 1e-6, "loop width = coefficient × hysteresis");
    // Reading noise goes into temp_c only.
    cfg.temperature.noise_c = 0.1;
    let noisy = Generator::generate(&cfg, 0).unwrap();
    let diff: Vec<f64> = noisy.temp_c.iter().zip(&out.temp_c).map(|(a, b)| a - b).collect();
    assert!((population_std_dev(&diff).unwrap() - 0.1).abs() < 0.01);
    assert_eq!(noisy.axes[0].drift, out.axes[0].drift, "the bias follows the true temperature");
}

#[test]
fn jumps_and_spikes_arrive_at_their_rates() {
    let axis = AxisConfig { jumps: Some(Jumps { rate_per_h: 36.0, size_dps: 0.1 }), ..AxisConfig::default() };
    // 100 h at 1 Hz: 3600 expected jumps per axis (Poisson, σ = 60).
    let out = Generator::generate(&config(1.0, 360_000.0, axis), 3).unwrap();
    for a in &out.axes {
        let steps: Vec<f64> = a.drift.windows(2).map(|w| w[1] - w[0]).filter(|d| *d != 0.0).collect();
        assert!((steps.len() as f64 - 3600.0).abs() < 4.0 * 60.0, "{} jumps", steps.len());
        let rms = (steps.iter().map(|s| s * s).sum::<f64>() / steps.len() as f64).sqrt();
        assert!((rms - 0.1).abs() < 0.01, "jump rms {rms}");
    }
    let axis = AxisConfig { spikes: Some(Spikes { rate_per_h: 360.0, size_dps: 3.0 }), ..AxisConfig::default() };
    // 10 h at 10 Hz: 3600 expected spikes.
    let out = Generator::generate(&config(10.0, 36_000.0, axis), 3).unwrap();
    for a in &out.axes {
        let spikes: Vec<f64> = a.drift.iter().copied().filter(|d| *d != 0.0).collect();
        assert!((spikes.len() as f64 - 3600.0).abs() < 4.0 * 60.0, "{} spikes", spikes.len());
        assert!(spikes.iter().all(|s| s.abs() == 3.0 || s.abs() == 6.0));
        let positive = spikes.iter().filter(|s| **s > 0.0).count() as f64 / spikes.len() as f64;
        assert!((positive - 0.5).abs() < 0.05);
    }
}

#[test]
fn flicker_bank_gives_a_flat_floor_over_the_configured_span() {
    for rate_hz in [1.0, 10.0, 100.0] {
        for (from, to) in [(1.0, 20.0), (1.0, 5000.0), (0.1, 100.0), (10.0, 10_000.0)] {
            let axis = AxisConfig {
                bias_instability: Some(BiasInstability::Flicker {
                    b_deg_h: 3600.0,
                    floor_from_s: from,
                    floor_to_s: to,
                }),
                ..AxisConfig::default()
            };
            let m_lo = ((from * rate_hz).ceil() as usize).max(1);
            let m_hi = (to * rate_hz) as usize;
            let mut m = m_lo;
            while m <= m_hi {
                let ratio = axis_adev(&axis, rate_hz, m) / FLICKER_FLOOR;
                assert!(
                    (ratio - 1.0).abs() < 0.02,
                    "fs {rate_hz} span {from}..{to}: τ = {} s gives {ratio}",
                    m as f64 / rate_hz
                );
                m = (m as f64 * 1.3).ceil() as usize;
            }
        }
    }
    // The bank sums to the documented PSD weight: variance B²·Δ/π per process.
    let poles = flicker_poles(1.0, 1.0, 1000.0, 0.1);
    assert!(poles.len() >= 2 * 5);
    let ratio = poles[1].1 / poles[0].1;
    assert!(ratio <= 10f64.sqrt() * (1.0 + 1e-12));
    assert!((poles[0].0 - ratio.ln() / std::f64::consts::PI).abs() < 1e-12);
    // The Gauss–Markov model peaks at 0.664·B near τ = 1.89·T.
    let peak = (1..4000).map(|i| gauss_markov_avar_continuous(1.0, 1.0, i as f64 * 1e-3)).fold(0.0, f64::max).sqrt();
    assert!((peak - gyrocomp::sim::terms::GAUSS_MARKOV_PEAK).abs() < 1e-6);
}

/// The sampled terms match their exact Allan variance. 2·10⁵ samples; at each checked m there are
/// at least 200 non-overlapping clusters, so the relative standard error of the overlapping ADEV is
/// under about 1/√(2·200) ≈ 5 %; the tolerance is 15 % (3σ).
#[test]
fn generated_terms_match_their_theoretical_allan_deviation() {
    let rate_hz = 10.0;
    let n = 200_000;
    let cases: Vec<(&str, AxisConfig)> = vec![
        ("white", AxisConfig { arw_deg_rt_h: Some(2.0), ..AxisConfig::default() }),
        (
            "gauss-markov T=3 s (interval means)",
            AxisConfig {
                bias_instability: Some(BiasInstability::GaussMarkov { b_deg_h: 20.0, correlation_time_s: 3.0 }),
                ..AxisConfig::default()
            },
        ),
        (
            "gauss-markov T=30 s (point samples)",
            AxisConfig {
                bias_instability: Some(BiasInstability::GaussMarkov { b_deg_h: 20.0, correlation_time_s: 30.0 }),
                ..AxisConfig::default()
            },
        ),
        (
            "flicker 0.1..100 s",
            AxisConfig {
                bias_instability: Some(BiasInstability::Flicker {
                    b_deg_h: 20.0,
                    floor_from_s: 0.1,
                    floor_to_s: 100.0,
                }),
                ..AxisConfig::default()
            },
        ),
        ("rrw", AxisConfig { rrw_deg_h_rt_h: Some(50.0), ..AxisConfig::default() }),
        (
            "angle quantisation + dither",
            AxisConfig {
                arw_deg_rt_h: Some(0.5),
                quantization: Some(Quantization { step_dps: 0.05, mode: QuantizationMode::Angle }),
                ..AxisConfig::default()
            },
        ),
        ("adis16405 x", Preset::Adis16405.config().axis_model(0)),
        ("paper", Preset::Paper.config().axis_model(0)),
    ];
    for (name, axis) in cases {
        let out = Generator::generate(&config(rate_hz, n as f64 / rate_hz, axis.clone()), 5).unwrap();
        for m in [1, 2, 5, 10, 30, 100, 300, 1000] {
            let want = axis_adev(&axis, rate_hz, m);
            // RRW and the preset axes: several independent axes tighten the estimate.
            let got = (out.axes.iter().map(|a| oavar(&a.raw, m)).sum::<f64>() / 3.0).sqrt();
            assert!((got / want - 1.0).abs() < 0.15, "{name}: m = {m}: sim {got:.4e} vs theory {want:.4e}");
        }
    }
}

#[test]
fn paper_preset_has_the_papers_drift_level() {
    let cfg = Preset::Paper.config();
    assert_eq!((cfg.rate_hz, cfg.samples()), (10.0, 15_000));
    let mut drift = Vec::new();
    let mut raw = Vec::new();
    for seed in 0..10 {
        let out = Generator::generate(&cfg, seed).unwrap();
        drift.push(population_std_dev(&out.axes[0].drift).unwrap());
        raw.push(population_std_dev(&out.axes[0].raw).unwrap());
    }
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    assert!((mean(&drift) - 0.0035).abs() < 0.0004, "drift std {}", mean(&drift));
    assert!((mean(&raw) - 0.0037).abs() < 0.0004, "raw std {}", mean(&raw));
}

#[test]
fn motion_plans_are_seeded_and_keep_the_static_fraction() {
    for kind in [MotionKind::Turns, MotionKind::Slow, MotionKind::Mixed] {
        for static_fraction in [0.0, 0.3, 0.5, 0.9] {
            let plan = MotionPlan::plan(kind, 11, 3600.0, static_fraction).unwrap();
            assert_eq!(plan, MotionPlan::plan(kind, 11, 3600.0, static_fraction).unwrap());
            assert_ne!(plan, MotionPlan::plan(kind, 12, 3600.0, static_fraction).unwrap());
            assert!(!plan.segments.is_empty());
            let realised = plan.static_fraction();
            assert!(realised >= static_fraction - 1e-9, "{kind:?}: {realised} < {static_fraction}");
            assert!(realised <= static_fraction + 300.0 / 3600.0, "{kind:?}: {realised} ≫ {static_fraction}");
            let mut end = 0.0;
            for s in &plan.segments {
                assert!(s.start_s >= end - 1e-9, "segments overlap");
                end = s.start_s + s.duration_s;
                let (rate_lo, rate_hi, d_hi) = match s.shape {
                    gyrocomp::sim::motion::SegmentShape::Turn => (1.0, 90.0, 60.0),
                    gyrocomp::sim::motion::SegmentShape::Slow => (0.05, 1.0, 300.0),
                };
                assert!((rate_lo..=rate_hi).contains(&s.peak_dps.abs()));
                assert!(s.duration_s <= d_hi);
                if kind == MotionKind::Turns {
                    assert_eq!(s.shape, gyrocomp::sim::motion::SegmentShape::Turn);
                }
            }
            assert!(end <= 3600.0 + 1e-9);
            // Rendered at 100 Hz, the truth integrates to the planned angles.
            let t: Vec<f64> = (0..360_000).map(|k| k as f64 / 100.0).collect();
            let (truth, moving) = plan.render(&t);
            let angle: f64 = truth.iter().map(|r| r.abs()).sum::<f64>() / 100.0;
            let planned: f64 = plan.segments.iter().map(|s| s.angle_deg().abs()).sum();
            assert!((angle - planned).abs() < 1e-3 * planned + 1e-9, "{angle} vs {planned}");
            let moving_fraction = moving.iter().sum::<f64>() / moving.len() as f64;
            assert!((moving_fraction - (1.0 - realised)).abs() < 1e-3);
            assert!(truth.iter().zip(&moving).all(|(r, m)| *m == 1.0 || *r == 0.0));
        }
    }
    assert!(MotionPlan::plan(MotionKind::Turns, 0, 100.0, 1.5).is_err());
    assert!(MotionPlan::plan(MotionKind::Turns, 0, 100.0, 1.0).unwrap().segments.is_empty());
}
