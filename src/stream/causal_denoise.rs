//! Causal wavelet denoising (docs/design.md "Denoise (causal)").
//!
//! For each new sample the last `window` samples are denoised as a batch (the paper's db4,
//! three-level, universal-soft-threshold step, σ estimated on the window) and the value `lag`
//! samples back is emitted: the estimate of `x[t − lag]` uses samples up to `x[t]` only.
//! A larger lag moves the estimate away from the window's right edge, where the boundary
//! extension biases it, at the price of `lag` samples of delay.
//!
//! Cost: the finest-level interior detail of the F samples ending at each new sample is computed
//! once, when the sample arrives, and kept in a ring aligned with the samples; each push then reads
//! those instead of recomputing the level-1 convolution over the window (bit-identical: the same
//! products summed in the same order), computing only the boundary coefficients and the suffix
//! the emitted sample needs ([`Denoiser::denoise_at_with`]).
//!
//! Warm-up: until the window is full the denoiser works on every sample seen so far; before
//! there are enough samples for the configured level (`(F − 1)·2^level`, 56 for db4 at level 3)
//! the estimate is the raw sample itself.

use std::fmt;

use super::ring::RingBuffer;
use crate::wavelet::dwt::interior_detail;
use crate::wavelet::{DenoiseConfig, Denoiser};

/// Settings of the causal denoiser.
#[derive(Debug, Clone, PartialEq)]
pub struct CausalConfig {
    /// The batch denoiser applied to each window.
    pub denoise: DenoiseConfig,
    /// Number of most recent samples denoised at each step.
    pub window: usize,
    /// How many samples back the emitted estimate lies (0 = the newest sample).
    pub lag: usize,
}

impl CausalConfig {
    /// Shortest window for which the configured level is meaningful: `(F − 1)·2^level`.
    pub fn min_window(&self) -> usize {
        (self.denoise.wavelet.filter_len() - 1) << self.denoise.level
    }

    /// Checks the window and lag against each other and the wavelet.
    pub fn validate(&self) -> Result<(), CausalConfigError> {
        let min = self.min_window();
        if self.window < min {
            return Err(CausalConfigError::WindowTooShort { window: self.window, min });
        }
        if self.lag >= self.window {
            return Err(CausalConfigError::LagTooLong { lag: self.lag, window: self.window });
        }
        Ok(())
    }
}

/// Why a [`CausalConfig`] was refused.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum CausalConfigError {
    /// The window is shorter than the wavelet and level need.
    WindowTooShort {
        /// Configured window.
        window: usize,
        /// Minimum window.
        min: usize,
    },
    /// The lag does not fit in the window.
    LagTooLong {
        /// Configured lag.
        lag: usize,
        /// Configured window.
        window: usize,
    },
}

impl fmt::Display for CausalConfigError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::WindowTooShort { window, min } => {
                write!(f, "denoise window {window} is shorter than the minimum {min} for this wavelet and level")
            }
            Self::LagTooLong { lag, window } => write!(f, "denoise lag {lag} must be smaller than the window {window}"),
        }
    }
}

impl std::error::Error for CausalConfigError {}

/// Streaming denoiser: push raw samples, receive denoised estimates `lag` samples behind.
#[derive(Debug, Clone)]
pub struct CausalDenoiser {
    config: CausalConfig,
    ring: RingBuffer,
    /// `finest[i]`: the interior finest detail of the samples ending at `ring[i]` (NaN while
    /// fewer than F samples have arrived; such entries are never read).
    finest: RingBuffer,
    denoiser: Denoiser,
}

impl CausalDenoiser {
    /// Plans a denoiser; all buffers are allocated here, none per sample.
    pub fn new(config: CausalConfig) -> Result<Self, CausalConfigError> {
        config.validate()?;
        Ok(Self {
            ring: RingBuffer::new(config.window),
            finest: RingBuffer::new(config.window),
            denoiser: Denoiser::new(config.denoise.clone(), config.window),
            config,
        })
    }

    /// The settings.
    pub fn config(&self) -> &CausalConfig {
        &self.config
    }

    /// Samples pushed so far.
    pub fn pushed(&self) -> u64 {
        self.ring.total_pushed()
    }

    /// The raw samples in the window, oldest first (for a warm restart).
    pub fn window_samples(&self) -> &[f64] {
        self.ring.as_slice()
    }

    /// Refills the window with `samples` (oldest first, the last `window` kept) without emitting
    /// anything: the state [`push`](Self::push) would have reached had they been pushed, minus
    /// the outputs already consumed (a warm restart).
    pub fn prefill(&mut self, samples: &[f64]) {
        self.ring.clear();
        self.finest.clear();
        for &x in &samples[samples.len().saturating_sub(self.config.window)..] {
            self.append(x);
        }
    }

    /// Appends a raw sample and its interior finest detail (module documentation).
    fn append(&mut self, x: f64) {
        self.ring.push(x);
        let window = self.ring.as_slice();
        let hi = self.config.denoise.wavelet.dec_hi();
        let d = if window.len() >= hi.len() { interior_detail(window, hi, window.len() - 1) } else { f64::NAN };
        self.finest.push(d);
    }

