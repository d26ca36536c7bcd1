//! Model comparison for a temperature response (issue 16, item 3): does the bias follow the
//! recorded temperature, although the baseline shows no significant gap?
//!
//! A fitted baseline takes a slow bias motion that follows the temperature (a warm-up of the
//! housing, a room's drift, steps of the air conditioning) into its rate random walk K and bias
//! instability B; the ensemble's band then hides it, and the effect's own matched filter (the
//! least-squares slope of the rate on the temperature, [`super::fit_time::temperature_slope`])
//! weighs every frequency alike, so the wander those terms allow at the lowest frequencies drowns
//! it. The question is one of nested models: do the data support a term c·T(t) beside the noise
//! terms, with the noise terms refitted either way?
//!
//! **Statistic**: the Whittle likelihood ratio Λ = 2(ℓ₀ − min_c ℓ₁(c)) of the recording with and
//! without the regressor, each with the noise terms (quantisation, white, flicker, rate random
//! walk; [`super::whittle`]) fitted by maximum likelihood. For fixed noise terms the likelihood is
//! quadratic in c, so c is their generalised least-squares estimate
//! ([`CrossPeriodogram::gls_coefficient`], Hannan 1963, "Regression for time series", in
//! *Time Series Analysis*, ed. Rosenblatt: regression in the frequency domain weights each
//! frequency by the inverse noise spectrum); the profile is found by alternating the two
//! (coordinate descent: ℓ never rises). Where the noise is white the weights are flat and c is
//! the ordinary slope; where a random walk dominates the low frequencies, the temperature's
//! faster changes carry the evidence. Both series are detrended alike, so a linear drift of the
//! bias is not taken for a temperature response. On the whole recording, as the Gauss–Markov
//! test ([`super::nested`]): a test of presence, with its own null at the same length.
//!
//! **Null**: Λ of [`super::nested::NULL_MEMBERS`] series simulated from the fit without the regressor (its
//! maximum-likelihood estimate), each fitted both ways against the recorded temperature: a
//! parametric bootstrap. c is identified under the null, so Λ is asymptotically χ²₁ (Wilks 1938);
//! the members' mean μ calibrates its scale where the noise terms misfit the recording's noise (a
//! Gauss–Markov bank fitted with flicker and random walk), never below the textbook: the
//! threshold is max(μ, 1) times the χ²₁ quantile at [`NESTED_LEVEL`]. Like the other own-null
//! routes, it counts only when the temperature effect ranks first ([`mod@super::diagnose`]).

use super::SimgapError;
use super::baseline::NoiseTerms;
use super::nested::{NESTED_LEVEL, NestedTest, null_statistics};
use super::whittle::{COLUMNS, CrossPeriodogram, coefficients_of, columns, fit, spectral_density, terms_of};
use crate::model::normal::normal_quantile;

/// Mixed into the seed so the null's series differ from the other tests'.
const TEMPERATURE_SEED: u64 = 0x7E3F_C0EF;
/// Alternations of the coefficient and the noise terms at most.
const MAX_ALTERNATIONS: usize = 30;
/// Relative change of ℓ below which the alternation stops.
const TOLERANCE: f64 = 1e-10;
/// The noise columns fitted (quantisation, white, flicker, rate random walk; no Gauss–Markov).
const NOISE_COLUMNS: [bool; COLUMNS] = [true, true, true, true, false];

/// What the likelihood gains by a temperature term (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TemperatureGain {
    /// Λ = 2(ℓ₀ − min_c ℓ₁(c)), ≥ 0.
    pub statistic: f64,
    /// The temperature coefficient c at the maximum, deg/s/°C.
    pub coefficient: f64,
    /// The noise terms of the fit without the term (the null's maximum-likelihood estimate).
    pub null_terms: NoiseTerms,
}

/// The gain of `x` against the regressor `temp_c` (the same length), sampled every `dt` s
/// (module docs): the terms of `start` (the flicker floor's start among them) begin the fits; the
/// flicker floor reaches `floor_to_s`.
pub fn temperature_gain(
    x: &[f64],
    temp_c: &[f64],
    dt: f64,
    start: &NoiseTerms,
    floor_to_s: f64,
) -> Result<TemperatureGain, SimgapError> {
    let spectra = CrossPeriodogram::of(x, temp_c)?;
    let without = spectra.residual(0.0);
    let cols = columns(&without, dt, start.floor_from_s, floor_to_s);
    let plain = fit(&without, &cols, NOISE_COLUMNS, coefficients_of(start, dt));
    let (mut best, mut coefficient) = (plain, 0.0);
    for _ in 0..MAX_ALTERNATIONS {
        let c = spectra.gls_coefficient(&spectral_density(&cols, &best.coefficients));
        let next = fit(&spectra.residual(c), &cols, NOISE_COLUMNS, best.coefficients);
        let change = best.neg_log_likelihood - next.neg_log_likelihood;
        // No gain (or a likelihood that is not a number): the profile is at its minimum.
        if change.is_nan() || change <= 0.0 {
            break;
        }
        best = next;
        coefficient = c;
        if change < TOLERANCE * best.neg_log_likelihood.abs().max(1.0) {
            break;
        }
    }
    let statistic = (2.0 * (plain.neg_log_likelihood - best.neg_log_likelihood)).max(0.0);
    let null_terms = terms_of(&plain.coefficients, dt, start);
    Ok(TemperatureGain { statistic, coefficient, null_terms })
}

