//! Model comparison for a ramp (issue 16, item 3): does the bias drift linearly, beyond what the
//! noise terms' slow wander allows, although the baseline shows no significant gap?
//!
//! A fitted baseline takes a slow linear drift into its rate ramp R (not simulated) or its rate
//! random walk K, and the ramp's own matched filter ([`super::fit_time::ramp_change`], the
//! least-squares line of the 1 s means on the training part) weighs every block alike, although
//! the flicker and random-walk wander makes neighbouring blocks move together.
//!
//! **Statistic**: the generalised least-squares slope of the recording's block means on time,
//! with an unknown constant beside it (Aitken 1935), in units of its standard error:
//! z = β̂/se(β̂), β̂ = [(XᵀC⁻¹X)⁻¹XᵀC⁻¹y]₁, X = [1, t]. C is the covariance of the block means
//! under the noise terms (white, flicker bank, rate random walk, angle quantisation;
//! [`block_covariance`]) fitted by the Whittle likelihood to the *detrended* recording
//! ([`super::whittle`]): a trend leaves that fit untouched, where the Allan fit would take part of
//! it for K or R. On the whole recording, like the other nested tests: a test of presence.
//!
//! **The random walk at its upper bound.** A rate random walk below the white noise at every
//! frequency the recording resolves is fitted as K = 0, and yet over the whole recording it
//! draws a line as large as the white noise's: with K = 0 in C, the slope's standard error is
//! too small. On 40 tuning controls (2680–2719, white noise and the generator's K) the test at the
//! maximum-likelihood K passed on three, two of them named a ramp. So C takes K at the upper end of
//! its profile-likelihood interval (2Δℓ = 3.84, the other terms refitted at each K;
//! [`walk_upper_bound`]): the largest random walk the spectrum does not rule out. On those
//! controls the bound is 2.5× the generator's K; it costs the weakest ramps on floors whose slow
//! Gauss–Markov bank the IEEE terms can only take as a random walk.
//!
//! **Null**: z of [`super::nested::NULL_MEMBERS`] series simulated from those terms, each refitted
//! and tested the same way (a parametric bootstrap: it carries the uncertainty of the fitted C
//! and the approximations of the block covariance into the threshold). The ramp is present when
//! z² exceeds max(μ, 1) times the χ²₁ quantile at [`super::nested::NESTED_LEVEL`], μ the members'
//! mean z² ([`super::nested_regressor::judge_chi_square`]). Like the other nested tests it
//! counts only when the ramp ranks first.

use nalgebra::{DMatrix, DVector};

use super::SimgapError;
use super::baseline::NoiseTerms;
use super::nested::{NestedTest, bootstrap};
use super::nested_regressor::judge_chi_square;
use super::whittle::{
    COLUMNS, NOISE_COLUMNS, Periodogram, WhittleFit, coefficients_of, columns, fit, fit_holding, spectral_density,
    terms_of,
};
use crate::sim::terms::flicker_poles;

/// Mixed into the seed so the null's series differ from the other tests'.
const RAMP_SEED: u64 = 0x5A3B_0D21;
/// Block means at most: a line is a slow signal, so little is lost by averaging, and the
/// covariance's Cholesky factor stays cheap for every null member.
const MAX_BLOCKS: usize = 300;
/// The rate random walk's column ([`super::whittle::columns`]).
const WALK_COLUMN: usize = 3;
/// 2Δℓ of the rate random walk's upper bound: the χ²₁ quantile at 95 % (the upper end of a
/// two-sided 95 % profile-likelihood interval).
pub const WALK_BOUND_CHI2: f64 = 3.841_458_820_694_124;
/// Factor of each step up of K² in the search for its bound.
pub const WALK_STEP: f64 = 1.5;
/// Steps at most (1.5⁶⁰ ≈ 4·10¹⁰).
pub const WALK_STEPS: usize = 60;

