//! Welch power spectral density of a rate series (Welch 1967, IEEE Trans. Audio Electroacoust.
//! 15(2)), computed as `scipy.signal.welch(x, fs, window="hann", nperseg=L, noverlap=L/2,
//! detrend="constant", scaling="density")` does:
//!
//! - segments of L samples starting every L/2 samples, ⌊(N − L/2)/(L/2)⌋ of them;
//! - each segment's mean removed, then multiplied by the periodic Hann window
//!   w\[j] = ½ − ½·cos(2πj/L);
//! - P\[k] = |FFT(w·x)\[k]|² / (f_s·Σw²), doubled for 0 < k < L/2 (one-sided density), averaged over
//!   the segments.
//!
//! The unit is (input unit)²/Hz, e.g. (deg/s)²/Hz; Σ_k P\[k]·f_s/L ≈ the variance of the series.
//! `tests/goldens/psd.json` (tools/goldens/psd_goldens.py) holds scipy's result.

use std::f64::consts::TAU;

use crate::diag::fft::{Complex64, Fft};

/// A one-sided power spectral density on the bins k = 0 … L/2.
#[derive(Debug, Clone, PartialEq)]
pub struct Psd {
    /// Frequency of each bin, Hz (k·f_s/L).
    pub freq_hz: Vec<f64>,
    /// Density of each bin, (input unit)²/Hz.
    pub density: Vec<f64>,
    /// Number of segments averaged.
    pub segments: usize,
}

/// Why the PSD could not be computed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PsdError {
    /// The segment length is not a power of two of at least 4.
    #[error("segment length {0} is not a power of two ≥ 4")]
    BadSegment(usize),
    /// The series is shorter than one segment.
    #[error("{samples} samples are fewer than one segment of {segment}")]
    TooShort {
        /// Samples given.
        samples: usize,
        /// Segment length.
        segment: usize,
    },
    /// The sample rate is not positive and finite.
    #[error("sample rate {0} Hz is not positive and finite")]
    BadRate(f64),
}

/// A planned Welch estimator for one segment length (window, FFT and buffers allocated once).
#[derive(Debug, Clone)]
pub struct Welch {
    fft: Fft,
    window: Vec<f64>,
    window_power: f64,
    /// The segment being transformed.
    buffer: Vec<Complex64>,
}

impl Welch {
    /// Plans segments of `segment` samples (a power of two ≥ 4).
    pub fn new(segment: usize) -> Result<Self, PsdError> {
        let fft = Fft::new(segment).filter(|_| segment >= 4).ok_or(PsdError::BadSegment(segment))?;
        let window: Vec<f64> = (0..segment).map(|j| 0.5 - 0.5 * (TAU * j as f64 / segment as f64).cos()).collect();
        let window_power = window.iter().map(|w| w * w).sum();
        Ok(Self { fft, window, window_power, buffer: vec![Complex64::new(0.0, 0.0); segment] })
    }

    /// The segment length L.
    pub fn segment(&self) -> usize {
        self.window.len()
    }

    /// Welch PSD of `x` sampled at `rate_hz` (module docs).
    pub fn estimate(&mut self, x: &[f64], rate_hz: f64) -> Result<Psd, PsdError> {
        if !(rate_hz.is_finite() && rate_hz > 0.0) {
            return Err(PsdError::BadRate(rate_hz));
        }
        let l = self.segment();
        if x.len() < l {
            return Err(PsdError::TooShort { samples: x.len(), segment: l });
        }
        let step = l / 2;
        let segments = (x.len() - step) / step;
        let half = l / 2;
        let mut density = vec![0.0; half + 1];
        for s in 0..segments {
            let seg = &x[s * step..s * step + l];
            let mean = seg.iter().sum::<f64>() / l as f64;
            for ((z, &v), &w) in self.buffer.iter_mut().zip(seg).zip(&self.window) {
                *z = Complex64::new((v - mean) * w, 0.0);
            }
            self.fft.process(&mut self.buffer);
            for (d, z) in density.iter_mut().zip(&self.buffer) {
                *d += z.re * z.re + z.im * z.im;
            }
        }
        let scale = 1.0 / (rate_hz * self.window_power * segments as f64);
        for (k, d) in density.iter_mut().enumerate() {
            *d *= if k == 0 || k == half { scale } else { 2.0 * scale };
        }
        let freq_hz = (0..=half).map(|k| k as f64 * rate_hz / l as f64).collect();
        Ok(Psd { freq_hz, density, segments })
    }
}

/// Welch PSD of `x` with segments of `segment` samples (a power of two ≥ 4); see the module docs.
pub fn welch(x: &[f64], rate_hz: f64, segment: usize) -> Result<Psd, PsdError> {
    Welch::new(segment)?.estimate(x, rate_hz)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn white_noise_density_integrates_to_its_variance() {
        // A deterministic pseudo-random sequence (LCG), uniform on [−0.5, 0.5): variance 1/12.
        let mut state = 12345u64;
        let x: Vec<f64> = (0..1 << 16)
            .map(|_| {
                state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
                (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
            })
            .collect();
        let psd = welch(&x, 10.0, 1024).unwrap();
        let power: f64 = psd.density.iter().sum::<f64>() * 10.0 / 1024.0;
        assert!((power - 1.0 / 12.0).abs() < 0.01 / 12.0, "{power}");
        // Flat: the one-sided level of white noise is 2σ²/f_s.
        let level = 2.0 / 12.0 / 10.0;
        let mid: f64 = psd.density[100..400].iter().sum::<f64>() / 300.0;
        assert!((mid / level - 1.0).abs() < 0.02, "{mid} vs {level}");
    }

    #[test]
    fn errors_are_reported() {
        assert_eq!(welch(&[0.0; 10], 1.0, 6).unwrap_err(), PsdError::BadSegment(6));
        assert_eq!(welch(&[0.0; 10], 1.0, 16).unwrap_err(), PsdError::TooShort { samples: 10, segment: 16 });
        assert_eq!(welch(&[0.0; 32], 0.0, 16).unwrap_err(), PsdError::BadRate(0.0));
    }
}
