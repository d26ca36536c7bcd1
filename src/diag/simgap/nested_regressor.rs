//! The Whittle likelihood gain of a deterministic regressor beside the noise terms, and the χ²
//! judgement of a likelihood ratio: the shared core of the nested tests of a temperature response
//! ([`super::nested_temperature`]) and a warm-up ([`super::nested_warmup`]).
//!
//! **Gain**: Λ = 2(ℓ₀ − min_c ℓ₁(c)) of a series with and without a term c·z(t), each with the
//! noise terms (quantisation, white, flicker, rate random walk; [`super::whittle`]) fitted by
//! maximum likelihood. For fixed noise terms the likelihood is quadratic in c, so c is their
//! generalised least-squares estimate ([`CrossPeriodogram::gls_coefficient`], Hannan 1963,
//! "Regression for time series", in *Time Series Analysis*, ed. Rosenblatt: regression in the
//! frequency domain weights each frequency by the inverse noise spectrum); the profile is found by
//! alternating the two (coordinate descent: ℓ never rises). Both series are detrended alike
//! ([`super::whittle`]), so a linear drift of the bias is not taken for the term.
//!
//! **Judgement** ([`judge_chi_square`]): c is identified under the null, so Λ is asymptotically
//! χ²₁ (Wilks 1938); the null members' mean μ calibrates its scale where the noise terms misfit
//! the recording's noise, never below the textbook: the threshold is max(μ, 1) times the χ²₁
//! quantile at [`NESTED_LEVEL`].

use super::baseline::NoiseTerms;
use super::nested::{NESTED_LEVEL, NestedTest};
use super::whittle::{
    COLUMNS, CrossPeriodogram, NOISE_COLUMNS, WhittleFit, coefficients_of, columns, fit, spectral_density, terms_of,
};
use crate::model::normal::chi2_upper;

/// Alternations of the coefficient and the noise terms at most.
const MAX_ALTERNATIONS: usize = 30;
/// Relative change of ℓ below which the alternation stops.
const TOLERANCE: f64 = 1e-10;

/// What the likelihood gains by a regressor's term (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RegressorGain {
    /// Λ = 2(ℓ₀ − min_c ℓ₁(c)), ≥ 0.
    pub statistic: f64,
    /// The regressor's coefficient c at the maximum (deg/s per unit of the regressor).
    pub coefficient: f64,
    /// The noise terms of the fit without the term (the null's maximum-likelihood estimate).
    pub null_terms: NoiseTerms,
}

/// The gain of a series against a regressor from their cross-periodogram `spectra`, sampled every
/// `dt` s (module docs): the terms of `start` (the flicker floor's start among them) begin the
/// fits; the flicker floor reaches `floor_to_s`.
pub fn regressor_gain(spectra: &CrossPeriodogram, dt: f64, start: &NoiseTerms, floor_to_s: f64) -> RegressorGain {
    let plain = PlainFit::of(spectra, dt, start, floor_to_s);
    regressor_gain_from(spectra, &plain, dt, start)
}

/// The fit without the regressor: the noise terms' Whittle fit of the series alone, and the model
/// columns at its bins. It depends on the series only, so a series tried against many regressors
/// of its length is fitted once.
#[derive(Debug, Clone)]
pub struct PlainFit {
    fit: WhittleFit,
    cols: Vec<[f64; COLUMNS]>,
}

impl PlainFit {
    /// The fit of the series of `spectra` without its regressor (arguments as [`regressor_gain`]).
    pub fn of(spectra: &CrossPeriodogram, dt: f64, start: &NoiseTerms, floor_to_s: f64) -> PlainFit {
        let without = spectra.residual(0.0);
        let cols = columns(&without, dt, start.floor_from_s, floor_to_s);
        let fit = fit(&without, &cols, NOISE_COLUMNS, coefficients_of(start, dt));
        PlainFit { fit, cols }
    }

    /// The noise terms of this fit (the null's maximum-likelihood estimate); `start` gives the
    /// terms the fit does not estimate.
    pub fn null_terms(&self, dt: f64, start: &NoiseTerms) -> NoiseTerms {
        terms_of(&self.fit.coefficients, dt, start)
    }
}

/// [`regressor_gain`] from the series' fit without the regressor, `plain` (of the same series).
pub fn regressor_gain_from(spectra: &CrossPeriodogram, plain: &PlainFit, dt: f64, start: &NoiseTerms) -> RegressorGain {
    let cols = &plain.cols;
    let (mut best, mut coefficient) = (plain.fit, 0.0);
    for _ in 0..MAX_ALTERNATIONS {
        let c = spectra.gls_coefficient(&spectral_density(cols, &best.coefficients));
        let next = fit(&spectra.residual(c), cols, NOISE_COLUMNS, best.coefficients);
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
    let statistic = (2.0 * (plain.fit.neg_log_likelihood - best.neg_log_likelihood)).max(0.0);
    RegressorGain { statistic, coefficient, null_terms: plain.null_terms(dt, start) }
}

/// The decision from the recording's Λ and its null members' (module docs): beyond
/// max(μ, 1)·χ²₁([`NESTED_LEVEL`]), μ the members' mean.
pub fn judge_chi_square(statistic: f64, null: &[f64]) -> NestedTest {
    let null_zero_share = null.iter().filter(|&&s| s <= 0.0).count() as f64 / null.len().max(1) as f64;
    let null_mean = null.iter().sum::<f64>() / null.len().max(1) as f64;
    let threshold = null_mean.max(1.0) * chi2_upper(1.0, 1.0 - NESTED_LEVEL);
    NestedTest { statistic, null_zero_share, null_mean, threshold, passed: statistic > threshold, outranked: false }
}

#[cfg(test)]
mod tests {
    use super::*;

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
}
