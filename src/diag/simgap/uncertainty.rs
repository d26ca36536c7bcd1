//! The uncertainty of the fitted noise terms, carried into the ensemble (parametric bootstrap,
//! Efron & Tibshirani 1993, ch. 6).
//!
//! The noise terms are estimates from one training part; a simulation with exactly those terms is
//! more certain about the hold-out part than the data allow (its N, for one, is known to a few
//! tenths of a per cent, and the short-τ Allan deviation of the hold-out is compared at that
//! precision). So each member j of an ensemble is simulated with its own terms: the fitted
//! squares (Q², N², B², K²) plus δ_j, where δ_j is the difference between the terms refitted to a
//! simulated training part of the baseline model and the baseline's own terms. The spread of the
//! refits around the fit stands for the spread of the fit around the truth.

use super::SimgapError;
use super::baseline::{NoiseTerms, fit_noise_terms};
use super::ensemble::member_seed;
use super::model::{SimModel, simulate};
use crate::sim::BiasInstability;
use crate::sim::rng::splitmix64;

/// Mixed into the seed so the bootstrap's series differ from the ensemble's.
const BOOTSTRAP_SEED: u64 = 0x0B00_7577;

/// Changes of the squared terms (Q², N², B², K²) of one member.
pub type Perturbation = [f64; 4];

fn squares(t: &NoiseTerms) -> [f64; 4] {
    [t.q * t.q, t.n * t.n, t.b * t.b, t.k * t.k]
}

/// One perturbation per member: refits of `members` simulated training parts of `terms`'s model
/// (`n_train` samples at `rate_hz`, flicker floor to `total_s`), minus `terms`.
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
    (0..members)
        .map(|j| {
            let x = simulate(&model, rate_hz, n_train, None, member_seed(splitmix64(seed ^ BOOTSTRAP_SEED), j))?;
            let refit = squares(&fit_noise_terms(&x, rate_hz, total_s, false)?);
            Ok(std::array::from_fn(|i| refit[i] - base[i]))
        })
        .collect()
}

/// `model` with its squared noise terms changed by `delta` (each kept ≥ 0).
pub fn perturbed(model: &SimModel, delta: &Perturbation) -> SimModel {
    let mut m = model.clone();
    let shift = |v: f64, scale: f64, d: f64| ((v / scale).powi(2) + d).max(0.0).sqrt() * scale;
    m.angle_noise_q_deg = shift(m.angle_noise_q_deg, 1.0, delta[0]);
    m.axis.arw_deg_rt_h = Some(shift(m.axis.arw_deg_rt_h.unwrap_or(0.0), 60.0, delta[1]));
    if let Some(BiasInstability::Flicker { b_deg_h, .. }) = &mut m.axis.bias_instability {
        *b_deg_h = shift(*b_deg_h, 3600.0, delta[2]);
    }
    m.axis.rrw_deg_h_rt_h = Some(shift(m.axis.rrw_deg_h_rt_h.unwrap_or(0.0), 216_000.0, delta[3]));
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
        let m = perturbed(&model, &[0.0, 0.04f64.powi(2) * 0.21, -1.0, 0.0]);
        // N² grows by 21 %: N by 10 %.
        assert!((m.axis.arw_deg_rt_h.unwrap() / 60.0 - 0.044).abs() < 1e-12);
        // B² cannot go below zero.
        assert!(matches!(m.axis.bias_instability, Some(BiasInstability::Flicker { b_deg_h, .. }) if b_deg_h == 0.0));
        let deltas = bootstrap(&terms, 10.0, 20_000, 2000.0, 4, 3).unwrap();
        assert_eq!(deltas.len(), 4);
        // Refits scatter around the fit: the N² changes are small.
        assert!(deltas.iter().all(|d| d[1].abs() < 0.05 * 0.04f64.powi(2)));
    }
}