/// The ramp's standard score z on `x` (sampled every `dt` s) and the Whittle-fitted terms behind
/// it, K at its upper bound (module docs); `start` begins the fit and gives the flicker floor's start, which reaches
/// `floor_to_s`.
pub fn ramp_score(x: &[f64], dt: f64, start: &NoiseTerms, floor_to_s: f64) -> Result<(f64, NoiseTerms), SimgapError> {
    let periodogram = Periodogram::of(x)?;
    let cols = columns(&periodogram, dt, start.floor_from_s, floor_to_s);
    let whittle = fit(&periodogram, &cols, NOISE_COLUMNS, coefficients_of(start, dt));
    let bounded = walk_upper_bound(&periodogram, &cols, &whittle);
    let terms = terms_of(&bounded.coefficients, dt, start);
    Ok((gls_slope_z(x, dt, &terms, floor_to_s)?, terms))
}

/// The noise fit with the rate random walk at the upper end of its profile-likelihood interval
/// (2Δℓ ≤ [`WALK_BOUND_CHI2`]; module docs): K² is stepped up by a factor of [`WALK_STEP`]
/// from the maximum-likelihood value (or, at zero, from where the walk makes 1 % of the fitted
/// spectrum at the lowest frequency), the other terms refitted at each step.
pub fn walk_upper_bound(periodogram: &Periodogram, cols: &[[f64; COLUMNS]], best: &WhittleFit) -> WhittleFit {
    let lowest = spectral_density(&cols[..1], &best.coefficients)[0];
    let reference = 0.01 * lowest / cols[0][WALK_COLUMN];
    let mut walk = best.coefficients[WALK_COLUMN].max(reference);
    let mut bound = *best;
    for _ in 0..WALK_STEPS {
        let held = fit_holding(periodogram, cols, NOISE_COLUMNS, bound.coefficients, Some((WALK_COLUMN, walk)));
        if 2.0 * (held.neg_log_likelihood - best.neg_log_likelihood) > WALK_BOUND_CHI2 {
            break;
        }
        if held.coefficients[WALK_COLUMN] > bound.coefficients[WALK_COLUMN] {
            bound = held;
        }
        walk *= WALK_STEP;
    }
    bound
}

/// The generalised least-squares slope of the block means of `x` on time, with a constant beside
/// it, in units of its standard error, under the covariance of `terms` (module docs).
pub fn gls_slope_z(x: &[f64], dt: f64, terms: &NoiseTerms, floor_to_s: f64) -> Result<f64, SimgapError> {
    let block = x.len().div_ceil(MAX_BLOCKS).max((1.0 / dt).round() as usize).max(1);
    let blocks = x.len() / block;
    if blocks < 8 {
        return Err(SimgapError::TooShort { samples: x.len(), need: 8 * block });
    }
    let y = DVector::from_iterator(
        blocks,
        (0..blocks).map(|i| x[i * block..(i + 1) * block].iter().sum::<f64>() / block as f64),
    );
    let c = block_covariance(terms, dt, floor_to_s, block, blocks);
    let chol = c.cholesky().ok_or_else(|| SimgapError::Numerical("block covariance not positive definite".into()))?;
    let x_design = DMatrix::from_fn(blocks, 2, |i, j| if j == 0 { 1.0 } else { (i as f64 + 0.5) / blocks as f64 });
    let cx = chol.solve(&x_design);
    let normal = x_design.transpose() * &cx;
    let rhs = cx.transpose() * y;
    let inverse = normal.try_inverse().ok_or_else(|| SimgapError::Numerical("GLS normal matrix singular".into()))?;
    let beta = &inverse * rhs;
    let se = inverse[(1, 1)].max(0.0).sqrt();
    Ok(if se > 0.0 { beta[1] / se } else { 0.0 })
}

