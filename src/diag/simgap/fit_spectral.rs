//! Fit of a sinusoidal disturbance: the strongest spectral line of the training part.
//!
//! 1. The least-squares line is removed and the series Hann-windowed and zero-padded to a power
//!    of two; its periodogram |X\[k]|² ([`crate::diag::fft`]).
//! 2. The line is the bin with the largest ratio to the median of the 32 bins around it, among
//!    frequencies with at least four cycles in the part (the slow wander of the bias is red, so the
//!    largest *power* would always be the lowest bin).
//! 3. Its frequency is refined by a golden-section search of the windowed DFT power within ±1 bin,
//!    then amplitude and phase come from least squares on sin/cos at that frequency.

use std::f64::consts::TAU;

use super::params::{EffectParams, Fitted, FittedEffect};
use super::robust::{linear_fit, median};
use crate::diag::fft::Fft;

/// Bins on each side in the background median.
const BACKGROUND_HALF: usize = 16;
/// Fewest cycles within the part for a candidate line.
const MIN_CYCLES: f64 = 4.0;
/// Golden-section iterations (each narrows the bracket by 0.618).
const REFINE_STEPS: usize = 40;
/// Largest FFT length (a longer part is searched on its first 2^21 samples).
const MAX_FFT: usize = 1 << 21;

/// Power of the DFT of `w·r` at `freq_hz` (also the Whittle periodogram's lowest ordinates,
/// [`super::whittle`]).
pub(super) fn dft_power(r: &[f64], window: &[f64], freq_hz: f64, rate_hz: f64) -> f64 {
    let step = TAU * freq_hz / rate_hz;
    let (mut c, mut s) = (0.0, 0.0);
    for (k, (v, w)) in r.iter().zip(window).enumerate() {
        let a = step * k as f64;
        c += v * w * a.cos();
        s += v * w * a.sin();
    }
    c * c + s * s
}

/// The strongest line of a series: steps 1–2 of the module docs.
#[derive(Debug, Clone, PartialEq)]
pub struct LineSearch {
    /// The series less its least-squares line.
    pub residual: Vec<f64>,
    /// The Hann window over it.
    pub window: Vec<f64>,
    /// FFT length.
    pub nfft: usize,
    /// Bin of the strongest line.
    pub bin: usize,
    /// Its power over the median of the 32 bins around it.
    pub ratio: f64,
}

impl LineSearch {
    /// Searches `x` sampled at `rate_hz`; `None` when it is too short for a periodogram.
    pub fn of(x: &[f64], rate_hz: f64) -> Option<LineSearch> {
        let n = x.len();
        let t: Vec<f64> = (0..n).map(|k| k as f64 / rate_hz).collect();
        let (slope, offset) = linear_fit(&t, x);
        let residual: Vec<f64> = x.iter().zip(&t).map(|(v, s)| v - offset - slope * s).collect();
        let window: Vec<f64> = (0..n).map(|j| 0.5 - 0.5 * (TAU * j as f64 / n as f64).cos()).collect();
        let nfft = n.next_power_of_two().min(MAX_FFT);
        let fft = Fft::new(nfft)?;
        let mut re = vec![0.0; nfft];
        let mut im = vec![0.0; nfft];
        for j in 0..n.min(nfft) {
            re[j] = residual[j] * window[j];
        }
        fft.forward(&mut re, &mut im);
        let power: Vec<f64> = (0..=nfft / 2).map(|k| re[k] * re[k] + im[k] * im[k]).collect();
        let k_min = ((MIN_CYCLES * nfft as f64 / n as f64).ceil() as usize).max(BACKGROUND_HALF + 1);
        let k_max = (nfft / 2).saturating_sub(BACKGROUND_HALF + 1);
        if k_min >= k_max {
            return None;
        }
        let mut best = (0.0, k_min);
        let mut around = Vec::with_capacity(2 * BACKGROUND_HALF);
        for k in k_min..=k_max {
            around.clear();
            around.extend_from_slice(&power[k - BACKGROUND_HALF..k]);
            around.extend_from_slice(&power[k + 1..=k + BACKGROUND_HALF]);
            let background = median(&around);
            if background > 0.0 && power[k] / background > best.0 {
                best = (power[k] / background, k);
            }
        }
        Some(LineSearch { residual, window, nfft, bin: best.1, ratio: best.0 })
    }
}