/// The test on `x` and its temperature `temp_c` (the whole recording, at `rate_hz`); `baseline`
/// (the Allan-fitted terms of the training part) starts the fits and gives the flicker floor's
/// start, the model's flicker floor reaches `total_s`, `seed` seeds the null (module docs).
pub fn temperature_test(
    x: &[f64],
    temp_c: &[f64],
    rate_hz: f64,
    baseline: &NoiseTerms,
    total_s: f64,
    seed: u64,
) -> Result<NestedTest, SimgapError> {
    let dt = 1.0 / rate_hz;
    let gain = temperature_gain(x, temp_c, dt, baseline, total_s)?;
    tracing::debug!("temperature nested test: c {:.3e} deg/s/C, null terms {:?}", gain.coefficient, gain.null_terms);
    let null = null_statistics(&gain.null_terms, rate_hz, x.len(), total_s, seed ^ TEMPERATURE_SEED, |member| {
        Ok(temperature_gain(member, temp_c, dt, &gain.null_terms, total_s)?.statistic)
    })?;
    tracing::debug!("temperature nested null: {:?}", null.iter().map(|v| format!("{v:.3}")).collect::<Vec<_>>());
    Ok(judge_chi_square(gain.statistic, &null))
}

/// The decision from the recording's Λ and its null members' (module docs): beyond
/// max(μ, 1)·χ²₁(`NESTED_LEVEL`), μ the members' mean.
pub fn judge_chi_square(statistic: f64, null: &[f64]) -> NestedTest {
    let null_zero_share = null.iter().filter(|&&s| s <= 0.0).count() as f64 / null.len().max(1) as f64;
    let null_mean = null.iter().sum::<f64>() / null.len().max(1) as f64;
    let z = normal_quantile(1.0 - 0.5 * (1.0 - NESTED_LEVEL));
    let threshold = null_mean.max(1.0) * z * z;
    NestedTest { statistic, null_zero_share, null_mean, threshold, passed: statistic > threshold, outranked: false }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diag::simgap::baseline::fit_noise_terms;
    use crate::diag::simgap::model::simulate;

    /// The χ²₁ quantile at the 1 % level is 6.635 (tables); a null mean below 1 does not lower
    /// the threshold, one above scales it.
    #[test]
    fn the_threshold_is_the_scaled_chi_square_quantile() {
        let test = judge_chi_square(0.0, &[0.0, 0.5, 1.0]);
        assert!((test.threshold - 6.634_896_6).abs() < 1e-3, "{}", test.threshold);
        assert!((test.null_zero_share - 1.0 / 3.0).abs() < 1e-12);
        let scaled = judge_chi_square(14.0, &[2.0, 2.0]);
        assert!((scaled.threshold - 2.0 * 6.634_896_6).abs() < 2e-3);
        assert!(scaled.passed);
        assert!(!judge_chi_square(13.0, &[2.0, 2.0]).passed);
    }

    /// A temperature like a lab's (a warm-up of 4 °C over 20 min, a slow swing, two steps of the
    /// air conditioning) on white noise and a strong rate random walk (0.03 deg/s/√Hz, 4e-4
    /// deg/s/√s: the independent generator's flat floor with 10× its random walk; 4,000 s at
    /// 10 Hz). With a bias of 0.025 deg/s/°C (the Allan-fitted K rises by 1.6–8× with it) the test
    /// finds it (Λ 19–38 against thresholds of 10.5–16) and puts c within 50 %; with none it stays
    /// quiet (Λ ≤ 3.6 against ≥ 10.6); on every seed.
    #[test]
    fn finds_an_absorbed_temperature_response_and_no_missing_one() {
        let (fs, len) = (10.0, 40_000);
        let total = len as f64 / fs;
        let floor = NoiseTerms {
            q: 0.0,
            n: 0.03,
            b: 0.0,
            k: 4e-4,
            r: 0.0,
            floor_from_s: 0.9,
            gauss_markov: None,
            rms_relative_residual: 0.0,
        };
        let model = floor.to_model(fs, total, 0.0);
        let temp: Vec<f64> = (0..len)
            .map(|i| {
                let t = i as f64 / fs;
                let step = |at: f64, size: f64| size / (1.0 + (-(t - at) / 60.0).exp());
                22.0 + 4.0 * (1.0 - (-t / 1200.0).exp())
                    + (std::f64::consts::TAU * t / 3000.0).sin()
                    + step(1500.0, 1.2)
                    + step(2900.0, -1.0)
            })
            .collect();
        let slope = 0.025;
        for seed in 1..=3 {
            let noise = simulate(&model, fs, len, None, seed).unwrap();
            for present in [false, true] {
                let x: Vec<f64> = if present {
                    noise.iter().zip(&temp).map(|(v, t)| v + slope * (t - 22.0)).collect()
                } else {
                    noise.clone()
                };
                let terms = fit_noise_terms(&x, fs, total, false).unwrap();
                let test = temperature_test(&x, &temp, fs, &terms, total, seed).unwrap();
                assert_eq!(test.passed, present, "seed {seed}, response present {present}: {test:?}");
                if present {
                    let c = temperature_gain(&x, &temp, 1.0 / fs, &terms, total).unwrap().coefficient;
                    assert!((c / slope - 1.0).abs() < 0.5, "seed {seed}: c {c} vs {slope}");
                }
            }
        }
    }
}