/// Covariance of the means of `blocks` consecutive blocks of `block` samples (every `dt` s) under
/// `terms` (the flicker floor to `floor_to_s`): white noise N²/dt/L; the flicker bank's
/// first-order Gauss–Markov processes (exact for point samples); the rate random walk from the
/// first sample (K²·dt per sample); the angle quantisation as differenced white angle noise
/// (the block mean telescopes to the difference of two angle errors).
pub fn block_covariance(terms: &NoiseTerms, dt: f64, floor_to_s: f64, block: usize, blocks: usize) -> DMatrix<f64> {
    let l = block as f64;
    let white = terms.n * terms.n / dt / l;
    let rrw = terms.k * terms.k * dt;
    let quant = (terms.q / dt).powi(2) / (l * l);
    let poles: Vec<(f64, f64)> =
        if terms.b > 0.0 { flicker_poles(terms.b, terms.floor_from_s, floor_to_s, dt) } else { Vec::new() };
    // The stationary part depends on the distance between the blocks only (Toeplitz).
    let stationary: Vec<f64> = (0..blocks)
        .map(|d| {
            let own = match d {
                0 => white + 2.0 * quant,
                1 => -quant,
                _ => 0.0,
            };
            own + poles
                .iter()
                .map(|&(variance, corr_s)| variance * gauss_markov_block((-dt / corr_s).exp(), block, d))
                .sum::<f64>()
        })
        .collect();
    DMatrix::from_fn(blocks, blocks, |i, j| {
        let lo = i.min(j) as f64;
        let walk = if i == j { lo * l + (l + 1.0) * (2.0 * l + 1.0) / (6.0 * l) } else { lo * l + (l + 1.0) / 2.0 };
        stationary[i.abs_diff(j)] + rrw * walk
    })
}

/// Covariance of two block means `d` blocks apart of a unit-variance AR(1) with coefficient `phi`.
fn gauss_markov_block(phi: f64, block: usize, d: usize) -> f64 {
    let l = block as f64;
    if phi <= 0.0 {
        return if d == 0 { 1.0 / l } else { 0.0 };
    }
    if d == 0 {
        // (L + 2 Σ_{h=1}^{L−1} (L − h) φ^h) / L², in closed form.
        let one = 1.0 - phi;
        let sum = phi * (l * one - (1.0 - phi.powf(l))) / (one * one);
        (l + 2.0 * sum) / (l * l)
    } else {
        let geo = (1.0 - phi.powf(l)) / (1.0 - phi);
        let lag = (d as f64 * l - (l - 1.0)).max(1.0);
        geo * geo * phi.powf(lag) / (l * l)
    }
}

