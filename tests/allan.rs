//! Integration tests of the overlapping Allan deviation (against allantools goldens) and of the
//! IEEE Std 952-1997 Annex C noise-term fit.

mod common;

use common::floats;
use gyrocomp::diag::allan::{AllanDeviation, Taus, oadev};
use gyrocomp::diag::noise_fit::{NoiseFit, Weighting, fit_allan, fit_noise_model};
use gyrocomp::diag::noise_model::NoiseModel;
use gyrocomp::model::rng::SplitMix64;
use serde_json::Value;

fn golden() -> Value {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/goldens/allan.json");
    let text = std::fs::read_to_string(path).expect("tests/goldens/allan.json (run tools/goldens/allan_goldens.py)");
    serde_json::from_str(&text).expect("valid golden JSON")
}

fn rel_err(a: f64, b: f64) -> f64 {
    if a == b { 0.0 } else { (a - b).abs() / a.abs().max(b.abs()) }
}

/// Compares one allantools result with ours; returns (points, bit-identical points).
fn check_against(name: &str, expected: &Value, got: &AllanDeviation) -> (usize, usize) {
    let tau = floats(&expected["tau_s"]);
    let adev = floats(&expected["adev"]);
    let ns: Vec<usize> = expected["ns"].as_array().unwrap().iter().map(|v| v.as_u64().unwrap() as usize).collect();
    // The exact allantools values, as IEEE-754 bit patterns (JSON decimals may parse 1 ulp off).
    let bits: Vec<u64> = expected["adev_bits"].as_array().unwrap().iter().map(|v| v.as_u64().unwrap()).collect();
    assert_eq!(got.len(), tau.len(), "{name}: number of taus");
    assert_eq!(got.n, ns, "{name}: number of terms");
    let mut identical = 0;
    for i in 0..tau.len() {
        assert!(rel_err(got.tau_s[i], tau[i]) <= 1e-15, "{name}: tau[{i}] {} vs {}", got.tau_s[i], tau[i]);
        let e = rel_err(got.adev[i], adev[i]);
        assert!(e <= 1e-9, "{name}: adev at tau {} = {} vs allantools {} (rel {e:e})", tau[i], got.adev[i], adev[i]);
        identical += usize::from(got.adev[i].to_bits() == bits[i]);
    }
    (tau.len(), identical)
}

#[test]
fn oadev_matches_allantools_goldens() {
    let g = golden();
    let (mut points, mut identical, mut all_checked) = (0, 0, 0);
    for case in g["cases"].as_array().unwrap() {
        let name = case["name"].as_str().unwrap();
        let rate = case["rate_hz"].as_f64().unwrap();
        let x = floats(&case["x"]);
        let octave = oadev(&x, rate, &Taus::Octave).unwrap();
        let (p, s) = check_against(&format!("{name} octave"), &case["octave"], &octave);
        (points, identical) = (points + p, identical + s);
        if !case["all"].is_null() {
            let all = oadev(&x, rate, &Taus::All).unwrap();
            let (p, s) = check_against(&format!("{name} all"), &case["all"], &all);
            (points, identical) = (points + p, identical + s);
            all_checked += 1;
        }
    }
    assert!(all_checked >= 1, "the goldens must include at least one taus=\"all\" case");
    eprintln!("oadev vs allantools: {points} points within 1e-9, {identical} bit-identical");
    // Stronger than the 1e-9 contract: the same operations in the same order (NumPy's pairwise
    // sums included) give the same bits. If this alone fails after regenerating the goldens with
    // another NumPy, check whether its summation order changed.
    assert_eq!(identical, points, "not bit-identical to allantools");
}

/// Octave grid 0.01 s … ≈ 10⁴ s (100 Hz, m = 1 … 2²⁰) with the default weights of N = 2.5·10⁶
/// samples (n/m, n = N + 1 − 2m).
fn octave_grid() -> (Vec<f64>, Vec<f64>) {
    let samples = 2_500_000usize;
    let m: Vec<usize> = (0..=20).map(|k| 1usize << k).collect();
    let w = m.iter().map(|&m| Weighting::IndependentTerms.weight(samples + 1 - 2 * m, m)).collect();
    (m.iter().map(|&m| m as f64 / 100.0).collect(), w)
}

fn fit_exact(truth: &NoiseModel) -> NoiseFit {
    let (tau, w) = octave_grid();
    let adev: Vec<f64> = tau.iter().map(|&t| truth.allan_deviation(t)).collect();
    fit_noise_model(&tau, &adev, &w).unwrap()
}

#[test]
fn fit_recovers_all_five_coefficients_of_an_exact_curve() {
    let truth = NoiseModel { q: 1e-3, n: 1e-2, b: 5e-3, k: 1e-4, r: 1e-6 };
    let fit = fit_exact(&truth);
    let got = fit.model;
    for (name, t, g) in [
        ("Q", truth.q, got.q),
        ("N", truth.n, got.n),
        ("B", truth.b, got.b),
        ("K", truth.k, got.k),
        ("R", truth.r, got.r),
    ] {
        assert!(rel_err(t, g) <= 1e-6, "{name}: fitted {g} vs true {t}");
    }
    assert_eq!(fit.active, [true; 5]);
    assert!(fit.rms_relative_residual < 1e-10);
}