    /// Pushes raw sample `x[t]` and returns the estimate of `x[t − lag]`, or `None` during the
    /// first `lag` pushes.
    pub fn push(&mut self, x: f64) -> Option<f64> {
        self.append(x);
        let held = self.ring.len();
        if held <= self.config.lag {
            return None;
        }
        let position = held - 1 - self.config.lag;
        Some(self.estimate_at(position))
    }

    /// Estimates for the last `lag` samples (which `push` has not yet emitted), from the current
    /// window with a shrinking lag; used at the end of an offline series.
    pub fn flush(&mut self) -> Vec<f64> {
        let held = self.ring.len();
        let pending = self.config.lag.min(held);
        (held - pending..held).map(|p| self.estimate_at(p)).collect()
    }

    fn estimate_at(&mut self, position: usize) -> f64 {
        let window = self.ring.as_slice();
        if window.len() < self.config.min_window() {
            return window[position];
        }
        self.denoiser.denoise_at_with(window, position, Some(self.finest.as_slice())).0
    }
}

/// Runs the causal denoiser over a whole series (offline), returning one estimate per sample:
/// `out[t]` uses samples up to `x[t + lag]` (fewer at the very end).
pub fn denoise_causal(x: &[f64], config: &CausalConfig) -> Result<Vec<f64>, CausalConfigError> {
    let mut denoiser = CausalDenoiser::new(config.clone())?;
    let mut out = Vec::with_capacity(x.len());
    for &v in x {
        out.extend(denoiser.push(v));
    }
    out.extend(denoiser.flush());
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::wavelet::denoise_batch;

    fn config(window: usize, lag: usize) -> CausalConfig {
        CausalConfig { denoise: DenoiseConfig::paper(), window, lag }
    }

    fn series(n: usize) -> Vec<f64> {
        (0..n).map(|i| (i as f64 * 0.03).sin() + 0.2 * ((i * 7919 % 97) as f64 / 97.0 - 0.5)).collect()
    }

    #[test]
    fn rejects_short_windows_and_long_lags() {
        assert_eq!(config(55, 0).validate(), Err(CausalConfigError::WindowTooShort { window: 55, min: 56 }));
        assert!(config(56, 0).validate().is_ok());
        assert_eq!(config(64, 64).validate(), Err(CausalConfigError::LagTooLong { lag: 64, window: 64 }));
    }

    #[test]
    fn emits_one_estimate_per_sample() {
        let x = series(500);
        for lag in [0, 3, 20] {
            assert_eq!(denoise_causal(&x, &config(64, lag)).unwrap().len(), x.len());
        }
    }

    /// Changing a sample after time t must not change any estimate emitted at or before t.
    #[test]
    fn estimates_never_use_future_samples() {
        let x = series(400);
        let (window, lag) = (64, 5);
        let base = denoise_causal(&x, &config(window, lag)).unwrap();
        let mut changed = x.clone();
        let t_change = 250;
        changed[t_change] += 10.0;
        let other = denoise_causal(&changed, &config(window, lag)).unwrap();
        // Estimates of samples whose emission time (target + lag) precedes the change agree.
        for target in 0..t_change - lag {
            assert_eq!(base[target], other[target], "target {target}");
        }
        assert_ne!(base[t_change - lag], other[t_change - lag]);
    }

    /// The cached finest details give the uncached single-position result bit for bit, through
    /// warm-up, the first full window and many slides (both parities of the decimation).
    #[test]
    fn cached_details_are_bit_identical_to_recomputing() {
        let x = series(700);
        for (window, lag) in [(64, 0), (64, 5), (81, 3), (256, 5)] {
            let c = config(window, lag);
            let mut streaming = CausalDenoiser::new(c.clone()).unwrap();
            let mut reference = Denoiser::new(c.denoise.clone(), window);
            for (t, &v) in x.iter().enumerate() {
                let Some(got) = streaming.push(v) else { continue };
                let w = &x[(t + 1).saturating_sub(window)..=t];
                let want = if w.len() < c.min_window() {
                    w[w.len() - 1 - lag]
                } else {
                    reference.denoise_at(w, w.len() - 1 - lag).0
                };
                assert_eq!(got.to_bits(), want.to_bits(), "window {window} lag {lag} t {t}");
            }
        }
    }

    /// A denoiser prefilled with the last window of a series continues exactly like one that saw
    /// the whole series (warm restart from a snapshot), finest-detail cache included.
    #[test]
    fn prefill_continues_bit_identically() {
        let x = series(600);
        let c = config(64, 5);
        let mut whole = CausalDenoiser::new(c.clone()).unwrap();
        for &v in &x[..400] {
            whole.push(v);
        }
        let mut restarted = CausalDenoiser::new(c).unwrap();
        restarted.prefill(&x[..400]);
        for &v in &x[400..] {
            assert_eq!(whole.push(v).map(f64::to_bits), restarted.push(v).map(f64::to_bits));
        }
    }

    #[test]
    fn full_window_equals_batch_on_that_window() {
        let x = series(300);
        let (window, lag) = (80, 7);
        let out = denoise_causal(&x, &config(window, lag)).unwrap();
        let t = 200;
        let (batch, _) = denoise_batch(&x[t + 1 - window..=t], &DenoiseConfig::paper());
        assert_eq!(out[t - lag], batch[window - 1 - lag]);
    }
}
