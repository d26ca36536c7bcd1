//! Each simulated noise term alone is recovered by the Allan-deviation noise fit of `gyrocomp allan`
//! (`diag::allan::oadev` on the octave grid, `diag::noise_fit::fit_allan` with the default
//! independent-terms weights) within 10 %.
//!
//! Why these lengths are enough: the fit weighs each octave τ = m/fs by its number of independent
//! second differences n/m, so the estimate rests on the short-τ points, where a term that is alone
//! dominates as much as anywhere. With N = 2^18 samples the m = 1, 2, 4, 8 points alone hold about
//! 2.6·10⁵, 1.3·10⁵, 6.6·10⁴, 3.3·10⁴ independent differences: relative standard errors of the Allan
//! variance of order 1/√(n/m) ≈ 0.2 … 0.6 %, far inside 10 %. The slowest term, flicker, has
//! correlated differences, so its run is longer (2^20 samples) and its floor spans the whole grid.
//! Every test runs three axes (independent streams) and two seeds, i.e. six independent runs, and
//! all six must pass; the worst relative error is printed (`cargo test -- --nocapture`).

use gyrocomp::diag::allan::{Taus, oadev};
use gyrocomp::diag::noise_fit::{Weighting, fit_allan};
use gyrocomp::diag::noise_model::NoiseModel;
use gyrocomp::sim::{AxisConfig, BiasInstability, Generator, Quantization, QuantizationMode, SimConfig};

fn config(rate_hz: f64, samples: usize, axis: AxisConfig) -> SimConfig {
    SimConfig::with_axis(rate_hz, samples as f64 / rate_hz, axis)
}

/// Fits the six runs (three axes × seeds 1, 2) and returns the fitted models.
fn fits(rate_hz: f64, samples: usize, axis: AxisConfig) -> Vec<NoiseModel> {
    let cfg = config(rate_hz, samples, axis);
    let mut models = Vec::new();
    for seed in [1, 2] {
        let out = Generator::generate(&cfg, seed).unwrap();
        for a in &out.axes {
            let allan = oadev(&a.raw, rate_hz, &Taus::Octave).unwrap();
            models.push(fit_allan(&allan, Weighting::IndependentTerms).unwrap().model);
        }
    }
    models
}

/// Asserts |got/want − 1| < 10 % for every run, and prints the worst.
fn check(name: &str, want: f64, got: impl Iterator<Item = f64>) {
    let mut worst: f64 = 0.0;
    for (run, g) in got.enumerate() {
        let rel = g / want - 1.0;
        assert!(rel.abs() < 0.10, "{name}: run {run}: fitted {g:.4e} vs configured {want:.4e} ({:+.1} %)", rel * 100.0);
        worst = worst.max(rel.abs());
    }
    println!("{name}: configured {want:.4e}, worst of 6 runs {:.2} %", worst * 100.0);
}

#[test]
fn white_noise_alone_gives_n() {
    let n_deg_rt_h = 2.4;
    let models = fits(100.0, 1 << 18, AxisConfig { arw_deg_rt_h: Some(n_deg_rt_h), ..AxisConfig::default() });
    check("N (deg/√s)", n_deg_rt_h / 60.0, models.iter().map(|m| m.n));
}

#[test]
fn flicker_alone_gives_b() {
    // 2^20 samples at 100 Hz (10,486 s): the octave grid runs from 0.01 s to 2621 s; the flat floor
    // is asked for over all of it.
    let b_deg_h = 30.0;
    let axis = AxisConfig {
        bias_instability: Some(BiasInstability::Flicker { b_deg_h, floor_from_s: 0.01, floor_to_s: 3000.0 }),
        ..AxisConfig::default()
    };
    let models = fits(100.0, 1 << 20, axis);
    check("B (deg/s)", b_deg_h / 3600.0, models.iter().map(|m| m.b));
}

#[test]
fn rate_random_walk_alone_gives_k() {
    let k_deg_h_rt_h = 40.0;
    let models = fits(100.0, 1 << 18, AxisConfig { rrw_deg_h_rt_h: Some(k_deg_h_rt_h), ..AxisConfig::default() });
    check("K (deg/s/√s)", k_deg_h_rt_h / 216_000.0, models.iter().map(|m| m.k));
}

#[test]
fn rate_ramp_alone_gives_r() {
    let r_deg_h2 = 100.0;
    let models = fits(10.0, 1 << 16, AxisConfig { ramp_deg_h2: Some(r_deg_h2), ..AxisConfig::default() });
    check("R (deg/s²)", r_deg_h2 / 3600.0 / 3600.0, models.iter().map(|m| m.r));
}

#[test]
fn angle_quantisation_gives_q() {
    // A quantiser needs a moving input: white noise of σ = Δ/2 per sample dithers it (the carried
    // rounding error is then uniform and white) and contributes as much Allan variance as Q at
    // m = 1, half at m = 2, … The fit must separate the τ⁻² and τ⁻¹ slopes: both are checked.
    let (rate_hz, step): (f64, f64) = (100.0, 0.1);
    let sigma = step / 2.0;
    let axis = AxisConfig {
        arw_deg_rt_h: Some(sigma / rate_hz.sqrt() * 60.0),
        quantization: Some(Quantization { step_dps: step, mode: QuantizationMode::Angle }),
        ..AxisConfig::default()
    };
    let q_deg = axis.quantization_q_deg(rate_hz);
    assert!((q_deg - step / (rate_hz * 12f64.sqrt())).abs() < 1e-15);
    let models = fits(rate_hz, 1 << 18, axis);
    check("Q (deg)", q_deg, models.iter().map(|m| m.q));
    check("N of the dither (deg/√s)", sigma / rate_hz.sqrt(), models.iter().map(|m| m.n));
}