#[test]
fn fit_returns_zero_for_absent_terms() {
    let truth = NoiseModel { q: 0.0, n: 1e-2, b: 0.0, k: 1e-4, r: 0.0 };
    let fit = fit_exact(&truth);
    assert_eq!(fit.active, [false, true, false, true, false]);
    assert_eq!((fit.model.q, fit.model.b, fit.model.r), (0.0, 0.0, 0.0));
    assert!(rel_err(fit.model.n, truth.n) <= 1e-6 && rel_err(fit.model.k, truth.k) <= 1e-6, "{:?}", fit.model);

    let truth = NoiseModel { q: 2e-3, n: 0.0, b: 3e-3, k: 0.0, r: 1e-6 };
    let fit = fit_exact(&truth);
    assert_eq!((fit.model.n, fit.model.k), (0.0, 0.0));
    for (t, g) in [(truth.q, fit.model.q), (truth.b, fit.model.b), (truth.r, fit.model.r)] {
        assert!(rel_err(t, g) <= 1e-6, "{:?}", fit.model);
    }
}

/// Uniform in (0, 1] from the library's SplitMix64: 53 random bits, never 0 (safe for ln).
fn uniform_nonzero(rng: &mut SplitMix64) -> f64 {
    ((rng.next_u64() >> 11) + 1) as f64 / (1u64 << 53) as f64
}

/// Two independent standard normal values (Box–Muller).
fn normal_pair(rng: &mut SplitMix64) -> (f64, f64) {
    let (u1, u2) = (uniform_nonzero(rng), uniform_nonzero(rng));
    let r = (-2.0 * u1.ln()).sqrt();
    let a = std::f64::consts::TAU * u2;
    (r * a.cos(), r * a.sin())
}

fn white_noise(seed: u64, len: usize, std: f64) -> Vec<f64> {
    let mut rng = SplitMix64::new(seed);
    let mut x = Vec::with_capacity(len + 1);
    while x.len() < len {
        let (a, b) = normal_pair(&mut rng);
        x.extend([std * a, std * b]);
    }
    x.truncate(len);
    x
}

#[test]
fn fit_recovers_white_noise_arw() {
    // White rate noise of std σ at f_s has σ²(τ) = σ²τ₀/τ exactly in expectation, so N = σ/√f_s.
    // With 2¹⁸ samples the short-τ points (which pin N down) have ≈ 2.6·10⁵ terms each and a
    // relative standard error well under 1 %; 5 % is a wide margin, checked over several seeds.
    let (fs, std) = (100.0f64, 0.1f64);
    let truth_n = std / fs.sqrt();
    for seed in [1, 2, 3] {
        let x = white_noise(seed, 1 << 18, std);
        let allan = oadev(&x, fs, &Taus::Octave).unwrap();
        let fit = fit_allan(&allan, Weighting::default()).unwrap();
        let e = rel_err(fit.model.n, truth_n);
        assert!(e <= 0.05, "seed {seed}: N = {} vs {truth_n} ({:.2} %), fit {:?}", fit.model.n, 100.0 * e, fit.model);
    }
}

/// Evidence for the default fit weighting (`cargo test --test allan -- --nocapture` prints it):
/// worst ARW error over 20 seeds for weights n/m and n, at several lengths. The default (n/m)
/// must stay within 5 % from 2^16 samples on and beat weighting by n.
#[test]
fn compare_weightings_on_white_noise() {
    let (fs, std) = (100.0f64, 0.1f64);
    let truth_n = std / fs.sqrt();
    for len in [1usize << 14, 1 << 16, 1 << 18, 1 << 20] {
        let mut worst = [0.0f64; 2];
        for seed in 1..=20 {
            let x = white_noise(seed, len, std);
            let allan = oadev(&x, fs, &Taus::Octave).unwrap();
            for (k, wt) in [Weighting::IndependentTerms, Weighting::Terms].into_iter().enumerate() {
                let fit = fit_allan(&allan, wt).unwrap();
                worst[k] = worst[k].max(rel_err(fit.model.n, truth_n));
            }
        }
        eprintln!("len {len}: worst N error over 20 seeds: n/m {:.3} %, n {:.3} %", 100.0 * worst[0], 100.0 * worst[1]);
        if len >= 1 << 16 {
            assert!(worst[0] < 0.05, "n/m weighting: worst N error {:.3} % at {len}", 100.0 * worst[0]);
            assert!(worst[0] < worst[1], "n/m weighting no better than n at {len}");
        }
    }
}

#[test]
fn octave_points_of_all_equal_octave() {
    let x = white_noise(7, 3000, 0.2);
    let all = oadev(&x, 10.0, &Taus::All).unwrap();
    let oct = oadev(&x, 10.0, &Taus::Octave).unwrap();
    assert_eq!(all.octave_points(), oct);
}