/// Fits the strongest spectral line of `x` (module docs).
pub fn fit_sinusoid(x: &[f64], rate_hz: f64) -> Fitted {
    let Some(LineSearch { residual: r, window, nfft, bin, .. }) = LineSearch::of(x, rate_hz) else {
        return Fitted::NotApplicable("training part too short for a periodogram".into());
    };
    let t: Vec<f64> = (0..x.len()).map(|k| k as f64 / rate_hz).collect();
    let best = (0.0, bin);
    let df = rate_hz / nfft as f64;
    let (mut a, mut b) = ((best.1 as f64 - 1.0) * df, (best.1 as f64 + 1.0) * df);
    let golden = 0.5 * (5f64.sqrt() - 1.0);
    let (mut c, mut d) = (b - golden * (b - a), a + golden * (b - a));
    let (mut pc, mut pd) = (dft_power(&r, &window, c, rate_hz), dft_power(&r, &window, d, rate_hz));
    for _ in 0..REFINE_STEPS {
        if pc > pd {
            b = d;
            (d, pd) = (c, pc);
            c = b - golden * (b - a);
            pc = dft_power(&r, &window, c, rate_hz);
        } else {
            a = c;
            (c, pc) = (d, pd);
            d = a + golden * (b - a);
            pd = dft_power(&r, &window, d, rate_hz);
        }
    }
    let freq = 0.5 * (a + b);
    // Least squares r ≈ p·sin(ωt) + q·cos(ωt) (2×2 normal equations).
    let omega = TAU * freq;
    let (mut ss, mut cc, mut sc, mut rs, mut rc) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for (v, s) in r.iter().zip(&t) {
        let (sn, cs) = (omega * s).sin_cos();
        ss += sn * sn;
        cc += cs * cs;
        sc += sn * cs;
        rs += v * sn;
        rc += v * cs;
    }
    let det = ss * cc - sc * sc;
    if det.abs() <= 1e-12 * ss * cc {
        return Fitted::NotApplicable("degenerate sinusoid fit".into());
    }
    let p = (rs * cc - rc * sc) / det;
    let q = (rc * ss - rs * sc) / det;
    let amplitude = p.hypot(q);
    let phase = q.atan2(p);
    let part = t.iter().map(|s| amplitude * (omega * s + phase).sin()).collect();
    Fitted::Found(FittedEffect {
        params: EffectParams::Sinusoid { amplitude_dps: amplitude, frequency_hz: freq, phase_deg: phase.to_degrees() },
        training_part: Some(part),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_a_line_under_noise_and_drift() {
        let fs = 10.0;
        let mut state = 99u64;
        let x: Vec<f64> = (0..20_000)
            .map(|k| {
                state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
                let u = (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
                let t = k as f64 / fs;
                0.4 + 1e-5 * t + 0.3 * u + 0.02 * (TAU * 0.123 * t + 1.0).sin()
            })
            .collect();
        let Fitted::Found(e) = fit_sinusoid(&x, fs) else { panic!() };
        let EffectParams::Sinusoid { amplitude_dps, frequency_hz, phase_deg } = e.params else { panic!() };
        assert!((frequency_hz - 0.123).abs() < 1e-4, "{frequency_hz}");
        assert!((amplitude_dps - 0.02).abs() < 0.003, "{amplitude_dps}");
        assert!((phase_deg - 1f64.to_degrees()).abs() < 10.0, "{phase_deg}");
    }
}
