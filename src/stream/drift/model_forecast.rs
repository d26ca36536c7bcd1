//! The paper's drift estimator as an online estimator (`cpso-lssvm`): the causal db4 denoiser,
//! the history of committed denoised samples (model input and training window), the model slot a
//! background retrainer installs CPSO-LSSVM models into, and the running static mean used before
//! the first model (status bit 0).
//!
//! With denoiser lag L the newest denoised value before sample t is `x̃[t−1−L]`; the model (on
//! normalised values, Eq. 21) forecasts `x̃[t]` from it directly (a model fitted with horizon
//! L + 1, the retrainer's) or by iterating a one-step model L + 1 times (see
//! [`InstalledModel::predict_ahead`](crate::stream::model_slot::InstalledModel::predict_ahead)).
//! While the platform moves, the drift of the last static sample is held: an iterated LS-SVM
//! drifts to its fixed point within tens of steps, while the drift itself changes slowly.

use std::sync::Arc;

use super::{DriftEstimate, DriftEstimator, PendingMean};
use crate::stream::calibration::NoiseCalibration;
use crate::stream::causal_denoise::{CausalConfig, CausalConfigError, CausalDenoiser};
use crate::stream::model_slot::ModelSlot;
use crate::stream::ring::RingBuffer;
use crate::stream::warm::AxisWarm;

/// One axis of the model forecaster. Every buffer is allocated in [`ModelForecast::new`]; the
/// per-sample methods allocate nothing.
#[derive(Debug)]
pub(crate) struct ModelForecast {
    denoiser: CausalDenoiser,
    /// Committed denoised samples x̃, oldest first: the PSR history and the training window.
    history: RingBuffer,
    /// Room for the normalised history a model reads plus the iterated predictions.
    scratch: Vec<f64>,
    /// Samples from the newest denoised value to the sample compensated: denoiser lag + 1.
    steps: usize,
    slot: Arc<ModelSlot>,
    bias: f64,
    bias_count: u64,
    bias_samples: u64,
    /// The forecast made for the sample being processed, and the one of the last sample
    /// committed as static (held while moving).
    candidate: DriftEstimate,
    last: DriftEstimate,
}

impl ModelForecast {
    /// A forecaster keeping `history` denoised samples; the fallback mean averages
    /// `bias_samples` (cumulative, then exponential).
    pub(crate) fn new(causal: CausalConfig, history: usize, bias_samples: u64) -> Result<Self, CausalConfigError> {
        let steps = causal.lag + 1;
        Ok(Self {
            denoiser: CausalDenoiser::new(causal)?,
            history: RingBuffer::new(history.max(1)),
            scratch: vec![0.0; history.max(1) + steps],
            steps,
            slot: Arc::new(ModelSlot::new()),
            bias: 0.0,
            bias_count: 0,
            bias_samples: bias_samples.max(1),
            candidate: DriftEstimate { drift: 0.0, variance: f64::INFINITY, from_model: false },
            last: DriftEstimate { drift: 0.0, variance: f64::INFINITY, from_model: false },
        })
    }
}

impl DriftEstimator for ModelForecast {
    fn name(&self) -> &'static str {
        "cpso-lssvm"
    }

    /// The model's forecast; the running mean when no model is installed, the history is shorter
    /// than the model needs, or the model returns a non-finite value. Pending samples are not
    /// used: the denoiser needs them in order, once confirmed. The variance is the fallback
    /// mean's (a kernel forecast carries no variance of its own).
    #[inline]
    fn predict(&mut self, _now: u64, _pending: PendingMean, noise: &NoiseCalibration) -> DriftEstimate {
        let variance = match self.bias_count {
            0 => f64::INFINITY,
            n => noise.mean_variance(n as usize).unwrap_or(f64::INFINITY),
        };
        let guard = self.slot.load();
        self.candidate = match guard
            .as_ref()
            .and_then(|m| m.predict_ahead(self.history.as_slice(), self.steps, &mut self.scratch))
        {
            Some(d) => DriftEstimate { drift: d, variance, from_model: true },
            None => DriftEstimate { drift: self.bias, variance, from_model: false },
        };
        self.candidate
    }

    fn predict_moving(&mut self, _now: u64, _pending: PendingMean, _noise: &NoiseCalibration) -> DriftEstimate {
        let from_model = self.slot.load().is_some();
        DriftEstimate { from_model, ..self.last }
    }

    /// Feeds the denoiser, the history and the running mean (cumulative over the first
    /// `bias_samples`, then exponential).
    #[inline]
    fn commit(&mut self, _index: u64, raw: f64, _noise: &NoiseCalibration) {
        // With commit delay 0 (the threshold gate) this is the drift just used for `raw`.
        self.last = self.candidate;
        if let Some(x) = self.denoiser.push(raw) {
            self.history.push(x);
        }
        self.bias_count = (self.bias_count + 1).min(self.bias_samples);
        self.bias += (raw - self.bias) / self.bias_count as f64;
    }

    fn model_slot(&self) -> Option<&Arc<ModelSlot>> {
        Some(&self.slot)
    }

    fn training_history(&self) -> &[f64] {
        self.history.as_slice()
    }

    fn max_model_history(&self) -> usize {
        self.history.capacity()
    }

    fn model_steps(&self) -> usize {
        self.steps
    }

    fn has_reference(&self) -> bool {
        self.bias_count > 0
    }

    fn warm(&self, warm: &mut AxisWarm) {
        warm.denoiser_window = self.denoiser.window_samples().to_vec();
        warm.history = self.history.as_slice().to_vec();
        warm.bias = self.bias;
        warm.bias_count = self.bias_count;
    }

    /// The newest samples that fit are kept.
    fn restore(&mut self, warm: &AxisWarm) {
        self.denoiser.prefill(&warm.denoiser_window);
        self.history.clear();
        for &x in &warm.history[warm.history.len().saturating_sub(self.history.capacity())..] {
            self.history.push(x);
        }
        self.bias = warm.bias;
        self.bias_count = warm.bias_count.min(self.bias_samples);
        self.last = DriftEstimate { drift: warm.drift, variance: f64::INFINITY, from_model: false };
        self.candidate = self.last;
    }
}
