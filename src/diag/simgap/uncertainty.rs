//! The uncertainty of the fitted noise terms, carried into the ensemble (parametric bootstrap,
//! Efron & Tibshirani 1993, ch. 6).
//!
//! The noise terms are estimates from one training part; a simulation with exactly those terms is
//! more certain about the hold-out part than the data allow: N, for one, is known to a few tenths
//! of a per cent, and the short-τ Allan deviation and the high PSD bands of the hold-out are
//! compared at about that precision. So each member j of an ensemble is simulated with its own
//! Q² and N²: the fitted ones plus δ_j, the difference between the terms refitted to a simulated
//! training part of the baseline model and the baseline's own terms (the spread of the refits
//! around the fit stands for the spread of the fit around the truth).
//!
//! B and K are left as fitted: their statistics (mid and long τ, the bias trajectory) scatter
//! more from one realisation to the next than from the terms' uncertainty, and perturbing them too
//! widened the bands so much that slow effects (a warm-up, a temperature dependence) went
//! unnoticed; on recordings without any effect, leaving them out raised no false alarm in 20
//! (measured with the self-test's no-effect control). Perturbing K on every fit was measured
//! again in the thirty-fifth session, for floors with a steep rate random walk: 3 more of 20 such
//! controls right, but 8 other tuning cases lost (3 of them bias steps) and 2 gained
//! (docs/evaluation.md).
//!
//! **K fitted at zero beside a ramp is the exception.** A variance term estimated on the boundary
//! of its range is the least dispersed model the data allow, not a central one, and a bootstrap
//! from it is too narrow (Andrews 2000, "Inconsistency of the bootstrap when a parameter is on the
//! boundary of the parameter space", Econometrica 68). The Allan fit gives K = 0 with R > 0 when
//! its rate ramp R (fitted, not simulated: [`super::baseline`]) takes a random walk's realised
//! trend (the thirty-first session's trace; 6 of 20 steep-walk tuning controls), and an ensemble
//! without any walk then calls that recording's wander a gap. So there each member draws K² from
//! the refit too (K²_j = the refit's K², ≥ 0: the walk that the fit shows on a recording of the
//! baseline itself). Where K > 0, or K = 0 with no trend beside it (the fit saw no walk, and
//! none went elsewhere), nothing changes. Drawing K at every K = 0 widened the bands of fits that
//! had no trend to hide and lost a slow sinusoid and a chirp to them (thirty-sixth session,
//! docs/evaluation.md).

use super::SimgapError;
use super::baseline::{NoiseTerms, fit_noise_terms};
use super::model::{SimModel, member_seed, simulate};
use crate::model::rng::splitmix64;
use crate::sim::config::{ARW_DEG_RT_H_PER_DEG_RT_S, RRW_DEG_H_RT_H_PER_DPS_RT_S};

/// Mixed into the seed so the bootstrap's series differ from the ensemble's.
const BOOTSTRAP_SEED: u64 = 0x0B00_7577;

/// Changes of the squared terms (Q², N², K²) of one member; K²'s is zero unless the fit put K at
/// zero beside a rate ramp (module docs).
pub type Perturbation = [f64; 3];

fn squares(t: &NoiseTerms) -> [f64; 3] {
    [t.q * t.q, t.n * t.n, t.k * t.k]
}

/// One perturbation per member: refits of `members` simulated training parts of `terms`'s model
/// (`n_train` samples at `rate_hz`, flicker floor to `total_s`), minus `terms`; K² only where
/// `terms.k` is zero and the rate ramp `terms.r` is not.
pub fn bootstrap(
    terms: &NoiseTerms,
    rate_hz: f64,
    n_train: usize,
    total_s: f64,
    members: usize,
    seed: u64,
) -> Result<Vec<Perturbation>, SimgapError> {
    let model = terms.to_model(rate_hz, total_s, 0.0);
    let base = squares(terms);
    let walk_on_boundary = terms.k == 0.0 && terms.r > 0.0;
    (0..members)
        .map(|j| {
            let x = simulate(&model, rate_hz, n_train, None, member_seed(splitmix64(seed ^ BOOTSTRAP_SEED), j))?;
            let refit = squares(&fit_noise_terms(&x, rate_hz, total_s, false)?);
            let mut delta: Perturbation = std::array::from_fn(|i| refit[i] - base[i]);
            if !walk_on_boundary {
                delta[2] = 0.0;
            }
            Ok(delta)
        })
        .collect()
}

