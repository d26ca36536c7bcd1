//! The baseline simulation: the IEEE Std 952 noise terms fitted to the training part.
//!
//! The simulated terms are quantisation Q, angle random walk N, bias instability B and rate random
//! walk K (docs/design.md "Sim-to-real diagnosis"). The fit ([`crate::diag::noise_fit::fit_terms`],
//! weights n/m as `gyrocomp allan`) is made on the robust Allan deviation at octave τ
//! ([`super::robust_allan`]) and also has the rate ramp R, which is *not* simulated: the ramp is a
//! candidate effect, and without the R column a trend or a warm-up in the training part would be
//! fitted as rate random walk and so hidden in the baseline's own band. With the `gauss_markov`
//! effect a sixth column is the Allan variance of a first-order Gauss–Markov process of
//! correlation time T ([`crate::sim::theory::gauss_markov_avar`], exact for the simulator's
//! sampling); T is chosen on a log grid by the smallest weighted residual.
//!
//! The fitted terms become a simulator model: N → `arw_deg_rt_h` = 60·N, B → a flicker bank with a
//! flat floor from the fitted start ([`fit_noise_terms_to`]) to the end of the recording, K →
//! `rrw_deg_h_rt_h` = 216 000·K, Q → white angle noise ([`super::model`]).

use serde::Serialize;

use super::SimgapError;
use super::model::SimModel;
use super::robust_allan::robust_oadev;
use crate::diag::allan::AllanDeviation;
use crate::diag::noise_fit::{TermFit, Weighting, fit_terms};
use crate::sim::config::{ARW_DEG_RT_H_PER_DEG_RT_S, RRW_DEG_H_RT_H_PER_DPS_RT_S};
use crate::sim::terms::flicker_poles;
use crate::sim::theory::gauss_markov_avar;
use crate::sim::{AxisConfig, BiasInstability};

/// Correlation times tried for the Gauss–Markov column.
const GM_GRID: usize = 40;
/// The grid runs from this many samples … (2 until the twenty-third session: a process of two or
/// three samples, which only tilts the white floor as a decimation filter does, then fitted the
/// short-τ Allan points best while the rate random walk took in a process of minutes, and the
/// Gauss–Markov effect was fitted at 0.2 s where the injected one had 217 s; the nested test's
/// grid starts at 30 samples for the same reason, the self-test's processes at 20)
const GM_MIN_SAMPLES: f64 = 10.0;
/// … to the training duration divided by this.
const GM_MAX_FRACTION: f64 = 10.0;

/// IEEE Std 952 terms fitted to a series (units of a deg/s rate and seconds), with an optional
/// Gauss–Markov process.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct NoiseTerms {
    /// Angle quantisation Q, deg.
    pub q: f64,
    /// Angle random walk N, deg/√s.
    pub n: f64,
    /// Bias instability B, deg/s.
    pub b: f64,
    /// Rate random walk K, deg/s/√s.
    pub k: f64,
    /// Rate ramp R, deg/s²: fitted so that a trend does not pass for rate random walk, but not
    /// simulated (the ramp is a candidate effect, not part of the baseline noise model).
    pub r: f64,
    /// Start of the flicker floor, s (it runs to the end of the recording).
    pub floor_from_s: f64,
    /// Gauss–Markov (stationary σ deg/s, correlation time s), when fitted.
    pub gauss_markov: Option<(f64, f64)>,
    /// Weighted RMS relative misfit of the Allan variance.
    pub rms_relative_residual: f64,
}

impl NoiseTerms {
    /// N in the datasheet's deg/√h (the simulator config's `arw_deg_rt_h`).
    pub fn n_deg_rt_h(&self) -> f64 {
        self.n * ARW_DEG_RT_H_PER_DEG_RT_S
    }

    /// B in the datasheet's deg/h (the simulator config's `b_deg_h`).
    pub fn b_deg_h(&self) -> f64 {
        self.b * 3600.0
    }

    /// K in the datasheet's deg/h/√h (the simulator config's `rrw_deg_h_rt_h`): 3600 · 60.
    pub fn k_deg_h_rt_h(&self) -> f64 {
        self.k * RRW_DEG_H_RT_H_PER_DPS_RT_S
    }

