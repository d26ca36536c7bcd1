//! The multi-scale tracker's noise model, measured on the unit (`super::multiscale`): the
//! winsorised Allan variance of the committed static samples *concatenated across gaps* (an
//! [`AllanCascade`] whose blocks are never broken), and its non-negative least-squares fit to
//! white noise, a random-walk bias and Gauss–Markov processes at fixed correlation times
//! ([`BANK_TAUS_S`]).
//!
//! Why across gaps: between two motions a static stretch lasts about a minute, so the
//! calibration's per-stretch levels end at a few tens of seconds, while the drift's slow terms
//! (the rate random walk of a flat floor, Gauss–Markov parts of minutes) show only at hundreds of
//! seconds. The concatenated series has them; a block that straddles a motion carries the bias'
//! change over it, which is drift too (the filter holds its prediction across the motion).
//!
//! The fit ([`fit_terms`], relative residuals weighted by each level's number of differences)
//! uses the exact Allan variance of each sampled term: white noise R/m, a sampled random walk
//! ([`random_walk_avar`]) and AR(1) processes ([`gauss_markov_avar_sampled`]); its coefficients
//! are the filter's per-sample variances directly. Prototype: `tools/eval/oracle_tracker.py
//! --fitted --refit-s`.

use crate::diag::noise_fit::fit_terms;
use crate::sim::theory::{gauss_markov_avar_sampled, random_walk_avar};
use crate::stream::allan_cascade::{AllanCascade, LEVELS};
use crate::stream::calibration::walk_for_memory;
use crate::stream::warm::{BANK_GM, BankModel};

/// Correlation times of the Gauss–Markov states, s: the time scales between a turn and a long
/// run (the prototype's bank).
pub const BANK_TAUS_S: [f64; BANK_GM] = [3.0, 10.0, 30.0, 100.0, 300.0, 1000.0];
/// Differences a level needs to enter the fit (at least eight blocks, as in the prototype).
pub const MIN_FIT_DIFFERENCES: u64 = 7;
/// Columns of the fit: white, random walk, the Gauss–Markov bank.
const COLUMNS: usize = 2 + BANK_GM;

/// The model fitted to `allan` at sample period `dt` s, its memory no shorter than
/// `min_memory` samples (below); `None` when fewer than three levels have
/// [`MIN_FIT_DIFFERENCES`] differences or the fit fails (the caller keeps its model).
///
/// The shortest memory: the bank must not follow what changes faster than the scalar tracker
/// would (the caller passes the calibration's τ\*, itself no shorter than the static detector's
/// reach): on a curve flat over decades (bias instability, as on the real ADIS16405) a fit
/// that is free at every time scale puts Gauss–Markov variance at the shortest ones, and with
/// the detector's leaks in the committed samples the tracker then follows slow rotations.
/// Gauss–Markov states with a correlation time under `min_memory` are left out of the fit, and
/// every state's increment variance per sample (q_b; σᵢ²(1 − φᵢ²)) is capped at 3R/m² with
/// m = `min_memory`, the random walk whose Allan minimum lies at m samples.
pub fn fit_bank(allan: &AllanCascade, dt: f64, min_memory: f64) -> Option<BankModel> {
    let mut tau = [0.0; LEVELS];
    let mut adev = [0.0; LEVELS];
    let mut weight = [0.0; LEVELS];
    let mut blocks = [0usize; LEVELS];
    let mut n = 0;
    for j in 0..LEVELS {
        if let Some((v, count)) = allan.level(j).filter(|&(v, c)| c >= MIN_FIT_DIFFERENCES && v > 0.0) {
            blocks[n] = 1 << j;
            tau[n] = blocks[n] as f64 * dt;
            adev[n] = v.sqrt();
            weight[n] = count as f64;
            n += 1;
        }
    }
    if n < 3 {
        return None;
    }
    let basis = |i: usize| -> [f64; COLUMNS] {
        let m = blocks[i];
        let mut row = [0.0; COLUMNS];
        row[0] = 1.0 / m as f64;
        row[1] = random_walk_avar(1.0, m);
        for (g, &tc) in BANK_TAUS_S.iter().enumerate() {
            row[2 + g] = gauss_markov_avar_sampled(1.0, tc, dt, m);
        }
        row
    };
    let mut allowed = [true; COLUMNS];
    for (g, &tc) in BANK_TAUS_S.iter().enumerate() {
        allowed[2 + g] = tc / dt >= min_memory;
    }
    let c = fit_terms(&tau[..n], &adev[..n], &weight[..n], basis, allowed).ok()?.squares;
    if c[0] <= 0.0 {
        // No white term: the curve's short end is unexplained (a stuck or quantised input).
        return None;
    }
    let cap = walk_for_memory(c[0], min_memory);
    let markov = std::array::from_fn(|g| {
        let increment = -(-2.0 * dt / BANK_TAUS_S[g]).exp_m1(); // 1 − φ²
        c[2 + g].min(cap / increment)
    });
    Some(BankModel { white: c[0], walk: c[1].min(cap), markov, fitted: true })
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_distr::{Distribution, StandardNormal};
    use rand_xoshiro::Xoshiro256PlusPlus;

    /// White noise (σ 0.1 deg/s) plus a Gauss–Markov process of 0.05 deg/s at 30 s, 10 Hz,
    /// 20,000 s: the fit finds the white variance within 3 % and puts the Gauss–Markov variance
    /// at and next to 30 s (its total within a factor of two), with no random walk to speak of;
    /// with a memory of at least 40 s the 3, 10 and 30 s states stay silent.
    #[test]
    fn a_gauss_markov_floor_is_recovered() {
        let dt = 0.1;
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(3);
        let phi = (-dt / 30.0f64).exp();
        let drive = 0.05 * (1.0 - phi * phi).sqrt();
        let mut g = 0.0;
        let mut allan = AllanCascade::new();
        for _ in 0..200_000 {
            let (e, w): (f64, f64) = (StandardNormal.sample(&mut rng), StandardNormal.sample(&mut rng));
            g = phi * g + drive * w;
            allan.push(g + 0.1 * e);
        }
        let model = fit_bank(&allan, dt, 1.0).expect("a fit");
        assert!((model.white / 0.01 - 1.0).abs() < 0.03, "{model:?}");
        let near: f64 = model.markov[1..4].iter().sum();
        assert!(near > 0.5 * 0.0025 && near < 2.0 * 0.0025, "{model:?}");
        // A random walk that over 1000 s would reach the Gauss–Markov σ at most.
        assert!(model.walk * 10_000.0 < 0.0025, "{model:?}");
        let slow = fit_bank(&allan, dt, 400.0).expect("a fit");
        assert_eq!(&slow.markov[..3], &[0.0; 3], "{slow:?}");
        let cap = 3.0 * slow.white / 400.0f64.powi(2);
        assert!(slow.walk <= cap, "{slow:?}");
    }

    #[test]
    fn too_little_data_fits_nothing() {
        let mut allan = AllanCascade::new();
        (0..20).for_each(|i| {
            allan.push(i as f64 * 0.01);
        });
        assert_eq!(fit_bank(&allan, 0.1, 1.0), None);
    }
}
