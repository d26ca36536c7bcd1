//! The noise terms of a recording once the fitted deterministic parts of effects are removed,
//! with a bootstrap correction of the bias that removal causes.
//!
//! Subtracting a *fitted* effect (a warm-up with free amplitude and time constant, a slope, steps
//! at detected places) also removes the part of the noise that happens to look like the effect, so
//! the Allan variance of the cleaned series underestimates the noise, most at long τ, and a model
//! refitted to it is too quiet. The correction measures that loss on simulations of the refitted
//! model (parametric bootstrap, Efron & Tibshirani 1993, ch. 10):
//!
//! 1. fit the noise terms θ₀ to the (robust, [`super::robust_allan`]) Allan variance of the
//!    cleaned series;
//! 2. for each of [`CORRECTION_MEMBERS`] seeded series n_j of θ₀: add the fitted deterministic
//!    part d, fit the same effects again on n_j + d and subtract what they find; the loss is
//!    b_j(τ) = σ²(n_j) − σ²(cleaned n_j + d);
//! 3. refit the noise terms to σ²(cleaned) + mean_j b_j (each point at least the cleaned value).

use super::SimgapError;
use super::baseline::{MIN_INDEPENDENT_AVERAGES, NoiseTerms, fit_noise_terms_to};
use super::effects::{TrainingData, fit_effect};
use super::model::{member_seed, simulate};
use super::params::{Fitted, FittedEffect};
use super::robust_allan::robust_oadev;
use crate::diag::allan::AllanDeviation;
use crate::model::rng::splitmix64;

/// Simulated series of the bias correction.
pub const CORRECTION_MEMBERS: usize = 8;
/// Mixed into the seed so the correction's series differ from the ensemble's.
const CORRECTION_SEED: u64 = 0xB1A5_C0DE;

/// Noise terms of `train` with the training parts of `effects` removed (module docs); the model
/// covers `total_s` seconds (the flicker floor's span), `seed` seeds the correction.
pub fn refit_noise_terms(
    train: &TrainingData<'_>,
    effects: &[&FittedEffect],
    gauss_markov: bool,
    total_s: f64,
    seed: u64,
) -> Result<NoiseTerms, SimgapError> {
    let fs = train.rate_hz;
    let parts: Vec<&Vec<f64>> = effects.iter().filter_map(|e| e.training_part.as_ref()).collect();
    let mut deterministic = vec![0.0; train.x.len()];
    for part in &parts {
        for (d, p) in deterministic.iter_mut().zip(part.iter()) {
            *d += p;
        }
    }
    let cleaned: Vec<f64> = train.x.iter().zip(&deterministic).map(|(x, d)| x - d).collect();
    let allan = robust_oadev(&cleaned, fs, MIN_INDEPENDENT_AVERAGES)?;
    let first = fit_noise_terms_to(&allan, total_s, gauss_markov)?;
    if parts.is_empty() {
        return Ok(first);
    }
    let model = first.to_model(fs, total_s, 0.0);
    let kinds: Vec<_> = effects.iter().filter(|e| e.training_part.is_some()).map(|e| e.params.kind()).collect();
    let mut loss = vec![0.0; allan.len()];
    for j in 0..CORRECTION_MEMBERS {
        let noise =
            simulate(&model, fs, train.x.len(), train.temp_c, member_seed(splitmix64(seed ^ CORRECTION_SEED), j))?;
        let member: Vec<f64> = noise.iter().zip(&deterministic).map(|(n, d)| n + d).collect();
        let data = TrainingData { x: &member, ..*train };
        let mut again = member.clone();
        for &kind in &kinds {
            if let Fitted::Found(FittedEffect { training_part: Some(part), .. }) = fit_effect(kind, &data) {
                for (a, p) in again.iter_mut().zip(&part) {
                    *a -= p;
                }
            }
        }
        let a_noise = robust_oadev(&noise, fs, MIN_INDEPENDENT_AVERAGES)?;
        let a_clean = robust_oadev(&again, fs, MIN_INDEPENDENT_AVERAGES)?;
        for (i, l) in loss.iter_mut().enumerate() {
            *l += (a_noise.adev[i].powi(2) - a_clean.adev[i].powi(2)) / CORRECTION_MEMBERS as f64;
        }
    }
    let corrected = AllanDeviation {
        adev: allan.adev.iter().zip(&loss).map(|(d, l)| (d * d + l.max(0.0)).sqrt()).collect(),
        ..allan
    };
    let relative: Vec<String> = loss.iter().zip(&allan.adev).map(|(l, d)| format!("{:.3}", l / (d * d))).collect();
    tracing::debug!("refit bias correction, share of the cleaned Allan variance per octave: {}", relative.join(" "));
    fit_noise_terms_to(&corrected, total_s, gauss_markov)
}