    /// The simulator model of these terms for a recording of `total_s` seconds at `rate_hz` with
    /// mean `bias_dps`.
    pub fn to_model(&self, rate_hz: f64, total_s: f64, bias_dps: f64) -> SimModel {
        let axis = AxisConfig {
            bias_dps: Some(bias_dps),
            arw_deg_rt_h: (self.n > 0.0).then_some(self.n_deg_rt_h()),
            bias_instability: (self.b > 0.0).then(|| BiasInstability::Flicker {
                b_deg_h: self.b_deg_h(),
                floor_from_s: self.floor_from_s,
                floor_to_s: total_s.max(2.0 / rate_hz),
            }),
            rrw_deg_h_rt_h: (self.k > 0.0).then_some(self.k_deg_h_rt_h()),
            ..AxisConfig::default()
        };
        SimModel {
            axis,
            angle_noise_q_deg: self.q,
            extra_gauss_markov: self.gauss_markov.filter(|(s, _)| *s > 0.0),
            ..SimModel::default()
        }
    }
}

/// Fits Q, N, B, K, R (and, with `gauss_markov`, a Gauss–Markov process) to the robust Allan
/// deviation of `train` at `rate_hz` ([`super::robust_allan`]), for a model whose flicker floor
/// reaches `floor_to_s` (the recording's length).
pub fn fit_noise_terms(
    train: &[f64],
    rate_hz: f64,
    floor_to_s: f64,
    gauss_markov: bool,
) -> Result<NoiseTerms, SimgapError> {
    fit_noise_terms_to(&robust_oadev(train, rate_hz, MIN_INDEPENDENT_AVERAGES)?, floor_to_s, gauss_markov)
}

/// Fewest independent averages (N/m) of a τ point in the fit: beyond, a single point that the
/// realisation made small has a huge relative residual and would steer the fit.
pub const MIN_INDEPENDENT_AVERAGES: usize = 8;

/// Start of the flicker floor tried: one sample times 3^k, up to this many seconds (a later
/// start would let the flicker floor imitate a Gauss–Markov bump of a few seconds).
const FLOOR_FROM_MAX_S: f64 = 1.0;

