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
//! **Statistic**: the Whittle likelihood ratio Λ of the recording with and without the term,
//! the noise terms refitted either way ([`super::nested_regressor`]). Where the noise is white the
//! weights are flat and c is the ordinary slope; where a random walk dominates the low
//! frequencies, the temperature's faster changes carry the evidence. On the whole recording, as
//! the Gauss–Markov test ([`super::nested`]): a test of presence, with its own null at the same
//! length.
//!
//! **Null**: Λ of [`super::nested::NULL_MEMBERS`] series simulated from the fit without the
//! regressor (its maximum-likelihood estimate), each fitted both ways against the recorded
//! temperature: a parametric bootstrap, judged against the scaled χ²₁ quantile
//! ([`judge_chi_square`]; the members' mean calibrates the scale where a Gauss–Markov bank is
//! fitted with flicker and random walk). Like the other own-null routes, it counts only when the
//! temperature effect ranks first ([`mod@super::diagnose`]).

use super::SimgapError;
use super::baseline::NoiseTerms;
use super::nested::{NestedTest, bootstrap};
use super::nested_regressor::{RegressorGain, judge_chi_square, regressor_gain};
use super::whittle::CrossPeriodogram;

/// Mixed into the seed so the null's series differ from the other tests'.
const TEMPERATURE_SEED: u64 = 0x7E3F_C0EF;

/// The gain of `x` against the regressor `temp_c` (the same length), sampled every `dt` s
/// (module docs): the terms of `start` (the flicker floor's start among them) begin the fits; the
/// flicker floor reaches `floor_to_s`.
pub fn temperature_gain(
    x: &[f64],
    temp_c: &[f64],
    dt: f64,
    start: &NoiseTerms,
    floor_to_s: f64,
) -> Result<RegressorGain, SimgapError> {
    Ok(regressor_gain(&CrossPeriodogram::of(x, temp_c)?, dt, start, floor_to_s))
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
    let gain = |series: &[f64], start: &NoiseTerms| {
        temperature_gain(series, temp_c, dt, start, total_s).map(|g| (g.statistic, g.null_terms))
    };
    let (statistic, null) = bootstrap("temperature", x, rate_hz, baseline, total_s, seed ^ TEMPERATURE_SEED, gain)?;
    Ok(judge_chi_square(statistic, &null))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diag::simgap::baseline::fit_noise_terms;
    use crate::diag::simgap::model::simulate;

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
        let floor = NoiseTerms::floor(0.03, 0.0, 4e-4);
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
