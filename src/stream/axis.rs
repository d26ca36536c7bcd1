//! The per-axis state of the [`Pipeline`](super::Pipeline): causal denoiser, the history of
//! static denoised samples (model input and training window), the model slot, the running bias
//! estimate used before the first model, and the last drift and compensated values.

use std::sync::Arc;

use super::causal_denoise::{CausalConfig, CausalConfigError, CausalDenoiser};
use super::model_slot::ModelSlot;
use super::ring::RingBuffer;
use super::snapshot::AxisWarm;

/// One axis. Every buffer is allocated in [`AxisState::new`]; the per-sample methods allocate
/// nothing.
#[derive(Debug)]
pub(crate) struct AxisState {
    denoiser: CausalDenoiser,
    /// Static denoised samples x̃, oldest first: the PSR history and the training window.
    pub(crate) history: RingBuffer,
    /// Room for the normalised history a model reads plus the iterated predictions.
    scratch: Vec<f64>,
    /// Samples from the newest denoised value to the sample compensated: denoiser lag + 1.
    steps: usize,
    pub(crate) slot: Arc<ModelSlot>,
    bias: f64,
    bias_count: u64,
    bias_samples: u64,
    /// Drift subtracted from the last accepted sample (held during motion and for rejects).
    pub(crate) drift: f64,
    /// Last compensated value of an accepted sample (the substitute for a rejected one).
    pub(crate) comp: f64,
}

impl AxisState {
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
            drift: 0.0,
            comp: 0.0,
        })
    }

    /// The forecast horizon every model must reach: denoiser lag + 1.
    pub(crate) fn steps(&self) -> usize {
        self.steps
    }

    /// The running static bias estimate (mean of recent accepted static raw samples); `None`
    /// before the first.
    pub(crate) fn bias(&self) -> Option<f64> {
        (self.bias_count > 0).then_some(self.bias)
    }

    /// Copies of the buffers and running values a warm restart needs.
    pub(crate) fn warm(&self) -> AxisWarm {
        AxisWarm {
            denoiser_window: self.denoiser.window_samples().to_vec(),
            history: self.history.as_slice().to_vec(),
            bias: self.bias,
            bias_count: self.bias_count,
            drift: self.drift,
            comp: self.comp,
        }
    }

    /// Restores what [`AxisState::warm`] copied (the newest samples that fit are kept).
    pub(crate) fn restore(&mut self, warm: &AxisWarm) {
        self.denoiser.prefill(&warm.denoiser_window);
        self.history.clear();
        for &x in &warm.history[warm.history.len().saturating_sub(self.history.capacity())..] {
            self.history.push(x);
        }
        self.bias = warm.bias;
        self.bias_count = warm.bias_count.min(self.bias_samples);
        self.drift = warm.drift;
        self.comp = warm.comp;
    }

    /// Largest model history this axis can serve.
    pub(crate) fn max_model_history(&self) -> usize {
        self.history.capacity()
    }

    /// The drift forecast for the next static sample from the state so far, and whether the
    /// model made it (`false`: the running bias estimate).
    ///
    /// With denoiser lag L the newest denoised value before sample t arrives is `x̃[t−1−L]`; the
    /// model (on normalised values, Eq. 21) forecasts `x̃[t]` from it directly (a model fitted
    /// with horizon L + 1, the retrainer's) or by iterating a one-step model L + 1 times (see
    /// [`InstalledModel::predict_ahead`](super::model_slot::InstalledModel::predict_ahead)). Falls back to the bias estimate when no model is installed, the static
    /// history is shorter than the model needs, or the model returns a non-finite value.
    #[inline]
    pub(crate) fn forecast(&mut self) -> (f64, bool) {
        let guard = self.slot.load();
        if let Some(m) = guard.as_ref()
            && let Some(d) = m.predict_ahead(self.history.as_slice(), self.steps, &mut self.scratch)
        {
            return (d, true);
        }
        (self.bias, false)
    }

    /// Feeds an accepted static raw sample to the denoiser, the history and the bias estimate
    /// (a running mean over the last ~`bias_samples`: cumulative, then exponential).
    #[inline]
    pub(crate) fn push_static(&mut self, raw: f64) {
        if let Some(x) = self.denoiser.push(raw) {
            self.history.push(x);
        }
        self.bias_count = (self.bias_count + 1).min(self.bias_samples);
        self.bias += (raw - self.bias) / self.bias_count as f64;
    }
}