/// [`fit_noise_terms`] on a given Allan deviation (octave points of a series of `allan.samples`
/// samples at `allan.rate_hz`; points with fewer than [`MIN_INDEPENDENT_AVERAGES`] are left out).
///
/// Columns: 3/τ² (Q²), 1/τ (N²), the exact Allan variance of the simulator's flicker bank per unit
/// B² with the floor from `f` to `floor_to_s` ([`crate::sim::terms::flicker_poles`]), τ/3 (K²),
/// τ²/2 (R²) and, with `gauss_markov`, a Gauss–Markov process per unit variance. `f` is chosen from
/// one sample × 3^k (up to 1 s) and the Gauss–Markov correlation time from a log grid, by the
/// smallest weighted residual.
pub fn fit_noise_terms_to(
    allan: &AllanDeviation,
    floor_to_s: f64,
    gauss_markov: bool,
) -> Result<NoiseTerms, SimgapError> {
    let allan = &allan.select(|m| m <= allan.samples / MIN_INDEPENDENT_AVERAGES);
    let dt = 1.0 / allan.rate_hz;
    let weights: Vec<f64> =
        allan.n.iter().zip(&allan.m).map(|(&n, &m)| Weighting::IndependentTerms.weight(n, m)).collect();
    let floor_to = floor_to_s.max(2.0 * dt);
    let mut floors = Vec::new();
    let mut from = dt;
    while from <= FLOOR_FROM_MAX_S.max(dt) && from < floor_to {
        let column: Vec<f64> = allan
            .m
            .iter()
            .map(|&m| flicker_poles(1.0, from, floor_to, dt).iter().map(|&(v, c)| gauss_markov_avar(v, c, dt, m)).sum())
            .collect();
        floors.push((from, column));
        from *= 3.0;
    }
    let fit_with = |flicker: &[f64], extra: Option<&[f64]>| {
        fit_terms(
            &allan.tau_s,
            &allan.adev,
            &weights,
            |i| {
                let tau = allan.tau_s[i];
                [3.0 / (tau * tau), 1.0 / tau, flicker[i], tau / 3.0, tau * tau / 2.0, extra.map_or(0.0, |e| e[i])]
            },
            [true, true, true, true, true, extra.is_some()],
        )
    };
    let terms = |fit: &TermFit<6>, from: f64, gm: Option<f64>| NoiseTerms {
        q: fit.squares[0].sqrt(),
        n: fit.squares[1].sqrt(),
        b: fit.squares[2].sqrt(),
        k: fit.squares[3].sqrt(),
        r: fit.squares[4].sqrt(),
        floor_from_s: from,
        gauss_markov: gm.map(|t| (fit.squares[5].sqrt(), t)),
        rms_relative_residual: fit.rms_relative_residual,
    };
    type Best = Option<(TermFit<6>, f64, Option<f64>)>;
    let keep = |fit: TermFit<6>, from: f64, gm: Option<f64>, best: &mut Best| {
        if best.as_ref().is_none_or(|(b, _, _)| fit.weighted_rss < b.weighted_rss) {
            *best = Some((fit, from, gm));
        }
    };
    let mut best: Best = None;
    for (from, column) in &floors {
        keep(fit_with(column, None)?, *from, None, &mut best);
    }
    if gauss_markov {
        let (lo, hi) = (GM_MIN_SAMPLES * dt, (allan.samples as f64 * dt / GM_MAX_FRACTION).max(4.0 * dt));
        for g in 0..GM_GRID {
            let corr = lo * (hi / lo).powf(g as f64 / (GM_GRID - 1) as f64);
            let gm: Vec<f64> = allan.m.iter().map(|&m| gauss_markov_avar(1.0, corr, dt, m)).collect();
            for (from, column) in &floors {
                let fit = fit_with(column, Some(&gm))?;
                if fit.active[5] {
                    keep(fit, *from, Some(corr), &mut best);
                }
            }
        }
    }
    let (fit, from, gm) = best.ok_or(SimgapError::Numerical("no noise-term fit".into()))?;
    Ok(terms(&fit, from, gm))
}

#[cfg(test)]
impl NoiseTerms {
    /// A floor of white noise `n` (deg/s/√Hz), flicker `b` (deg/s) and rate random walk `k`
    /// (deg/s/√s) alone, its flicker from 0.9 s: the truth the tests simulate from.
    pub(crate) fn floor(n: f64, b: f64, k: f64) -> Self {
        Self { q: 0.0, n, b, k, r: 0.0, floor_from_s: 0.9, gauss_markov: None, rms_relative_residual: 0.0 }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diag::simgap::model::simulate;

    /// The fitted terms reproduce a simulated axis they were fitted to (white + flicker + RRW).
    #[test]
    fn recovers_a_simulated_axis() {
        let truth = NoiseTerms::floor(0.04, 0.008, 1e-4);
        let x = simulate(&truth.to_model(10.0, 20_000.0, 0.4), 10.0, 200_000, None, 5).unwrap();
        let fit = fit_noise_terms(&x, 10.0, 20_000.0, false).unwrap();
        assert!((fit.n / truth.n - 1.0).abs() < 0.03, "{fit:?}");
        assert!((fit.b / truth.b - 1.0).abs() < 0.2, "{fit:?}");
        assert!(fit.gauss_markov.is_none());
    }

    /// A strong Gauss–Markov process is found with about its correlation time.
    #[test]
    fn finds_a_gauss_markov_process() {
        let truth = NoiseTerms {
            q: 0.0,
            n: 0.04,
            b: 0.0,
            k: 0.0,
            r: 0.0,
            floor_from_s: 0.1,
            gauss_markov: Some((0.05, 20.0)),
            rms_relative_residual: 0.0,
        };
        let x = simulate(&truth.to_model(10.0, 10_000.0, 0.0), 10.0, 100_000, None, 6).unwrap();
        let fit = fit_noise_terms(&x, 10.0, 10_000.0, true).unwrap();
        let (sigma, corr) = fit.gauss_markov.expect("a Gauss–Markov process");
        assert!((sigma / 0.05 - 1.0).abs() < 0.3 && (corr / 20.0 - 1.0).abs() < 0.5, "{fit:?}");
    }
}