/// `model` with its Q², N² and K² changed by `delta` (each kept ≥ 0).
pub fn perturbed(model: &SimModel, delta: &Perturbation) -> SimModel {
    let mut m = model.clone();
    let shift = |v: f64, scale: f64, d: f64| ((v / scale).powi(2) + d).max(0.0).sqrt() * scale;
    m.angle_noise_q_deg = shift(m.angle_noise_q_deg, 1.0, delta[0]);
    m.axis.arw_deg_rt_h = Some(shift(m.axis.arw_deg_rt_h.unwrap_or(0.0), ARW_DEG_RT_H_PER_DEG_RT_S, delta[1]));
    // K is drawn only where it was fitted at zero beside a ramp (`bootstrap`); elsewhere the walk
    // is left exactly as fitted, not round-tripped through the square root.
    if delta[2] != 0.0 {
        m.axis.rrw_deg_h_rt_h =
            Some(shift(m.axis.rrw_deg_h_rt_h.unwrap_or(0.0), RRW_DEG_H_RT_H_PER_DPS_RT_S, delta[2]));
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn perturbation_shifts_squares_and_clamps() {
        let terms = NoiseTerms {
            q: 0.0,
            n: 0.04,
            b: 0.008,
            k: 1e-4,
            r: 0.0,
            floor_from_s: 1.0,
            gauss_markov: None,
            rms_relative_residual: 0.0,
        };
        let model = terms.to_model(10.0, 1000.0, 0.0);
        let m = perturbed(&model, &[-1.0, 0.04f64.powi(2) * 0.21, 0.0]);
        // N² grows by 21 %: N by 10 %; Q² cannot go below zero; B and K are left alone.
        assert!((m.axis.arw_deg_rt_h.unwrap() / 60.0 - 0.044).abs() < 1e-12);
        assert_eq!(m.angle_noise_q_deg, 0.0);
        assert_eq!(
            (m.axis.bias_instability.clone(), m.axis.rrw_deg_h_rt_h),
            (model.axis.bias_instability.clone(), model.axis.rrw_deg_h_rt_h)
        );
        let deltas = bootstrap(&terms, 10.0, 20_000, 2000.0, 4, 3).unwrap();
        assert_eq!(deltas.len(), 4);
        // Refits scatter around the fit: the N² changes are small; K, fitted above zero, is kept.
        assert!(deltas.iter().all(|d| d[1].abs() < 0.05 * 0.04f64.powi(2)));
        assert!(deltas.iter().all(|d| d[2] == 0.0));
    }

    #[test]
    fn walk_fitted_at_zero_is_drawn_from_the_refits() {
        let terms = NoiseTerms {
            q: 0.0,
            n: 0.03,
            b: 0.005,
            k: 0.0,
            r: 2e-5,
            floor_from_s: 0.1,
            gauss_markov: None,
            rms_relative_residual: 0.0,
        };
        let model = terms.to_model(10.0, 3000.0, 0.0);
        // A K² change sets the walk from nothing: K = 2e-4 deg/s/√s is 43.2 deg/h/√h.
        let m = perturbed(&model, &[0.0, 0.0, 4e-8]);
        assert!((m.axis.rrw_deg_h_rt_h.unwrap() - 43.2).abs() < 1e-9);
        assert_eq!(m.axis.arw_deg_rt_h, model.axis.arw_deg_rt_h);
        // Every member's K² is a refit's, so never negative, and the refits do not all agree on zero.
        let deltas = bootstrap(&terms, 10.0, 21_000, 3000.0, 8, 5).unwrap();
        assert!(deltas.iter().all(|d| d[2] >= 0.0));
        assert!(deltas.iter().any(|d| d[2] > 0.0));
        // Without a ramp beside it, K = 0 is what the fit saw: no walk is drawn.
        let flat = NoiseTerms { r: 0.0, ..terms };
        assert!(bootstrap(&flat, 10.0, 21_000, 3000.0, 8, 5).unwrap().iter().all(|d| d[2] == 0.0));
    }
}
