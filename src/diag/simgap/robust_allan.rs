//! A robust overlapping Allan deviation for fitting the noise terms: a *trimmed* mean of the
//! squared second differences instead of their mean.
//!
//! With the phase x (integrated, mean-removed rate, [`crate::diag::allan::phase_from_rate`]) the
//! overlapping estimator averages d_i² = (x_{i+2m} − 2x_{i+m} + x_i)² (NIST SP 1065 eq. 11). This
//! one averages only the smallest 75 % of them and divides by the mean of the lower 75 % of the χ²₁
//! law, P(χ²₃ ≤ q₀.₇₅(χ²₁))/0.75 = 0.368 524: for Gaussian noise (d_i/σ standard normal) a consistent
//! estimate of the same Allan variance. A transient that makes fewer than a quarter of the
//! differences at a τ large — a warm-up, a few bias jumps, spikes — is trimmed away, so the fitted
//! noise terms describe the noise rather than absorbing the effect (a warm-up fitted as rate random
//! walk would hide itself in the baseline's band). The trimmed mean, unlike the median, does not
//! jump between levels when the data are quantised. Trimmed means as robust scale estimates:
//! Huber & Ronchetti, *Robust Statistics*, 2nd ed., §5.

use super::SimgapError;
use crate::diag::allan::{AllanDeviation, checked_phase};

/// Share of the squared differences kept (the smallest).
pub const KEPT: f64 = 0.75;
/// Mean of the lower [`KEPT`] share of the χ² law with one degree of freedom (scipy:
/// `chi2.cdf(chi2.ppf(0.75, 1), 3) / 0.75`).
pub const CHI2_1_LOWER_MEAN: f64 = 0.368_524_050_983_562_5;

/// Robust (trimmed) overlapping Allan deviation of `rate` at `rate_hz` at the octave factors m = 1, 2, 4, …
/// with at least `min_averages` independent averages (m ≤ N/min_averages). `n` and `m` are
/// filled as by [`crate::diag::allan::oadev`], so the result feeds the same fits.
pub fn robust_oadev(rate: &[f64], rate_hz: f64, min_averages: usize) -> Result<AllanDeviation, SimgapError> {
    let phase = checked_phase(rate, rate_hz)?;
    let mut squares = Vec::with_capacity(phase.len());
    let octaves = std::iter::successors(Some(1usize), |m| Some(m * 2))
        .take_while(|&m| m <= rate.len() / min_averages.max(1) && phase.len() > 2 * m + 1);
    let points = octaves.map(|m| {
        let n = phase.len() - 2 * m;
        squares.clear();
        squares.extend((0..n).map(|i| {
            let d = phase[i + 2 * m] - 2.0 * phase[i + m] + phase[i];
            d * d
        }));
        let kept = ((KEPT * n as f64).round() as usize).clamp(1, n);
        if kept < n {
            squares.select_nth_unstable_by(kept, f64::total_cmp);
        }
        let lower_mean = squares[..kept].iter().sum::<f64>() / kept as f64;
        let avar = lower_mean / CHI2_1_LOWER_MEAN / (2.0 * (m as f64 / rate_hz).powi(2));
        (m, avar.sqrt(), n)
    });
    Ok(AllanDeviation::from_points(rate_hz, rate.len(), points)?)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diag::allan::{Taus, oadev};

    fn white(n: usize, seed: u64) -> Vec<f64> {
        // Box–Muller on an LCG: Gaussian white noise of σ = 1.
        let mut state = seed;
        let mut uniform = move || {
            state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
            ((state >> 11) as f64 + 0.5) / (1u64 << 53) as f64
        };
        (0..n).map(|_| (-2.0 * uniform().ln()).sqrt() * (std::f64::consts::TAU * uniform()).cos()).collect()
    }

    #[test]
    fn agrees_with_the_mean_estimator_on_gaussian_noise() {
        let x = white(200_000, 7);
        let robust = robust_oadev(&x, 10.0, 8).unwrap();
        let plain = oadev(&x, 10.0, &Taus::Factors(robust.m.clone())).unwrap();
        for i in 0..robust.len() {
            let ratio = robust.adev[i] / plain.adev[i];
            assert!(
                (ratio - 1.0).abs() < 0.03 + 0.3 / (robust.n[i] as f64 / robust.m[i] as f64).sqrt(),
                "m {}: {ratio}",
                robust.m[i]
            );
        }
    }

    #[test]
    fn quantised_data_give_the_same_level() {
        let x: Vec<f64> = white(200_000, 9).iter().map(|v| (v / 0.4).round() * 0.4).collect();
        let robust = robust_oadev(&x, 10.0, 8).unwrap();
        let plain = oadev(&x, 10.0, &Taus::Factors(vec![1, 2, 4])).unwrap();
        for i in 0..3 {
            assert!(
                (robust.adev[i] / plain.adev[i] - 1.0).abs() < 0.02,
                "m {}: {} vs {}",
                robust.m[i],
                robust.adev[i],
                plain.adev[i]
            );
        }
    }

    #[test]
    fn ignores_a_transient_that_the_mean_estimator_sees() {
        let mut x = white(100_000, 8);
        for (k, v) in x.iter_mut().enumerate().take(3000) {
            *v += 5.0 * (-(k as f64) / 600.0).exp();
        }
        let robust = robust_oadev(&x, 1.0, 8).unwrap();
        let plain = oadev(&x, 1.0, &Taus::Factors(robust.m.clone())).unwrap();
        // White noise alone gives σ = 1/√τ; the transient inflates the mean estimator at long τ.
        let worst = |a: &[f64]| (0..a.len()).map(|i| a[i] * robust.tau_s[i].sqrt()).fold(0.0, f64::max);
        assert!(worst(&plain.adev) > 2.0, "{}", worst(&plain.adev));
        assert!(worst(&robust.adev) < 1.3, "{}", worst(&robust.adev));
    }
}