/// The test on `x` (the whole recording, at `rate_hz`); `baseline` starts the fits and gives the
/// flicker floor's start, the model's flicker floor reaches `total_s`, `seed` seeds the null
/// (module docs).
pub fn ramp_test(
    x: &[f64],
    rate_hz: f64,
    baseline: &NoiseTerms,
    total_s: f64,
    seed: u64,
) -> Result<NestedTest, SimgapError> {
    let dt = 1.0 / rate_hz;
    let gain = |series: &[f64], start: &NoiseTerms| {
        ramp_score(series, dt, start, total_s).map(|(z, terms)| (z.powi(2), terms))
    };
    let (statistic, null) = bootstrap("ramp", x, rate_hz, baseline, total_s, seed ^ RAMP_SEED, gain)?;
    Ok(judge_chi_square(statistic, &null))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diag::simgap::baseline::fit_noise_terms;
    use crate::diag::simgap::model::simulate;

    /// Series simulated from known terms score z ~ N(0, 1) under those terms' covariance.
    #[test]
    fn the_slope_score_is_standard_under_its_own_terms() {
        let (fs, len) = (10.0, 30_000);
        let total = len as f64 / fs;
        for (b, k) in [(0.0, 4e-4), (0.003, 0.0), (0.003, 4e-5)] {
            let terms = NoiseTerms::floor(0.03, b, k);
            let model = terms.to_model(fs, total, 0.0);
            let z: Vec<f64> = (0..64)
                .map(|seed| {
                    gls_slope_z(&simulate(&model, fs, len, None, seed).unwrap(), 1.0 / fs, &terms, total).unwrap()
                })
                .collect();
            let ms = z.iter().map(|v| v * v).sum::<f64>() / z.len() as f64;
            eprintln!("b {b} k {k}: mean z² {ms:.3}");
            assert!((0.6..1.5).contains(&ms), "b {b} k {k}: mean z² {ms}");
        }
    }

    /// White noise with a random walk too weak for the spectrum to show (the generator's flat
    /// floor, 4,000 s at 10 Hz): the walk's bound is above zero and above the true K on every
    /// seed, within the interval (2Δℓ ≤ 3.84), and one step further up leaves it.
    #[test]
    fn the_random_walk_bound_covers_a_walk_the_spectrum_does_not_show() {
        let (fs, len) = (10.0, 40_000);
        let dt = 1.0 / fs;
        let truth = NoiseTerms::floor(0.03, 0.0, 4e-5);
        let model = truth.to_model(fs, len as f64 * dt, 0.0);
        for seed in 1..=3 {
            let x = simulate(&model, fs, len, None, seed).unwrap();
            let p = Periodogram::of(&x).unwrap();
            let cols = columns(&p, dt, truth.floor_from_s, len as f64 * dt);
            let best = fit(&p, &cols, NOISE_COLUMNS, coefficients_of(&truth, dt));
            let bound = walk_upper_bound(&p, &cols, &best);
            let (k_best, k_bound) = ((best.coefficients[3] / dt).sqrt(), (bound.coefficients[3] / dt).sqrt());
            assert!(k_bound > truth.k && k_bound >= k_best, "seed {seed}: K {k_best:e} → bound {k_bound:e}");
            assert!(2.0 * (bound.neg_log_likelihood - best.neg_log_likelihood) <= WALK_BOUND_CHI2);
            let beyond =
                fit_holding(&p, &cols, NOISE_COLUMNS, bound.coefficients, Some((3, WALK_STEP * bound.coefficients[3])));
            assert!(2.0 * (beyond.neg_log_likelihood - best.neg_log_likelihood) > WALK_BOUND_CHI2, "seed {seed}");
        }
    }

    /// White noise, flicker and a rate random walk (the independent generator's nominal levels,
    /// 3,000 s at 10 Hz): a drift of 0.07 deg/s over the recording is found on every seed (z² 13
    /// and 26 against 6.6, with K at its upper bound), none is not (z² ≤ 0.08), and a warm-up of
    /// 0.05 deg/s settling over 300 s is not taken for a ramp (z² ≤ 3.0).
    #[test]
    fn finds_a_ramp_and_no_missing_one() {
        let (fs, len) = (10.0, 30_000);
        let total = len as f64 / fs;
        let floor = NoiseTerms::floor(0.03, 0.003, 4e-5);
        let model = floor.to_model(fs, total, 0.0);
        let ramp = |k: usize| 0.07 * k as f64 / len as f64;
        let warmup = |k: usize| 0.05 * (-(k as f64) / fs / 300.0).exp();
        for seed in 1..=2 {
            let noise = simulate(&model, fs, len, None, seed).unwrap();
            for (name, shape, present) in [
                ("none", None, false),
                ("ramp", Some(&ramp as &dyn Fn(usize) -> f64), true),
                ("warm-up", Some(&warmup), false),
            ] {
                let x: Vec<f64> = noise.iter().enumerate().map(|(k, v)| v + shape.map_or(0.0, |f| f(k))).collect();
                let terms = fit_noise_terms(&x, fs, total, false).unwrap();
                let test = ramp_test(&x, fs, &terms, total, seed).unwrap();
                assert_eq!(test.passed, present, "seed {seed}, {name}: {test:?}");
            }
        }
    }
}
