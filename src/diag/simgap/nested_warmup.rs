//! Model comparison for a warm-up (issue 16, item 3): does the bias start with an exponential
//! settling, although the baseline shows no significant gap?
//!
//! A fitted baseline takes a warm-up into its rate random walk K (the Allan deviation of an
//! exponential rises at long τ like a random walk's), and the warm-up's own matched filter (the
//! least-squares amplitude of the best exponential of the 1 s means, [`super::fit_time::warmup_fit`],
//! against the noise refitted without it) weighs every second alike, so the slow wander that K
//! allows drowns it: on tuning case 2500 (oracle z 12) that filter stood 2.0 σ out.
//!
//! **Statistic**: the Whittle likelihood ratio of the recording with and without a term
//! A·e^(−t/T), the noise terms refitted either way (the temperature test's profile,
//! [`super::nested_regressor::regressor_gain`]: A by generalised least squares in the frequency
//! domain, so the faster early part of the decay, where the random walk has little power, carries
//! the evidence), maximised over [`GRID`] time constants log-spaced over the warm-up fit's range
//! ([`super::fit_time::WARMUP_RANGE`]) of the recording. Series and regressor are detrended alike, so a ramp is not taken for a warm-up.
//! On the whole recording, like the other nested tests: a test of presence.
//!
//! **Null**: Λ of [`super::nested::NULL_MEMBERS`] series simulated from the fit without the term,
//! each tested the same way (parametric bootstrap). T is not identified under the null, so Λ is a
//! maximum over correlated χ²₁ ordinates, not χ²₁ (Davies 1987, "Hypothesis testing when a nuisance
//! parameter is present only under the alternative", Biometrika 74); its upper tail is taken as
//! exponential with the members' mean, as the Gauss–Markov test's ([`super::nested::judge_gain`]).
//! Like the other nested tests it counts only when the warm-up ranks first.

use super::SimgapError;
use super::baseline::NoiseTerms;
use super::fit_time::WARMUP_RANGE;
use super::nested::{NestedTest, bootstrap, judge_gain};
use super::nested_regressor::{PlainFit, regressor_gain_from};
use super::whittle::{CrossPeriodogram, SpectralTransform};

/// Mixed into the seed so the null's series differ from the other tests'.
const WARMUP_SEED: u64 = 0x3A7B_11C5;
/// Time constants tried.
pub const GRID: usize = 10;

/// The transforms of the regressors e^(−t/T) of the grid for a series of `len` samples.
fn regressors(len: usize, rate_hz: f64) -> Result<Vec<SpectralTransform>, SimgapError> {
    let duration = len as f64 / rate_hz;
    let (lo, hi) = (duration * WARMUP_RANGE.0, duration * WARMUP_RANGE.1);
    (0..GRID)
        .map(|g| {
            let tc = lo * (hi / lo).powf(g as f64 / (GRID - 1) as f64);
            SpectralTransform::of(&(0..len).map(|k| (-(k as f64) / rate_hz / tc).exp()).collect::<Vec<_>>())
        })
        .collect()
}

/// The largest likelihood ratio Λ of `x` (sampled every `dt` s) over the grid's `regressors`, and
/// the noise terms of the fit without the term (module docs); `start` begins the fits and gives
/// the flicker floor's start, which reaches `floor_to_s`.
pub fn warmup_gain(
    x: &[f64],
    regressors: &[SpectralTransform],
    dt: f64,
    start: &NoiseTerms,
    floor_to_s: f64,
) -> Result<(f64, NoiseTerms), SimgapError> {
    let tx = SpectralTransform::of(x)?;
    let spectra = regressors.iter().map(|z| CrossPeriodogram::of_transforms(&tx, z)).collect::<Result<Vec<_>, _>>()?;
    let Some(first) = spectra.first() else { return Ok((0.0, *start)) };
    // The fit without the term depends on the series only: one serves every time constant.
    let plain = PlainFit::of(first, dt, start, floor_to_s);
    let best = spectra.iter().map(|s| regressor_gain_from(s, &plain, dt, start).statistic).fold(0.0, f64::max);
    Ok((best, plain.null_terms(dt, start)))
}

/// The test on `x` (the whole recording, at `rate_hz`); `baseline` starts the fits and gives the
/// flicker floor's start, the model's flicker floor reaches `total_s`, `seed` seeds the null
/// (module docs).
pub fn warmup_test(
    x: &[f64],
    rate_hz: f64,
    baseline: &NoiseTerms,
    total_s: f64,
    seed: u64,
) -> Result<NestedTest, SimgapError> {
    let dt = 1.0 / rate_hz;
    let z = regressors(x.len(), rate_hz)?;
    let gain = |series: &[f64], start: &NoiseTerms| warmup_gain(series, &z, dt, start, total_s);
    let (statistic, null) = bootstrap("warmup", x, rate_hz, baseline, total_s, seed ^ WARMUP_SEED, gain)?;
    Ok(judge_gain(statistic, &null))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diag::simgap::baseline::fit_noise_terms;
    use crate::diag::simgap::model::simulate;

    /// White noise and a strong rate random walk (the independent generator's flat floor with 10×
    /// its random walk; 3,000 s at 10 Hz), where the Allan-fitted K takes a warm-up in: with
    /// 0.1 deg/s settling over 300 s the test finds it, with none it stays quiet, on every seed;
    /// a ramp of the same size is not taken for a warm-up (the series is detrended).
    #[test]
    fn finds_an_absorbed_warmup_and_no_missing_one() {
        let (fs, len) = (10.0, 30_000);
        let total = len as f64 / fs;
        let floor = NoiseTerms::floor(0.03, 0.0, 4e-4);
        let model = floor.to_model(fs, total, 0.0);
        let warmup = |k: usize| 0.1 * (-(k as f64) / fs / 300.0).exp();
        let ramp = |k: usize| 0.1 * k as f64 / len as f64;
        for seed in 1..=2 {
            let noise = simulate(&model, fs, len, None, seed).unwrap();
            for (name, shape, present) in [
                ("none", None, false),
                ("warm-up", Some(&warmup as &dyn Fn(usize) -> f64), true),
                ("ramp", Some(&ramp), false),
            ] {
                let x: Vec<f64> = noise.iter().enumerate().map(|(k, v)| v + shape.map_or(0.0, |f| f(k))).collect();
                let terms = fit_noise_terms(&x, fs, total, false).unwrap();
                let test = warmup_test(&x, fs, &terms, total, seed).unwrap();
                assert_eq!(test.passed, present, "seed {seed}, {name}: {test:?}");
            }
        }
    }
}
